//! GA throughput: evaluations per second of one generation (64 genomes,
//! each a full packing) with 1 and 2 rayon threads, and so the parallel
//! efficiency t₁ / (2·t₂). Scenes: the thesis' AP-4 (20 mm square, 1.2–4.8 mm)
//! and the dense target (50 mm square, Table 3.1).
//! Run: `cargo bench --bench ga`. Scene and thread pools are built outside the timing.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use gapack::ga::{Limits, PorosityProblem, Search};
use gapack::{Cancel, config};

/// Genomes per generation, as in the shipped configs.
const POPULATION: usize = 64;

fn generation(c: &mut Criterion) {
    let mut group = c.benchmark_group("ga_generation");
    group.sample_size(10);
    for name in ["ap4", "dense_target"] {
        let path = format!("{}/../configs/{name}.toml", env!("CARGO_MANIFEST_DIR"));
        let text = std::fs::read_to_string(&path).expect("shipped config");
        let cfg = config::parse(&text, &path).expect("valid config");
        let settings = cfg.optimise.expect("[optimise] table");
        let problem = PorosityProblem::new(&cfg.scene, settings);
        let limits = Limits {
            population: POPULATION,
            ..Limits::from(&settings)
        };
        group.throughput(Throughput::Elements(POPULATION as u64));
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("thread pool");
            group.bench_with_input(BenchmarkId::new(name, threads), &threads, |b, _| {
                b.iter(|| {
                    pool.install(|| {
                        black_box(
                            Search::start(&problem, limits, 1, &Cancel::new())
                                .expect("a fresh token is never raised")
                                .initial()
                                .len(),
                        )
                    })
                })
            });
        }
    }
    group.finish();
}

criterion_group! {
    name = benches;
    // No report charts: criterion's would need a system font.
    config = Criterion::default().without_plots();
    targets = generation
}
criterion_main!(benches);
