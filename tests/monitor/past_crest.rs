//! A physical latch's joint past its crest is predicted to latch: the hold
//! ramp and the magnet pull it onto the stop (`docs/monitor.md` §6).
//!
//! `tests/wings/plunger_magnet_bounces.toml`: joint 2 rebounds out over its
//! plunger's crest several times and latches after a last, slow approach,
//! whose energy balance (its margin frozen on the entry ramp) calls a stop on
//! the ramp. From the true crossing, on that last approach, of the depth the
//! tracker takes for past the crest (the crest less four readings' σ,
//! `StopLimits::inside_deg`), and two readings for the tracker to see it, to
//! the latch's declaration, the prediction must be `latch`, at 100 Hz and
//! 1 kHz, three sensor seeds each.

use super::*;

/// Readings the latch tracker needs to see the joint within the crest.
const SEE_READINGS: f64 = 2.0;
/// Readings' σ within the crest that the tracker takes for past it
/// (`bounce::STOP_SIGMAS`).
const STOP_SIGMAS: f64 = 4.0;

/// The true time joint `j` last came within `crest_deg` \[deg\] of its stop
/// before its latch \[s\].
fn last_crossing(traj: &Trajectory, j: usize, crest_deg: f64) -> Option<f64> {
    let latch = traj.latch_s[j]?;
    let phi = &traj.phi_deg[j];
    (1..traj.t_s.len())
        .filter(|&i| traj.t_s[i] <= latch)
        .filter(|&i| phi[i - 1].abs() > crest_deg && phi[i].abs() <= crest_deg)
        .map(|i| traj.t_s[i])
        .next_back()
}

#[test]
fn a_joint_past_its_crest_is_predicted_to_latch() {
    let path = deploywatch_tests::repo_root().join("tests/wings/plunger_magnet_bounces.toml");
    let mut mech = Mechanism::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let crest_deg = mech.latch(1).expect("joint 2's plunger").plunger.crest_deg
        - STOP_SIGMAS * SensorModel::REFERENCE.noise_sigma_deg;
    for rate in [100.0, 1000.0] {
        mech.sample_hz = rate;
        let cfg = monitor_config::<2>(&mech).unwrap();
        for seed in 1..=3 {
            let (traj, run) = simulate_run(&mech, &[], seed);
            let crossed = last_crossing(&traj, 1, crest_deg).expect("joint 2 latches");
            let st = replay(&cfg, &run);
            let declared = st
                .iter()
                .find(|s| f64::from(s.t_s) > crossed && s.joints[1].latch == LatchState::Latched)
                .map(|s| f64::from(s.t_s))
                .expect("declared");
            let seen = crossed + SEE_READINGS / rate;
            let wrong: Vec<(f32, Prediction)> = st
                .iter()
                .filter(|s| (seen..declared).contains(&f64::from(s.t_s)))
                .map(|s| (s.t_s, s.joints[1].prediction))
                .filter(|&(_, p)| p != Prediction::Latch)
                .collect();
            println!(
                "{rate} Hz seed {seed}: crest crossed {crossed:.3} s, declared {declared:.3} s, {} statuses not `latch`",
                wrong.len()
            );
            assert!(
                wrong.is_empty(),
                "{rate} Hz seed {seed}: crossed {crossed:.3}, declared {declared:.3}: {:?}",
                &wrong[..wrong.len().min(5)]
            );
        }
    }
}
