//! The monitor's prediction on seed 001's runs: Monte-Carlo at half stroke, rollouts from the
//! true state, the friction estimate at half stroke, stall and no-stall calls.

use super::*;

/// The outcome of one Monte-Carlo joint: what the monitor predicted at half
/// stroke (or at the end of the run if the joint never got there) and
/// whether it latched.
#[derive(Clone, Copy, Debug)]
struct Outcome {
    predicted: Prediction,
    latched: bool,
}

impl Outcome {
    fn is_right(&self) -> bool {
        matches!(
            (self.predicted, self.latched),
            (Prediction::Latch, true) | (Prediction::Stall, false)
        )
    }
}

/// One Monte-Carlo run of seed001_T01 with the [`scatter`], measured with
/// sensor seed `seed`.
fn monte_carlo_run(
    mech: &Mechanism,
    cfg: &MonitorConfig<3>,
    rng: &mut SplitMix,
    seed: u64,
) -> [Outcome; 3] {
    let effects = scatter(rng);
    let (traj, run) = simulate_run(mech, &effects, seed);
    let st = replay(cfg, &run);
    std::array::from_fn(|j| {
        let i = half_stroke_index(&traj, mech.joints[j].stowed_deg, j).unwrap_or(st.len() - 1);
        let s = &st[i.min(st.len() - 1)];
        let out = Outcome {
            predicted: s.joints[j].prediction,
            latched: traj.latch_s[j].is_some(),
        };
        if !out.is_right() {
            let js = &s.joints[j];
            println!(
                "wrong: sensor seed {seed} joint {}: at t = {:.2} s T_C = {:.3} ± {:.3} N·m \
                 (truth {:.3}, spring ×{:.3}), predicted {} (confidence {:.1}, latch at {}); \
                 outcome {}",
                j + 1,
                s.t_s,
                js.coulomb_nm,
                js.coulomb_sd_nm,
                effects[2 * j].value(),
                1.0 - effects[2 * j + 1].value(),
                js.prediction,
                js.confidence,
                js.time_to_latch_s
                    .map_or("-".to_string(), |v| format!("{:.2} s", v + s.t_s)),
                traj.latch_s[j].map_or_else(
                    || format!(
                        "no latch by the deadline ({:.1}° left)",
                        traj.phi_deg[j].last().unwrap_or(&f64::NAN).abs()
                    ),
                    |t| format!("latched at {t:.2} s")
                ),
            );
        }
        out
    })
}

/// The Monte-Carlo draws: splitmix64 seed of the friction and spring
/// scatter, first sensor seed. The first is the one tabulated in
/// docs/monitor.md; the others are independent repeats.
const MC_DRAWS: [(u64, u64); 6] = [
    (2024, 1000),
    (7, 5000),
    (99, 9000),
    (31337, 13000),
    (4242, 17000),
    (1, 21000),
];

/// One 200-run Monte-Carlo of friction and spring scatter on seed001_T01:
/// the latch / stall prediction made at half stroke against the outcome.
/// Returns (runs with every joint right, joint predictions right).
fn monte_carlo(
    mech: &Mechanism,
    cfg: &MonitorConfig<3>,
    draws: u64,
    sensor: u64,
) -> (usize, usize) {
    let mut rng = SplitMix(draws);
    // table[joint][latched as usize][prediction: latch, stall, unknown]
    let mut table = [[[0usize; 3]; 2]; 3];
    let mut runs_right = 0;
    for k in 0..MC_RUNS {
        let out = monte_carlo_run(mech, cfg, &mut rng, sensor + k as u64);
        for (j, o) in out.iter().enumerate() {
            let col = match o.predicted {
                Prediction::Latch => 0,
                Prediction::Stall | Prediction::RampStop => 1,
                Prediction::Unknown => 2,
            };
            table[j][usize::from(o.latched)][col] += 1;
        }
        runs_right += usize::from(out.iter().all(Outcome::is_right));
    }
    println!(
        "draws {draws}, sensor seeds {sensor}–{}:",
        sensor + MC_RUNS as u64 - 1
    );
    println!("| joint | outcome | predicted latch | predicted stall | unknown |");
    println!("|---|---|---|---|---|");
    let mut right = 0;
    for (j, t) in table.iter().enumerate() {
        for (latched, name) in [(1, "latched"), (0, "stalled")] {
            let r = t[latched];
            println!("| {} | {name} | {} | {} | {} |", j + 1, r[0], r[1], r[2]);
        }
        right += t[1][0] + t[0][1];
    }
    let total = MC_RUNS * 3;
    println!(
        "runs with every joint right: {runs_right}/{MC_RUNS} ({:.1} %); joint predictions right: {right}/{total} ({:.1} %)",
        100.0 * runs_right as f64 / MC_RUNS as f64,
        100.0 * right as f64 / total as f64
    );
    let stalled: usize = table.iter().map(|t| t[0].iter().sum::<usize>()).sum();
    assert!(
        stalled > 0 && stalled < total,
        "the scatter must give both outcomes ({stalled} stalls)"
    );
    (runs_right, right)
}

