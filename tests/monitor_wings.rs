//! The on-board monitor on random wings (`tests/src/wing_gen.rs`: 2–8
//! panels, linear, tape and curve springs, ideal, plunger and pawl latches
//! mixed in one wing): a spike injected mid-stroke into a clean run (the
//! reference sensor's noise only) is flagged. That the clean run itself
//! raises no fault flag (but `latch_disagree` at a joint whose pawl
//! breaks: a failed latch) is not yet true on every wing: that test is
//! ignored in the default run (`docs/monitor.md` §6.2, "Known false flags
//! on random wings").
//!
//! ```sh
//! cargo test --release -p deploywatch-tests --test monitor_wings -- --nocapture
//! ```
//!
//! `MONITOR_WINGS=n` sets the number of wings (24 by default),
//! `MONITOR_WINGS_SEED` the first seed; a failing wing's seed is printed.

use deploywatch_core::monitor::{Monitor, Status};
use deploywatch_sim::deployment::{self, SimOptions, Trajectory};
use deploywatch_sim::fault_injection::{apply, SensorFault};
use deploywatch_sim::latch_deployment::{simulate_physical, LatchEventKind};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::monitor_config::{monitor_config, samples};
use deploywatch_sim::run::Run;
use deploywatch_sim::sensor::{measure, SensorModel};
use deploywatch_tests::wing_gen::wing_toml;
use deploywatch_tests::SplitMix;
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

