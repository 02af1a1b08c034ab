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
                js.latch_probability,
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
    let (_, run) = reference_run(&which, 0.2, 1);
    let cfg = monitor_config::<3>(&mech).unwrap();
    let mut m = Monitor::new(&cfg).unwrap();
    for (i, s) in samples::<3>(&run).unwrap().iter().enumerate() {
        let st = m.update(s);
        let until: usize = std::env::var("N").ok().and_then(|v| v.parse().ok()).unwrap_or(60);
        if i > until { break; }
        if i % std::env::var("EVERY").ok().and_then(|v| v.parse().ok()).unwrap_or(1usize) != 0 { continue; }
        let o = m.observer(jj).unwrap();
        let k = m.rate_filter(jj).unwrap();
        println!("{:5.2} q{:8.3} w{:8.4}±{:7.4} a{:7.3} r{:6.3} y{:?} rv{:.2e} C{:.3}±{:.3}", st.t_s, k.jerk_psd(), k.rate(), k.rate_var().sqrt(), k.acceleration(), o.disturbance_nm(), o.regressors(), o.residual_var(), st.joints[jj].coulomb_nm, st.joints[jj].coulomb_sd_nm);
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
            .flat_map(|s| s.joints.iter().enumerate().filter(|(_, j)| j.prediction == Prediction::Stall).map(move |(j, js)| format!("{:.2}:j{} {:.2} m{:.0}", s.t_s, j + 1, js.latch_probability, js.margin_pct.unwrap_or(0.0))))
            .collect();
        line += &format!(" stall-preds {stalls:?}");
        let (_, run2) = simulate_run(&mech2, &coulomb(&SEED001_FRICTION), seed);
        let cfg2 = monitor_config::<3>(&mech2).unwrap();
        let st2 = replay(&cfg2, &run2);
        let first = st2.iter().position(|s| s.joints[0].prediction == Prediction::Stall).map(|i| st2[i].t_s);
        let at05 = st2.iter().find(|s| s.t_s >= 0.5).map(|s| (s.joints[0].coulomb_nm, s.joints[0].coulomb_sd_nm, s.joints[0].latch_probability));
        line += &format!(" | T02 first stall {first:?} at0.5 {at05:?}");
        println!("{line}");
    }
}
