//! What the binary exports (`packing.vtp`, `packing.npz`) share: the
//! packing's per-particle arrays, each streamed straight from the
//! [`Packing`] as little-endian bytes, a chunk at a time, so that no copy
//! of the packing is ever made whatever its size.

use std::io::{self, Write};

use crate::geometry::{Grain, Outline};
use crate::layering::Material;
use crate::output::csv::GrainColumns;
use crate::output::format::ParticleColumn;
use crate::packer::Packing;

/// Values per chunk: the buffer an array is formatted into before it is
/// written (at most 24 bytes a value: 384 KiB).
const CHUNK: usize = 16 * 1024;

/// The element type of an array.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Kind {
    /// IEEE double.
    F64,
    /// Signed 32-bit integer.
    I32,
    /// Signed 64-bit integer.
    I64,
}

impl Kind {
    /// Bytes per value.
    pub(super) fn size(self) -> u64 {
        match self {
            Kind::F64 | Kind::I64 => 8,
            Kind::I32 => 4,
        }
    }

    /// VTK's name of the type.
    pub(super) fn vtk(self) -> &'static str {
        match self {
            Kind::F64 => "Float64",
            Kind::I32 => "Int32",
            Kind::I64 => "Int64",
        }
    }

    /// numpy's `descr` of the type, little-endian.
    pub(super) fn npy(self) -> &'static str {
        match self {
            Kind::F64 => "<f8",
            Kind::I32 => "<i4",
            Kind::I64 => "<i8",
        }
    }
}

/// The bytes of element `i` of an array, appended to the buffer.
type Put<'a> = Box<dyn Fn(usize, &mut Vec<u8>) + Sync + 'a>;

/// One array of a binary export: `len` tuples of `components` values of
/// type `kind`, made element by element by `put`.
pub(super) struct Array<'a> {
    /// Its name in the file.
    pub(super) name: &'static str,
    /// Its element type.
    pub(super) kind: Kind,
    /// Values per tuple (3 for VTK's points, else 1).
    pub(super) components: usize,
    /// Tuples.
    pub(super) len: usize,
    put: Put<'a>,
}

impl<'a> Array<'a> {
    /// An array of `len` tuples, tuple `i` appended by `put`.
    pub(super) fn new(
        name: &'static str,
        kind: Kind,
        components: usize,
        len: usize,
        put: impl Fn(usize, &mut Vec<u8>) + Sync + 'a,
    ) -> Self {
        Array {
            name,
            kind,
            components,
            len,
            put: Box::new(put),
        }
    }

    /// A column of `f64`, value `i` given by `value`.
    fn f64(name: &'static str, len: usize, value: impl Fn(usize) -> f64 + Sync + 'a) -> Self {
        Array::new(name, Kind::F64, 1, len, move |i, buf| {
            buf.extend_from_slice(&value(i).to_le_bytes());
        })
    }

    /// A column of `i32`, value `i` given by `value`.
    fn i32(name: &'static str, len: usize, value: impl Fn(usize) -> i32 + Sync + 'a) -> Self {
        Array::new(name, Kind::I32, 1, len, move |i, buf| {
            buf.extend_from_slice(&value(i).to_le_bytes());
        })
    }

    /// Its size in bytes.
    pub(super) fn bytes(&self) -> u64 {
        (self.len as u64)
            .saturating_mul(self.components as u64)
            .saturating_mul(self.kind.size())
    }

    /// Hands its bytes to `sink`, a chunk at a time, in order.
    pub(super) fn each_chunk(
        &self,
        mut sink: impl FnMut(&[u8]) -> io::Result<()>,
    ) -> io::Result<()> {
        let per = self.components.max(1) * self.kind.size() as usize;
        let mut buf = Vec::with_capacity(CHUNK * per);
        let mut start = 0;
        while start < self.len {
            let end = self.len.min(start + CHUNK);
            buf.clear();
            for i in start..end {
                (self.put)(i, &mut buf);
            }
            sink(&buf)?;
            start = end;
        }
        Ok(())
    }

    /// Bytes `start..end` of the array (within [`Array::bytes`]), made in
    /// `scratch`: the tuples they fall in, cut to the range.
    pub(super) fn byte_range<'s>(
        &self,
        start: usize,
        end: usize,
        scratch: &'s mut Vec<u8>,
    ) -> &'s [u8] {
        let per = self.components.max(1) * self.kind.size() as usize;
        let (first, last) = (start / per, end.div_ceil(per).min(self.len));
        scratch.clear();
        for i in first..last {
            (self.put)(i, scratch);
        }
        let skip = first * per;
        &scratch[start - skip..end - skip]
    }

    /// Writes its bytes to `out`.
    pub(super) fn write_to(&self, out: &mut dyn Write) -> io::Result<()> {
        self.each_chunk(|chunk| out.write_all(chunk))
    }
}