fn cases() -> usize {
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
    Ok(s.iter().map(|s| m.update_and_predict(s)).collect())
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
fn broken_pawls(mech: &Mechanism, opts: &SimOptions) -> Result<Vec<usize>, String> {
    if !mech.has_physical_latch() {
        return Ok(Vec::new());
    }
    let grid = deployment::sample_grid(mech, opts).map_err(|e| e.to_string())?;
    let lr = simulate_physical(mech, &[], opts, grid).map_err(|e| e.to_string())?;
    let mut joints: Vec<usize> = lr
        .events
        .iter()
        .filter(|e| e.kind == LatchEventKind::PawlBreak)
        .map(|e| e.joint)
        .collect();
    joints.dedup();
    Ok(joints)
}

/// What one wing did: its joints (0: a rig with physical latches, refused
/// at load), the clean run's flags (empty: none) and whether the injected
/// spike was flagged (`None`: no quiet site to put it).
struct WingResult {
    joints: usize,
    clean: Option<String>,
    spike: Option<Result<(), String>>,
}

/// One wing: its clean run's flags, and a spike injected into it.
fn check_wing(seed: u64, physical_share: f64) -> Result<WingResult, String> {
    let w = wing_toml(seed, physical_share);
    if w.rig && !w.physical.is_empty() {
        return Ok(WingResult {
            joints: 0,
            clean: None,
            spike: None,
        });
    }
    let mech = Mechanism::from_toml_str(&w.toml, "random.toml").map_err(|e| e.to_string())?;
    let opts = SimOptions::default();
    let mut traj =
        deployment::simulate(&mech, &[], &opts).map_err(|e| format!("run failed: {e}"))?;
    // Held at rest only once every joint has latched (the simulation then
    // stops at the last latch); a run that went to its end is not at rest.
    if (0..traj.joints()).all(|j| traj.latched[j].last().copied().unwrap_or(false)) {
        hold(&mut traj, 1.0 / mech.sample_hz);
    }
    let run = measure(&traj, &[], &SensorModel::REFERENCE, seed);
    let broken = broken_pawls(&mech, &opts)?;
    // A broken pawl is a failed latch, flagged `latch_disagree` (the
    // drawing's lock cannot open, `docs/monitor.md` §4.1): the only flag a
    // clean run may raise, and only at that joint.
    let flagged: Vec<_> = replay_flags(&mech, &run)?
        .into_iter()
        .filter(|(_, j, f)| !(broken.contains(j) && f == "latch_disagree"))
        .collect();
    let clean = match flagged.first() {
        None => None,
        Some(first) => {
            // The wing, to simulate and replay with the CLI.
            let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
            let toml = dir.join(format!("wing_{seed}.toml"));
            std::fs::write(&toml, &w.toml).map_err(|e| e.to_string())?;
            Some(format!(
                "seed {seed}: {} joints, physical {:?}: {} flagged statuses on a clean run, first {first:?} (wing in {})",
                w.joints,
                w.physical,
                flagged.len(),
                toml.display()
            ))
        }
    };
    let spike = spike_site(&mech, &traj)
        .map(|(j, t)| spike_flagged(&mech, &run, seed, j, t))
        .transpose()?;
    Ok(WingResult {
        joints: w.joints,
        clean,
        spike,
    })
}

/// Injects a [`SPIKE_DEG`] spike into `run` at joint `j` (0-based) at `t`
/// \[s\]: `Err` naming it unless that joint is flagged within
/// [`FLAG_SAMPLES`].
fn spike_flagged(
    mech: &Mechanism,
    run: &Run,
    seed: u64,
    j: usize,
    t: f64,
) -> Result<Result<(), String>, String> {
    let spike = SensorFault::Spike {
        joint: j + 1,
        t_s: t,
        magnitude_deg: SPIKE_DEG,
        samples: 1,
    };
    let mut faulted = run.clone();
    apply(&mut faulted, &[spike], seed).map_err(|e| e.to_string())?;
    let found = replay_flags(mech, &faulted)?;
    let within = FLAG_SAMPLES as f64 / mech.sample_hz + 1e-6;
    let caught = found.iter().any(|&(ts, jj, _)| {
        jj == j + 1 && f64::from(ts) >= t - 1e-6 && f64::from(ts) <= t + within
    });
    Ok(if caught {
        Ok(())
    } else {
        Err(format!(
            "seed {seed}: a {SPIKE_DEG}° spike at joint {} at {t:.3} s not flagged",
            j + 1
        ))
    })
}

/// Replays `cases()` random wings whose joints get a physical latch with
/// probability `physical_share`: (clean runs with flags, spikes not
/// flagged), each naming its wing.
fn random_wings(physical_share: f64) -> (Vec<String>, Vec<String>) {
    let first: u64 = std::env::var("MONITOR_WINGS_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(38);
    let mut rng = SplitMix(first);
    let (mut wings, mut spiked) = (0, 0);
    let (mut noisy, mut missed) = (Vec::new(), Vec::new());
    for _ in 0..cases() {
        let seed = (rng.next_f64() * (1u64 << 53) as f64) as u64;
        let r = match check_wing(seed, physical_share) {
            Ok(r) => r,
            Err(e) => panic!("seed {seed}: {e}"),
        };
        if r.joints == 0 {
            println!("seed {seed}: a rig with physical latches, refused at load");
            continue;
        }
        wings += 1;
        if let Some(c) = r.clean {
            println!("FLAGS {c}");
            noisy.push(c);
        }
        match r.spike {
            Some(Ok(())) => spiked += 1,
            Some(Err(e)) => {
                println!("MISSED {e}");
                missed.push(e);
            }
            None => {}
        }
    }
    println!(
        "physical share {physical_share}: {wings} wings, {} clean runs with flags, {spiked} spikes flagged, {} missed",
        noisy.len(),
        missed.len()
    );
    (noisy, missed)
}

/// A spike injected mid-stroke into a clean run of a random wing, ideal or
/// mixed latches, is flagged within three samples. The wings' seeds are
/// drawn from `SplitMix(MONITOR_WINGS_SEED)` (38 by default).
#[test]
fn random_wings_a_spike_is_flagged() {
    for share in [0.0, 0.5] {
        let (_, missed) = random_wings(share);
        assert!(missed.is_empty(), "{missed:#?}");
    }
}

/// Clean runs of random wings raise no fault flag. Not yet true
/// (`docs/monitor.md` §6.2 gives the causes: wings deploying
/// in a tenth of a second outrun the rate filter's start and motion model,
/// pawls rattling in their notches shake the chain near the sampling's
/// Nyquist frequency); run with `--ignored`, every flagged wing is listed
/// with its seed and TOML file.
#[test]
#[ignore = "known: flags on some random wings (docs/monitor.md §6.2)"]
fn random_wings_clean_runs_raise_no_flag() {
    for share in [0.0, 0.5] {
        let (noisy, _) = random_wings(share);
        assert!(noisy.is_empty(), "{noisy:#?}");
    }
}
