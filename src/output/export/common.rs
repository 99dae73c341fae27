//! What the export writers share: text building, number formatting, the
//! set-up of an export (each disk's material and its row in the file's
//! unit, densities, the extent) and safe material labels.

use std::collections::BTreeSet;
use std::fmt;
use std::io::{self, Write as _};

use crate::geometry::{Point, bounds_of_disks};
use crate::layering::Material;
use crate::output::OutputError;
use crate::output::digits::{push_f64, write_rows};
use crate::output::format::ExportOptions;
use crate::packer::Packing;

/// gapack's version, written in the header of every export that has one.
pub(super) const VERSION: &str = env!("CARGO_PKG_VERSION");

/// How a checked export writes its file: to a stream, as it is produced;
/// only the stream can fail.
pub(crate) type Writer<'a> = crate::output::run::Stream<'a>;

/// The bytes `writer` writes, made in memory.
pub(super) fn bytes(writer: Writer<'_>) -> Vec<u8> {
    let mut out = Vec::new();
    // Writing to a Vec cannot fail.
    let _ = writer(&mut out);
    out
}

/// Bytes buffered before a text's lines go to the stream.
const LINES_BUFFER: usize = 1 << 16;

/// A text file written line by line to a stream: the lines gathered in a
/// small buffer, the tables of rows formatted in parallel blocks
/// ([`Lines::rows`]). The first I/O error is kept and every later write
/// skipped, so that the lines need not be checked one by one.
pub(super) struct Lines<'w> {
    out: &'w mut dyn io::Write,
    buffer: Vec<u8>,
    error: Option<io::Error>,
}

impl<'w> Lines<'w> {
    /// A text written to `out`.
    pub(super) fn new(out: &'w mut dyn io::Write) -> Self {
        Lines {
            out,
            buffer: Vec::with_capacity(LINES_BUFFER),
            error: None,
        }
    }

    /// Append one line (`\n`-terminated).
    pub(super) fn line(&mut self, args: fmt::Arguments<'_>) {
        // Writing to a Vec cannot fail.
        let _ = io::Write::write_fmt(&mut self.buffer, args);
        self.buffer.push(b'\n');
        if self.buffer.len() >= LINES_BUFFER {
            self.flush();
        }
    }

    /// `rows` rows, row `i` appended to a buffer by `row(i, buffer)`,
    /// formatted in parallel blocks and written in order
    /// ([`write_rows`]).
    pub(super) fn rows(&mut self, rows: usize, row: impl Fn(usize, &mut Vec<u8>) + Sync) {
        self.flush();
        if self.error.is_none()
            && let Err(error) = write_rows(self.out, rows, row)
        {
            self.error = Some(error);
        }
    }

    /// Writes the buffered lines.
    fn flush(&mut self) {
        if self.error.is_none()
            && let Err(error) = self.out.write_all(&self.buffer)
        {
            self.error = Some(error);
        }
        self.buffer.clear();
    }

    /// Writes what is left.
    ///
    /// # Errors
    /// The first I/O error of the stream.
    pub(super) fn finish(mut self) -> io::Result<()> {
        self.flush();
        self.error.map_or(Ok(()), Err)
    }
}

/// Appends `x` as [`Num`] writes it (`push_f64` within its plain range,
/// `{:e}` outside it).
pub(super) fn push_num(out: &mut Vec<u8>, x: f64) {
    let a = x.abs();
    if a == 0.0 || (1e-5..1e16).contains(&a) {
        push_f64(out, x);
    } else {
        // Writing to a Vec cannot fail.
        let _ = write!(out, "{x:e}");
    }
}

/// A number written in the shortest form that reads back to the same `f64`:
/// plain decimals for magnitudes in [1e-5, 1e16) (and zero), exponent form
/// (`1.5e-7`) otherwise, so no line grows long. Every reader the exports
/// target (C `strtod`, C++ streams, Python `float`, PFC) reads both forms.
#[derive(Debug, Clone, Copy)]
pub(super) struct Num(pub(super) f64);

impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let a = self.0.abs();
        if a == 0.0 || (1e-5..1e16).contains(&a) {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

/// What every export starts from: the packing, each disk's material
/// (checked against the materials given) and the length scale, with the
/// disks as rows ([`Export::rows`]) and the packing's extent and largest
/// radius.
pub(super) struct Export<'a> {
    /// The packing exported.
    pub(super) packing: &'a Packing,
    /// The export's length unit per mm (1 for files in mm).
    pub(super) s: f64,
    /// Per packed disk, its index in `materials` (`None` without materials).
    kinds: Vec<Option<usize>>,
}

