//! The on-board monitor (`deploywatch_core::monitor`) on runs of the
//! simulator with its reference sensor model (issue 3).

use deploywatch_core::monitor::{Monitor, MonitorConfig, Prediction, Sample, Status};
use deploywatch_core::LatchState;
use deploywatch_sim::effect::{Effect, EffectKind};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::monitor_config::{monitor_config, samples};
use deploywatch_sim::run::Run;
use deploywatch_sim::sensor::{measure, SensorModel};
use deploywatch_sim::sim::{simulate, SimOptions, Trajectory};
use deploywatch_tests::data_dir;

/// The papers' identified friction, seed 001 (N·m at joints 1–3).
const SEED001_FRICTION: [f64; 3] = [2.63, 1.7, 0.001];

fn mechanism(name: &str) -> Mechanism {
    Mechanism::load(&data_dir().join("mechanisms").join(format!("{name}.toml"))).expect("mechanism file")
}

fn coulomb(values: &[f64]) -> Vec<Effect> {
    values
        .iter()
        .enumerate()
        .map(|(j, &v)| Effect::joint(EffectKind::CoulombFriction, j + 1, v))
        .collect()
}

/// Simulates a mechanism with extra effects and measures it with the
/// reference sensor. The simulator ends a run at the last latch; the run is
/// extended by `HOLD_S` of samples at the rest state (latched joints at 0,
/// switches closed, sensor noise going on), as a real monitor keeps sampling.
fn simulate_run(mech: &Mechanism, effects: &[Effect], seed: u64) -> (Trajectory, Run) {
    let opts = SimOptions {
        stop_when_deployed: false,
        ..SimOptions::default()
    };
    let mut traj = simulate(mech, effects, &opts).expect("simulation");
    hold(&mut traj, HOLD_S, 1.0 / mech.sample_hz);
    let run = measure(&traj, &[], &SensorModel::REFERENCE, seed);
    (traj, run)
}

/// Samples the monitor keeps receiving after the last latch [s].
const HOLD_S: f64 = 0.2;

fn hold(traj: &mut Trajectory, hold_s: f64, dt: f64) {
    let Some(&t_last) = traj.t_s.last() else { return };
    let n = traj.joints();
    let mut t = t_last;
    let mut k = 0;
    while t < t_last + hold_s - 1e-9 {
        k += 1;
        t = t_last + k as f64 * dt;
        traj.t_s.push(t);
        for j in 0..n {
            let latched = traj.latched[j].last().copied().unwrap_or(false);
            let phi = traj.phi_deg[j].last().copied().unwrap_or(0.0);
            traj.phi_deg[j].push(if latched { 0.0 } else { phi });
            traj.latched[j].push(latched);
            traj.rate_deg_s[j].push(0.0);
        }
    }
}

/// A reference solution (`data/reference/NAME.csv`, 1 kHz, noise-free)
/// decimated to 100 Hz, held for `hold_s` after its end (latched joints stay
/// at 0, the others where they were), and measured with the reference sensor.
fn reference_run(name: &str, hold_s: f64, seed: u64) -> (Trajectory, Run) {
    let text = std::fs::read_to_string(data_dir().join("reference").join(format!("{name}.csv"))).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let n = (header.len() - 1) / 2;
    let mut traj = Trajectory {
        phi_deg: vec![Vec::new(); n],
        rate_deg_s: vec![Vec::new(); n],
        latched: vec![Vec::new(); n],
        latch_s: vec![None; n],
        ..Trajectory::default()
    };
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.trim().parse::<f64>().unwrap()).collect())
        .collect();
    for (i, r) in rows.iter().enumerate() {
        for j in 0..n {
            if r[1 + n + j] > 0.5 && traj.latch_s[j].is_none() {
                traj.latch_s[j] = Some(r[0]);
            }
        }
        if i % 10 != 0 {
            continue;
        }
        traj.t_s.push(r[0]);
        for j in 0..n {
            traj.phi_deg[j].push(r[1 + j]);
            traj.latched[j].push(r[1 + n + j] > 0.5);
            traj.rate_deg_s[j].push(0.0);
        }
    }
    let last = rows.last().unwrap().clone();
    let mut t = *traj.t_s.last().unwrap();
    while t < last[0] + hold_s {
        t += 0.01;
        traj.t_s.push((t * 100.0).round() / 100.0);
        for j in 0..n {
            traj.phi_deg[j].push(last[1 + j]);
            traj.latched[j].push(last[1 + n + j] > 0.5);
            traj.rate_deg_s[j].push(0.0);
        }
    }
    traj.end_s = t;
    let sensor = if std::env::var("IDEAL").is_ok_and(|v| v == "1") { SensorModel::IDEAL } else { SensorModel::REFERENCE };
    let run = measure(&traj, &[], &sensor, seed);
    (traj, run)
}

