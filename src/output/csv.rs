//! CSV tables: `packing.csv` (one row per packed disk, `id,x,y,r` in mm,
//! and `material` when the disks carry one), `convergence.csv` (one row per
//! generation of a GA run), `profile.csv` (one row per bin of a layering),
//! `window.csv` (one row per window of a fracture) and `wells.csv` (one row
//! per well of a batch).

use std::io::{self, Write};

use super::digits::{push_f64, push_int, write_rows};
use super::error::OutputError;
use super::plot::variant_label;
use crate::compare::CompareRun;
use crate::fracture::WindowStep;
use crate::ga::Generation;
use crate::geometry::{Grain, Outline};
use crate::layering::{Material, ProfileRow};
use crate::metrics::ShapeStats;
use crate::output::format::ParticleColumn;
use crate::packer::Packing;
use crate::stability::{StabilityRun, Status};

/// File name of the layering profile table.
pub const PROFILE_CSV: &str = "profile.csv";

/// File name of the disk table.
pub const PACKING_CSV: &str = "packing.csv";

/// File name of a fracture window's table.
pub const WINDOW_CSV: &str = "window.csv";

/// File name of a batch's table of wells.
pub const WELLS_CSV: &str = "wells.csv";

/// One well of a batch as `wells.csv` lists it.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WellRow {
    /// The well's name.
    pub well: String,
    /// Aperture at the wellbore (mm).
    pub width_mm: f64,
    /// Fracture height (m).
    pub height_m: f64,
    /// Disks packed (in window mode, in the last window).
    pub particles: usize,
    /// Porosity (in window mode, the window's estimate).
    pub porosity: f64,
    /// KS distance of the packed sizes to the grading.
    pub psd_ks: f64,
    /// Mean disk–disk contacts per disk (in window mode, the window's estimate).
    pub coordination: f64,
    /// Time to pack the well (all its windows in window mode) (s).
    pub seconds: f64,
    /// The particles' shape, when they are not disks (`None` for disks).
    #[serde(default)]
    pub shape: Option<WellShape>,
}

/// The shape of a well's particles as `wells.csv` gives it: means over
/// the particles of the packing written (the last window's in window mode).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WellShape {
    /// Mean aspect ratio (greatest over least width).
    pub aspect: f64,
    /// Mean Riley sphericity.
    pub sphericity: f64,
    /// Mean Wadell roundness.
    pub roundness: f64,
    /// Anisotropy of the long axes' fabric (0: no preferred direction, 1: aligned).
    pub anisotropy: f64,
}

impl WellShape {
    /// The figures `wells.csv` gives of `stats`.
    pub fn of(stats: &ShapeStats) -> WellShape {
        WellShape {
            aspect: stats.aspect.mean,
            sphericity: stats.sphericity.mean,
            roundness: stats.roundness.mean,
            anisotropy: stats.fabric.anisotropy,
        }
    }
}

/// The columns `wells.csv` adds when the particles are not disks.
const WELL_SHAPE_COLUMNS: [&str; 4] = [
    "aspect_mean",
    "sphericity_mean",
    "roundness_mean",
    "fabric_anisotropy",
];

/// One row per well: `well,width_mm,height_m,particles,porosity,psd_ks,coordination,seconds`,
/// and when the particles are not disks `aspect_mean,sphericity_mean,roundness_mean,fabric_anisotropy`.
///
/// # Errors
/// [`OutputError::Csv`] if the CSV writer fails (it does not on memory).
pub fn wells_csv(rows: &[WellRow]) -> Result<Vec<u8>, OutputError> {
    let shapes = rows.iter().any(|r| r.shape.is_some());
    let mut writer = ::csv::Writer::from_writer(Vec::new());
    let mut header = vec![
        "well",
        "width_mm",
        "height_m",
        "particles",
        "porosity",
        "psd_ks",
        "coordination",
        "seconds",
    ];
    if shapes {
        header.extend(WELL_SHAPE_COLUMNS);
    }
    writer.write_record(&header)?;
    for r in rows {
        let mut record = vec![
            r.well.clone(),
            r.width_mm.to_string(),
            r.height_m.to_string(),
            r.particles.to_string(),
            r.porosity.to_string(),
            r.psd_ks.to_string(),
            r.coordination.to_string(),
            r.seconds.to_string(),
        ];
        if shapes {
            match r.shape {
                Some(s) => record.extend(
                    [s.aspect, s.sphericity, s.roundness, s.anisotropy].map(|v| v.to_string()),
                ),
                None => record.extend([""; 4].map(str::to_owned)),
            }
        }
        writer.write_record(&record)?;
    }
    writer
        .into_inner()
        .map_err(|e| OutputError::Csv(e.into_error().into()))
}

