//! One seed000 case 2 truss deployment with the paper's EFT (3.35 s of
//! motion, 9 tree coordinates, 6 loop rows, three lock events), default
//! tolerances, 100 Hz output. `cargo bench -p deploywatch-sim --bench truss`;
//! the median is recorded in docs/performance.md. The accuracy at these
//! settings is checked by tests/truss.rs (golden files, 100 Hz).

use criterion::{criterion_group, criterion_main, Criterion};
use deploywatch_sim::model::mechanism::Mechanism;
use deploywatch_sim::simulate::deployment::SimOptions;
use deploywatch_sim::simulate::multibody::simulate_wing;
use std::hint::black_box;
use std::path::PathBuf;

fn bench(c: &mut Criterion) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../data/mechanisms/seed000_case2_truss_eft.toml");
    let mech = Mechanism::load(&path).expect("bundled mechanism");
    let opts = SimOptions::default();
    let run = simulate_wing(&mech, &opts).expect("simulation");
    println!("seed000_case2_truss_eft: {:?}", run.run.stats);
    c.bench_function("simulate seed000_case2_truss_eft (100 Hz output)", |b| {
        b.iter(|| simulate_wing(black_box(&mech), &opts).expect("simulation"))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
