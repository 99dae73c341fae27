//! Packing throughput: disks per second for 10⁴, 10⁵ and 10⁶ disks (Table 3.4
//! grading, square domains), MX quadtree against the uniform grid.
//! Run: `cargo bench --bench packing`. Setup (scene building) is not timed.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use gapack::{Domain, Grading, IndexKind, PackerSettings, Scene, WallMode, pack};

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

fn packing(c: &mut Criterion) {
    let mut group = c.benchmark_group("pack");
    group.sample_size(10);
    for n in [1e4, 1e5, 1e6] {
        for (name, index) in [
            ("mx-quadtree", IndexKind::MxQuadtree),
            ("grid", IndexKind::Grid),
        ] {
            let scene = Scene {
                domain: Domain::rectangle(side_for(n), side_for(n)).expect("valid side"),
                walls: WallMode::Exact,
                wall_disk_diameter: None,
                grading: table_3_4(),
                gradient: None,
                packer: PackerSettings {
                    index,
                    ..PackerSettings::default()
                },
                seed: 1,
            };
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