fn replay<const N: usize>(cfg: &MonitorConfig<N>, run: &Run) -> Vec<Status<N>> {
    let mut m = Monitor::new(cfg).expect("monitor config");
    samples::<N>(run).expect("joint count").iter().map(|s| m.update(s)).collect()
}

#[test]
#[ignore]
fn diag() {
    let which = std::env::var("DIAG").unwrap_or_else(|_| "seed001_T01".into());
    let fr: Vec<f64> = std::env::var("FRIC")
        .map(|s| s.split(',').map(|x| x.parse().unwrap()).collect())
        .unwrap_or(SEED001_FRICTION.to_vec());
    let mech_name = which.trim_end_matches("_eft").trim_end_matches("_nominal").to_string();
    let mech = mechanism(&mech_name);
    let (traj, run) = if std::env::var("REF").is_ok() {
        reference_run(&which, 0.2, 1)
    } else {
        simulate_run(&mech, &coulomb(&fr), 1)
    };
    let cfg = monitor_config::<3>(&mech).unwrap();
    let st = replay(&cfg, &run);
    println!("latch_s {:?}", traj.latch_s);
    for (i, s) in st.iter().enumerate() {
        let every: usize = std::env::var("EVERY").ok().and_then(|v| v.parse().ok()).unwrap_or(10);
        let until: f32 = std::env::var("UNTIL").ok().and_then(|v| v.parse().ok()).unwrap_or(1e9);
        if i % every != 0 || s.t_s > until {
            continue;
        }
        let mut line = format!("{:6.2}", s.t_s);
        for (j, js) in s.joints.iter().enumerate() {
            line += &format!(
                "|{:7.2} {:6.1} C{:4.2}±{:4.2} v{:5.3} r{:5.2} {:4} {:?}/{:4.2} m{:5.0} ttl{:4.2}",
                js.phi_deg,
                js.rate_deg_s,
                js.coulomb_nm,
                js.coulomb_sd_nm,
                js.viscous_nms,
                js.friction_torque_nm,
                &js.latch.as_str()[..4],
                js.prediction,
                js.confidence,
                js.margin_pct.unwrap_or(f32::NAN),
                js.time_to_latch_s.unwrap_or(f32::NAN)
            );
            if !js.faults.is_empty() {
                line += &format!(" [{}]", js.faults);
            }
        }
        println!("{line}");
    }
}

