//! `gapack bench --seams` and `gapack bench --periodic-edges`: zones of a
//! packing (along the strips' seams, along a periodic cell's edges)
//! measured against the rest, over seeds.

use std::time::Instant;

use super::BenchArgs;
use gapack::strips;
use gapack::{Domain, Grading, PackerSettings, Point, Scene, Strips, pack};
use gapack::{mean_sd, porosity, solid_area};

/// One zone of `gapack bench --seams`, over the seeds.
#[derive(Debug, Clone, serde::Serialize)]
pub struct SeamRow {
    /// The grading packed (a thesis table).
    pub grading: &'static str,
    /// Side of the square (mm), and the strips `"auto"` cut it into.
    pub side_mm: f64,
    pub strips: usize,
    /// How the square was packed: in strips, or in one piece.
    pub packed: &'static str,
    /// Which zone: near the seams (within 3 largest diameters), or away.
    pub zone: &'static str,
    /// Mean and standard deviation over the seeds of the zone's porosity,
    /// coordination and KS distance to the grading.
    pub porosity: f64,
    pub porosity_sd: f64,
    /// Standard deviation of the porosity of one-diameter cells within the
    /// zone (mean over the seeds).
    pub cell_sd: f64,
    pub coordination: f64,
    pub coordination_sd: f64,
    pub psd_ks: f64,
    pub psd_ks_sd: f64,
    /// Disks in the zone (mean over the seeds).
    pub disks: f64,
}

/// A grading table: `(diameter mm, percent passing)`.
type Table = &'static [(f64, f64)];

/// Half width of the seams' zone, in largest diameters.
const SEAM_BAND_DIAMETERS: f64 = 3.0;

/// The gradings of `gapack bench --seams`, each with the side of its square
/// (mm): the thesis' nearly one-size proppant in its 1000 mm square, and its
/// polydisperse benchmark grading in a square wide enough for `"auto"` to cut
/// (strips at least 200 largest diameters wide).
const SEAM_GRADINGS: [(&str, Table, f64); 2] = [
    ("Table 3.4", gapack::THESIS_TABLE_3_4, 1000.0),
    ("Table 3.1", gapack::THESIS_TABLE_3_1, 1500.0),
];

/// `gapack bench --seams`: for each grading of [`SEAM_GRADINGS`], a square
/// (of side `side` mm if given), for each seed packed in strips (`"auto"`)
/// and in one piece, each measured within 3 largest diameters of the strips'
/// seams and away from them, 3 largest diameters clear of the walls.
pub fn run_seams(side: Option<f64>, seeds: u64) -> anyhow::Result<Vec<SeamRow>> {
    let mut rows = Vec::new();
    for (name, table, default_side) in SEAM_GRADINGS {
        let grading = Grading::from_table(table, Default::default(), Default::default())?;
        let side = side.unwrap_or(default_side);
        let half = SEAM_BAND_DIAMETERS * grading.d_max();
        // Per (packed, zone): the zone of each seed.
        let mut zones: [Vec<gapack::Zone>; 4] = Default::default();
        // The layout, and so the seams, depend on the scene, not its seed.
        let strips_of = Scene::new(Domain::rectangle(side, side)?, grading.clone()).with_packer(
            PackerSettings {
                strips: Strips::Auto,
                ..PackerSettings::default()
            },
        );
        let count = strips::count(&strips_of).ok_or_else(|| {
            anyhow::anyhow!(
                "a {side} mm square of {name} is packed in one piece: take a larger side"
            )
        })?;
        let seams = strips::seams(&strips_of, count);
        for seed in 1..=seeds {
            let scene = strips_of.clone().with_seed(seed);
            let mut whole = scene.clone();
            whole.packer.strips = Strips::Count(1);
            for (k, scene) in [scene, whole].iter().enumerate() {
                let packing = pack(scene)?;
                let [near, away] = gapack::zones(&packing, scene, &seams, half, half);
                zones[2 * k].push(near);
                zones[2 * k + 1].push(away);
            }
        }
        let names = [
            ("strips", "near seams"),
            ("strips", "away"),
            ("one piece", "near the same lines"),
            ("one piece", "away"),
        ];
        rows.extend(names.into_iter().zip(zones).map(|((packed, zone), all)| {
            let of = |f: fn(&gapack::Zone) -> f64| mean_sd(&all.iter().map(f).collect::<Vec<_>>());
            let (porosity, porosity_sd) = of(|z| z.porosity);
            let (coordination, coordination_sd) = of(|z| z.coordination);
            let (psd_ks, psd_ks_sd) = of(|z| z.psd_ks);
            SeamRow {
                grading: name,
                side_mm: side,
                strips: count,
                packed,
                zone,
                porosity,
                porosity_sd,
                cell_sd: of(|z| z.cell_sd).0,
                coordination,
                coordination_sd,
                psd_ks,
                psd_ks_sd,
                disks: of(|z| z.disks as f64).0,
            }
        }));
    }
    Ok(rows)
}

