//! Packing throughput: disks per second for 10⁴ to 10⁷ disks (Table 3.4
//! grading, square domains), MX quadtree against the uniform grid, in one
//! piece and, from 10⁶ disks, in strips (`packer.strips = "auto"`, on the
//! threads `RAYON_NUM_THREADS` gives). Run: `cargo bench -p
//! gapack-benchmarks --bench packing` (`-- pack-strips` for the strips
//! alone). Setup (scene building) is not timed.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use gapack::{IndexKind, PackerSettings, Strips, pack};

mod common;

const INDEXES: [(&str, IndexKind); 2] = [
    ("mx-quadtree", IndexKind::MxQuadtree),
    ("grid", IndexKind::Grid),
];

/// Measure `pack` on the square of about `n` disks for each index, packed
/// in `strips`, as group `group`.
fn measure(c: &mut Criterion, group: &str, sizes: &[f64], strips: Strips) {
    let mut group = c.benchmark_group(group);
    group.sample_size(10);
    for &n in sizes {
        for (name, index) in INDEXES {
            let packer = PackerSettings {
                index,
                strips,
                ..PackerSettings::default()
            };
            let scene = common::square(n, packer);
            let disks = pack(&scene).expect("packs").disks.len() as u64;
            group.throughput(Throughput::Elements(disks));
            group.bench_with_input(BenchmarkId::new(name, n as u64), &scene, |b, s| {
                b.iter(|| pack(s).expect("packs"))
            });
        }
    }
    group.finish();
}

fn packing(c: &mut Criterion) {
    measure(c, "pack", &[1e4, 1e5, 1e6, 1e7], Strips::Count(1));
    measure(c, "pack-strips", &[1e6, 1e7], Strips::Auto);
}

criterion_group! {
    name = benches;
    // No report charts: criterion's would need a system font.
    config = Criterion::default().without_plots();
    targets = packing
}
criterion_main!(benches);
