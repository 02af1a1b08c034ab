//! Invariants of the simulator on random valid wings
//! (`deploywatch_tests::wing_gen`), checked by proptest. Each case is one
//! wing drawn from a seed (printed by proptest on failure with the wing's
//! TOML); the wing is loaded from its TOML text as a user's file:
//!
//! - an enabled `[rig]` on a wing with a physical latch is refused naming
//!   the rig, never dropped silently;
//! - a run ends normally;
//! - an ideal joint never passes its latch angle (it latches there), and a
//!   joint latched at the end is at its latch angle;
//! - the latch instants (the summary) and the per-sample switch (the CSV)
//!   agree: a joint with a latch instant is latched at every later sample,
//!   one without is latched at none (ideal joints);
//! - a physical joint never passes its stop by more than 1°;
//! - the run is deterministic (two runs are identical).
//!
//! Ignored in the default run: a whole run finds faults of the simulator
//! not fixed on main. Run it with `cargo test --release -p deploywatch-tests --test random_wings -- --ignored`.
//! Cases: `DEPLOYWATCH_WINGS` (default 500). The larger run of
//! `docs/simulator.md`:
//! `DEPLOYWATCH_WINGS=5000 cargo test --release -p deploywatch-tests --test random_wings`.

use deploywatch_sim::deployment::{self, SimOptions};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_tests::wing_gen::{wing_toml, Wing};
use proptest::prelude::*;

fn cases() -> u32 {
    std::env::var("DEPLOYWATCH_WINGS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(500)
}

/// Share of physical latches among the drawn joints.
const PHYSICAL_SHARE: f64 = 0.25;

fn check(w: &Wing) -> Result<(), TestCaseError> {
    let mech = Mechanism::from_toml_str(&w.toml, "random.toml");
    if w.rig && !w.physical.is_empty() {
        let e = mech.err().map(|e| e.to_string()).unwrap_or_default();
        prop_assert!(e.contains("rig") && e.contains("physical latch"), "{e}");
        return Ok(());
    }
    let mech = mech.map_err(|e| TestCaseError::fail(e.to_string()))?;
    let opts = SimOptions::default();
    let run = deployment::simulate(&mech, &[], &opts);
    let again = deployment::simulate(&mech, &[], &opts);
    prop_assert_eq!(&run, &again, "not deterministic");
    let traj = match run {
        Ok(t) => t,
        Err(e) => return Err(TestCaseError::fail(format!("run failed: {e}"))),
    };
    for j in 0..w.joints {
        let side = mech.joints[j].stowed_deg.signum();
        let phi = &traj.phi_deg[j];
        let ideal = !w.physical.contains(&(j + 1));
        let pass = if ideal { 1e-6 } else { 1.0 };
        let worst = phi.iter().map(|p| -side * p).fold(f64::MIN, f64::max);
        prop_assert!(
            worst <= pass,
            "joint {} passes its latch by {worst} deg",
            j + 1
        );
        if !ideal {
            continue;
        }
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
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases()))]
    #[test]
    #[ignore = "a whole run finds simulator faults not fixed yet: run it by hand (this file's header)"]
    fn random_wings_keep_the_invariants(seed in any::<u64>()) {
        let w = wing_toml(seed, PHYSICAL_SHARE);
        check(&w).map_err(|e| TestCaseError::fail(format!("seed {seed}: {e}\n{}", w.toml)))?;
    }
}
