//! Deployments per core-second of the reliability analysis: seed 001 T01
//! with its identified friction given a 5 % lognormal dispersion
//! (docs/reliability.md §6), 200 draws evaluated on one thread the way
//! every estimator evaluates them (`Problem::margins_batch`: one sample at
//! the end, the verdict's tolerance). `cargo bench -p deploywatch-sim
//! --bench reliability`; the median is recorded in docs/reliability.md §6.

use criterion::{criterion_group, criterion_main, Criterion};
use deploywatch_sim::reliability::mc::draw;
use std::hint::black_box;
use std::path::PathBuf;

#[path = "../examples/common/reliability_case.rs"]
mod case;

/// Draws per iteration.
const DRAWS: usize = 200;

fn bench(c: &mut Criterion) {
    let vary: Vec<String> = case::T01_VARY.iter().map(|v| v.to_string()).collect();
    let problem = case::problem(
        &PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(case::T01),
        &vary,
    )
    .expect("the bundled case");
    let xs: Vec<Vec<f64>> = (0..DRAWS as u64)
        .map(|i| problem.x_of(&draw(0, 0, i, 3)))
        .collect();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("pool");
    let mut g = c.benchmark_group("reliability");
    g.sample_size(10);
    g.bench_function("seed001_T01 200 deployments, one thread", |b| {
        b.iter(|| pool.install(|| black_box(problem.margins_batch(black_box(&xs)).expect("sim"))))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