#[test]
#[ignore]
fn diag_obs() {
    let which = std::env::var("DIAG").unwrap_or_else(|_| "seed001_T01_eft".into());
    let jj: usize = std::env::var("J").ok().and_then(|v| v.parse().ok()).unwrap_or(1);
    let mech = mechanism(which.trim_end_matches("_eft").trim_end_matches("_nominal"));
    let seed: u64 = std::env::var("SEED").ok().and_then(|v| v.parse().ok()).unwrap_or(1);
    let (_, run) = simulate_run(&mech, &coulomb(&SEED001_FRICTION), seed);
    let cfg = monitor_config::<3>(&mech).unwrap();
    let mut m = Monitor::new(&cfg).unwrap();
    for (i, s) in samples::<3>(&run).unwrap().iter().enumerate() {
        let st = m.update(s);
        let until: usize = std::env::var("N").ok().and_then(|v| v.parse().ok()).unwrap_or(60);
        if i > until { break; }
        if i % std::env::var("EVERY").ok().and_then(|v| v.parse().ok()).unwrap_or(1usize) != 0 { continue; }
        let o = m.observer(jj).unwrap();
        let k = m.rate_filter(jj).unwrap();
        println!("{:5.2} q{:8.3} nis{:5.2} w{:8.4}±{:7.4} a{:7.3} r{:6.3} y{:?} lag{:.2e} L{:.2} C{:.3}±{:.3}", st.t_s, k.jerk_psd(), k.nis(), k.rate(), k.rate_var().sqrt(), k.acceleration(), o.disturbance_nm(), o.regressors(), o.lag_var(), o.coulomb_lower_bound(k.rate()), st.joints[jj].coulomb_nm, st.joints[jj].coulomb_sd_nm);
    }
}

#[test]
#[ignore]
fn diag_sim() {
    let mech = mechanism("seed001_T01");
    for stop in [true, false] {
        let opts = SimOptions { stop_when_deployed: stop, ..SimOptions::default() };
        let traj = simulate(&mech, &coulomb(&SEED001_FRICTION), &opts).unwrap();
        println!("stop={stop} latch_s {:?} end {}", traj.latch_s, traj.end_s);
    }
}

/// Index of the first sample at which joint `j` has covered half its stroke
/// (|φ| ≤ ½ |φ_stowed|, true angle).
fn half_stroke_index(traj: &Trajectory, stowed_deg: f64, j: usize) -> Option<usize> {
    traj.phi_deg[j].iter().position(|p| p.abs() <= 0.5 * stowed_deg.abs())
}

/// splitmix64: a small deterministic generator for the Monte-Carlo draws.
struct SplitMix(u64);

impl SplitMix {
    fn next_f64(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }
}

#[test]
#[ignore]
fn diag_seeds() {
    let mech = mechanism("seed001_T01");
    let mech2 = mechanism("seed001_T02");
    let cfg = monitor_config::<3>(&mech).unwrap();
    for seed in 1..=12u64 {
        let (traj, run) = simulate_run(&mech, &coulomb(&SEED001_FRICTION), seed);
        let st = replay(&cfg, &run);
        let mut line = format!("seed {seed:2} T01:");
        for j in 0..2 {
            let i = half_stroke_index(&traj, mech.joints[j].stowed_deg, j).unwrap();
            let js = &st[i].joints[j];
            line += &format!(" j{} {:.3}±{:.3} ({:+.1}%)", j + 1, js.coulomb_nm, js.coulomb_sd_nm, 100.0 * (js.coulomb_nm as f64 / SEED001_FRICTION[j] - 1.0));
        }
        let stalls: Vec<String> = st
            .iter()
            .flat_map(|s| s.joints.iter().enumerate().filter(|(_, j)| j.prediction == Prediction::Stall).map(move |(j, js)| format!("{:.2}:j{} {:.2} m{:.0}", s.t_s, j + 1, js.confidence, js.margin_pct.unwrap_or(0.0))))
            .collect();
        line += &format!(" stall-preds {stalls:?}");
        let (_, run2) = simulate_run(&mech2, &coulomb(&SEED001_FRICTION), seed);
        let cfg2 = monitor_config::<3>(&mech2).unwrap();
        let st2 = replay(&cfg2, &run2);
        let first = st2.iter().position(|s| s.joints[0].prediction == Prediction::Stall).map(|i| st2[i].t_s);
        let at05 = st2.iter().find(|s| s.t_s >= 0.5).map(|s| (s.joints[0].coulomb_nm, s.joints[0].coulomb_sd_nm, s.joints[0].confidence));
        line += &format!(" | T02 first stall {first:?} at0.5 {at05:?}");
        println!("{line}");
    }
}

