//! Packing throughput of particles that are not disks: ellipses (aspect
//! 1.5) and superellipses (α = β = 4, aspect 2) beside disks of the same
//! grading (Table 3.4, sieve sizes) and square, one core, one piece. Run:
//! `cargo bench -p gapack-benchmarks --bench shapes`. `gapack bench
//! --shapes` measures the same scenes with peak memory (docs/shapes.md).

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use gapack::{PackerSettings, ShapeSpec, pack};

mod common;

fn shapes(c: &mut Criterion) {
    let mut group = c.benchmark_group("shapes");
    group.sample_size(10);
    for n in [1e4, 1e5] {
        for (name, shape) in [
            ("disks", None),
            ("ellipses-1.5", Some(ShapeSpec::ellipses(1.5))),
            (
                "superellipses-4-2",
                Some(ShapeSpec::superellipses(2.0, 4.0)),
            ),
        ] {
            let square = common::square(n, PackerSettings::default());
            let scene = match shape {
                Some(s) => square.with_shape(s),
                None => square,
            };
            let count = pack(&scene).expect("packs").disks.len() as u64;
            group.throughput(Throughput::Elements(count));
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
    targets = shapes
}
criterion_main!(benches);
