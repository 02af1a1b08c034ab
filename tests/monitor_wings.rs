//! The on-board monitor on random wings (`tests/src/wing_gen.rs`: 2–8
//! panels, linear, tape and curve springs, ideal, plunger and pawl latches
//! mixed in one wing): a clean run (the reference sensor's noise only)
//! raises no fault flag (but `latch_disagree` at a joint whose pawl
//! breaks: a failed latch), and a spike injected into it mid-stroke is
//! flagged (`docs/monitor.md` §6.2).
//!
//! ```sh
//! cargo test --release -p deploywatch-tests --test monitor_wings -- --nocapture
//! ```
//!
//! `MONITOR_WINGS=n` sets the number of wings (24 by default); a failing
//! wing's seed is printed.

use deploywatch_core::monitor::{Monitor, Status};
use deploywatch_sim::deployment::{self, SimOptions, Trajectory};
use deploywatch_sim::fault_injection::{apply, SensorFault};
use deploywatch_sim::latch_deployment::{simulate_physical, LatchEventKind};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::monitor_config::{monitor_config, samples};
use deploywatch_sim::run::Run;
use deploywatch_sim::sensor::{measure, SensorModel};
use deploywatch_tests::wing_gen::wing_toml;
use proptest::prelude::*;
use std::path::PathBuf;

/// Samples the monitor keeps receiving after the end of the simulation \[s\].
const HOLD_S: f64 = 0.2;

/// Size of the injected spike \[deg\]: well above the noise (σ = 0.02°),
/// well below a latch impact's jump.
const SPIKE_DEG: f64 = 3.0;

/// A spike is injected only this far \[s\] from every switch change of
/// the wing (an impact excuses a rejected reading, `docs/monitor.md` §6.2).
const QUIET_S: f64 = 0.1;

/// Samples after the spike within which its flag must come (the
/// returning-spike check decides at the next reading).
const FLAG_SAMPLES: usize = 3;