/// The 200-run Monte-Carlo, six times over independent draws:
/// in each, the latch / stall prediction made at half stroke is right for
/// every joint in ≥ 95 % of the runs, and ≥ 98 % of the joint
/// predictions are right. Rerun with `cargo test -p deploywatch-tests --test
/// monitor monte_carlo -- --nocapture` (tables in docs/monitor.md §8;
/// `MC_STEPS=0` runs the cheap variant, the one-joint energy balance only,
/// against the same bounds, which it does not meet: `MC_STEPS=0 cargo test
/// -p deploywatch-tests --test monitor monte_carlo -- --nocapture` prints
/// its table).
#[test]
fn monte_carlo_prediction_at_half_stroke() {
    let mech = mechanism("seed001_T01");
    let mut cfg = monitor_config::<3>(&mech).unwrap();
    let cheap = std::env::var("MC_STEPS").ok().and_then(|v| v.parse().ok());
    if let Some(steps) = cheap {
        cfg.margin.rollout.steps_per_slice = steps;
    }
    let results: Vec<(usize, usize)> = MC_DRAWS
        .iter()
        .map(|&(draws, sensor)| monte_carlo(&mech, &cfg, draws, sensor))
        .collect();
    let all: usize = results.iter().map(|r| r.0).sum();
    println!("all draws: {all}/{} runs right", MC_RUNS * MC_DRAWS.len());
    // The cheap variant (`MC_STEPS`) is held to the same bounds: a knob that
    // skipped them would let the test pass without asserting anything.
    if let Some(steps) = cheap {
        println!("MC_STEPS={steps}: rollout steps per slice, held to the same bounds");
    }
    assert_eq!(results.len(), MC_DRAWS.len(), "every draw ran");
    for (&(draws, _), &(runs_right, right)) in MC_DRAWS.iter().zip(results.iter()) {
        assert!(
            runs_right * 100 >= 95 * MC_RUNS,
            "draws {draws}: only {runs_right}/{MC_RUNS} runs right at half stroke"
        );
        assert!(
            right * 100 >= 98 * 3 * MC_RUNS,
            "draws {draws}: only {right} joint predictions right"
        );
    }
}