/// One packed disk as an export writes it: lengths in the export's unit.
pub(super) struct Row {
    /// Index in placement order (`packing.csv`'s id, from 0).
    pub(super) id: usize,
    /// Centre, x.
    pub(super) x: Num,
    /// Centre, y.
    pub(super) y: Num,
    /// Radius.
    pub(super) r: Num,
    /// Diameter.
    pub(super) d: Num,
    /// Index into the materials (`None` without materials).
    pub(super) material: Option<usize>,
}

impl<'a> Export<'a> {
    /// The export of `packing` with `materials`, lengths times `s` (the
    /// unit's length for one mm).
    ///
    /// A disk beyond `packing.materials` has material 0 (as in
    /// `packing.csv`).
    ///
    /// # Errors
    /// [`OutputError::UnknownMaterial`] for the first disk whose index is
    /// not in a non-empty `materials`.
    pub(super) fn new(
        packing: &'a Packing,
        materials: &'a [Material],
        s: f64,
    ) -> Result<Self, OutputError> {
        let kinds = if materials.is_empty() {
            vec![None; packing.disks.len()]
        } else {
            (0..packing.disks.len())
                .map(|disk| {
                    let material = packing.materials.get(disk).copied().unwrap_or(0);
                    let index = usize::from(material);
                    if index < materials.len() {
                        Ok(Some(index))
                    } else {
                        Err(OutputError::UnknownMaterial {
                            disk,
                            material,
                            count: materials.len(),
                        })
                    }
                })
                .collect::<Result<_, _>>()?
        };
        Ok(Export { packing, s, kinds })
    }

    /// The DEM export of `packing`: lengths in `opts.units`.
    ///
    /// # Errors
    /// As [`Export::new`].
    pub(super) fn dem(
        packing: &'a Packing,
        materials: &'a [Material],
        opts: &ExportOptions,
    ) -> Result<Self, OutputError> {
        Export::new(packing, materials, opts.units.per_mm())
    }

    /// How many disks.
    pub(super) fn len(&self) -> usize {
        self.packing.disks.len()
    }

    /// Packed disk `id` (placement order), lengths scaled.
    pub(super) fn row(&self, id: usize) -> Row {
        let (disk, s) = (&self.packing.disks[id], self.s);
        Row {
            id,
            x: Num(disk.c.x * s),
            y: Num(disk.c.y * s),
            r: Num(disk.r * s),
            d: Num(2.0 * disk.r * s),
            material: self.kinds[id],
        }
    }

    /// Axis-aligned box (mm) holding the domain and every packed disk
    /// whole; a periodic cell's own bounds (its disks cross them, as
    /// periodic images).
    pub(super) fn extent(&self) -> (Point, Point) {
        extent(self.packing)
    }

    /// Largest packed radius (mm), 0 without disks; with grains, the
    /// largest circumradius.
    pub(super) fn r_max(&self) -> f64 {
        reach_max(self.packing)
    }
}

/// The domain's box grown to hold every packed particle whole (a periodic
/// cell: the cell): disks by their radius, grains by their circumradius.
pub(super) fn extent(packing: &Packing) -> (Point, Point) {
    let bounds = packing.domain.bounds();
    if packing.domain.is_periodic() {
        return bounds;
    }
    if packing.grains.is_empty() {
        return bounds_of_disks(bounds, &packing.disks);
    }
    let reach = reach_max(packing);
    packing.disks.iter().fold(bounds, |(lo, hi), d| {
        (
            Point::new(lo.x.min(d.c.x - reach), lo.y.min(d.c.y - reach)),
            Point::new(hi.x.max(d.c.x + reach), hi.y.max(d.c.y + reach)),
        )
    })
}

/// Largest radius (disks) or circumradius (grains) packed (mm), 0 without any.
pub(super) fn reach_max(packing: &Packing) -> f64 {
    if packing.grains.is_empty() {
        packing.disks.iter().map(|d| d.r).fold(0.0, f64::max)
    } else {
        packing
            .grains
            .iter()
            .map(|g| g.outline.circumradius())
            .fold(0.0, f64::max)
    }
}

/// Density (kg/m³) of material `m`: its `density` property, else the
/// options' default.
pub(super) fn density(materials: &[Material], m: Option<usize>, opts: &ExportOptions) -> f64 {
    m.and_then(|m| materials.get(m))
        .and_then(|m| m.properties.iter().find(|(key, _)| key == "density"))
        .map_or(opts.density, |&(_, value)| value)
}

