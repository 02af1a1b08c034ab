//! The on-board monitor on random wings (`tests/src/wing_gen.rs`: 2–8
//! panels, linear, tape and curve springs, ideal, plunger and pawl latches
//! mixed in one wing, simulated with the named effects drawn for the wing,
//! read by the reference sensor with its noise): a clean run raises no
//! fault flag (but `latch_disagree` at a joint whose pawl breaks: a failed
//! latch), not even at a joint the monitor reports `unresolved` (shaken
//! faster than 100 Hz resolves: the monitor says so instead of raising a
//! fault; those statuses are counted), and a spike injected mid-stroke
//! into it is flagged (`docs/monitor.md` §6.2, "Random wings").
//!
//! ```sh
//! cargo test --release -p deploywatch-tests --test monitor_wings -- --nocapture
//! ```
//!
//! `MONITOR_WINGS=n` sets the number of wings per latch mix (ideal latches
//! only; half the joints physical), 32 by default; `MONITOR_WINGS_SEED`
//! the first seed (38 by default). A failing wing's seed is printed, with
//! the truth at its first flag, and its TOML written;
//! `MONITOR_WINGS_TRACE=1` prints the samples around each flag. The whole
//! experiment, recorded in `docs/measured.md`:
//!
//! ```sh
//! MONITOR_WINGS=300 DEPLOYWATCH_FULL=1 cargo test -p deploywatch-tests --test monitor_wings -- --nocapture
//! ```

use deploywatch_core::monitor::{Monitor, Resolution, Status};
use deploywatch_sim::deployment::{self, SimOptions, Trajectory};
use deploywatch_sim::effect::Effect;
use deploywatch_sim::fault_injection::{apply, SensorFault};
use deploywatch_sim::latch_deployment::{simulate_physical, LatchEventKind};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::monitor_config::{monitor_config, samples};
use deploywatch_sim::run::Run;
use deploywatch_sim::sensor::{measure, SensorModel};
use deploywatch_tests::wing_gen::wing_toml;
use deploywatch_tests::SplitMix;
use std::path::PathBuf;
use std::sync::OnceLock;
use std::time::Instant;

/// Samples the monitor keeps receiving after the end of the simulation \[s\].
const HOLD_S: f64 = 0.2;

/// Size of the injected spike \[deg\]: well above the noise (σ = 0.02°),
/// well below a latch impact's jump.
const SPIKE_DEG: f64 = 3.0;

/// A spike is injected only this far \[s\] from every switch change of
/// the wing (an impact excuses a rejected reading, `docs/monitor.md` §6.2).
const QUIET_S: f64 = 0.1;

/// A physical latch's joint this close to its stop \[deg\] may hit it (the
/// crest of the generator's plunger, 0.6°, and the encoder's noise).
const IMPACT_REACH_DEG: f64 = 1.0;

/// Samples after the spike within which its flag must come (the
/// returning-spike check decides at the next reading).
const FLAG_SAMPLES: usize = 3;

/// The latch mixes: the share of joints drawn with a physical latch.
const SHARES: [f64; 2] = [0.0, 0.5];