/// The rollout on its own, fed what the monitor can only estimate: started
/// at half stroke from the simulator's true state with the true friction
/// and spring scale of each Monte-Carlo run, it predicts the simulated
/// outcome of every joint. Only a latch within [`DEADLINE_EDGE_S`] of the
/// deadline, where f32 steps of 20 ms against the f64 simulator decide,
/// may go either way. This separates the prediction's physics from the
/// estimates it starts from (docs/monitor.md §8). The latch times are
/// compared with the simulation's for the monitor's steps (lengthened in a
/// glide, `docs/monitor.md` §6) and for fixed steps (`glide_dt_s = dt_s`):
/// the glide may add at most [`GLIDE_TOLERANCE_S`] to the mean and the
/// 95th percentile of the error.
#[test]
fn rollout_from_the_true_state_predicts_the_simulation() {
    let mech = mechanism("seed001_T01");
    let cfg = monitor_config::<3>(&mech).unwrap();
    let mut fixed = cfg.margin.rollout;
    fixed.glide_dt_s = fixed.dt_s;
    let (mut checked, mut edge) = (0, 0);
    let (mut err_glide, mut err_fixed, mut apart) = (Vec::new(), Vec::new(), 0.0f64);
    for &(draws, _) in MC_DRAWS.iter() {
        let mut rng = SplitMix(draws);
        for k in 0..MC_RUNS {
            let effects = scatter(&mut rng);
            let traj = simulate_truth(&mech, &effects);
            for j in 0..3 {
                let Some(i) = half_stroke_index(&traj, mech.joints[j].stowed_deg, j) else {
                    continue;
                };
                let from_truth = |rc| rollout_from_truth(&cfg, rc, &traj, &effects, i, j);
                let (raw, raw_fixed) = (from_truth(cfg.margin.rollout), from_truth(fixed));
                let predicted = raw.filter(|t| *t <= mech.duration_s);
                let truth = traj.latch_s[j];
                checked += 1;
                if let (Some(t), Some(a), Some(b)) = (truth, raw, raw_fixed) {
                    err_glide.push((a - t).abs());
                    err_fixed.push((b - t).abs());
                    apart = apart.max((a - b).abs());
                }
                if predicted.is_some() == truth.is_some() {
                    continue;
                }
                let near = |t: Option<f64>| {
                    t.is_some_and(|t| (t - mech.duration_s).abs() <= DEADLINE_EDGE_S)
                };
                println!(
                    "draws {draws} run {k} joint {}: rollout latch {raw:?}, simulated {truth:?}",
                    j + 1
                );
                assert!(
                    near(raw) || near(truth),
                    "draws {draws} run {k} joint {}: rollout says latch at {raw:?} s, \
                     the simulation {truth:?}",
                    j + 1
                );
                edge += 1;
            }
        }
    }
    println!("{checked} joint outcomes checked, {edge} decided within {DEADLINE_EDGE_S} s of the deadline");
    let stats = |e: &mut Vec<f64>| {
        e.sort_by(f64::total_cmp);
        let mean = e.iter().sum::<f64>() / e.len().max(1) as f64;
        (mean, e[e.len() * 95 / 100], e[e.len() - 1])
    };
    let (g, f) = (stats(&mut err_glide), stats(&mut err_fixed));
    println!(
        "latch time against the simulation over {} latches (mean, 95th percentile, max): \
         glide steps {:.4} / {:.4} / {:.4} s, fixed steps {:.4} / {:.4} / {:.4} s; \
         the two apart by at most {apart:.4} s",
        err_glide.len(),
        g.0,
        g.1,
        g.2,
        f.0,
        f.1,
        f.2
    );
    // The lengthened steps of the glide keep the fixed step's accuracy.
    assert!(
        g.0 <= f.0 + GLIDE_TOLERANCE_S && g.1 <= f.1 + GLIDE_TOLERANCE_S,
        "glide steps: latch times off by {g:?} s against {f:?} s with fixed steps"
    );
}

/// How much the glide's lengthened steps may add to the mean and the 95th
/// percentile of the rollout's latch-time error against the simulation \[s\].
const GLIDE_TOLERANCE_S: f64 = 0.005;

/// The rollout of `cfg` with schedule `rc` from the simulated true state at
/// sample `i` (true friction and springs), run to the end: joint `j`'s
/// latch instant \[s\], if it latches (before or after the deadline).
fn rollout_from_truth(
    cfg: &MonitorConfig<3>,
    rc: deploywatch_core::monitor::RolloutConfig,
    traj: &Trajectory,
    effects: &[Effect],
    i: usize,
    j: usize,
) -> Option<f64> {
    let coulomb_nm = std::array::from_fn(|q| effects[2 * q].value() as f32);
    let spring_scale = std::array::from_fn(|q| 1.0 - effects[2 * q + 1].value() as f32);
    rollout_latches(cfg, rc, traj, i, coulomb_nm, spring_scale)[j]
}

/// How close to the deadline a latch may fall for the rollout and the
/// simulator to disagree \[s\].
const DEADLINE_EDGE_S: f64 = 0.1;

/// Seeds of the sensor noise the single-run tests are repeated over.
const SEEDS: std::ops::RangeInclusive<u64> = 1..=10;

