//! Spatial indexes on the packer's own query pattern: for each disk of a real
//! packing, in placement order, one box query around it (half side
//! 3·r + r_max + 0.01·r, as the packer gathers a front's neighbours), the hits
//! filtered by exact distance, then the disk inserted. MX quadtree and
//! uniform grid (the packer's), a kd-tree (kiddo, Chebyshev distance = a box)
//! and an R-tree (rstar, envelope query), for 10³ to 10⁵ disks.
//! Run: `cargo bench --bench index`.
//!
//! Also writes `target/index-bench/index.csv` and a chart of operations
//! per second against the disk count (`index.svg`, `index.png`).

use std::hint::black_box;
use std::time::Instant;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use gapack::output::{Drawable, LineChart, Mark, Series};
use gapack::{Disk, Point};
use gapack::{Grid, MxQuadtree, SpatialIndex};
use gapack::{PackerSettings, pack};
use kiddo::{Chebyshev, KdTree};
use rstar::primitives::GeomWithData;
use rstar::{AABB, RTree};

mod common;

/// The disks of a packing of about `n` disks (Table 3.4, square domain).
fn disks(n: f64) -> Vec<Disk> {
    pack(&common::square(n, PackerSettings::default()))
        .expect("packs")
        .disks
}

/// One structure under test: insert in order, then box queries.
trait Index {
    fn build(lo: Point, hi: Point, bucket: f64) -> Self;
    fn insert(&mut self, id: u32, p: Point);
    /// Call `f` with every id whose point may lie in the box `c ± half`.
    fn query(&self, c: Point, half: f64, f: &mut dyn FnMut(u32));
}

struct Packer<I>(I);

impl<I: SpatialIndex> Index for Packer<I> {
    fn build(lo: Point, hi: Point, bucket: f64) -> Self {
        Packer(I::new(lo, hi, I::BUCKET_DIAMETERS * bucket))
    }
    fn insert(&mut self, id: u32, p: Point) {
        self.0.insert(id, p);
    }
    fn query(&self, c: Point, half: f64, f: &mut dyn FnMut(u32)) {
        let (lo, hi) = (
            Point::new(c.x - half, c.y - half),
            Point::new(c.x + half, c.y + half),
        );
        self.0.visit_box(lo, hi, f);
    }
}

struct Kd(KdTree<f64, 2>);

impl Index for Kd {
    fn build(_: Point, _: Point, _: f64) -> Self {
        Kd(KdTree::new())
    }
    fn insert(&mut self, id: u32, p: Point) {
        self.0.add(&[p.x, p.y], u64::from(id));
    }
    fn query(&self, c: Point, half: f64, f: &mut dyn FnMut(u32)) {
        for n in self.0.within_unsorted::<Chebyshev>(&[c.x, c.y], half) {
            f(n.item as u32);
        }
    }
}

struct RStar(RTree<GeomWithData<[f64; 2], u32>>);

impl Index for RStar {
    fn build(_: Point, _: Point, _: f64) -> Self {
        RStar(RTree::new())
    }
    fn insert(&mut self, id: u32, p: Point) {
        self.0.insert(GeomWithData::new([p.x, p.y], id));
    }
    fn query(&self, c: Point, half: f64, f: &mut dyn FnMut(u32)) {
        let envelope = AABB::from_corners([c.x - half, c.y - half], [c.x + half, c.y + half]);
        for g in self.0.locate_in_envelope(&envelope) {
            f(g.data);
        }
    }
}

/// Replay the packer's pattern on `disks`: query around each, then insert it.
/// Returns the number of true neighbours found (so nothing is optimised away).
fn replay<I: Index>(disks: &[Disk]) -> usize {
    let r_max = disks.iter().fold(0.0f64, |m, d| m.max(d.r));
    let (mut lo, mut hi) = (
        Point::new(f64::MAX, f64::MAX),
        Point::new(f64::MIN, f64::MIN),
    );
    for d in disks {
        lo = Point::new(lo.x.min(d.c.x), lo.y.min(d.c.y));
        hi = Point::new(hi.x.max(d.c.x), hi.y.max(d.c.y));
    }
    let mut index = I::build(lo, hi, 2.0 * r_max);
    let mut found = 0usize;
    for (id, d) in disks.iter().enumerate() {
        let reach = 3.0 * d.r + r_max;
        let half = reach + 0.01 * d.r;
        index.query(d.c, half, &mut |j| {
            let o = disks[j as usize];
            if (o.c - d.c).norm_squared() < reach * reach {
                found += 1;
            }
        });
        index.insert(id as u32, d.c);
    }
    found
}