/// `material` (Int32): each particle's index into `materials`, as
/// `packing.csv`'s `material` column names it (a particle beyond
/// `packing.materials` has material 0); 0 without materials.
pub(super) fn material<'a>(packing: &'a Packing, materials: &[Material]) -> Array<'a> {
    let named = !materials.is_empty();
    Array::i32("material", packing.disks.len(), move |i| {
        if named {
            i32::from(packing.materials.get(i).copied().unwrap_or(0))
        } else {
            0
        }
    })
}

/// The shape columns of `packing.csv`, as arrays (none for disks): `angle`
/// (radians); with superellipses `a`, `b`, `alpha`, `beta`; with rounded
/// polygons `template` (int) and `rounding` — NaN (or template −1) on a
/// particle of the other family, where `packing.csv` leaves the cell empty.
/// A polygon's vertex list, a variable-length cell, is in `packing.csv`
/// only.
pub(super) fn shape_arrays(packing: &Packing) -> Vec<Array<'_>> {
    let grains = &packing.grains;
    let n = grains.len();
    let columns = GrainColumns::of(grains);
    let mut arrays = Vec::new();
    if n == 0 {
        return arrays;
    }
    arrays.push(Array::f64("angle", n, |i| grains[i].angle));
    if columns.superellipse {
        let se = |g: &Grain, k: usize| match g.outline {
            Outline::Superellipse { a, b, alpha, beta } => [a, b, alpha, beta][k],
            Outline::Polygon { .. } => f64::NAN,
        };
        for (k, name) in ["a", "b", "alpha", "beta"].into_iter().enumerate() {
            arrays.push(Array::f64(name, n, move |i| se(&grains[i], k)));
        }
    }
    if columns.polygon {
        arrays.push(Array::i32("template", n, |i| match &grains[i].outline {
            Outline::Polygon { template, .. } => i32::from(*template),
            Outline::Superellipse { .. } => -1,
        }));
        arrays.push(Array::f64("rounding", n, |i| match &grains[i].outline {
            Outline::Polygon { rounding, .. } => *rounding,
            Outline::Superellipse { .. } => f64::NAN,
        }));
    }
    arrays
}

/// The per-particle `columns` of `[output] per_particle`, as float64
/// arrays under their names.
pub(super) fn extra_arrays(columns: &[ParticleColumn]) -> impl Iterator<Item = Array<'_>> {
    columns
        .iter()
        .map(|c| Array::f64(c.name, c.values.len(), |i| c.at(i)))
}

/// The per-particle columns: `x`, `y`, `r` (mm; for particles that are
/// not disks, `r` is the area-equivalent radius), then the shape columns
/// ([`shape_arrays`]) and `material` (int32), in `packing.csv`'s order.
pub(super) fn columns<'a>(packing: &'a Packing, materials: &[Material]) -> Vec<Array<'a>> {
    let disks = &packing.disks;
    let n = disks.len();
    let mut arrays = vec![
        Array::f64("x", n, |i| disks[i].c.x),
        Array::f64("y", n, |i| disks[i].c.y),
        Array::f64("r", n, |i| disks[i].r),
    ];
    arrays.extend(shape_arrays(packing));
    arrays.push(material(packing, materials));
    arrays
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Disk, Domain};

    #[test]
    fn an_array_streams_every_value_in_chunks_in_order() {
        let n = 2 * CHUNK + 7;
        let a = Array::f64("v", n, |i| i as f64 * 0.5);
        assert_eq!(a.bytes(), 8 * n as u64);
        let mut out = Vec::new();
        let mut chunks = 0;
        a.each_chunk(|c| {
            chunks += 1;
            out.extend_from_slice(c);
            Ok(())
        })
        .expect("in memory");
        assert_eq!(chunks, 3);
        assert_eq!(out.len() as u64, a.bytes());
        for (i, v) in out.chunks_exact(8).enumerate() {
            let v = f64::from_le_bytes(v.try_into().expect("8 bytes"));
            assert_eq!(v.to_bits(), (i as f64 * 0.5).to_bits());
        }
    }

    #[test]
    fn disks_have_the_csv_columns_and_no_shape_columns() {
        let domain = Domain::rectangle(10.0, 10.0).expect("a domain");
        let packing = Packing::of_disks(domain, vec![Disk::new(1.0, 2.0, 0.5)]);
        let names: Vec<&str> = columns(&packing, &[]).iter().map(|a| a.name).collect();
        assert_eq!(names, ["x", "y", "r", "material"]);
    }
}