/// One zone of `gapack bench --periodic-edges`, over the seeds.
#[derive(Debug, Clone, serde::Serialize)]
pub struct EdgeRow {
    /// The grading packed.
    pub grading: &'static str,
    /// The periodic cell (mm).
    pub width_mm: f64,
    pub height_mm: f64,
    /// Which zone: the bands along the cell's edges (`EDGE_BAND_MM` wide on
    /// each side of each edge, as one-band-wide cells), the inside, the
    /// edges' porosity minus the inside's (per seed), the same bands along
    /// the two lines through the cell's centre, along the two lines half a
    /// period from the first disk (where the front closes on itself; the
    /// edges themselves when the first disk sits at the centre), their
    /// porosity minus the inside's (per seed), or the whole cell.
    pub zone: &'static str,
    /// Mean, standard deviation, least and greatest over the seeds of the
    /// zone's porosity.
    pub porosity: f64,
    pub porosity_sd: f64,
    pub porosity_min: f64,
    pub porosity_max: f64,
    /// Standard deviation of the porosity of the zone's cells (mean over
    /// the seeds; NaN for the difference and the whole cell).
    pub cell_sd: f64,
    /// Mean over the seeds of the zone's coordination and KS distance to
    /// the grading (NaN for the difference and the whole cell).
    pub coordination: f64,
    pub psd_ks: f64,
    /// Disks in the zone (mean over the seeds).
    pub disks: f64,
    /// Mean seconds per packing.
    pub seconds: f64,
}

/// Width of the bands along a periodic cell's edges (mm).
const EDGE_BAND_MM: f64 = 1.0;

/// The cells of `gapack bench --periodic-edges`: (grading name, its
/// diameters as a table, width, height in mm): the periodic cell of
/// configs/periodic_pfc.toml (1–1.66 mm uniform), and the thesis' nearly
/// one-size proppant in the same cell.
const EDGE_CELLS: [(&str, Table, f64, f64); 2] = [
    ("1-1.66 mm", &[(1.0, 0.0), (1.66, 100.0)], 50.0, 100.0),
    ("Table 3.4", gapack::THESIS_TABLE_3_4, 50.0, 100.0),
];