/// One row per window tried: `length_mm,particles,porosity,coordination,spread,seconds`
/// (porosity and coordination of the window's core; spread empty with one block).
///
/// # Errors
/// [`OutputError::Csv`] if the CSV writer fails (it does not on memory).
pub fn window_csv(steps: &[WindowStep]) -> Result<Vec<u8>, OutputError> {
    let mut writer = ::csv::Writer::from_writer(Vec::new());
    writer.write_record([
        "length_mm",
        "particles",
        "porosity",
        "coordination",
        "spread",
        "seconds",
    ])?;
    for s in steps {
        let spread = if s.spread.is_finite() {
            s.spread.to_string()
        } else {
            String::new()
        };
        writer.write_record([
            s.length.to_string(),
            s.particles.to_string(),
            s.porosity.to_string(),
            s.coordination.to_string(),
            spread,
            s.seconds.to_string(),
        ])?;
    }
    writer
        .into_inner()
        .map_err(|e| OutputError::Csv(e.into_error().into()))
}

/// File name of a comparison's table.
pub const COMPARE_CSV: &str = "compare.csv";

/// One row per run of `gapack compare`: `method,seed,seconds,particles,porosity,target_error,psd_ks,max_overlap,coordination,local_porosity_std`
/// (`method` names the advancing front's index and contact rule too;
/// `target_error` empty without a target, `local_porosity_std` empty when
/// fewer than two windows fit).
///
/// # Errors
/// [`OutputError::Csv`] if the CSV writer fails (it does not on memory).
pub fn compare_csv(runs: &[CompareRun]) -> Result<Vec<u8>, OutputError> {
    let mut writer = ::csv::Writer::from_writer(Vec::new());
    writer.write_record([
        "method",
        "seed",
        "seconds",
        "particles",
        "porosity",
        "target_error",
        "psd_ks",
        "max_overlap",
        "coordination",
        "local_porosity_std",
    ])?;
    let cell = |v: Option<f64>| {
        v.filter(|v| v.is_finite())
            .map_or(String::new(), |v| v.to_string())
    };
    for r in runs {
        writer.write_record([
            variant_label(&r.variant),
            r.seed.to_string(),
            r.seconds.to_string(),
            r.particles.to_string(),
            r.porosity.to_string(),
            cell(r.target_error),
            r.psd_ks.to_string(),
            r.max_overlap.to_string(),
            r.coordination.to_string(),
            cell(Some(r.local_porosity_std)),
        ])?;
    }
    writer
        .into_inner()
        .map_err(|e| OutputError::Csv(e.into_error().into()))
}

/// File name of a stability sweep's table.
pub const STABILITY_CSV: &str = "stability.csv";

