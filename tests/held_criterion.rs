//! `not_held`: a joint fails when its latch does not hold it at the end
//! (a ball plunger short of its crest, a pawl out of its notch), whatever
//! its switch reads (`host-sim/src/analysis/reliability/criteria.rs`).
//!
//! - With ideal latches it is `not_latched`: the same margins to the bit
//!   on draws of seed 001 T01.
//! - On seed 001 T01 with its pawls (friction given a 5 % normal
//!   dispersion, the crude Monte-Carlo draws of seed 0, the fixed sample
//!   below), a joint locked by its pawl whose switch is open at `T` fails
//!   `not_latched` and not `not_held`; the sample holds such a draw. The
//!   `not_held` verdicts are the same at the reference's tolerance (1e-6)
//!   and at 1e-7, and with the energy ledger booked but not enforced.
//!   `cargo run --release -p deploywatch-sim --example physical_held`
//!   measures both criteria on more draws (docs/measured.md).

use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::reliability::mc::draw;
use deploywatch_sim::reliability::Problem;
use std::path::PathBuf;

/// seed 001 T01 `name` with the laws `vary` and `--fail not_latched`.
fn problem(name: &str, vary: &[String]) -> Problem {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../data/mechanisms")
        .join(format!("{name}.toml"));
    Problem {
        mech: Mechanism::load(&path).expect("bundled mechanism"),
        vary: vary.iter().map(|v| v.parse().expect("vary")).collect(),
        fixed: Vec::new(),
        fail: vec!["not_latched".parse().expect("criterion")],
        corr: Vec::new(),
    }
}

fn not_latched() -> [deploywatch_sim::reliability::criteria::Criterion; 1] {
    ["not_latched".parse().expect("criterion")]
}

fn not_held() -> [deploywatch_sim::reliability::criteria::Criterion; 1] {
    ["not_held".parse().expect("criterion")]
}

#[test]
fn with_ideal_latches_not_held_is_not_latched() {
    let vary: Vec<String> = [(1, 2.63), (2, 1.7), (3, 0.001)]
        .iter()
        .map(|(j, c)| format!("coulomb_friction:joint={j}:lognormal({c},0.05)"))
        .collect();
    let p = problem("seed001_T01", &vary);
    let (mut failed, mut passed) = (0, 0);
    for i in 0..40 {
        let o = p.deploy(&p.x_of(&draw(0, 0, i, 3))).expect("run");
        let (a, b) = (o.g(&not_latched()), o.g(&not_held()));
        assert_eq!(a.to_bits(), b.to_bits(), "draw {i}: {a} vs {b}");
        if a <= 0.0 {
            failed += 1;
        } else {
            passed += 1;
        }
    }
    assert!(passed > 0, "no draw deployed: the comparison shows nothing");
    // Draws that fail make the comparison cover the stroke still to go.
    let far: Vec<String> = [(1, 2.63), (2, 4.0), (3, 0.001)]
        .iter()
        .map(|(j, c)| format!("coulomb_friction:joint={j}:lognormal({c},0.05)"))
        .collect();
    let q = problem("seed001_T01", &far);
    for i in 0..4 {
        let o = q.deploy(&q.x_of(&draw(0, 0, i, 3))).expect("run");
        let (a, b) = (o.g(&not_latched()), o.g(&not_held()));
        assert_eq!(
            a.to_bits(),
            b.to_bits(),
            "joint 2 at 4 N·m, draw {i}: {a} vs {b}"
        );
        failed += usize::from(a <= 0.0);
    }
    assert!(failed > 0, "no draw failed: the comparison shows nothing");
}

#[test]
fn a_pawl_locked_with_its_switch_open_is_held() {
    let vary: Vec<String> = [0.1315, 0.085, 0.00005]
        .iter()
        .enumerate()
        .map(|(j, sd)| format!("coulomb_friction:joint={}:normal(0,{sd})", j + 1))
        .collect();
    let p = problem("seed001_T01_pawl", &vary);
    let mut switch_open_but_held = 0;
    for i in 0..8 {
        let x = p.x_of(&draw(0, 0, i, 3));
        let (o, _) = p.deploy_tuned(&x, &|_| {}).expect("run");
        let held = o.g(&not_held()) > 0.0;
        if o.g(&not_latched()) <= 0.0 && held {
            switch_open_but_held += 1;
        }
        let tighter = |o: &mut deploywatch_sim::deployment::SimOptions| {
            o.rtol = 1e-7;
            o.atol = 1e-7;
        };
        let free = |o: &mut deploywatch_sim::deployment::SimOptions| o.max_drift = f64::INFINITY;
        for (name, tune) in [
            ("1e-7", &tighter as &dyn Fn(&mut _)),
            ("no ledger check", &free),
        ] {
            let (other, _) = p.deploy_tuned(&x, tune).expect("run");
            assert_eq!(
                other.g(&not_held()) > 0.0,
                held,
                "draw {i}: not_held's verdict moves at {name}: {o:?} vs {other:?}"
            );
        }
    }
    assert!(
        switch_open_but_held > 0,
        "no draw of the sample has a latch holding with its switch open"
    );
}