/// seed001_T01 with the paper's friction: the Coulomb estimate of each joint
/// whose friction is ≥ 0.3 N·m is within 15 % of the truth by the time the
/// joint has covered half its stroke.
#[test]
fn t01_friction_within_15_percent_at_half_stroke() {
    t01_friction_at_half_stroke("", &[]);
}

/// T01 with the papers' friction and `faults` injected: every Coulomb
/// estimate of a joint whose friction is ≥ 0.3 N·m is within 15 % of the
/// truth at half stroke, over every seed; a jitter fault is also flagged.
fn t01_friction_at_half_stroke(label: &str, faults: &[SensorFault]) {
    let mech = mechanism("seed001_T01");
    let cfg = monitor_config::<3>(&mech).unwrap();
    let mut worst = 0.0f64;
    for seed in SEEDS {
        let (traj, mut run) = simulate_run(&mech, &coulomb(&SEED001_FRICTION), seed);
        apply(&mut run, faults, seed).unwrap();
        let st = replay(&cfg, &run);
        if faults
            .iter()
            .any(|f| matches!(f, SensorFault::TimeJitter { .. }))
        {
            assert!(
                st.iter()
                    .any(|s| s.joints[0].faults.contains(Fault::TimeJitter)),
                "seed {seed}: jitter not flagged"
            );
        }
        for (j, &truth) in SEED001_FRICTION.iter().enumerate() {
            if truth < 0.3 {
                continue;
            }
            let i = half_stroke_index(&traj, mech.joints[j].stowed_deg, j)
                .expect("joint reaches half stroke");
            let est = st[i].joints[j];
            let err = est.coulomb_nm as f64 / truth - 1.0;
            println!(
                "{label}seed {seed:2} joint {} at t = {:.2} s: T_C = {:.3} ± {:.3} N·m (truth {truth}, {:+.1} %)",
                j + 1,
                st[i].t_s,
                est.coulomb_nm,
                est.coulomb_sd_nm,
                100.0 * err
            );
            worst = worst.max(err.abs());
            assert!(err.abs() <= 0.15, "seed {seed} joint {}: {err:+.3}", j + 1);
        }
    }
    println!("{label}worst relative error {:.1} %", 100.0 * worst);
}

/// The same with 1 ms σ of time-stamp jitter (`faults::apply`'s
/// `jitter:sigma=0.001`, clipped to ±4.5 ms): the Coulomb estimates at half
/// stroke stay within 15 % (the observer learns on the centred fit of the
/// stamped times), and the jitter is flagged.
#[test]
fn t01_friction_within_15_percent_at_half_stroke_with_1_ms_jitter() {
    t01_friction_at_half_stroke("jitter, ", &[SensorFault::TimeJitter { sigma_s: 0.001 }]);
}

/// seed001_T02 with the paper's friction: joint 1 (2 × TS-3 against
/// 2.63 N·m) never latches; the monitor says so within 0.5 s of the start,
/// and does not take it back.
#[test]
fn t02_joint1_stall_predicted_within_half_a_second() {
    let mech = mechanism("seed001_T02");
    let cfg = monitor_config::<3>(&mech).unwrap();
    for seed in SEEDS {
        let (traj, run) = simulate_run(&mech, &coulomb(&SEED001_FRICTION), seed);
        assert_eq!(traj.latch_s[0], None, "joint 1 of T02 must not latch");
        let st = replay(&cfg, &run);
        let first = st
            .iter()
            .position(|s| s.joints[0].prediction == Prediction::Stall)
            .expect("a stall prediction");
        println!(
            "seed {seed:2}: joint 1 stall predicted at t = {:.2} s (confidence {:.2}, T_C = {:.2} ± {:.2} N·m)",
            st[first].t_s, st[first].joints[0].confidence, st[first].joints[0].coulomb_nm, st[first].joints[0].coulomb_sd_nm
        );
        assert!(
            st[first].t_s <= 0.5,
            "seed {seed}: first stall prediction at {} s",
            st[first].t_s
        );
        let latch_later = st[first..]
            .iter()
            .find(|s| s.joints[0].prediction == Prediction::Latch);
        assert!(
            latch_later.is_none(),
            "seed {seed}: latch predicted again at {:?}",
            latch_later.map(|s| s.t_s)
        );
        assert!(st.iter().all(|s| s.joints[0].latch != LatchState::Latched));
    }
}