/// One row per run of `gapack stability`: `shape,ratio,width,method,seed,status,seconds,particles,empty,max_overlap,psd_ks,pass`
/// (`ratio` d_max/d_min, `width` in d_max, `status` finished | refused |
/// timed-out, `empty` the share farther than d_max from every disk).
///
/// # Errors
/// [`OutputError::Csv`] if the CSV writer fails (it does not on memory).
pub fn stability_csv(runs: &[StabilityRun]) -> Result<Vec<u8>, OutputError> {
    let mut writer = ::csv::Writer::from_writer(Vec::new());
    writer.write_record([
        "shape",
        "ratio",
        "width",
        "method",
        "seed",
        "status",
        "seconds",
        "particles",
        "empty",
        "max_overlap",
        "psd_ks",
        "pass",
    ])?;
    for r in runs {
        let status = match r.status {
            Status::Finished => "finished",
            Status::Refused => "refused",
            Status::TimedOut => "timed-out",
        };
        writer.write_record([
            r.case.shape.name().to_owned(),
            r.case.ratio.to_string(),
            r.case.width.to_string(),
            variant_label(&r.variant),
            r.seed.to_string(),
            status.to_owned(),
            r.seconds.to_string(),
            r.particles.to_string(),
            r.empty.to_string(),
            r.max_overlap.to_string(),
            r.psd_ks.to_string(),
            r.passed().to_string(),
        ])?;
    }
    writer
        .into_inner()
        .map_err(|e| OutputError::Csv(e.into_error().into()))
}

/// File name of the GA's convergence table.
pub const CONVERGENCE_CSV: &str = "convergence.csv";

/// One row per bin: `bin,s`, then `target_<name>` and `achieved_<name>` for
/// each material (fractions of the bin's solid area; empty in a bin with no
/// solid).
///
/// # Errors
/// [`OutputError::Csv`] if the CSV writer fails (it does not on memory).
pub fn profile_csv(rows: &[ProfileRow], materials: &[Material]) -> Result<Vec<u8>, OutputError> {
    let mut writer = ::csv::Writer::from_writer(Vec::new());
    let mut header = vec!["bin".to_owned(), "s".to_owned()];
    for prefix in ["target", "achieved"] {
        header.extend(materials.iter().map(|m| format!("{prefix}_{}", m.name)));
    }
    writer.write_record(&header)?;
    let cell = |v: f64| {
        if v.is_finite() {
            v.to_string()
        } else {
            String::new()
        }
    };
    for row in rows {
        let mut record = vec![row.bin.to_string(), row.s.to_string()];
        record.extend(row.target.iter().map(|&v| cell(v)));
        record.extend(row.achieved.iter().map(|&v| cell(v)));
        writer.write_record(&record)?;
    }
    writer
        .into_inner()
        .map_err(|e| OutputError::Csv(e.into_error().into()))
}

/// One row per generation: `generation,best,mean,worst,evaluations,seconds`,
/// where best, mean and worst are porosities (best: the best genome so far;
/// mean and worst: of the generation's population) and `evaluations` counts
/// distinct genomes evaluated so far.
///
/// # Errors
/// [`OutputError::Csv`] if the CSV writer fails (it does not on memory).
pub fn convergence_csv(history: &[Generation]) -> Result<Vec<u8>, OutputError> {
    let mut writer = ::csv::Writer::from_writer(Vec::new());
    writer.write_record([
        "generation",
        "best",
        "mean",
        "worst",
        "evaluations",
        "seconds",
    ])?;
    for g in history {
        writer.write_record([
            g.index.to_string(),
            g.best.value.to_string(),
            g.mean_value.to_string(),
            g.worst_value.to_string(),
            g.evaluations.to_string(),
            g.seconds.to_string(),
        ])?;
    }
    writer
        .into_inner()
        .map_err(|e| OutputError::Csv(e.into_error().into()))
}

/// Which particle columns a packing's table carries: none for disks; the
/// superellipse columns, the rounded-polygon columns, or both (a packing
/// that mixes the two families leaves the other family's cells empty).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct GrainColumns {
    /// `a, b, alpha, beta` (after `angle`).
    pub(crate) superellipse: bool,
    /// `template, rounding, vertices` (after `angle`, and after the
    /// superellipse columns when both are present).
    pub(crate) polygon: bool,
}

impl GrainColumns {
    /// The columns `grains` need.
    pub(crate) fn of(grains: &[Grain]) -> Self {
        let mut c = GrainColumns::default();
        for g in grains {
            match g.outline {
                Outline::Superellipse { .. } => c.superellipse = true,
                Outline::Polygon { .. } => c.polygon = true,
            }
        }
        c
    }