/// The outcome of one Monte-Carlo joint: what the monitor predicted at half
/// stroke (or at the end of the run if the joint never got there) and
/// whether it latched.
#[derive(Clone, Copy, Debug)]
struct Outcome {
    predicted: Prediction,
    latched: bool,
}

/// One Monte-Carlo run of seed001_T01: the paper's friction scaled by
/// U(0.5, 1.5) and each spring by U(0.9, 1.1) (as `spring_softening`
/// s ∈ [−0.1, 0.1]), joint by joint, measured with sensor seed `seed`.
fn monte_carlo_run(mech: &Mechanism, cfg: &MonitorConfig<3>, rng: &mut SplitMix, seed: u64) -> [Outcome; 3] {
    let mut effects = Vec::new();
    for (j, base) in SEED001_FRICTION.iter().enumerate() {
        effects.push(Effect::joint(EffectKind::CoulombFriction, j + 1, base * rng.uniform(0.5, 1.5)));
        let soft = rng.uniform(-0.1, 0.1) * std::env::var("MC_SPRING").ok().and_then(|v| v.parse::<f64>().ok()).unwrap_or(1.0);
        effects.push(Effect::joint(EffectKind::SpringSoftening, j + 1, soft));
    }
    let (traj, run) = simulate_run(mech, &effects, seed);
    let st = replay(cfg, &run);
    if std::env::var("MC_VERBOSE").is_ok() {
        for j in 0..3 {
            let i = half_stroke_index(&traj, mech.joints[j].stowed_deg, j).unwrap_or(st.len() - 1).min(st.len() - 1);
            let js = &st[i].joints[j];
            let latched = traj.latch_s[j].is_some();
            let right = matches!((js.prediction, latched), (Prediction::Latch, true) | (Prediction::Stall, false));
            if !right {
                use deploywatch_core::rollout::{Rollout, RolloutStart};
                let chain = Monitor::new(cfg).unwrap().chain().clone();
                let oracle = |dt: f32| {
                    let mut rc = cfg.margin.rollout;
                    rc.dt_s = dt;
                    rc.steps_per_update = 255;
                    let mut r = Rollout::new(RolloutStart {
                        state: deploywatch_core::ChainState {
                            phi: std::array::from_fn(|k| (traj.phi_deg[k][i] as f32).to_radians()),
                            phi_dot: std::array::from_fn(|k| (traj.rate_deg_s[k][i] as f32).to_radians()),
                        },
                        latched: std::array::from_fn(|k| traj.latched[k][i]),
                        coulomb_nm: std::array::from_fn(|k| effects[2 * k].value as f32),
                        viscous_nms: [0.0; 3],
                        spring_scale: [1.0; 3],
                        capture_rad: std::array::from_fn(|k| cfg.joints[k].capture_deg.to_radians()),
                    });
                    for _ in 0..100 { r.advance(&chain, &rc); }
                    r.outcome().map(|o| o.latches)
                };
                println!("   oracle rollout dt 20ms {:?} dt 5ms {:?} dt 1ms {:?}", oracle(0.02), oracle(0.005), oracle(0.001));
                println!(
                    "seed {seed} j{} fric {:.3} soft {:+.3} latched {latched} final {:.1}° t_half {:.2} pred {:?} p {:.2} m {:?} C {:.2}±{:.2} rate {:.1} | finals {:?}",
                    j + 1, effects[2 * j].value, effects[2 * j + 1].value, traj.phi_deg[j].last().unwrap(), st[i].t_s, js.prediction, js.confidence, js.margin_pct, js.coulomb_nm, js.coulomb_sd_nm, js.rate_deg_s,
                    (0..3).map(|k| (traj.phi_deg[k].last().unwrap().round(), traj.latch_s[k].map(|t| (t * 100.0).round() / 100.0))).collect::<Vec<_>>()
                );
            }
        }
    }
    std::array::from_fn(|j| {
        let i = half_stroke_index(&traj, mech.joints[j].stowed_deg, j).unwrap_or(st.len() - 1);
        Outcome {
            predicted: st[i.min(st.len() - 1)].joints[j].prediction,
            latched: traj.latch_s[j].is_some(),
        }
    })
}

