//! `packing.npz`: the packing's columns as numpy arrays in one zip, read
//! with `numpy.load`, written by hand and streamed from the packing.

use std::io::{self, Write};

use super::binary::{Array, columns};
use crate::layering::Material;
use crate::packer::Packing;

/// File name of the packing as numpy arrays.
pub const PACKING_NPZ: &str = "packing.npz";

/// The largest size or offset a plain zip field holds: beyond (or at)
/// it, the field says so and the zip64 extra field holds the value.
const ZIP32_MAX: u64 = 0xFFFF_FFFF;

/// Version needed to extract: 2.0 for stored entries, 4.5 with zip64.
const VERSION_PLAIN: u16 = 20;
/// Version needed to extract an entry with zip64 fields.
const VERSION_ZIP64: u16 = 45;

/// MS-DOS date of every entry, 1980-01-01 (the earliest it holds; time
/// 00:00), so that the same packing gives the same bytes.
const DOS_DATE: u16 = (1 << 5) | 1;

/// The packed particles (not the wall disks) as numpy's `.npz`: a zip of
/// uncompressed (stored) `.npy` files, one per column of `packing.csv`
/// but `id` (the index): `x.npy`, `y.npy`, `r.npy` (float64, mm; for
/// particles that are not disks `r` is the area-equivalent radius), for a
/// packing of shapes `angle.npy` and, where `packing.csv` has them,
/// `a`, `b`, `alpha`, `beta` (superellipses), `template` (int32) and
/// `rounding` (rounded polygons) — NaN, or template −1, on a particle of
/// the other family —, and `material.npy` (int32: the index into the
/// config's materials, 0 without materials). Each `.npy` is format 1.0,
/// little-endian, one dimension, C order.
///
/// Streamed to `out` from the packing, array by array (each is gone over
/// twice: once for its CRC-32, once to write it, so that the sizes and
/// CRC stand in the local header, before the data). Sizes and offsets
/// past 4 GiB (an archive of more than about 10⁸ particles) are written
/// as zip64, which numpy's reader (Python's `zipfile`) reads.
///
/// # Errors
/// The I/O error of `out`.
pub fn write_packing_npz(
    packing: &Packing,
    materials: &[Material],
    out: &mut dyn Write,
) -> io::Result<()> {
    write_npz(&columns(packing, materials), ZIP32_MAX, out)
}

/// One entry as the central directory lists it.
struct Entry {
    name: String,
    crc: u32,
    size: u64,
    offset: u64,
}