fn cases() -> u32 {
    std::env::var("MONITOR_WINGS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(24)
}

/// Extends the trajectory by `HOLD_S` at its last state (a monitor keeps
/// sampling after the deployment).
fn hold(traj: &mut Trajectory, dt: f64) {
    let Some(&t_last) = traj.t_s.last() else {
        return;
    };
    let steps = (HOLD_S / dt).round() as usize;
    for k in 1..=steps {
        traj.t_s.push(t_last + k as f64 * dt);
        for j in 0..traj.joints() {
            let phi = traj.phi_deg[j].last().copied().unwrap_or(0.0);
            let latched = traj.latched[j].last().copied().unwrap_or(false);
            traj.phi_deg[j].push(phi);
            traj.latched[j].push(latched);
            traj.rate_deg_s[j].push(0.0);
        }
    }
}

/// The statuses of `run` replayed through the monitor of `mech`.
fn replay<const N: usize>(mech: &Mechanism, run: &Run) -> Result<Vec<Status<N>>, String> {
    let cfg = monitor_config::<N>(mech).map_err(|e| e.to_string())?;
    let mut m = Monitor::new(&cfg).map_err(|e| format!("{e:?}"))?;
    let s = samples::<N>(run).ok_or("joint count")?;
    Ok(s.iter().map(|s| m.update_and_predict(s).clone()).collect())
}

/// Every fault flag of a replay: (time \[s\], joint 1-based, flags).
fn flags<const N: usize>(st: &[Status<N>]) -> Vec<(f32, usize, String)> {
    let mut out = Vec::new();
    for s in st {
        for (j, js) in s.joints.iter().enumerate() {
            if !js.faults.is_empty() {
                out.push((s.t_s, j + 1, js.faults.to_string()));
            }
        }
    }
    out
}

/// The flags of `run` replayed with the monitor of its joint count.
fn replay_flags(mech: &Mechanism, run: &Run) -> Result<Vec<(f32, usize, String)>, String> {
    Ok(match mech.joint_count() {
        2 => flags(&replay::<2>(mech, run)?),
        3 => flags(&replay::<3>(mech, run)?),
        4 => flags(&replay::<4>(mech, run)?),
        5 => flags(&replay::<5>(mech, run)?),
        6 => flags(&replay::<6>(mech, run)?),
        7 => flags(&replay::<7>(mech, run)?),
        8 => flags(&replay::<8>(mech, run)?),
        n => return Err(format!("{n} joints")),
    })
}

/// A sample mid-stroke of some joint (half its stowed angle covered),
/// `QUIET_S` from every switch change of the wing: (joint 0-based, time).
fn spike_site(mech: &Mechanism, traj: &Trajectory) -> Option<(usize, f64)> {
    let mut changes = Vec::new();
    for j in 0..traj.joints() {
        for i in 1..traj.t_s.len() {
            if traj.latched[j][i] != traj.latched[j][i - 1] {
                changes.push(traj.t_s[i]);
            }
        }
    }
    (0..traj.joints()).find_map(|j| {
        let half = 0.5 * mech.joints[j].stowed_deg.abs();
        let i = traj.phi_deg[j].iter().position(|p| p.abs() <= half)?;
        let t = traj.t_s[i];
        let quiet = changes.iter().all(|c| (c - t).abs() > QUIET_S);
        (quiet && i > 10).then_some((j, t))
    })
}

/// The joints (1-based) whose pawl breaks in the simulated run.
fn broken_pawls(mech: &Mechanism, opts: &SimOptions) -> Result<Vec<usize>, TestCaseError> {
    if !mech.has_physical_latch() {
        return Ok(Vec::new());
    }
    let grid = deployment::sample_grid(mech, opts).map_err(|e| TestCaseError::fail(e.to_string()))?;
    let lr = simulate_physical(mech, &[], opts, grid).map_err(|e| TestCaseError::fail(e.to_string()))?;
    let mut joints: Vec<usize> = lr
        .events
        .iter()
        .filter(|e| e.kind == LatchEventKind::PawlBreak)
        .map(|e| e.joint)
        .collect();
    joints.dedup();
    Ok(joints)
}

/// One wing: the clean run raises no flag, a spike is flagged. Returns
/// (joints, whether a spike was injected).
fn check_wing(seed: u64) -> Result<(usize, bool), TestCaseError> {
    let w = wing_toml(seed, 0.5);
    if w.rig && !w.physical.is_empty() {
        // Refused at load (a rig with physical latches).
        return Ok((0, false));
    }
    let mech = Mechanism::from_toml_str(&w.toml, "random.toml")
        .map_err(|e| TestCaseError::fail(e.to_string()))?;
    let opts = SimOptions::default();
    let mut traj = deployment::simulate(&mech, &[], &opts)
        .map_err(|e| TestCaseError::fail(format!("run failed: {e}")))?;
    hold(&mut traj, 1.0 / mech.sample_hz);
    let run = measure(&traj, &[], &SensorModel::REFERENCE, seed);
    let broken = broken_pawls(&mech, &opts)?;
    // A broken pawl is a failed latch, flagged `latch_disagree` (the
    // drawing's lock cannot open, `docs/monitor.md` §4.1): the only flag a
    // clean run may raise, and only at that joint.
    let clean: Vec<_> = replay_flags(&mech, &run)
        .map_err(TestCaseError::fail)?
        .into_iter()
        .filter(|(_, j, f)| !(broken.contains(j) && f == "latch_disagree"))
        .collect();
    if !clean.is_empty() {
        // The wing and its run, to replay with the CLI.
        let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
        let toml = dir.join(format!("wing_{seed}.toml"));
        std::fs::write(&toml, &w.toml).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert!(
            false,
            "seed {seed}: {} joints, physical {:?}: flags on a clean run, first {:?} (wing in {})",
            w.joints,
            w.physical,
            clean.first(),
            toml.display()
        );
    }
    let Some((j, t)) = spike_site(&mech, &traj) else {
        return Ok((w.joints, false));
    };
    let spike = SensorFault::Spike {
        joint: j + 1,
        t_s: t,
        magnitude_deg: SPIKE_DEG,
        samples: 1,
    };
    let mut faulted = run.clone();
    apply(&mut faulted, &[spike], seed).map_err(|e| TestCaseError::fail(e.to_string()))?;
    let found = replay_flags(&mech, &faulted).map_err(TestCaseError::fail)?;
    let within = FLAG_SAMPLES as f64 / mech.sample_hz + 1e-6;
    let caught = found.iter().any(|&(ts, jj, _)| {
        jj == j + 1 && f64::from(ts) >= t - 1e-6 && f64::from(ts) <= t + within
    });
    prop_assert!(
        caught,
        "seed {seed}: a {SPIKE_DEG}° spike at joint {} at {t:.3} s not flagged (flags {:?})",
        j + 1,
        found
    );
    Ok((w.joints, true))
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: cases(),
        max_shrink_iters: 0,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// Clean runs of random wings raise no fault flag; a spike injected
    /// mid-stroke is flagged within three samples.
    #[test]
    fn random_wings_clean_runs_raise_no_flag_and_a_spike_is_flagged(seed in any::<u64>()) {
        let (joints, spiked) = check_wing(seed)?;
        println!("seed {seed}: {joints} joints, clean: no flag, spike: {}",
            if spiked { "flagged" } else { "no quiet site" });
    }
}
