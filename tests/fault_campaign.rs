//! Fault-injection campaign of the on-board monitor:
//! every sensor fault of `deploywatch_sim::fault_injection` × the four reference
//! mechanisms (nominal and with the papers' friction) × 3 sensor seeds.
//!
//! Each run is simulated, measured with the reference sensor, faulted, and
//! replayed through the monitor. Per fault the campaign counts the runs, the
//! joints whose final latch state is right, the false latch declarations
//! (latched before the true latch instant, or for a joint that never
//! latches), the lost latches (latched, then not), the missed stalls (a
//! joint that never latches and is neither predicted to stall nor reported
//! stalled at the end) and the largest error of the Coulomb estimate at half
//! stroke for the joints with friction of 0.3 N·m or more.
//!
//! Rerun: `cargo test -p deploywatch-tests --test fault_campaign -- --nocapture`
//! (the table is printed as Markdown; `docs/robustness.md` has a copy).

use deploywatch_core::monitor::LatchState;
use deploywatch_core::monitor::{Monitor, MonitorConfig, Prediction, Status};
use deploywatch_sim::deployment::{simulate, SimOptions, Trajectory};
use deploywatch_sim::fault_injection::{apply, DropoutMode, SensorFault};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::monitor_config::{monitor_config, samples};
use deploywatch_sim::run::Run;
use deploywatch_sim::sensor::{measure, SensorModel};
use deploywatch_tests::{coulomb, hold_at_rest, mechanism};

/// The papers' identified friction, seed 001 (N·m at joints 1–3).
const SEED001_FRICTION: [f64; 3] = [2.63, 1.7, 0.001];
/// The papers' identified friction, seed 000 (N·m at joints 1–2).
const SEED000_FRICTION: [f64; 2] = [0.54, 0.472];
/// Sensor seeds per scenario.
const SEEDS: [u64; 3] = [1, 2, 3];
/// Samples the monitor keeps receiving after the end of the simulation \[s\]
/// (a monitor keeps sampling; the encoder-only latch confirmation of a
/// switch stuck open needs a few tenths of a second).
const HOLD_S: f64 = 0.6;
/// Friction at or above which a joint's estimate is scored [N·m].
const SCORED_FRICTION_NM: f64 = 0.3;

/// The fault variants of the campaign: a name and a builder from the target
/// joint (1-based), a reference time (the joint's latch instant, or the
/// instant of its fastest motion if it never latches), the true angle there and the
/// seed.
type Builder = fn(usize, f64, f64, u64) -> SensorFault;

fn variants() -> Vec<(&'static str, Builder)> {
    vec![
        ("dropout (stale, 0.1 s over the latch)", |j, t, _, _| {
            SensorFault::Dropout {
                joint: j,
                start_s: (t - 0.05).max(0.0),
                duration_s: 0.1,
                mode: DropoutMode::Stale,
            }
        }),
        ("dropout (missing, 0.1 s over the latch)", |j, t, _, _| {
            SensorFault::Dropout {
                joint: j,
                start_s: (t - 0.05).max(0.0),
                duration_s: 0.1,
                mode: DropoutMode::Missing,
            }
        }),
        (
            "spike (2 samples to the latch angle, 30 ms before it)",
            |j, t, phi, _| SensorFault::Spike {
                joint: j,
                t_s: (t - 0.03).max(0.0),
                magnitude_deg: -phi,
                samples: 2,
            },
        ),
        (
            "stuck (0.2 s before the latch; seed 2: at 0°)",
            |j, t, _, seed| SensorFault::StuckAt {
                joint: j,
                start_s: (t - 0.2).max(0.0),
                value_deg: (seed == 2).then_some(0.0),
            },
        ),
        ("parity (1 bit, 20 % of words)", |j, _, _, _| {
            SensorFault::ParityError {
                joint: j,
                rate: 0.2,
                bits: 1,
            }
        }),
        ("parity (2 bits, 5 % of words)", |j, _, _, _| {
            SensorFault::ParityError {
                joint: j,
                rate: 0.05,
                bits: 2,
            }
        }),
        ("chatter (bounce 20 ms)", |j, _, _, _| {
            SensorFault::SwitchChatter {
                joint: j,
                bounce_s: 0.02,
            }
        }),
        ("switch stuck open", |j, _, _, _| SensorFault::SwitchStuck {
            joint: j,
            closed: false,
        }),
        ("switch stuck closed", |j, _, _, _| {
            SensorFault::SwitchStuck {
                joint: j,
                closed: true,
            }
        }),
        ("jitter (σ = 1 ms)", |_, _, _, _| SensorFault::TimeJitter {
            sigma_s: 0.001,
        }),
        ("gap (0.1 s over the latch)", |_, t, _, _| {
            SensorFault::TimeGap {
                start_s: (t - 0.05).max(0.01),
                duration_s: 0.1,
            }
        }),
    ]
}

