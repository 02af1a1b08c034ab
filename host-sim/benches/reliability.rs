//! Deployments per core-second of the reliability analysis: seed 001 T01
//! with its identified friction given a 5 % lognormal dispersion
//! (docs/reliability.md §6), 200 draws evaluated on one thread the way
//! every estimator evaluates them (`Problem::margins_batch`: one sample at
//! the end, the verdict's tolerance). `cargo bench -p deploywatch-sim
//! --bench reliability`; the median is recorded in docs/reliability.md §6.

use criterion::{criterion_group, criterion_main, Criterion};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::reliability::mc::draw;
use deploywatch_sim::reliability::Problem;
use std::hint::black_box;
use std::path::PathBuf;

/// Draws per iteration.
const DRAWS: usize = 200;

fn bench(c: &mut Criterion) {
    let mech = Mechanism::load(
        &PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../data/mechanisms/seed001_T01.toml"),
    )
    .expect("bundled mechanism");
    let problem = Problem {
        mech,
        vary: [
            "coulomb_friction:joint=1:lognormal(2.63,0.05)",
            "coulomb_friction:joint=2:lognormal(1.7,0.05)",
            "coulomb_friction:joint=3:lognormal(0.001,0.05)",
        ]
        .iter()
        .map(|v| v.parse().expect("vary"))
        .collect(),
        fixed: Vec::new(),
        fail: vec!["not_latched".parse().expect("criterion")],
        corr: Vec::new(),
    };
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
