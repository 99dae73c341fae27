//! `packing.vtp`: the packing as VTK XML PolyData with its arrays in one
//! raw binary appended block, for ParaView and VisIt at any size.

use std::fmt::Write as _;
use std::io::{self, Write};

use rayon::prelude::*;

use super::binary::{Array, Kind, extra_arrays, material, shape_arrays};
use super::common::VERSION;
use crate::layering::Material;
use crate::output::digits::write_blocks;
use crate::output::format::ParticleColumn;
use crate::output::format::VtpCompression;
use crate::packer::Packing;

/// File name of the packing as VTK XML PolyData.
pub const PACKING_VTP: &str = "packing.vtp";

/// The packed particles (not the wall disks) as a VTK XML PolyData file
/// (`version="1.0"`, little-endian, `header_type="UInt64"`), streamed to
/// `out` array by array from the packing, never held whole.
///
/// One point per particle at `(x, y, 0)` in mm (`Points`, Float64), in
/// placement order (point `i` is row `i` of `packing.csv`), each with a
/// one-point vertex cell (`Verts`: `connectivity` and `offsets`, Int64) so
/// that the points show without a filter. Point data: `radius` (Float64;
/// for particles that are not disks the area-equivalent radius), for a
/// packing of shapes `angle` (radians) and, where `packing.csv` has them,
/// `a`, `b`, `alpha`, `beta` of superellipses and `template` (Int32),
/// `rounding` of rounded polygons (NaN, or template −1, on a particle of
/// the other family); `material` (Int32: the index into the config's
/// materials, 0 without materials) and `id` (Int64: the row of
/// `packing.csv`).
///
/// The data are uncompressed, in one `<AppendedData encoding="raw">`
/// block after its `_` marker: each array as a UInt64 byte count and its
/// little-endian values, each `DataArray`'s `offset` counting from the
/// byte after the marker.
///
/// # Errors
/// The I/O error of `out`.
pub fn write_packing_vtp(
    packing: &Packing,
    materials: &[Material],
    out: &mut dyn Write,
) -> io::Result<()> {
    write_packing_vtp_with(packing, materials, VtpCompression::None, &[], out)
}