    /// The header names after `r`: `angle` and the families' columns.
    pub(crate) fn names(self) -> Vec<&'static str> {
        let mut names = Vec::new();
        if self.superellipse || self.polygon {
            names.push("angle");
        }
        if self.superellipse {
            names.extend(["a", "b", "alpha", "beta"]);
        }
        if self.polygon {
            names.extend(["template", "rounding", "vertices"]);
        }
        names
    }

    /// The cells of `grain` under [`GrainColumns::names`], in shortest
    /// round-trip form (empty under the other family's columns): the
    /// reference [`GrainColumns::push_cells`] is tested against.
    #[cfg(test)]
    pub(crate) fn cells(self, grain: &Grain) -> Vec<String> {
        let mut cells = vec![grain.angle.to_string()];
        match &grain.outline {
            Outline::Superellipse { a, b, alpha, beta } => {
                if self.superellipse {
                    cells.extend([a, b, alpha, beta].map(ToString::to_string));
                }
                if self.polygon {
                    cells.extend(std::iter::repeat_n(String::new(), 3));
                }
            }
            Outline::Polygon {
                template,
                vertices,
                rounding,
            } => {
                if self.superellipse {
                    cells.extend(std::iter::repeat_n(String::new(), 4));
                }
                if self.polygon {
                    cells.extend([
                        template.to_string(),
                        rounding.to_string(),
                        vertex_list(vertices),
                    ]);
                }
            }
        }
        cells
    }
}

impl GrainColumns {
    /// [`GrainColumns::cells`] appended to `buf`, each after a comma.
    fn push_cells(self, grain: &Grain, buf: &mut Vec<u8>) {
        buf.push(b',');
        push_f64(buf, grain.angle);
        match &grain.outline {
            Outline::Superellipse { a, b, alpha, beta } => {
                if self.superellipse {
                    for v in [*a, *b, *alpha, *beta] {
                        buf.push(b',');
                        push_f64(buf, v);
                    }
                }
                if self.polygon {
                    buf.extend_from_slice(b",,,");
                }
            }
            Outline::Polygon {
                template,
                vertices,
                rounding,
            } => {
                if self.superellipse {
                    buf.extend_from_slice(b",,,,");
                }
                if self.polygon {
                    buf.push(b',');
                    push_int(buf, *template);
                    buf.push(b',');
                    push_f64(buf, *rounding);
                    buf.push(b',');
                    for (k, p) in vertices.iter().enumerate() {
                        if k > 0 {
                            buf.push(b';');
                        }
                        push_f64(buf, p.x);
                        buf.push(b' ');
                        push_f64(buf, p.y);
                    }
                }
            }
        }
    }
}

/// A polygon's vertices as one CSV field: `x1 y1;x2 y2;…` (a space
/// between the coordinates of a vertex, a semicolon between vertices),
/// each number in shortest round-trip form.
#[cfg(test)]
pub(crate) fn vertex_list(vertices: &[crate::geometry::Point]) -> String {
    vertices
        .iter()
        .map(|p| format!("{} {}", p.x, p.y))
        .collect::<Vec<_>>()
        .join(";")
}

