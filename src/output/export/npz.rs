//! `packing.npz`: the packing's columns as numpy arrays in one zip, read
//! with `numpy.load`, written by hand and streamed from the packing.

use std::io::{self, Write};

use super::binary::{Array, columns as packing_columns, extra_arrays};
use crate::layering::Material;
use crate::output::format::ParticleColumn;
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
    write_packing_npz_with(packing, materials, &[], out)
}

/// [`write_packing_npz`] with the per-particle `columns` (`[output]
/// per_particle`) as float64 arrays after `material`, in their order
/// (`h6.npy`).
///
/// # Errors
/// The I/O error of `out`.
pub fn write_packing_npz_with(
    packing: &Packing,
    materials: &[Material],
    columns: &[ParticleColumn],
    out: &mut dyn Write,
) -> io::Result<()> {
    let mut arrays = packing_columns(packing, materials);
    arrays.extend(extra_arrays(columns));
    write_npz(&arrays, ZIP32_MAX, out)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::export::binary::Kind;

    fn le(b: &[u8], at: usize, n: usize) -> u64 {
        b[at..at + n]
            .iter()
            .rev()
            .fold(0, |v, &byte| (v << 8) | u64::from(byte))
    }

    /// The entries of a zip as (name, stored bytes), read from its end
    /// record (zip64 when it says so), central directory and local
    /// headers, each checked against its CRC-32.
    fn entries(b: &[u8]) -> Vec<(String, Vec<u8>)> {
        let eocd = b.len() - 22;
        assert_eq!(le(b, eocd, 4), 0x0605_4b50);
        let (mut count, mut start) = (le(b, eocd + 10, 2), le(b, eocd + 16, 4));
        if start == ZIP32_MAX {
            let locator = eocd - 20;
            assert_eq!(le(b, locator, 4), 0x0706_4b50);
            let record = le(b, locator + 8, 8) as usize;
            assert_eq!(le(b, record, 4), 0x0606_4b50);
            count = le(b, record + 32, 8);
            start = le(b, record + 48, 8);
        }
        let mut at = start as usize;
        let mut out = Vec::new();
        for _ in 0..count {
            assert_eq!(le(b, at, 4), 0x0201_4b50);
            let crc = le(b, at + 16, 4) as u32;
            let mut size = le(b, at + 24, 4);
            let (n, x, c) = (le(b, at + 28, 2), le(b, at + 30, 2), le(b, at + 32, 2));
            let mut local = le(b, at + 42, 4);
            let name = String::from_utf8(b[at + 46..at + 46 + n as usize].to_vec()).unwrap();
            let mut extra = at + 46 + n as usize;
            if x > 0 {
                assert_eq!(le(b, extra, 2), 1, "the zip64 extra field");
                extra += 4;
                if size == ZIP32_MAX {
                    size = le(b, extra, 8);
                    assert_eq!(le(b, extra + 8, 8), size);
                    extra += 16;
                }
                if local == ZIP32_MAX {
                    local = le(b, extra, 8);
                }
            }
            let local = local as usize;
            assert_eq!(le(b, local, 4), 0x0403_4b50);
            let (ln, lx) = (le(b, local + 26, 2) as usize, le(b, local + 28, 2) as usize);
            if le(b, local + 18, 4) == ZIP32_MAX {
                assert_eq!(le(b, local + 30 + ln + 4, 8), size, "local zip64 size");
            } else {
                assert_eq!(le(b, local + 18, 4), size);
            }
            let data = local + 30 + ln + lx;
            let bytes = b[data..data + size as usize].to_vec();
            assert_eq!(crc32fast::hash(&bytes), crc, "{name}");
            out.push((name, bytes));
            at += 46 + (n + x + c) as usize;
        }
        out
    }

    fn arrays() -> Vec<Array<'static>> {
        let v = |i: usize| (i as f64).sqrt() - 2.0;
        vec![
            Array::new("v", Kind::F64, 1, 1000, move |i, b| {
                b.extend_from_slice(&v(i).to_le_bytes());
            }),
            Array::new("m", Kind::I32, 1, 3, |i, b| {
                b.extend_from_slice(&(i as i32 - 1).to_le_bytes());
            }),
        ]
    }

    #[test]
    fn a_plain_and_a_zip64_archive_hold_the_same_npy_files() {
        let mut plain = Vec::new();
        write_npz(&arrays(), ZIP32_MAX, &mut plain).expect("in memory");
        let mut wide = Vec::new();
        write_npz(&arrays(), 0, &mut wide).expect("in memory");
        assert_ne!(plain, wide);
        // No zip64 record in the plain archive.
        assert!(!plain.windows(4).any(|w| w == 0x0606_4b50u32.to_le_bytes()));
        let (a, b) = (entries(&plain), entries(&wide));
        assert_eq!(a, b);
        assert_eq!(a.len(), 2);
        let (name, v) = &a[0];
        assert_eq!(name, "v.npy");
        let head = usize::from(u16::from_le_bytes([v[8], v[9]])) + 10;
        assert_eq!(head % 64, 0);
        let dict = std::str::from_utf8(&v[10..head]).unwrap();
        assert!(dict.starts_with("{'descr': '<f8', 'fortran_order': False, 'shape': (1000,), }"));
        assert_eq!(v.len() - head, 8000);
        let last = f64::from_le_bytes(v[v.len() - 8..].try_into().unwrap());
        assert_eq!(last.to_bits(), (999f64.sqrt() - 2.0).to_bits());
        let (name, m) = &a[1];
        assert_eq!(name, "m.npy");
        let head = usize::from(u16::from_le_bytes([m[8], m[9]])) + 10;
        assert!(std::str::from_utf8(&m[10..head]).unwrap().contains("'<i4'"));
        assert_eq!(m[head..], [-1i32, 0, 1].map(i32::to_le_bytes).concat());
    }
}