/// `gapack bench --periodic-edges`: for each cell of [`EDGE_CELLS`] and
/// seeds 1..=`seeds`, a periodic cell packed by the advancing front, its
/// porosity in 1 mm cells along the four edges (a band 1 mm wide on each
/// side of each edge, the images across it counted) against the other
/// cells, and in the same bands along the lines through its centre and
/// along those half a period from its first disk.
pub fn run_periodic_edges(seeds: u64) -> anyhow::Result<Vec<EdgeRow>> {
    let mut rows = Vec::new();
    for (name, table, width, height) in EDGE_CELLS {
        let grading = Grading::from_table(table, Default::default(), Default::default())?;
        let cell = Domain::periodic_rectangle(width, height)?;
        let (lo, hi) = cell.bounds();
        let edges = [
            [lo, Point::new(hi.x, lo.y)],
            [Point::new(hi.x, lo.y), hi],
            [hi, Point::new(lo.x, hi.y)],
            [Point::new(lo.x, hi.y), lo],
        ];
        let scene = Scene::new(cell.clone(), grading).with_walls(gapack::WallMode::Periodic);
        // The two lines through a point, across the cell.
        let lines_through = |p: Point| {
            [
                [Point::new(lo.x, p.y), Point::new(hi.x, p.y)],
                [Point::new(p.x, lo.y), Point::new(p.x, hi.y)],
            ]
        };
        let centre_lines = lines_through(Point::new((lo.x + hi.x) / 2.0, (lo.y + hi.y) / 2.0));
        // Per seed: edges, inside, centre lines, closure lines, whole cell,
        // and the seconds.
        let (mut near, mut away, mut centre, mut closure, mut whole, mut seconds) = (
            Vec::new(),
            Vec::new(),
            Vec::new(),
            Vec::new(),
            Vec::new(),
            0.0,
        );
        for seed in 1..=seeds {
            let scene = scene.clone().with_seed(seed);
            let t = Instant::now();
            let packing = pack(&scene)?;
            seconds += t.elapsed().as_secs_f64();
            let [n, a] = gapack::zones(&packing, &scene, &edges, EDGE_BAND_MM / 2.0, 0.0);
            near.push(n);
            away.push(a);
            let [c, _] = gapack::zones(&packing, &scene, &centre_lines, EDGE_BAND_MM / 2.0, 0.0);
            centre.push(c);
            // Half a period from the first disk, where the front closes last.
            let first = packing.disks.first().map_or(lo, |d| d.c);
            let last = cell.wrap(Point::new(
                first.x + (hi.x - lo.x) / 2.0,
                first.y + (hi.y - lo.y) / 2.0,
            ));
            let [c, _] = gapack::zones(
                &packing,
                &scene,
                &lines_through(last),
                EDGE_BAND_MM / 2.0,
                0.0,
            );
            closure.push(c);
            whole.push(porosity(solid_area(&packing.disks), cell.area()));
        }
        let seconds = seconds / seeds.max(1) as f64;
        let stats = |v: &[f64]| {
            let (mean, sd) = mean_sd(v);
            let min = v.iter().copied().fold(f64::INFINITY, f64::min);
            let max = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            (mean, sd, min, max)
        };
        let row = |zone, p: &[f64], z: Option<&[gapack::Zone]>| {
            let (porosity, porosity_sd, porosity_min, porosity_max) = stats(p);
            let of = |f: fn(&gapack::Zone) -> f64| {
                z.map_or(f64::NAN, |z| {
                    mean_sd(&z.iter().map(f).collect::<Vec<_>>()).0
                })
            };
            EdgeRow {
                grading: name,
                width_mm: width,
                height_mm: height,
                zone,
                porosity,
                porosity_sd,
                porosity_min,
                porosity_max,
                cell_sd: of(|z| z.cell_sd),
                coordination: of(|z| z.coordination),
                psd_ks: of(|z| z.psd_ks),
                disks: of(|z| z.disks as f64),
                seconds,
            }
        };
        let p = |z: &[gapack::Zone]| z.iter().map(|z| z.porosity).collect::<Vec<_>>();
        let diff: Vec<f64> = near
            .iter()
            .zip(&away)
            .map(|(n, a)| n.porosity - a.porosity)
            .collect();
        rows.push(row("edges", &p(&near), Some(&near)));
        rows.push(row("inside", &p(&away), Some(&away)));
        rows.push(row("edges - inside", &diff, None));
        rows.push(row("centre lines", &p(&centre), Some(&centre)));
        rows.push(row("closure lines", &p(&closure), Some(&closure)));
        let diff: Vec<f64> = closure
            .iter()
            .zip(&away)
            .map(|(c, a)| c.porosity - a.porosity)
            .collect();
        rows.push(row("closure - inside", &diff, None));
        rows.push(row("whole cell", &whole, None));
    }
    Ok(rows)
}