/// Counts of one fault variant.
#[derive(Default, Clone)]
struct Tally {
    runs: usize,
    joints: usize,
    final_right: usize,
    false_latches: usize,
    lost_latches: usize,
    stalls: usize,
    missed_stalls: usize,
    /// Runs in which the monitor raised some fault flag.
    flagged: usize,
    /// Runs whose fault changed no sample, and those of them flagged.
    unchanged: usize,
    unchanged_flagged: usize,
    /// Runs with a fault that changed samples but raised no flag.
    unflagged: Vec<String>,
    max_friction_err_nm: f64,
    max_friction_err_rel: f64,
    failures: Vec<String>,
}

/// One scenario: a mechanism, its true friction and the simulated motion.
struct Scenario {
    name: String,
    mech: Mechanism,
    friction: Vec<f64>,
    traj: Trajectory,
}

fn scenarios() -> Vec<Scenario> {
    let mut out = Vec::new();
    for (name, paper) in [
        ("seed000_case1", &SEED000_FRICTION[..]),
        ("seed000_case3", &SEED000_FRICTION[..]),
        ("seed001_T01", &SEED001_FRICTION[..]),
        ("seed001_T02", &SEED001_FRICTION[..]),
    ] {
        let mech = mechanism(name);
        for with_friction in [false, true] {
            let effects = if with_friction {
                coulomb(paper)
            } else {
                Vec::new()
            };
            let opts = SimOptions {
                stop_when_deployed: false,
                ..SimOptions::default()
            };
            let mut traj = simulate(&mech, &effects, &opts).expect("simulation");
            hold_at_rest(&mut traj, HOLD_S, 1.0 / mech.sample_hz);
            let friction = mech
                .joints
                .iter()
                .enumerate()
                .map(|(j, jt)| {
                    jt.friction.coulomb_nm
                        + if with_friction {
                            paper.get(j).copied().unwrap_or(0.0)
                        } else {
                            0.0
                        }
                })
                .collect();
            out.push(Scenario {
                name: format!("{name}{}", if with_friction { "+paper" } else { "" }),
                mech: mech.clone(),
                friction,
                traj,
            });
        }
    }
    out
}

