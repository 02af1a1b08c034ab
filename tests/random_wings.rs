//! Invariants of the simulator on random valid wings
//! (`deploywatch_tests::wing_gen`), checked by proptest. Each case is one
//! wing drawn from a seed (printed by proptest on failure with the wing's
//! TOML and its effects); the wing is loaded from its TOML text as a user's
//! file and simulated with its drawn named effects:
//!
//! - an enabled `[rig]` on a wing with a physical latch is refused naming
//!   the rig, never dropped silently;
//! - the run ends normally: its energy ledger closes (a drift over 1e-6 of
//!   the stored energy would stop it with `SimError::EnergyDrift`), and a
//!   physical-latch run's reported worst drift is within that too;
//! - an ideal joint never passes its latch angle (it latches there), and a
//!   joint latched at the end is at its latch angle;
//! - the latch instants (the summary), the per-sample switch (the CSV) and
//!   the events agree: an ideal joint with a latch instant is latched at
//!   every later sample and has its latch event then, one without is
//!   latched at none; a physical joint has a latch instant exactly when its
//!   switch is closed at the end, the instant is its last switch-closing
//!   event (or 0), and the switch stays closed from then on;
//! - no physical joint passes its stop: the stop's elastic energy at the
//!   deepest sample is at most the energy stored at the start;
//! - no joint passes its stowed angle silently: a joint whose samples go
//!   more than `STOWED_TOLERANCE_DEG` past it is reported by the run
//!   (`Trajectory::past_stowed`), first past no later than its first such
//!   sample and at least as far as its farthest sample, and a joint reported
//!   is past by more than the tolerance (the format models no stop there:
//!   `docs/simulator.md`, "The stowed side"; counted in the record);
//! - the run is deterministic (two runs are identical);
//! - the core's `f32` chain (the monitor's, `deploywatch_core::Chain<f32>`)
//!   and the simulator's `f64` chain agree on the mass matrix and the
//!   spring torques at three states of the wing.
//!
//! `cargo test --release -p deploywatch-tests --test random_wings`;
//! cases: `DEPLOYWATCH_WINGS` (default 500). The larger run of `docs/simulator.md`
//! (recorded in `docs/measured.md` with `DEPLOYWATCH_FULL=1`):
//! `DEPLOYWATCH_WINGS=5000 DEPLOYWATCH_FULL=1 cargo test --release -p deploywatch-tests --test random_wings -- --nocapture`.

use deploywatch_core::monitor::Monitor;
use deploywatch_core::physics::latch_contact::LatchMark;
use deploywatch_core::Branch;
use deploywatch_sim::deployment::{self, SimOptions, Trajectory};
use deploywatch_sim::latch_deployment::{simulate_physical, LatchEventKind, LatchRun};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::monitor_config::monitor_config;
use deploywatch_sim::stowed::STOWED_TOLERANCE_DEG;
use deploywatch_tests::wing_gen::{wing_toml, Wing, PHYSICAL_SHARE};
use proptest::prelude::*;
use proptest::test_runner::TestRunner;
use std::cell::RefCell;
use std::time::Instant;