/// [`write_packing_vtp`], the arrays stored as `compression` asks, with
/// the per-particle `columns` (`[output] per_particle`) as Float64 point
/// data after `id`, in their order.
///
/// With [`VtpCompression::Zlib`] the file is as VTK's own writer makes it
/// with `vtkZLibDataCompressor`: the `VTKFile` element names the
/// compressor, and each array in the appended block is a header of UInt64
/// — the number of blocks, the uncompressed size of a block (32768
/// bytes), that of the last block if partial (else 0), then each block's
/// compressed size — followed by the blocks, each a zlib stream of its
/// part of the little-endian values (level 1). `offset` counts from the
/// byte after the marker to each array's header.
///
/// The blocks are compressed on all cores, in order, so the bytes do not
/// depend on the number of threads; the offsets in the XML head need
/// every array's compressed size before any array is written, so the
/// blocks are compressed twice (once to measure them, once to write
/// them) rather than held: memory stays a few blocks per thread.
///
/// # Errors
/// The I/O error of `out`.
pub fn write_packing_vtp_with(
    packing: &Packing,
    materials: &[Material],
    compression: VtpCompression,
    columns: &[ParticleColumn],
    out: &mut dyn Write,
) -> io::Result<()> {
    let disks = &packing.disks;
    let n = disks.len();
    let mut point_data = vec![Array::new("radius", Kind::F64, 1, n, |i, buf| {
        buf.extend_from_slice(&disks[i].r.to_le_bytes());
    })];
    point_data.extend(shape_arrays(packing));
    point_data.push(material(packing, materials));
    point_data.push(Array::new("id", Kind::I64, 1, n, index(0)));
    point_data.extend(extra_arrays(columns));
    let points = Array::new("Points", Kind::F64, 3, n, |i, buf| {
        for v in [disks[i].c.x, disks[i].c.y, 0.0] {
            buf.extend_from_slice(&v.to_le_bytes());
        }
    });
    let connectivity = Array::new("connectivity", Kind::I64, 1, n, index(0));
    let offsets = Array::new("offsets", Kind::I64, 1, n, index(1));

    let arrays: Vec<&Array<'_>> = point_data
        .iter()
        .chain([&points, &connectivity, &offsets])
        .collect();
    let zlib = compression == VtpCompression::Zlib;
    // Each array's compressed blocks' sizes (none uncompressed).
    let sizes: Vec<Vec<u64>> = arrays
        .iter()
        .map(|a| {
            if zlib {
                (0..blocks(a))
                    .into_par_iter()
                    .map_init(Vec::new, |scratch, b| {
                        compressed(a, b, scratch).len() as u64
                    })
                    .collect()
            } else {
                Vec::new()
            }
        })
        .collect();
    // Each array's offset in the appended block: the headers and arrays
    // before it.
    let mut at = 0u64;
    let mut stored = arrays.iter().zip(&sizes).map(|(a, sizes)| {
        let here = at;
        let size = if zlib {
            8 * (3 + sizes.len() as u64) + sizes.iter().sum::<u64>()
        } else {
            8 + a.bytes()
        };
        at = at.saturating_add(size);
        here
    });
    let mut offset = |_: &Array<'_>| stored.next().unwrap_or(0);
    let mut x = String::with_capacity(2048);
    // Writing to a String cannot fail.
    let _ = writeln!(x, "<?xml version=\"1.0\"?>");
    let _ = writeln!(
        x,
        "<!-- gapack {VERSION} packing: {n} particles, lengths in mm -->"
    );
    let compressor = if zlib {
        " compressor=\"vtkZLibDataCompressor\""
    } else {
        ""
    };
    let _ = writeln!(
        x,
        "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"{compressor}>"
    );
    let _ = writeln!(x, "  <PolyData>");
    let _ = writeln!(
        x,
        "    <Piece NumberOfPoints=\"{n}\" NumberOfVerts=\"{n}\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">"
    );
    let _ = writeln!(x, "      <PointData Scalars=\"radius\">");
    for a in &point_data {
        data_array(&mut x, a, offset(a));
    }
    let _ = writeln!(x, "      </PointData>");
    let _ = writeln!(x, "      <Points>");
    data_array(&mut x, &points, offset(&points));
    let _ = writeln!(x, "      </Points>");
    let _ = writeln!(x, "      <Verts>");
    data_array(&mut x, &connectivity, offset(&connectivity));
    data_array(&mut x, &offsets, offset(&offsets));
    let _ = writeln!(x, "      </Verts>");
    let _ = writeln!(x, "    </Piece>");
    let _ = writeln!(x, "  </PolyData>");
    let _ = write!(x, "  <AppendedData encoding=\"raw\">\n   _");
    out.write_all(x.as_bytes())?;
    for (a, sizes) in arrays.iter().zip(&sizes) {
        if zlib {
            let total = a.bytes();
            let mut header = vec![sizes.len() as u64, BLOCK as u64, total % BLOCK as u64];
            header.extend(sizes);
            for v in header {
                out.write_all(&v.to_le_bytes())?;
            }
            write_blocks(out, sizes.len(), |b, buf| {
                let mut scratch = Vec::new();
                buf.extend_from_slice(&compressed(a, b, &mut scratch));
            })?;
        } else {
            out.write_all(&a.bytes().to_le_bytes())?;
            a.write_to(out)?;
        }
    }
    out.write_all(b"\n  </AppendedData>\n</VTKFile>\n")
}

/// Uncompressed bytes of a zlib block (VTK's default block size).
const BLOCK: usize = 32_768;

/// zlib level of the blocks: the fastest, since coordinates barely
/// compress and the indices compress well at any level.
const ZLIB_LEVEL: u8 = 1;

/// How many zlib blocks array `a` takes.
fn blocks(a: &Array<'_>) -> usize {
    usize::try_from(a.bytes())
        .unwrap_or(usize::MAX)
        .div_ceil(BLOCK)
}

/// Block `b` of array `a`, zlib-compressed (`scratch`: its values).
fn compressed(a: &Array<'_>, b: usize, scratch: &mut Vec<u8>) -> Vec<u8> {
    let total = usize::try_from(a.bytes()).unwrap_or(usize::MAX);
    let start = b * BLOCK;
    let data = a.byte_range(start, (start + BLOCK).min(total), scratch);
    miniz_oxide::deflate::compress_to_vec_zlib(data, ZLIB_LEVEL)
}

/// Element `i` of an Int64 array is `i + from`.
fn index(from: i64) -> impl Fn(usize, &mut Vec<u8>) + Sync {
    move |i, buf| {
        let v = i64::try_from(i).unwrap_or(i64::MAX).saturating_add(from);
        buf.extend_from_slice(&v.to_le_bytes());
    }
}

/// One appended `DataArray` element.
fn data_array(x: &mut String, a: &Array<'_>, offset: u64) {
    let components = if a.components > 1 {
        format!(" NumberOfComponents=\"{}\"", a.components)
    } else {
        String::new()
    };
    let _ = writeln!(
        x,
        "        <DataArray type=\"{}\" Name=\"{}\"{components} format=\"appended\" offset=\"{offset}\"/>",
        a.kind.vtk(),
        a.name
    );
}