/// Scores one faulted run of a scenario into `tally`.
fn score<const N: usize>(
    sc: &Scenario,
    cfg: &MonitorConfig<N>,
    label: &str,
    build: Builder,
    seed: u64,
    tally: &mut Tally,
) {
    let traj = &sc.traj;
    let clean: Run = measure(traj, &[], &SensorModel::REFERENCE, seed);
    let target = ((seed as usize - 1) % N) + 1;
    let jt = target - 1;
    // The latch instant; for a joint that never latches, the instant of
    // its fastest motion (at rest, a stalled joint's stale or spiked
    // encoder is indistinguishable from its noise within the 0.1 s of a
    // dropout: the stuck check, 0.2 s at rest, is for that).
    let t_ref = traj.latch_s[jt].unwrap_or_else(|| {
        let k = (0..traj.t_s.len())
            .max_by(|&a, &b| {
                traj.rate_deg_s[jt][a]
                    .abs()
                    .total_cmp(&traj.rate_deg_s[jt][b].abs())
            })
            .unwrap_or(0);
        traj.t_s[k]
    });
    let i_ref = traj
        .t_s
        .iter()
        .position(|&t| t >= t_ref - 0.03 - 1e-9)
        .unwrap_or(0);
    let phi_ref = traj.phi_deg[jt][i_ref];
    let fault = build(target, t_ref, phi_ref, seed);
    let mut run = clean.clone();
    let touched: usize = apply(&mut run, &[fault], seed)
        .unwrap_or_else(|e| panic!("{fault}: {e}"))
        .iter()
        .map(|r| r.samples)
        .sum();
    // Row of the faulted run → row of the trajectory: identity unless rows
    // were removed (a gap), then by the untouched time stamps.
    let orig: Vec<usize> = if run.len() == clean.len() {
        (0..run.len()).collect()
    } else {
        let mut k = 0;
        run.t_s
            .iter()
            .map(|&t| {
                while clean.t_s[k] != t {
                    k += 1;
                }
                k
            })
            .collect()
    };
    let mut m = Monitor::new(cfg).expect("monitor config");
    let st: Vec<Status<N>> = samples::<N>(&run)
        .expect("joint count")
        .iter()
        .map(|s| m.replay_step(s))
        .collect();
    tally.runs += 1;
    let flagged = st.iter().any(|s| !s.is_clean());
    tally.flagged += usize::from(flagged);
    if touched == 0 {
        // The fault changed no sample (chatter or a switch stuck open on a
        // joint that never latches: its switch never closes): a clean run.
        tally.unchanged += 1;
        tally.unchanged_flagged += usize::from(flagged);
    }
    if flagged && label == "none (reference)" {
        if let Some((i, s)) = st.iter().enumerate().find(|(_, s)| !s.is_clean()) {
            let j = (0..N)
                .find(|&j| !s.joints[j].faults.is_empty())
                .unwrap_or(0);
            tally.unflagged.push(format!(
                "{label}: {} seed {seed}: FLAGGED joint {} at {:.3} s: {}",
                sc.name,
                j + 1,
                traj.t_s[orig[i]],
                s.joints[j].faults
            ));
        }
    }
    if !flagged && touched > 0 && label != "none (reference)" && std::env::var("FC_DEBUG").is_ok() {
        let i0 = run.t_s.iter().position(|&t| t >= t_ref - 0.08).unwrap_or(0);
        for i in i0..(i0 + 14).min(st.len()) {
            println!(
                "  t {:.3} z {:.3} sw {} filt {:.3} rate {:.1} true {:.3} {}",
                run.t_s[i],
                run.phi_deg[jt][i],
                run.latch[jt][i],
                st[i].joints[jt].phi_deg,
                st[i].joints[jt].rate_deg_s,
                traj.phi_deg[jt][orig[i]],
                st[i].joints[jt].latch
            );
        }
    }
    if !flagged && touched > 0 && label != "none (reference)" {
        tally.unflagged.push(format!(
            "{label}: {} seed {seed}: {fault} ({touched} samples changed)",
            sc.name
        ));
    }
    let ctx = |j: usize| format!("{label}: {} seed {seed} joint {}: {fault}", sc.name, j + 1);
    for j in 0..N {
        tally.joints += 1;
        let truly = traj.latch_s[j].is_some();
        let last = st.last().map(|s| s.joints[j]).unwrap_or_default();
        let final_latched = last.latch == LatchState::Latched;
        if final_latched == truly {
            tally.final_right += 1;
        } else {
            tally.failures.push(format!(
                "{}: final {} (truly latched: {truly})",
                ctx(j),
                last.latch
            ));
        }
        let mut seen = false;
        let mut false_here = false;
        let mut lost_here = false;
        for (i, s) in st.iter().enumerate() {
            let latched = s.joints[j].latch == LatchState::Latched;
            if latched && !traj.latched[j][orig[i]] && !false_here {
                false_here = true;
                tally.failures.push(format!(
                    "{}: latch declared at {:.4} s, true latch {:?}",
                    ctx(j),
                    traj.t_s[orig[i]],
                    traj.latch_s[j]
                ));
            }
            if seen && !latched && !lost_here {
                lost_here = true;
                tally.failures.push(format!(
                    "{}: latch lost at {:.4} s",
                    ctx(j),
                    traj.t_s[orig[i]]
                ));
            }
            seen |= latched;
        }
        tally.false_latches += usize::from(false_here);
        tally.lost_latches += usize::from(lost_here);
        if !truly {
            tally.stalls += 1;
            if last.prediction != Prediction::Stall && last.latch != LatchState::Stalled {
                tally.missed_stalls += 1;
            }
        }
        let tc = sc.friction[j];
        if tc >= SCORED_FRICTION_NM {
            let stowed = sc.mech.joints[j].stowed_deg;
            let half = traj.phi_deg[j]
                .iter()
                .position(|p| p.abs() <= 0.5 * stowed.abs())
                .unwrap_or(traj.t_s.len() - 1);
            let row = orig.iter().position(|&o| o >= half).unwrap_or(st.len() - 1);
            let err = (f64::from(st[row].joints[j].coulomb_nm) - tc).abs();
            tally.max_friction_err_nm = tally.max_friction_err_nm.max(err);
            tally.max_friction_err_rel = tally.max_friction_err_rel.max(err / tc);
        }
    }
}

