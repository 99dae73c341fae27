//! Picture rendering time for packings of 10⁴, 10⁵ and 10⁶ disks (Table 3.4
//! grading, square domains): `packing.png` (disks rasterised, PNG encoded),
//! the porosity map (computed, then drawn as PNG) and the grading chart.
//! Run: `cargo bench --bench pictures`. Packing the scenes is not timed.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use gapack::output::{Drawable, diameter_range, packing_png, porosity_map_chart, psd_chart};
use gapack::{Domain, Grading, PackerSettings, Scene, WallMode, pack};

fn table_3_4() -> Grading {
    Grading::from_table(
        gapack::grading::THESIS_TABLE_3_4,
        Default::default(),
        Default::default(),
    )
    .expect("valid table")
}

/// Side of the square holding about `n` disks of Table 3.4 at the bulk porosity 0.18.
fn side_for(n: f64) -> f64 {
    (n * table_3_4().mean_disk_area() / 0.82).sqrt()
}

fn pictures(c: &mut Criterion) {
    let mut group = c.benchmark_group("pictures");
    group.sample_size(10);
    for n in [1e4, 1e5, 1e6] {
        let scene = Scene {
            domain: Domain::rectangle(side_for(n), side_for(n)).expect("valid side"),
            walls: WallMode::Exact,
            wall_disk_diameter: None,
            grading: table_3_4(),
            gradient: None,
            packer: PackerSettings::default(),
            seed: 1,
        };
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