/// The zip of `arrays` as `.npy` files; a size or offset from `zip64_from`
/// on (at most [`ZIP32_MAX`]) is written as zip64.
fn write_npz(arrays: &[Array<'_>], zip64_from: u64, out: &mut dyn Write) -> io::Result<()> {
    let limit = zip64_from.min(ZIP32_MAX);
    let mut out = Counted { out, at: 0 };
    let mut entries = Vec::with_capacity(arrays.len());
    for a in arrays {
        let head = npy_header(a);
        let size = (head.len() as u64).saturating_add(a.bytes());
        let mut crc = crc32fast::Hasher::new();
        crc.update(&head);
        a.each_chunk(|chunk| {
            crc.update(chunk);
            Ok(())
        })?;
        let entry = Entry {
            name: format!("{}.npy", a.name),
            crc: crc.finalize(),
            size,
            offset: out.at,
        };
        let big = size >= limit;
        let mut h = Vec::with_capacity(64);
        put32(&mut h, 0x0403_4b50);
        put16(&mut h, if big { VERSION_ZIP64 } else { VERSION_PLAIN });
        put16(&mut h, 0); // flags
        put16(&mut h, 0); // stored
        put16(&mut h, 0); // time
        put16(&mut h, DOS_DATE);
        put32(&mut h, entry.crc);
        let size32 = if big { ZIP32_MAX as u32 } else { size as u32 };
        put32(&mut h, size32);
        put32(&mut h, size32);
        put16(&mut h, entry.name.len() as u16);
        put16(&mut h, if big { 20 } else { 0 });
        h.extend_from_slice(entry.name.as_bytes());
        if big {
            put16(&mut h, 1); // the zip64 extra field
            put16(&mut h, 16);
            put64(&mut h, size);
            put64(&mut h, size);
        }
        out.write_all(&h)?;
        out.write_all(&head)?;
        a.write_to(&mut out)?;
        entries.push(entry);
    }
    let start = out.at;
    for e in &entries {
        let (big_size, big_offset) = (e.size >= limit, e.offset >= limit);
        let mut extra = Vec::new();
        if big_size {
            put64(&mut extra, e.size);
            put64(&mut extra, e.size);
        }
        if big_offset {
            put64(&mut extra, e.offset);
        }
        let version = if extra.is_empty() {
            VERSION_PLAIN
        } else {
            VERSION_ZIP64
        };
        let mut h = Vec::with_capacity(80);
        put32(&mut h, 0x0201_4b50);
        put16(&mut h, version); // made by (MS-DOS attributes)
        put16(&mut h, version);
        put16(&mut h, 0);
        put16(&mut h, 0);
        put16(&mut h, 0);
        put16(&mut h, DOS_DATE);
        put32(&mut h, e.crc);
        let size32 = if big_size {
            ZIP32_MAX as u32
        } else {
            e.size as u32
        };
        put32(&mut h, size32);
        put32(&mut h, size32);
        put16(&mut h, e.name.len() as u16);
        put16(
            &mut h,
            if extra.is_empty() {
                0
            } else {
                4 + extra.len() as u16
            },
        );
        put16(&mut h, 0); // comment
        put16(&mut h, 0); // disk
        put16(&mut h, 0); // internal attributes
        put32(&mut h, 0); // external attributes
        put32(
            &mut h,
            if big_offset {
                ZIP32_MAX as u32
            } else {
                e.offset as u32
            },
        );
        h.extend_from_slice(e.name.as_bytes());
        if !extra.is_empty() {
            put16(&mut h, 1);
            put16(&mut h, extra.len() as u16);
            h.extend_from_slice(&extra);
        }
        out.write_all(&h)?;
    }
    let end = out.at;
    let (count, size) = (entries.len() as u64, end - start);
    let big = start >= limit || size >= limit || count >= 0xFFFF;
    let mut h = Vec::with_capacity(100);
    if big {
        put32(&mut h, 0x0606_4b50);
        put64(&mut h, 44); // the record's size after this field
        put16(&mut h, VERSION_ZIP64);
        put16(&mut h, VERSION_ZIP64);
        put32(&mut h, 0);
        put32(&mut h, 0);
        put64(&mut h, count);
        put64(&mut h, count);
        put64(&mut h, size);
        put64(&mut h, start);
        put32(&mut h, 0x0706_4b50); // the locator
        put32(&mut h, 0);
        put64(&mut h, end);
        put32(&mut h, 1);
    }
    let count16 = if big { 0xFFFF } else { count as u16 };
    put32(&mut h, 0x0605_4b50);
    put16(&mut h, 0);
    put16(&mut h, 0);
    put16(&mut h, count16);
    put16(&mut h, count16);
    put32(&mut h, if big { ZIP32_MAX as u32 } else { size as u32 });
    put32(&mut h, if big { ZIP32_MAX as u32 } else { start as u32 });
    put16(&mut h, 0); // comment
    out.write_all(&h)
}

/// The NPY 1.0 header of an array: magic, version, length, and the
/// dictionary padded with spaces and a newline to a multiple of 64 bytes.
fn npy_header(a: &Array<'_>) -> Vec<u8> {
    let dict = format!(
        "{{'descr': '{}', 'fortran_order': False, 'shape': ({},), }}",
        a.kind.npy(),
        a.len
    );
    let unpadded = 10 + dict.len() + 1;
    let total = unpadded.div_ceil(64) * 64;
    let mut h = Vec::with_capacity(total);
    h.extend_from_slice(b"\x93NUMPY\x01\x00");
    put16(&mut h, (total - 10) as u16);
    h.extend_from_slice(dict.as_bytes());
    h.resize(total - 1, b' ');
    h.push(b'\n');
    h
}

/// Appends `v`, little-endian.
fn put16(h: &mut Vec<u8>, v: u16) {
    h.extend_from_slice(&v.to_le_bytes());
}

/// Appends `v`, little-endian.
fn put32(h: &mut Vec<u8>, v: u32) {
    h.extend_from_slice(&v.to_le_bytes());
}

/// Appends `v`, little-endian.
fn put64(h: &mut Vec<u8>, v: u64) {
    h.extend_from_slice(&v.to_le_bytes());
}

/// A writer that counts the bytes written through it (the offsets of the
/// zip's records).
struct Counted<'w> {
    out: &'w mut dyn Write,
    at: u64,
}

impl Write for Counted<'_> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.out.write(buf)?;
        self.at += n as u64;
        Ok(n)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.out.flush()
    }
}