fn campaign_on<const N: usize>(sc: &Scenario, tallies: &mut [Tally], with_none: bool) {
    let cfg = monitor_config::<N>(&sc.mech).expect("monitor config");
    let mut all: Vec<(&str, Builder)> = Vec::new();
    if with_none {
        // A fault that changes nothing: the spike of 0°.
        all.push(("none (reference)", |j, t, _, _| SensorFault::Spike {
            joint: j,
            t_s: t,
            magnitude_deg: 0.0,
            samples: 1,
        }));
    }
    all.extend(variants());
    for (k, (label, build)) in all.into_iter().enumerate() {
        for seed in SEEDS {
            score::<N>(sc, &cfg, label, build, seed, &mut tallies[k]);
        }
    }
}

#[test]
fn every_fault_every_mechanism_no_false_or_lost_latch() {
    let start = std::time::Instant::now();
    let labels: Vec<&str> = std::iter::once("none (reference)")
        .chain(variants().iter().map(|(l, _)| *l))
        .collect();
    let mut tallies = vec![Tally::default(); labels.len()];
    for sc in scenarios() {
        match sc.mech.joints.len() {
            2 => campaign_on::<2>(&sc, &mut tallies, true),
            3 => campaign_on::<3>(&sc, &mut tallies, true),
            n => panic!("{}: {n} joints", sc.name),
        }
    }
    println!(
        "| fault | runs | flagged | unchanged by the fault | joints | correct final latch state | false latch declarations | lost latches | missed stalls | max friction-estimate error |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for (label, t) in labels.iter().zip(&tallies) {
        println!(
            "| {label} | {} | {} | {} | {} | {}/{} | {} | {} | {}/{} | {:.3} N·m ({:.0} %) |",
            t.runs,
            t.flagged,
            t.unchanged,
            t.joints,
            t.final_right,
            t.joints,
            t.false_latches,
            t.lost_latches,
            t.missed_stalls,
            t.stalls,
            t.max_friction_err_nm,
            100.0 * t.max_friction_err_rel
        );
    }
    println!("campaign: {:.1} s", start.elapsed().as_secs_f64());
    let failures: Vec<&String> = tallies.iter().flat_map(|t| &t.failures).collect();
    for f in &failures {
        println!("FAIL {f}");
    }
    // Every single fault leaves at least one sensor of each joint healthy
    // (a clock fault leaves both readings right), so every final state must
    // be right, and no fault may make or undo a latch.
    assert!(failures.is_empty(), "{} failures", failures.len());
    for u in tallies.iter().flat_map(|t| &t.unflagged) {
        println!("UNFLAGGED {u}");
    }
    // No flag without a fault, and every injected fault flagged: every
    // run whose fault changed a sample. A fault that changed none (chatter
    // or a switch stuck open on a joint that never latches, whose switch
    // never closes) leaves a clean run, which must raise no flag either.
    for (label, t) in labels.iter().zip(&tallies) {
        if *label == "none (reference)" {
            assert_eq!(t.flagged, 0, "{label}: flags on runs without a fault");
        } else {
            assert_eq!(
                t.unchanged_flagged, 0,
                "{label}: flags on runs the fault did not change"
            );
            assert!(
                t.unflagged.is_empty(),
                "{label}: {} of {} faulted runs not flagged",
                t.unflagged.len(),
                t.runs - t.unchanged
            );
        }
    }
}
