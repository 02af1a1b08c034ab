//! One seed001_T01 nominal deployment (2.36 s of motion), at the default
//! tolerances, after checking that it is within 0.001° RMS of the golden
//! trajectory. `cargo bench -p deploywatch-sim --bench simulate`;
//! the median is recorded in docs/performance.md.

use criterion::{criterion_group, criterion_main, Criterion};
use deploywatch_sim::deployment::{simulate, SimOptions};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::run::Run;
use std::hint::black_box;
use std::path::PathBuf;

fn data(p: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../data")
        .join(p)
}

fn bench(c: &mut Criterion) {
    let mech = Mechanism::load(&data("mechanisms/seed001_T01.toml")).expect("bundled mechanism");
    let golden = Run::load(&data("reference/seed001_T01_nominal.csv")).expect("bundled golden run");
    // The golden files end at the last latch (formats.md: settle_s = 0).
    let opts = SimOptions {
        settle_s: Some(0.0),
        ..SimOptions::default()
    };
    // Accuracy at the benchmarked settings, on the golden 1 kHz grid.
    let fine = simulate(
        &mech,
        &[],
        &SimOptions {
            sample_hz: Some(1000.0),
            ..opts
        },
    )
    .expect("simulation");
    let mut sse = 0.0;
    let mut n = 0;
    for j in 0..3 {
        for i in 0..golden.len() {
            let d = fine.phi_deg[j][i] - golden.phi_deg[j][i];
            sse += d * d;
            n += 1;
        }
    }
    let rms = (sse / n as f64).sqrt();
    println!(
        "seed001_T01 nominal: RMS {rms:.2e} deg from golden, {:?}",
        fine.stats
    );
    assert!(rms <= 1e-3, "accuracy {rms} deg > 0.001 deg");

    c.bench_function("simulate seed001_T01 nominal (100 Hz output)", |b| {
        b.iter(|| simulate(black_box(&mech), &[], &opts).expect("simulation"))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