/// The packed disks (not the wall disks) as CSV: header `id,x,y,r`, `id` from
/// 0 in placement order, lengths in mm; with `materials` and disks that
/// carry one, a last column `material` holds its name (a single material
/// names every disk).
///
/// A packing of other particles (non-empty `packing.grains`) has, after
/// `r` (then the particle's area-equivalent radius), the column `angle`
/// (radians, counter-clockwise from the x axis to the particle's own x
/// axis), then for superellipses `a,b,alpha,beta` (semi-axes in mm along
/// the particle's own axes and the exponents of |x'/a|^alpha + |y'/b|^beta
/// ≤ 1) and for rounded polygons `template,rounding,vertices` (the
/// template's index, the corner radius in mm, and the vertices in the
/// particle's own axes as `x1 y1;x2 y2;…`, counter-clockwise about the
/// centroid); `material` comes last as for disks.
///
/// The per-particle `columns` (`[output] per_particle`, e.g. `h6`) come
/// last, after `material`, in their order: a reader of the table without
/// them finds its columns where they were, and without them the table is
/// as it was. NaN is written `NaN`.
///
/// Numbers use Rust's shortest round-trip formatting, so they read back
/// exactly and the same packing always gives the same bytes.
///
/// Streamed to `out` in blocks of rows formatted on all cores and written
/// in order: the table is never held whole in memory (a few blocks of
/// about a megabyte each), and its bytes do not depend on the number of
/// threads.
///
/// # Errors
/// The first I/O error of `out`.
pub fn write_packing_csv(
    packing: &Packing,
    materials: &[Material],
    columns: &[ParticleColumn],
    out: &mut dyn Write,
) -> io::Result<()> {
    let named = !materials.is_empty();
    let shapes = GrainColumns::of(&packing.grains);
    let mut header = vec!["id", "x", "y", "r"];
    if !packing.grains.is_empty() {
        header.extend(shapes.names());
    }
    if named {
        header.push("material");
    }
    header.extend(columns.iter().map(|c| c.name));
    out.write_all(header.join(",").as_bytes())?;
    out.write_all(b"\n")?;
    // Each material's cell, quoted as CSV needs, once.
    let names = materials
        .iter()
        .map(|m| csv_cell(&m.name))
        .collect::<io::Result<Vec<_>>>()?;
    // The row's end: its material, its per-particle columns, the newline.
    let material = |id: usize, buf: &mut Vec<u8>| {
        if named {
            let m = packing.materials.get(id).map_or(0, |&m| usize::from(m));
            buf.push(b',');
            if let Some(name) = names.get(m) {
                buf.extend_from_slice(name);
            }
        }
        for c in columns {
            buf.push(b',');
            push_f64(buf, c.at(id));
        }
        buf.push(b'\n');
    };
    let disks = &packing.disks;
    if packing.grains.is_empty() {
        return write_rows(out, disks.len(), |id, buf| {
            let disk = &disks[id];
            push_int(buf, id);
            for v in [disk.c.x, disk.c.y, disk.r] {
                buf.push(b',');
                push_f64(buf, v);
            }
            material(id, buf);
        });
    }
    let rows = disks.len().min(packing.grains.len());
    write_rows(out, rows, |id, buf| {
        let disk = &disks[id];
        push_int(buf, id);
        for v in [disk.c.x, disk.c.y, disk.r] {
            buf.push(b',');
            push_f64(buf, v);
        }
        shapes.push_cells(&packing.grains[id], buf);
        material(id, buf);
    })
}