const SIZES: [f64; 3] = [1e3, 1e4, 1e5];

fn indexes(c: &mut Criterion) {
    let mut group = c.benchmark_group("index");
    group.sample_size(10);
    for n in SIZES {
        let d = disks(n);
        // Every structure must find the same neighbours.
        let expected = replay::<Packer<Grid>>(&d);
        assert_eq!(replay::<Packer<MxQuadtree>>(&d), expected);
        assert_eq!(replay::<Kd>(&d), expected);
        assert_eq!(replay::<RStar>(&d), expected);
        group.throughput(Throughput::Elements(d.len() as u64));
        let id = |name| BenchmarkId::new(name, n as u64);
        group.bench_with_input(id("mx-quadtree"), &d, |b, d| {
            b.iter(|| black_box(replay::<Packer<MxQuadtree>>(d)))
        });
        group.bench_with_input(id("grid"), &d, |b, d| {
            b.iter(|| black_box(replay::<Packer<Grid>>(d)))
        });
        group.bench_with_input(id("kd-tree (kiddo)"), &d, |b, d| {
            b.iter(|| black_box(replay::<Kd>(d)))
        });
        group.bench_with_input(id("r-tree (rstar)"), &d, |b, d| {
            b.iter(|| black_box(replay::<RStar>(d)))
        });
    }
    group.finish();
    chart();
}

/// Best of five replays per structure and size, as disks (query + insert) per
/// second: `target/index-bench/index.csv`, `.svg`, `.png`.
fn chart() {
    let names = ["mx-quadtree", "grid", "kd-tree (kiddo)", "r-tree (rstar)"];
    let runs: [fn(&[Disk]) -> usize; 4] = [
        replay::<Packer<MxQuadtree>>,
        replay::<Packer<Grid>>,
        replay::<Kd>,
        replay::<RStar>,
    ];
    let mut series: Vec<Series> = names
        .iter()
        .enumerate()
        .map(|(i, name)| Series {
            name: (*name).to_owned(),
            points: Vec::new(),
            mark: Mark::Line,
            colour: i,
        })
        .collect();
    let mut csv = String::from("disks,index,seconds,disks_per_second\n");
    for n in SIZES {
        let d = disks(n);
        for (i, run) in runs.iter().enumerate() {
            let best = (0..5)
                .map(|_| {
                    let t = Instant::now();
                    black_box(run(&d));
                    t.elapsed().as_secs_f64()
                })
                .fold(f64::INFINITY, f64::min);
            let rate = d.len() as f64 / best;
            csv.push_str(&format!("{},{},{best},{rate}\n", d.len(), names[i]));
            series[i]
                .points
                .push(((d.len() as f64).log10(), rate / 1e6));
        }
    }
    let chart = LineChart {
        title: "Spatial indexes on the packer's query pattern".to_owned(),
        x_label: "log10(disks)".to_owned(),
        y_label: "million disks (query + insert) per second".to_owned(),
        series,
    };
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("../index-bench");
    let _ = std::fs::create_dir_all(&dir);
    let _ = std::fs::write(dir.join("index.csv"), csv);
    if let Ok(svg) = chart.to_svg() {
        let _ = std::fs::write(dir.join("index.svg"), svg);
    }
    if let Ok(png) = chart.to_png() {
        let _ = std::fs::write(dir.join("index.png"), png);
    }
}

criterion_group! {
    name = benches;
    // No report charts: criterion's would need a system font.
    config = Criterion::default().without_plots();
    targets = indexes
}
criterion_main!(benches);