/// `gapack bench --seams`: print the table, then write seams.csv.
pub(super) fn seams_command(args: &BenchArgs) -> Result<(), crate::cli::Failure> {
    use crate::cli::{Failure, print_line};
    use anyhow::Context;
    use gapack::jobs::{DirStore, Store};
    let rows = run_seams(args.side, args.seeds)
        .context("cannot run the seam benchmark")
        .map_err(Failure::Run)?;
    print_line(format_args!(
        "{:<10} {:>7} {:>6} {:<10} {:<20} {:>17} {:>8} {:>15} {:>17} {:>8}",
        "grading",
        "side",
        "strips",
        "packed",
        "zone",
        "porosity",
        "cell_sd",
        "coordination",
        "psd_ks",
        "disks"
    ));
    for r in &rows {
        print_line(format_args!(
            "{:<10} {:>7} {:>6} {:<10} {:<20} {:>8.4} ± {:<6.4} {:>8.4} {:>6.3} ± {:<6.3} {:>7.4} ± {:<7.4} {:>8.0}",
            r.grading,
            r.side_mm,
            r.strips,
            r.packed,
            r.zone,
            r.porosity,
            r.porosity_sd,
            r.cell_sd,
            r.coordination,
            r.coordination_sd,
            r.psd_ks,
            r.psd_ks_sd,
            r.disks
        ));
    }
    let mut w = csv::Writer::from_writer(Vec::new());
    for row in &rows {
        w.serialize(row)
            .context("cannot format seams.csv")
            .map_err(Failure::Run)?;
    }
    let bytes = w
        .into_inner()
        .context("cannot format seams.csv")
        .map_err(Failure::Run)?;
    DirStore::new(&args.out)
        .write(&[("seams.csv".to_owned(), bytes)])
        .context("cannot write seams.csv")
        .map_err(Failure::Run)?;
    print_line(args.out.join("seams.csv").display());
    Ok(())
}

/// `gapack bench --periodic-edges`: print the table, then write periodic_edges.csv.
pub(super) fn periodic_edges_command(args: &BenchArgs) -> Result<(), crate::cli::Failure> {
    use crate::cli::{Failure, print_line};
    use anyhow::Context;
    use gapack::jobs::{DirStore, Store};
    let rows = run_periodic_edges(args.seeds)
        .context("cannot run the periodic-edges benchmark")
        .map_err(Failure::Run)?;
    print_line(format_args!(
        "{:<10} {:>9} {:<15} {:>17} {:>15} {:>8} {:>6} {:>7} {:>7} {:>8}",
        "grading",
        "cell_mm",
        "zone",
        "porosity",
        "min..max",
        "cell_sd",
        "coord",
        "psd_ks",
        "disks",
        "seconds"
    ));
    for r in &rows {
        print_line(format_args!(
            "{:<10} {:>9} {:<15} {:>8.4} ± {:<6.4} {:>7.4}..{:<6.4} {:>8.4} {:>6.3} {:>7.4} {:>7.0} {:>8.3}",
            r.grading,
            format!("{}x{}", r.width_mm, r.height_mm),
            r.zone,
            r.porosity,
            r.porosity_sd,
            r.porosity_min,
            r.porosity_max,
            r.cell_sd,
            r.coordination,
            r.psd_ks,
            r.disks,
            r.seconds
        ));
    }
    let mut w = csv::Writer::from_writer(Vec::new());
    for row in &rows {
        w.serialize(row)
            .context("cannot format periodic_edges.csv")
            .map_err(Failure::Run)?;
    }
    let bytes = w
        .into_inner()
        .context("cannot format periodic_edges.csv")
        .map_err(Failure::Run)?;
    DirStore::new(&args.out)
        .write(&[("periodic_edges.csv".to_owned(), bytes)])
        .context("cannot write periodic_edges.csv")
        .map_err(Failure::Run)?;
    print_line(args.out.join("periodic_edges.csv").display());
    Ok(())
}