/// `text` as one CSV cell: quoted as the `csv` crate quotes it (only when
/// it holds a comma, a quote or a line break).
fn csv_cell(text: &str) -> io::Result<Vec<u8>> {
    // The cell as the second of a record, so that the writer closes it
    // as in a row: `,cell\n`.
    let mut writer = ::csv::Writer::from_writer(Vec::new());
    writer.write_record(["", text])?;
    let record = writer
        .into_inner()
        .map_err(|e| io::Error::other(e.into_error()))?;
    Ok(record
        .strip_prefix(b",")
        .and_then(|r| r.strip_suffix(b"\n"))
        .unwrap_or(&record)
        .to_vec())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fmt::Write as _;

    /// The table as it was written before the fast formatting: `csv::Writer`
    /// and `Display`, the reference the fast path must equal byte for byte.
    fn write_packing_csv_display(
        packing: &Packing,
        materials: &[Material],
        out: &mut dyn Write,
    ) -> io::Result<()> {
        let mut writer = ::csv::Writer::from_writer(out);
        let named = !materials.is_empty();
        let shapes = GrainColumns::of(&packing.grains);
        if !packing.grains.is_empty() {
            let mut header = vec!["id", "x", "y", "r"];
            header.extend(shapes.names());
            if named {
                header.push("material");
            }
            writer.write_record(&header)?;
            for (id, (disk, grain)) in packing.disks.iter().zip(&packing.grains).enumerate() {
                let mut record = vec![
                    id.to_string(),
                    disk.c.x.to_string(),
                    disk.c.y.to_string(),
                    disk.r.to_string(),
                ];
                record.extend(shapes.cells(grain));
                if named {
                    let m = packing.materials.get(id).map_or(0, |&m| usize::from(m));
                    record.push(materials.get(m).map_or(String::new(), |m| m.name.clone()));
                }
                writer.write_record(&record)?;
            }
            return writer.flush();
        }
        if named {
            writer.write_record(["id", "x", "y", "r", "material"])?;
        } else {
            writer.write_record(["id", "x", "y", "r"])?;
        }
        // One row's fields, formatted into buffers reused from row to row.
        let mut fields: [String; 5] = Default::default();
        for (id, disk) in packing.disks.iter().enumerate() {
            for field in &mut fields {
                field.clear();
            }
            let [i, x, y, r, material] = &mut fields;
            // Formatting into a String cannot fail.
            let _ = (
                write!(i, "{id}"),
                write!(x, "{}", disk.c.x),
                write!(y, "{}", disk.c.y),
                write!(r, "{}", disk.r),
            );
            if named {
                let m = packing.materials.get(id).map_or(0, |&m| usize::from(m));
                if let Some(m) = materials.get(m) {
                    material.push_str(&m.name);
                }
                writer.write_record(&fields)?;
            } else {
                writer.write_record(&fields[..4])?;
            }
        }
        writer.flush()
    }

    use crate::geometry::{Disk, Domain, WallMode};

    #[test]
    fn rows_in_placement_order_with_round_trip_numbers() {
        let packing = Packing {
            walls: WallMode::Disks,
            boundary: vec![Disk::new(0.0, 0.0, 0.5)],
            ..Packing::of_disks(
                Domain::rectangle(10.0, 10.0).expect("valid rectangle"),
                vec![Disk::new(1.0, 2.0, 0.5), Disk::new(0.1 + 0.2, 7.25, 1e-7)],
            )
        };
        let mut bytes = Vec::new();
        write_packing_csv(&packing, &[], &[], &mut bytes).expect("csv");
        let text = String::from_utf8(bytes).expect("utf-8");
        assert_eq!(
            text,
            "id,x,y,r\n0,1,2,0.5\n1,0.30000000000000004,7.25,0.0000001\n"
        );
        let x: f64 = text
            .lines()
            .nth(2)
            .and_then(|l| l.split(',').nth(1))
            .map_or(0.0, |v| v.parse().unwrap_or(0.0));
        assert_eq!(x, 0.1 + 0.2);
    }

    #[test]
    fn per_particle_columns_come_last_and_leave_the_rest_unchanged() {
        let material = Material {
            name: "sand, fine".to_owned(),
            properties: Vec::new(),
        };
        for kind in [0, 3] {
            let packing = random_packing(9, kind, 300);
            let n = packing.disks.len();
            let mut values: Vec<f64> = (0..n).map(|i| i as f64 * 0.1 + 1e-7).collect();
            values[0] = f64::NAN;
            let columns = [
                ParticleColumn {
                    name: "h6",
                    values: values.clone(),
                },
                ParticleColumn {
                    name: "extra",
                    values: vec![2.5; n],
                },
            ];
            let materials = std::slice::from_ref(&material);
            let (mut plain, mut with) = (Vec::new(), Vec::new());
            write_packing_csv(&packing, materials, &[], &mut plain).expect("plain");
            write_packing_csv(&packing, materials, &columns, &mut with).expect("with");
            let (plain, with) = (
                String::from_utf8(plain).expect("utf-8"),
                String::from_utf8(with).expect("utf-8"),
            );
            assert_eq!(plain.lines().count(), with.lines().count());
            for (k, (a, b)) in plain.lines().zip(with.lines()).enumerate() {
                let end = if k == 0 {
                    ",h6,extra".to_owned()
                } else {
                    let v = values[k - 1];
                    let cell = if v.is_nan() {
                        "NaN".to_owned()
                    } else {
                        v.to_string()
                    };
                    format!(",{cell},2.5")
                };
                assert_eq!(b, format!("{a}{end}"), "kind {kind}, line {k}");
            }
        }
    }

    /// A random packing: disks, superellipses, rounded polygons or both,
    /// with coordinates of every magnitude the formatter treats apart
    /// (whole numbers, tiny and huge values), and material indices.
    pub(crate) fn random_packing(seed: u64, kind: usize, n: usize) -> Packing {
        use crate::geometry::{Disk, Domain};
        use rand::{Rng, SeedableRng};
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
        let value = |rng: &mut rand_xoshiro::Xoshiro256PlusPlus| match rng.gen_range(0..6) {
            0 => rng.gen_range(-100.0..100.0_f64).round(),
            1 => rng.gen_range(0.0..1e-5),
            2 => rng.gen_range(1e15..1e17),
            _ => rng.gen_range(-2000.0..2000.0),
        };
        let disks: Vec<Disk> = (0..n)
            .map(|_| Disk::new(value(&mut rng), value(&mut rng), value(&mut rng).abs()))
            .collect();
        let mut packing =
            Packing::of_disks(Domain::rectangle(10.0, 10.0).expect("rectangle"), disks);
        packing.materials = (0..n).map(|_| rng.gen_range(0..4)).collect();
        if kind > 0 {
            packing.grains = (0..n)
                .map(|_| {
                    let polygon = kind == 2 || (kind == 3 && rng.r#gen::<bool>());
                    let outline = if polygon {
                        let count = rng.gen_range(3..7);
                        Outline::Polygon {
                            template: rng.r#gen(),
                            vertices: (0..count)
                                .map(|_| {
                                    crate::geometry::Point::new(value(&mut rng), value(&mut rng))
                                })
                                .collect(),
                            rounding: value(&mut rng),
                        }
                    } else {
                        Outline::Superellipse {
                            a: value(&mut rng),
                            b: value(&mut rng),
                            alpha: value(&mut rng),
                            beta: value(&mut rng),
                        }
                    };
                    Grain {
                        outline,
                        angle: value(&mut rng),
                    }
                })
                .collect();
        }
        packing
    }

    #[test]
    fn the_fast_table_is_the_display_table_byte_for_byte() {
        let material = |name: &str| Material {
            name: name.to_owned(),
            properties: Vec::new(),
        };
        let sets = [
            vec![],
            vec![material("ceramic")],
            vec![
                material("hard, metal"),
                material("say \"hi\""),
                material(""),
                material("two\nlines"),
            ],
        ];
        for threads in [1, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("pool");
            for (seed, (kind, n)) in [(0, 0), (1, 0), (2, 1), (3, 2), (4, 3), (5, 0), (6, 3)]
                .into_iter()
                .zip([0, 1, 20_000, 700, 700, 40_000, 1_500])
                .enumerate()
                .map(|(s, ((k, _), n))| (s as u64, (k, n)))
            {
                let packing = random_packing(seed, kind, n);
                for materials in &sets {
                    let mut old = Vec::new();
                    write_packing_csv_display(&packing, materials, &mut old).expect("old");
                    let mut new = Vec::new();
                    pool.install(|| write_packing_csv(&packing, materials, &[], &mut new))
                        .expect("new");
                    let (old, new) = (
                        String::from_utf8(old).expect("utf-8"),
                        String::from_utf8(new).expect("utf-8"),
                    );
                    let first = old.lines().zip(new.lines()).find(|(a, b)| a != b);
                    assert!(
                        old == new,
                        "seed {seed}, kind {kind}, {} materials: {first:?}",
                        materials.len()
                    );
                }
            }
        }
    }
}