/// Integer type of material `m` for codes that number types from 1:
/// index + 1, or 1 without materials.
pub(super) fn type_id(m: Option<usize>) -> usize {
    m.map_or(1, |m| m + 1)
}

/// Number of types: one per material, at least one.
pub(super) fn type_count(materials: &[Material]) -> usize {
    materials.len().max(1)
}

/// One label per material that any reader takes as a single word: its name
/// with every character other than an ASCII letter, digit or `_` replaced
/// by `_`. Should two labels then coincide (or one be empty), every material
/// is labelled `material_<index + 1>` instead, so labels stay unique.
pub(super) fn labels(materials: &[Material]) -> Vec<String> {
    let safe: Vec<String> = materials
        .iter()
        .map(|m| {
            m.name
                .chars()
                .map(|c| {
                    if c.is_ascii_alphanumeric() || c == '_' {
                        c
                    } else {
                        '_'
                    }
                })
                .collect()
        })
        .collect();
    let distinct: BTreeSet<&str> = safe.iter().map(String::as_str).collect();
    if distinct.len() == safe.len() && !distinct.contains("") {
        safe
    } else {
        (1..=materials.len())
            .map(|id| format!("material_{id}"))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn material(name: &str) -> Material {
        Material {
            name: name.to_owned(),
            properties: vec![("density".to_owned(), 3900.0)],
        }
    }

    #[test]
    fn numbers_read_back_exactly_in_either_form() {
        for v in [
            0.0,
            -0.0,
            1.0,
            0.1 + 0.2,
            1e-5,
            9.99e-6,
            1.5e-7,
            6.02e23,
            1e16,
            123.456,
        ] {
            let text = Num(v).to_string();
            assert_eq!(text.parse::<f64>(), Ok(v), "{text}");
            assert!(text.len() <= 24, "{text}");
        }
        assert_eq!(Num(0.25).to_string(), "0.25");
        assert_eq!(Num(1.5e-7).to_string(), "1.5e-7");
    }

    #[test]
    fn push_num_writes_what_num_displays() {
        use rand::{Rng, SeedableRng};
        use rand_xoshiro::Xoshiro256PlusPlus;
        let num = |x: f64| {
            let mut out = Vec::new();
            push_num(&mut out, x);
            String::from_utf8(out).expect("ascii")
        };
        let mut edges = vec![
            0.0,
            -0.0,
            1.0,
            0.5,
            1e-5,
            -1e-5,
            1e-5_f64.next_down(),
            1e16,
            1e16_f64.next_down(),
            -1e16,
            1.5e-7,
            6.02e23,
            f64::MAX,
            f64::MIN_POSITIVE,
            5e-324,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            2650.0e-9,
            1224.2,
        ];
        for e in -30..=30 {
            let p = 10f64.powi(e);
            edges.extend([p, -p, p * 1.5, p.next_up(), p.next_down()]);
        }
        for x in edges {
            assert_eq!(num(x), Num(x).to_string(), "{x:e}");
        }
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
        for _ in 0..100_000 {
            let bits = f64::from_bits(rng.r#gen::<u64>());
            let coordinate = rng.gen_range(-2000.0..2000.0_f64);
            for x in [
                bits,
                coordinate,
                coordinate * 1e-3,
                coordinate.round() * 1e-9,
            ] {
                assert_eq!(num(x), Num(x).to_string(), "{:x}", x.to_bits());
            }
        }
    }

    #[test]
    fn labels_are_single_words_and_unique() {
        let names = [material("ceramic"), material("hard metal")];
        assert_eq!(labels(&names), ["ceramic", "hard_metal"]);
        let clash = [material("a b"), material("a_b")];
        assert_eq!(labels(&clash), ["material_1", "material_2"]);
        let empty = [material("")];
        assert_eq!(labels(&empty), ["material_1"]);
    }

    #[test]
    fn density_falls_back_to_the_default() {
        let opts = ExportOptions::default();
        let with = [material("ceramic")];
        let without = [Material {
            name: "x".to_owned(),
            properties: vec![("youngs_modulus".to_owned(), 1.0)],
        }];
        assert_eq!(density(&with, Some(0), &opts), 3900.0);
        assert_eq!(density(&without, Some(0), &opts), 2650.0);
        assert_eq!(density(&[], None, &opts), 2650.0);
    }
}
