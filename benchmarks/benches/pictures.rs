//! Picture rendering time for packings of 10⁴, 10⁵ and 10⁶ disks (Table 3.4
//! grading, square domains): `packing.png` (disks rasterised, PNG encoded),
//! the porosity map (computed, then drawn as PNG) and the grading chart.
//! Run: `cargo bench --bench pictures`. Packing the scenes is not timed.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use gapack::output::{Drawable, diameter_range, packing_png, porosity_map_chart, psd_chart};
use gapack::{PackerSettings, pack};

mod common;

fn pictures(c: &mut Criterion) {
    let mut group = c.benchmark_group("pictures");
    group.sample_size(10);
    for n in [1e4, 1e5, 1e6] {
        let scene = common::square(n, PackerSettings::default());
        let packing = pack(&scene).expect("packs");
        group.throughput(Throughput::Elements(packing.disks.len() as u64));
        let id = |name| BenchmarkId::new(name, n as u64);
        group.bench_function(id("packing.png"), |b| {
            b.iter(|| packing_png(&packing, &[], diameter_range(&packing)).expect("renders"))
        });
        group.bench_function(id("porosity_map.png"), |b| {
            b.iter(|| porosity_map_chart(&packing).to_png().expect("renders"))
        });
        group.bench_function(id("psd.png"), |b| {
            b.iter(|| {
                psd_chart(&packing, Some(&scene.grading))
                    .to_png()
                    .expect("renders")
            })
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    // No report charts: criterion's would need a system font.
    config = Criterion::default().without_plots();
    targets = pictures
}
criterion_main!(benches);