fn cases() -> u32 {
    std::env::var("DEPLOYWATCH_WINGS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(500)
}

/// The ledger's closure asked of every run, relative to the
/// stored energy.
const LEDGER_CLOSURE: f64 = 1e-6;

/// Checks the wing's invariants; the physical-latch run's worst ledger
/// drift relative to the stored energy (0 without one) and the farthest
/// the run reports a joint swung back past its stowed angle \[deg\] (0 if
/// none).
fn check(w: &Wing) -> Result<(f64, f64), TestCaseError> {
    let mech = Mechanism::from_toml_str(&w.toml, "random.toml");
    if w.rig && !w.physical.is_empty() {
        let e = mech.err().map(|e| e.to_string()).unwrap_or_default();
        prop_assert!(e.contains("rig") && e.contains("physical latch"), "{e}");
        return Ok((0.0, 0.0));
    }
    let mech = mech.map_err(|e| TestCaseError::fail(e.to_string()))?;
    let opts = SimOptions::default();
    let run = deployment::simulate(&mech, &w.effects, &opts);
    let again = deployment::simulate(&mech, &w.effects, &opts);
    prop_assert_eq!(&run, &again, "not deterministic");
    let traj = run.map_err(|e| TestCaseError::fail(format!("run failed: {e}")))?;
    let mut drift = 0.0;
    if !w.physical.is_empty() {
        let grid = deployment::sample_grid(&mech, &opts).map_err(fail)?;
        let lr = simulate_physical(&mech, &w.effects, &opts, grid).map_err(fail)?;
        prop_assert_eq!(&lr.traj, &traj, "the latch run differs from the run");
        check_physical(w, &mech, &lr)?;
        drift = lr.energy.worst_drift_j / lr.energy.stored_j.abs();
    }
    for j in (0..w.joints).filter(|j| !w.physical.contains(&(j + 1))) {
        check_ideal(&mech, &traj, j)?;
    }
    let past_stowed = check_stowed(&mech, &traj)?;
    check_f32(&mech)?;
    Ok((drift, past_stowed))
}

fn fail(e: impl std::fmt::Display) -> TestCaseError {
    TestCaseError::fail(e.to_string())
}

/// No joint passes its stowed angle silently: every joint whose samples
/// go more than [`STOWED_TOLERANCE_DEG`] past it is in the run's
/// `past_stowed`, with its stowed angle, first past no later than its first
/// such sample and at least as far as its farthest sample, within 1e-6°
/// (the turning point is located on the dense output; the run watches
/// every step, not only the samples); every joint reported is past by more
/// than the tolerance. The farthest reported \[deg\] (0 if none).
fn check_stowed(mech: &Mechanism, traj: &Trajectory) -> Result<f64, TestCaseError> {
    for (j, joint) in mech.joints.iter().enumerate() {
        let side = joint.stowed_deg.signum();
        let past = |p: &f64| side * p - joint.stowed_deg.abs();
        let farthest = traj.phi_deg[j].iter().map(past).fold(0.0f64, f64::max);
        let first = traj.phi_deg[j]
            .iter()
            .position(|p| past(p) > STOWED_TOLERANCE_DEG)
            .map(|i| traj.t_s[i]);
        let reported = traj.past_stowed.iter().find(|p| p.joint == j + 1);
        match (first, reported) {
            (None, None) => {}
            (Some(t), None) => prop_assert!(
                false,
                "joint {} passes its stowed angle {} deg by {farthest} deg at {t} s, unreported",
                j + 1,
                joint.stowed_deg
            ),
            (first, Some(r)) => {
                prop_assert_eq!(r.stowed_deg, joint.stowed_deg);
                prop_assert!(r.past_deg() > STOWED_TOLERANCE_DEG, "{r}");
                prop_assert!(
                    r.past_deg() >= farthest - 1e-6,
                    "{r}: samples {farthest} deg past"
                );
                prop_assert!(r.first_s <= r.farthest_s, "{r}");
                if let Some(t) = first {
                    prop_assert!(r.first_s <= t + 1e-9, "{r}: a sample past at {t} s");
                }
            }
        }
    }
    Ok(traj
        .past_stowed
        .iter()
        .map(|p| p.past_deg())
        .fold(0.0, f64::max))
}

/// An ideal joint: never past its latch; the summary's instant, the CSV's
/// switch and the angle agree.
fn check_ideal(mech: &Mechanism, traj: &Trajectory, j: usize) -> Result<(), TestCaseError> {
    let side = mech.joints[j].stowed_deg.signum();
    let phi = &traj.phi_deg[j];
    let worst = phi.iter().map(|p| -side * p).fold(f64::MIN, f64::max);
    prop_assert!(
        worst <= 1e-6,
        "joint {} passes its latch by {worst} deg",
        j + 1
    );
    let latched = &traj.latched[j];
    match traj.latch_s[j] {
        Some(t) => {
            for (i, (&ts, &l)) in traj.t_s.iter().zip(latched).enumerate() {
                if ts >= t + 1e-9 {
                    prop_assert!(l, "joint {} latched at {t} s, switch open at {ts} s", j + 1);
                    prop_assert!(
                        phi[i].abs() <= 1e-6,
                        "joint {} latched at {} deg",
                        j + 1,
                        phi[i]
                    );
                }
            }
        }
        None => prop_assert!(
            latched.iter().all(|l| !l),
            "joint {}: no latch instant, but the switch closes",
            j + 1
        ),
    }
    Ok(())
}

/// A physical-latch run: its ledger, and each physical joint's stop, latch
/// instant, switch and events.
fn check_physical(w: &Wing, mech: &Mechanism, lr: &LatchRun) -> Result<(), TestCaseError> {
    let e = &lr.energy;
    prop_assert!(
        e.worst_drift_j <= LEDGER_CLOSURE * e.stored_j.abs(),
        "ledger drift {:.3e} of the {} J stored",
        e.worst_drift_j,
        e.stored_j
    );
    let traj = &lr.traj;
    for &jj in &w.physical {
        let j = jj - 1;
        let (Some(spec), Some(joint)) = (&mech.latches[j], mech.joints.get(j)) else {
            return Err(fail(format!("joint {jj}: no physical latch read")));
        };
        let l = spec.to_core::<f64>(joint.stowed_deg, 1.0, 1.0);
        let deepest = traj.phi_deg[j]
            .iter()
            .map(|p| l.stop_energy(p.to_radians()))
            .fold(0.0, f64::max);
        prop_assert!(
            deepest <= e.stored_j * (1.0 + LEDGER_CLOSURE),
            "joint {jj} passes its stop: {deepest} J in the stop, {} J stored",
            e.stored_j
        );
        let closed_end = traj.latched[j].last().copied().unwrap_or(false);
        prop_assert_eq!(
            traj.latch_s[j].is_some(),
            closed_end,
            "joint {}: summary vs CSV",
            jj
        );
        let Some(t) = traj.latch_s[j] else { continue };
        let last_close = lr
            .events
            .iter()
            .rev()
            .find(|ev| {
                ev.joint == jj
                    && ev.kind == LatchEventKind::Mark(LatchMark::Switch)
                    && ev.rate_rad_s < 0.0
            })
            .map_or(0.0, |ev| ev.t_s);
        prop_assert_eq!(t, last_close, "joint {}: summary vs events", jj);
        for (&ts, &closed) in traj.t_s.iter().zip(&traj.latched[j]) {
            prop_assert!(
                ts < t + 1e-6 || closed,
                "joint {jj} latched at {t} s, switch open at {ts} s"
            );
        }
    }
    Ok(())
}

/// The monitor's `f32` chain against the simulator's `f64` chain of the
/// wing (no effects) at the stowed, half-way and deployed states: mass
/// matrices within 1e-5 of the largest entry, spring torques within 1e-4
/// of the largest torque plus 1e-6 N·m. Wings the monitor does not take
/// (its configuration refuses them) are skipped.
fn check_f32(mech: &Mechanism) -> Result<(), TestCaseError> {
    macro_rules! by_count {
        ($($n:literal)*) => {
            match mech.joint_count() {
                $($n => compare::<$n>(mech),)*
                n => Err(fail(format!("{n} joints"))),
            }
        };
    }
    by_count!(2 3 4 5 6 7 8)
}

fn compare<const N: usize>(mech: &Mechanism) -> Result<(), TestCaseError> {
    let Ok(cfg) = monitor_config::<N>(mech) else {
        return Ok(());
    };
    if Monitor::new(&cfg).is_err() {
        return Ok(());
    }
    // The monitor's model of the chain: the one `Monitor::new` built.
    let lo = cfg.chain().map_err(fail)?;
    let je = vec![Default::default(); N];
    let hi = mech
        .chain::<N>(&je, Default::default())
        .ok_or_else(|| fail("the host chain"))?;
    for s in [1.0, 0.5, 0.0] {
        let phi: [f64; N] = std::array::from_fn(|j| s * mech.joints[j].stowed_deg.to_radians());
        let m64 = hi.mass_matrix(&phi);
        let m32 = lo.mass_matrix(&phi.map(|p| p as f32));
        let scale = m64.iter().flatten().fold(0.0_f64, |a, x| a.max(x.abs()));
        for (r64, r32) in m64.iter().zip(&m32) {
            for (a, b) in r64.iter().zip(r32) {
                prop_assert!(
                    (a - f64::from(*b)).abs() <= 1e-5 * scale,
                    "mass matrix {a} vs {b} at {s}"
                );
            }
        }
        for (j, (&p, (a, b))) in phi
            .iter()
            .zip(hi.joints().iter().zip(lo.joints()))
            .enumerate()
        {
            let t64 = a.spring.torque(p, Branch::Unfold);
            let t32 = b.spring.torque(p as f32, Branch::Unfold);
            let scale = t64.abs().max(1.0);
            prop_assert!(
                (t64 - f64::from(t32)).abs() <= 1e-4 * scale + 1e-6,
                "joint {} spring torque {t64} (f64) vs {t32} (f32) at {p:.3} rad",
                j + 1
            );
        }
    }
    Ok(())
}

/// What the wings drawn were, for the record.
#[derive(Default)]
struct Tally {
    wings: usize,
    physical: usize,
    refused_rigs: usize,
    rigs: usize,
    effects: usize,
    panels: [usize; 9],
    worst_drift: f64,
    past_stowed: usize,
    worst_past_stowed_deg: f64,
}

#[test]
fn random_wings_keep_the_invariants() {
    let n = cases();
    let tally = RefCell::new(Tally::default());
    let start = Instant::now();
    let mut runner = TestRunner::new(ProptestConfig::with_cases(n));
    let result = runner.run(&any::<u64>(), |seed| {
        let w = wing_toml(seed, PHYSICAL_SHARE);
        let (drift, past) = check(&w).map_err(|e| {
            TestCaseError::fail(format!(
                "seed {seed}: {e}\neffects: {:?}\n{}",
                w.effects, w.toml
            ))
        })?;
        let mut t = tally.borrow_mut();
        t.wings += 1;
        t.physical += usize::from(!w.physical.is_empty());
        t.refused_rigs += usize::from(w.rig && !w.physical.is_empty());
        t.rigs += usize::from(w.rig && w.physical.is_empty());
        t.effects += usize::from(!w.effects.is_empty());
        t.panels[w.joints] += 1;
        t.worst_drift = t.worst_drift.max(drift);
        t.past_stowed += usize::from(past > 0.0);
        t.worst_past_stowed_deg = t.worst_past_stowed_deg.max(past);
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    let secs = start.elapsed().as_secs_f64();
    let t = tally.into_inner();
    let per_count: Vec<String> = (2..=8).map(|k| format!("{k}: {}", t.panels[k])).collect();
    let body = format!(
        "## Simulator: random wings\n\n\
         {} random valid wings of `tests/src/wing_gen.rs` (seeds drawn by proptest), each \
         simulated twice with its drawn named effects and checked against the invariants \
         of `tests/random_wings.rs` (`docs/simulator.md`, \"Random wings\").\n\n\
         | quantity | measured |\n|---|---|\n\
         | wings (panels {}) | {} |\n\
         | with a physical latch (simulated) | {} |\n\
         | with a rig and a physical latch (refused, as asked) | {} |\n\
         | with a rig (simulated) | {} |\n\
         | with a named effect | {} |\n\
         | invariant violations | 0 |\n\
         | worst ledger drift of a physical-latch run (of the stored energy) | {:.2e} |\n\
         | with a joint swung back past its stowed angle, reported by the run (no stop modelled there) | {} (farthest {:.1}°) |\n\
         | wall time (release build, this machine) | {secs:.0} s |\n",
        t.wings,
        per_count.join(", "),
        t.wings,
        t.physical - t.refused_rigs,
        t.refused_rigs,
        t.rigs,
        t.effects,
        t.worst_drift,
        t.past_stowed,
        t.worst_past_stowed_deg,
    );
    deploywatch_tests::record::record(
        "random-wings",
        "DEPLOYWATCH_WINGS=5000 DEPLOYWATCH_FULL=1 cargo test --release -p deploywatch-tests --test random_wings -- --nocapture",
        &body,
    )
    .expect("docs/measured.md written");
}

/// The wing of seed 2854563807019586449 (five panels, pawls at joints 4
/// and 5), with its drawn air drag and without: a released stop whose law
/// pushed again at a step's start was never re-engaged, so joint 5 sank
/// 3.5° into its stop with no force, its elastic energy booked as negative
/// contact damping (−52 J), and was thrown out past its stowed angle at
/// 177 rad/s (without drag: `EnergyDrift` 1.01e-6). Asserted: the contact
/// work is dissipated (≥ 0), the ledger closes, and no joint leaves the
/// range between its stowed angle and its stop's reach.
#[test]
fn a_released_stop_that_pushes_again_presses() {
    let w = wing_toml(2_854_563_807_019_586_449, PHYSICAL_SHARE);
    let mech = Mechanism::from_toml_str(&w.toml, "random.toml").expect("wing");
    let opts = SimOptions::default();
    let no_drag: Vec<_> = w
        .effects
        .iter()
        .filter(|e| !e.to_string().starts_with("air_drag"))
        .cloned()
        .collect();
    assert!(no_drag.len() < w.effects.len(), "the wing has its air drag");
    for effects in [&w.effects, &no_drag] {
        let grid = deployment::sample_grid(&mech, &opts).expect("grid");
        let lr = simulate_physical(&mech, effects, &opts, grid).expect("run");
        let e = &lr.energy;
        assert!(e.contact_j >= 0.0, "contact work {} J", e.contact_j);
        assert!(e.worst_drift_j <= LEDGER_CLOSURE * e.stored_j, "{e:?}");
        for (j, joint) in mech.joints.iter().enumerate() {
            let side = joint.stowed_deg.signum();
            for p in &lr.traj.phi_deg[j] {
                let u = side * p;
                assert!(
                    u <= joint.stowed_deg.abs() + 1e-9 && u > -1.0,
                    "joint {} at {p}°",
                    j + 1
                );
            }
        }
    }
}

/// The wing of seed 4396247749337846826 (three panels, a pawl at joint 3
/// on tape springs): joint 3 stuck by its friction band when joints 1 and
/// 2 latched (ideal) in one plastic impulse; the impulse gave it a rate
/// but it stayed held, its friction and contact work booked on a rate it
/// did not move at, until the ledger stopped the run (`EnergyDrift`
/// 1.00e-6 at 1.95 s). An impulse frees a stuck joint.
#[test]
fn an_ideal_latch_impulse_frees_a_stuck_joint() {
    let w = wing_toml(4_396_247_749_337_846_826, PHYSICAL_SHARE);
    let mech = Mechanism::from_toml_str(&w.toml, "random.toml").expect("wing");
    let opts = SimOptions::default();
    let grid = deployment::sample_grid(&mech, &opts).expect("grid");
    let lr = simulate_physical(&mech, &w.effects, &opts, grid).expect("run");
    let e = &lr.energy;
    assert!(e.sticks > 0, "{e:?}");
    assert!(e.worst_drift_j <= LEDGER_CLOSURE * e.stored_j, "{e:?}");
}