/// 200-run Monte-Carlo of friction and spring scatter on seed001_T01:
/// the latch / stall prediction made at half stroke against the outcome.
/// Rerun with `cargo test -p deploywatch-tests --test monitor
/// monte_carlo_prediction -- --nocapture` (the table is in docs/monitor.md).
#[test]
fn monte_carlo_prediction_at_half_stroke() {
    let mech = mechanism("seed001_T01");
    let cfg = monitor_config::<3>(&mech).unwrap();
    let mut rng = SplitMix(2024);
    let runs = 200;
    // table[joint][latched as usize][prediction: latch, stall, unknown]
    let mut table = [[[0usize; 3]; 2]; 3];
    let mut runs_right = 0;
    for k in 0..runs {
        let out = monte_carlo_run(&mech, &cfg, &mut rng, 1000 + k as u64);
        let mut all = true;
        for (j, o) in out.iter().enumerate() {
            let col = match o.predicted {
                Prediction::Latch => 0,
                Prediction::Stall => 1,
                Prediction::Unknown => 2,
            };
            table[j][usize::from(o.latched)][col] += 1;
            let right = matches!((o.predicted, o.latched), (Prediction::Latch, true) | (Prediction::Stall, false));
            all &= right;
        }
        runs_right += usize::from(all);
    }
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
    let total = runs * 3;
    println!(
        "runs with every joint right: {runs_right}/{runs}; joint predictions right: {right}/{total} ({:.1} %)",
        100.0 * right as f64 / total as f64
    );
    let stalled: usize = table.iter().map(|t| t[0].iter().sum::<usize>()).sum();
    assert!(stalled > 0 && stalled < total, "the scatter must give both outcomes ({stalled} stalls)");
    assert!(runs_right * 100 >= 95 * runs, "only {runs_right}/{runs} runs predicted right at half stroke");
}

#[test]
#[ignore]
fn diag_rollout_vs_sim() {
    use deploywatch_core::rollout::{Rollout, RolloutStart};
    let mech = mechanism("seed001_T01");
    let cfg = monitor_config::<3>(&mech).unwrap();
    let chain = Monitor::new(&cfg).unwrap().chain().clone();
    for f1 in [2.63, 3.0, 3.3, 3.5, 3.8] {
        let fr = [f1, 1.7, 0.001];
        let (traj, _) = simulate_run(&mech, &coulomb(&fr), 1);
        for dt in [0.01f32, 0.005, 0.002] {
            for cap in [1.0f32] {
                let mut rc = cfg.margin.rollout;
                rc.dt_s = dt;
                rc.steps_per_update = 255;
                let mut r = Rollout::new(RolloutStart {
                    state: deploywatch_core::ChainState {
                        phi: std::array::from_fn(|k| (mech.joints[k].stowed_deg as f32).to_radians()),
                        phi_dot: [0.0; 3],
                    },
                    latched: [false; 3],
                    coulomb_nm: fr.map(|v| v as f32),
                    viscous_nms: [0.0; 3],
                    spring_scale: [1.0; 3],
                    capture_rad: std::array::from_fn(|k| cap * cfg.joints[k].capture_deg.to_radians()),
                });
                for _ in 0..1000 {
                    r.advance(&chain, &rc);
                }
                println!(
                    "f1 {f1} dt {dt} cap {cap}: sim {:?} rollout {:?}",
                    traj.latch_s.iter().map(|t| t.map(|v| (v * 100.0).round() / 100.0)).collect::<Vec<_>>(),
                    r.outcome().map(|o| if o.latches { Some((o.latch_after_s * 100.0).round() / 100.0) } else { None })
                );
            }
        }
    }
}
