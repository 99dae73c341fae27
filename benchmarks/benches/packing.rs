//! Packing throughput: disks per second for 10⁴, 10⁵ and 10⁶ disks (Table 3.4
//! grading, square domains), MX quadtree against the uniform grid.
//! Run: `cargo bench --bench packing`. Setup (scene building) is not timed.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use gapack::{IndexKind, PackerSettings, pack};

mod common;

fn packing(c: &mut Criterion) {
    let mut group = c.benchmark_group("pack");
    group.sample_size(10);
    for n in [1e4, 1e5, 1e6] {
        for (name, index) in [
            ("mx-quadtree", IndexKind::MxQuadtree),
            ("grid", IndexKind::Grid),
        ] {
            let packer = PackerSettings {
                index,
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

criterion_group! {
    name = benches;
    // No report charts: criterion's would need a system font.
    config = Criterion::default().without_plots();
    targets = packing
}
criterion_main!(benches);