/// A joint jammed mid-stroke (T01, joint 3's readings held where they
/// first reach −90°, with a wobble of the encoder's noise, its switch
/// open; the run held [`JAM_HOLD_S`] past its last latch): once the tracker
/// calls it `stalled`, no status predicts it to latch at more than the
/// unconfirmed 0.5, though the rollouts, which start it from rest with a
/// friction estimate that does not know the jam, latch it; once the other
/// joints have latched it is predicted to stall within [`JAM_CALLED_S`], and
/// from then on never to latch.
#[test]
fn a_jammed_joint_is_never_confidently_predicted_to_latch() {
    let mech = mechanism("seed001_T01");
    let cfg = monitor_config::<3>(&mech).unwrap();
    let mut traj = simulate_truth(&mech, &coulomb(&SEED001_FRICTION));
    hold_at_rest(&mut traj, JAM_HOLD_S, 1.0 / mech.sample_hz);
    let mut run = measure(&traj, &[], &SensorModel::REFERENCE, 1);
    let i0 = run.phi_deg[2].iter().position(|p| *p >= -90.0).unwrap();
    let held = run.phi_deg[2][i0];
    let wobble = [0.0, 0.02, -0.02, 0.01, -0.01];
    for i in i0..run.t_s.len() {
        run.phi_deg[2][i] = held + wobble[i % wobble.len()];
        run.latch[2][i] = false;
    }
    let st = replay(&cfg, &run);
    let stalled: Vec<_> = st
        .iter()
        .filter(|s| s.joints[2].latch == LatchState::Stalled)
        .collect();
    assert!(!stalled.is_empty(), "the jammed joint is never stalled");
    for s in &stalled {
        let js = &s.joints[2];
        assert!(
            js.prediction != Prediction::Latch || js.confidence <= 0.5,
            "at {} s: {} at confidence {}",
            s.t_s,
            js.prediction,
            js.confidence
        );
    }
    let others = st
        .iter()
        .find(|s| {
            s.joints[..2]
                .iter()
                .all(|js| js.latch == LatchState::Latched)
        })
        .expect("joints 1 and 2 latch")
        .t_s;
    let called = stalled
        .iter()
        .position(|s| s.joints[2].prediction == Prediction::Stall)
        .expect("the jam is predicted to stall");
    println!(
        "stalled from {:.2} s, joints 1 and 2 latched at {others:.2} s, stall predicted at {:.2} s",
        stalled[0].t_s, stalled[called].t_s
    );
    assert!(stalled[called].t_s - others.max(stalled[0].t_s) <= JAM_CALLED_S);
    assert!(
        stalled[called..]
            .iter()
            .all(|s| s.joints[2].prediction == Prediction::Stall),
        "a latch predicted again"
    );
}

/// How long the jam test's run goes on after its last latch \[s\].
const JAM_HOLD_S: f64 = 2.0;

/// The time from the chain's coming to rest around a jammed joint to the
/// jam's stall prediction the test allows \[s\]: a few refreshes of the
/// prediction (each under half a second, `docs/monitor.md` §6.1).
const JAM_CALLED_S: f32 = 0.5;

/// seed001_T01 with the paper's friction deploys: no joint is ever
/// predicted to stall, at any sample.
#[test]
fn t01_never_predicts_a_stall() {
    let mech = mechanism("seed001_T01");
    let cfg = monitor_config::<3>(&mech).unwrap();
    for seed in SEEDS {
        let (traj, run) = simulate_run(&mech, &coulomb(&SEED001_FRICTION), seed);
        assert!(traj.deployed());
        for s in replay(&cfg, &run) {
            for (j, js) in s.joints.iter().enumerate() {
                assert_ne!(
                    js.prediction,
                    Prediction::Stall,
                    "seed {seed} joint {} at {} s",
                    j + 1,
                    s.t_s
                );
            }
        }
    }
}