/// Wings per latch mix (`MONITOR_WINGS`, 32 by default).
fn cases() -> usize {
    std::env::var("MONITOR_WINGS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(32)
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

/// What the monitor said of one joint at one sample: estimated angle
/// \[deg\], rate [deg/s], latch state, fault flags (empty: none) and
/// whether its readings resolve its motion.
#[derive(Clone, Debug)]
struct View {
    phi_deg: f32,
    rate_deg_s: f32,
    latch: String,
    faults: String,
    resolution: Resolution,
}

/// The statuses of `run` replayed through the monitor of `mech`, per
/// sample, per joint.
fn replay<const N: usize>(mech: &Mechanism, run: &Run) -> Result<Vec<Vec<View>>, String> {
    let cfg = monitor_config::<N>(mech).map_err(|e| e.to_string())?;
    let mut m = Monitor::new(&cfg).map_err(|e| format!("{e:?}"))?;
    let s = samples::<N>(run).ok_or("joint count")?;
    let view = |st: &Status<N>| -> Vec<View> {
        st.joints
            .iter()
            .map(|js| View {
                phi_deg: js.phi_deg,
                rate_deg_s: js.rate_deg_s,
                latch: js.latch.to_string(),
                faults: js.faults.to_string(),
                resolution: js.resolution,
            })
            .collect()
    };
    Ok(s.iter().map(|s| view(&m.replay_step(s))).collect())
}

/// `run` replayed with the monitor of its joint count.
fn replay_views(mech: &Mechanism, run: &Run) -> Result<Vec<Vec<View>>, String> {
    match mech.joint_count() {
        2 => replay::<2>(mech, run),
        3 => replay::<3>(mech, run),
        4 => replay::<4>(mech, run),
        5 => replay::<5>(mech, run),
        6 => replay::<6>(mech, run),
        7 => replay::<7>(mech, run),
        8 => replay::<8>(mech, run),
        n => Err(format!("{n} joints")),
    }
}

/// Every fault flag of a replay: (sample, joint 1-based, flags).
fn flags(views: &[Vec<View>]) -> Vec<(usize, usize, String)> {
    let mut out = Vec::new();
    for (i, s) in views.iter().enumerate() {
        for (j, v) in s.iter().enumerate() {
            if !v.faults.is_empty() {
                out.push((i, j + 1, v.faults.clone()));
            }
        }
    }
    out
}

/// One sample of joint `j` (0-based) as a line: the truth, the reading and
/// switch, and what the monitor said.
fn sample_line(traj: &Trajectory, run: &Run, views: &[Vec<View>], i: usize, j: usize) -> String {
    let truth = if i < traj.t_s.len() {
        format!(
            "truth {:.3}° {:.1}°/s{}",
            traj.phi_deg[j][i],
            traj.rate_deg_s[j][i],
            if traj.latched[j][i] { " latched" } else { "" }
        )
    } else {
        "truth (held)".to_string()
    };
    let v = &views[i][j];
    format!(
        "t {:.3} s: {truth}; read {:.3}° switch {}; monitor {:.3}° {:.1}°/s {} {} [{}]",
        run.t_s[i],
        run.phi_deg[j][i],
        u8::from(run.latch[j][i]),
        v.phi_deg,
        v.rate_deg_s,
        v.latch,
        v.resolution.as_str(),
        v.faults
    )
}

/// With `MONITOR_WINGS_TRACE` set: the samples around each flag.
fn trace(traj: &Trajectory, run: &Run, views: &[Vec<View>], flagged: &[(usize, usize, String)]) {
    if std::env::var_os("MONITOR_WINGS_TRACE").is_none() {
        return;
    }
    for &(i, j, ref f) in flagged.iter().take(20) {
        println!("  {f} at joint {j}:");
        for k in i.saturating_sub(6)..(i + 3).min(run.t_s.len()) {
            println!("    {}", sample_line(traj, run, views, k, j - 1));
        }
    }
}

/// A sample mid-stroke of some joint (half its stowed angle covered),
/// `QUIET_S` from every switch change of the wing and from every sample at
/// which a joint of `physical` (1-based) is within [`IMPACT_REACH_DEG`] of
/// its stop, or gets there by the next sample at its speed (a plunger's joint may hit its stop and bounce out without its
/// switch closing): (joint 0-based, time).
fn spike_site(mech: &Mechanism, traj: &Trajectory, physical: &[usize]) -> Option<(usize, f64)> {
    let mut changes = Vec::new();
    for j in 0..traj.joints() {
        let near_stop = physical.contains(&(j + 1));
        for i in 1..traj.t_s.len() {
            // Within reach, or heading there by the next sample at its
            // speed (as the monitor announces an impact, `docs/monitor.md`
            // §6.2).
            let (d, d_prev) = (traj.phi_deg[j][i].abs(), traj.phi_deg[j][i - 1].abs());
            let reach = d.min(2.0 * d - d_prev) <= IMPACT_REACH_DEG;
            if traj.latched[j][i] != traj.latched[j][i - 1] || (near_stop && reach) {
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
fn broken_pawls(
    mech: &Mechanism,
    effects: &[Effect],
    opts: &SimOptions,
) -> Result<Vec<usize>, String> {
    if !mech.has_physical_latch() {
        return Ok(Vec::new());
    }
    let grid = deployment::sample_grid(mech, opts).map_err(|e| e.to_string())?;
    let lr = simulate_physical(mech, effects, opts, grid).map_err(|e| e.to_string())?;
    let mut joints: Vec<usize> = lr
        .events
        .iter()
        .filter(|e| e.kind == LatchEventKind::PawlBreak)
        .map(|e| e.joint)
        .collect();
    joints.dedup();
    Ok(joints)
}

/// Statuses of a replay in which a joint is unresolved, and the joints
/// (1-based) that ever are.
fn unresolved(views: &[Vec<View>]) -> (usize, Vec<usize>) {
    let mut joints = Vec::new();
    let mut n = 0;
    for s in views {
        for (j, v) in s.iter().enumerate() {
            if v.resolution == Resolution::Unresolved {
                n += 1;
                if !joints.contains(&(j + 1)) {
                    joints.push(j + 1);
                }
            }
        }
    }
    joints.sort_unstable();
    (n, joints)
}

/// What one wing did: its joints (0: a rig with physical latches, refused
/// at load), whether it has a physical latch, the clean run's flags (`None`: none) and whether the injected
/// spike was flagged (`None`: no quiet site to put it).
struct WingResult {
    joints: usize,
    physical: bool,
    /// Statuses of the clean run with a joint unresolved (joint-samples).
    unresolved: usize,
    clean: Option<String>,
    spike: Option<Result<(), String>>,
}

/// One wing: its clean run's flags, and a spike injected into it.
fn check_wing(seed: u64, physical_share: f64) -> Result<WingResult, String> {
    let w = wing_toml(seed, physical_share);
    if w.rig && !w.physical.is_empty() {
        return Ok(WingResult {
            joints: 0,
            physical: true,
            unresolved: 0,
            clean: None,
            spike: None,
        });
    }
    let mech = Mechanism::from_toml_str(&w.toml, "random.toml").map_err(|e| e.to_string())?;
    let opts = SimOptions::default();
    let mut traj =
        deployment::simulate(&mech, &w.effects, &opts).map_err(|e| format!("run failed: {e}"))?;
    // Held at rest only once every joint has latched (the simulation then
    // stops at the last latch); a run that went to its end is not at rest.
    if (0..traj.joints()).all(|j| traj.latched[j].last().copied().unwrap_or(false)) {
        hold(&mut traj, 1.0 / mech.sample_hz);
    }
    let run = measure(&traj, &[], &SensorModel::REFERENCE, seed);
    let broken = broken_pawls(&mech, &w.effects, &opts)?;
    let views = replay_views(&mech, &run)?;
    // A broken pawl is a failed latch, flagged `latch_disagree` (the
    // drawing's lock cannot open, `docs/monitor.md` §4.1): the only flag a
    // clean run may raise, and only at that joint. A joint the monitor
    // reports unresolved is no excuse: it says so instead of a fault.
    let flagged: Vec<_> = flags(&views)
        .into_iter()
        .filter(|(_, j, f)| !(broken.contains(j) && f == "latch_disagree"))
        .collect();
    let (unresolved, unresolved_joints) = unresolved(&views);
    if unresolved > 0 {
        println!(
            "seed {seed}: unresolved at joints {unresolved_joints:?} in {unresolved} statuses (physical {:?})",
            w.physical
        );
    }
    trace(&traj, &run, &views, &flagged);
    let clean = match flagged.first() {
        None => None,
        Some(&(i, j, _)) => {
            // The wing, to simulate and replay with the CLI.
            let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
            let toml = dir.join(format!("wing_{seed}.toml"));
            std::fs::write(&toml, &w.toml).map_err(|e| e.to_string())?;
            Some(format!(
                "seed {seed}: {} joints, physical {:?}, effects {:?}: {} flagged statuses on a clean run, first at joint {j}, {} (wing in {})",
                w.joints,
                w.physical,
                w.effects.iter().map(ToString::to_string).collect::<Vec<_>>(),
                flagged.len(),
                sample_line(&traj, &run, &views, i, j - 1),
                toml.display()
            ))
        }
    };
    let spike = spike_site(&mech, &traj, &w.physical)
        .map(|(j, t)| spike_flagged(&mech, &run, seed, j, t))
        .transpose()?;
    Ok(WingResult {
        joints: w.joints,
        physical: !w.physical.is_empty(),
        unresolved,
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
    let views = replay_views(mech, &faulted)?;
    let found = flags(&views);
    let within = FLAG_SAMPLES as f64 / mech.sample_hz + 1e-6;
    let caught = found.iter().any(|&(i, jj, _)| {
        let ts = faulted.t_s[i];
        jj == j + 1 && ts >= t - 1e-6 && ts <= t + within
    });
    Ok(if caught {
        Ok(())
    } else {
        if std::env::var_os("MONITOR_WINGS_TRACE").is_some() {
            let i = faulted.t_s.iter().position(|&x| x >= t - 1e-6).unwrap_or(0);
            let clean = Trajectory::default();
            for jj in 0..faulted.phi_deg.len() {
                println!("  joint {}:", jj + 1);
                for k in i.saturating_sub(3)..(i + 3).min(faulted.t_s.len()) {
                    println!("    {}", sample_line(&clean, &faulted, &views, k, jj));
                }
            }
        }
        Err(format!(
            "seed {seed}: a {SPIKE_DEG}° spike at joint {} at {t:.3} s not flagged",
            j + 1
        ))
    })
}

/// What the wings of one latch mix did.
#[derive(Debug, Default)]
struct Mix {
    /// Wings replayed (a rig with physical latches is refused at load and
    /// not counted).
    wings: usize,
    /// Of them, with a physical latch.
    physical: usize,
    /// Refused at load.
    refused: usize,
    /// Clean runs with a flag, each naming its wing.
    noisy: Vec<String>,
    /// Wings with a joint unresolved in their clean run, and those
    /// statuses (joint-samples).
    unresolved_wings: usize,
    unresolved: usize,
    /// Spikes injected, and those not flagged, each naming its wing.
    spiked: usize,
    missed: Vec<String>,
}

/// Replays `cases()` random wings whose joints get a physical latch with
/// probability `physical_share`.
fn random_wings(physical_share: f64) -> Mix {
    let first: u64 = std::env::var("MONITOR_WINGS_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(38);
    let mut rng = SplitMix(first);
    let mut mix = Mix::default();
    // `MONITOR_WING=seed`: that wing alone (a failing seed reproduces it).
    let only: Option<u64> = std::env::var("MONITOR_WING")
        .ok()
        .and_then(|s| s.parse().ok());
    let seeds: Vec<u64> = match only {
        Some(seed) => vec![seed],
        None => (0..cases())
            .map(|_| (rng.next_f64() * (1u64 << 53) as f64) as u64)
            .collect(),
    };
    for seed in seeds {
        let r = match check_wing(seed, physical_share) {
            Ok(r) => r,
            Err(e) => panic!("seed {seed}: {e}"),
        };
        if r.joints == 0 {
            mix.refused += 1;
            continue;
        }
        mix.wings += 1;
        mix.physical += usize::from(r.physical);
        mix.unresolved_wings += usize::from(r.unresolved > 0);
        mix.unresolved += r.unresolved;
        if let Some(c) = r.clean {
            println!("FLAGS {c}");
            mix.noisy.push(c);
        }
        match r.spike {
            Some(Ok(())) => mix.spiked += 1,
            Some(Err(e)) => {
                println!("MISSED {e}");
                mix.spiked += 1;
                mix.missed.push(e);
            }
            None => {}
        }
    }
    println!(
        "physical share {physical_share}: {} wings, {} clean runs with flags, {} with a joint unresolved ({} statuses), {} spikes, {} missed",
        mix.wings,
        mix.noisy.len(),
        mix.unresolved_wings,
        mix.unresolved,
        mix.spiked,
        mix.missed.len()
    );
    mix
}

/// Both latch mixes, replayed once for the tests of this file, and the
/// wall time they took \[s\].
fn mixes() -> &'static (Vec<Mix>, f64) {
    static MIXES: OnceLock<(Vec<Mix>, f64)> = OnceLock::new();
    MIXES.get_or_init(|| {
        let start = Instant::now();
        let mixes: Vec<Mix> = SHARES.iter().map(|&s| random_wings(s)).collect();
        let secs = start.elapsed().as_secs_f64();
        record(&mixes, secs);
        (mixes, secs)
    })
}

/// Writes the figures into `docs/measured.md` (only a whole run from the
/// default first seed, with `DEPLOYWATCH_FULL=1`: `tests/src/record.rs`).
fn record(mixes: &[Mix], secs: f64) {
    if std::env::var_os("MONITOR_WINGS_SEED").is_some()
        || std::env::var_os("MONITOR_WING").is_some()
    {
        return;
    }
    let rows: Vec<String> = SHARES
        .iter()
        .zip(mixes)
        .map(|(share, m)| {
            format!(
                "| {share} | {} ({} refused at load: a rig with physical latches) | {} | {} | {} ({} statuses) | {} of {} |",
                m.wings,
                m.refused,
                m.physical,
                m.noisy.len(),
                m.unresolved_wings,
                m.unresolved,
                m.spiked - m.missed.len(),
                m.spiked
            )
        })
        .collect();
    let body = format!(
        "## Monitor: random wings, clean runs and spikes\n\n\
         Random wings of `tests/src/wing_gen.rs` (seeds from `SplitMix(38)`), each simulated \
         with its drawn named effects, read by the reference sensor (σ = 0.02°, 14 bits) and \
         replayed through the monitor of its joint count; then a {SPIKE_DEG}° spike injected \
         mid-stroke (`docs/monitor.md` §6.2, \"Random wings\").\n\n\
         | physical share | wings | with a physical latch | clean runs with a flag | clean runs with a joint `unresolved` (joint-statuses) | spikes flagged within {FLAG_SAMPLES} samples |\n\
         |---|---|---|---|---|---|\n{}\n\n\
         Wall time (test profile, this machine, shared with other builds): {secs:.0} s.\n",
        rows.join("\n")
    );
    deploywatch_tests::record::record(
        "monitor-wings",
        "MONITOR_WINGS=300 DEPLOYWATCH_FULL=1 cargo test -p deploywatch-tests --test monitor_wings -- --nocapture",
        &body,
    )
    .expect("docs/measured.md written");
}

/// A spike injected mid-stroke into a clean run of a random wing, ideal or
/// mixed latches, is flagged within three samples. The wings' seeds are
/// drawn from `SplitMix(MONITOR_WINGS_SEED)` (38 by default).
#[test]
fn random_wings_a_spike_is_flagged() {
    let missed: Vec<&String> = mixes().0.iter().flat_map(|m| &m.missed).collect();
    assert!(missed.is_empty(), "{missed:#?}");
}

/// Clean runs of random wings, ideal or mixed latches, raise no fault
/// flag (but `latch_disagree` where a pawl breaks), at a joint reported
/// `unresolved` or not; the unresolved statuses are counted and
/// recorded. Every flagged wing is listed with its seed, the truth at its
/// first flag and its TOML file.
#[test]
fn random_wings_clean_runs_raise_no_flag() {
    let noisy: Vec<&String> = mixes().0.iter().flat_map(|m| &m.noisy).collect();
    assert!(noisy.is_empty(), "{} flagged:\n{noisy:#?}", noisy.len());
}
