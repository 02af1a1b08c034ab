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

/// Simulates the whole `duration_s` (not stopping at the last latch, so that
/// the monitor sees samples after it) and measures it with the reference
/// sensor.
fn run(mech: &Mechanism, effects: &[Effect], seed: u64) -> (Trajectory, Run) {
    let opts = SimOptions {
        stop_when_deployed: false,
        ..SimOptions::default()
    };
    let traj = simulate(mech, effects, &opts).expect("simulation");
    let run = measure(&traj, &[], &SensorModel::REFERENCE, seed);
    (traj, run)
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
    let sensor = if std::env::var("IDEAL").is_ok() { SensorModel::IDEAL } else { SensorModel::REFERENCE };
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
        run(&mech, &coulomb(&fr), 1)
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
                " | {:8.2} {:7.2}({:6.1}) C{:5.2}±{:4.2} v{:5.3} r{:6.2} {:9} {:?}/{:4.2} m{:6.0} ttl{:5.2}",
                js.phi_deg,
                js.rate_deg_s,
                traj.rate_deg_s[j][i],
                js.coulomb_nm,
                js.coulomb_sd_nm,
                js.viscous_nms,
                js.friction_torque_nm,
                js.latch.as_str(),
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
fn diag_sim() {
    let mech = mechanism("seed001_T01");
    for stop in [true, false] {
        let opts = SimOptions { stop_when_deployed: stop, ..SimOptions::default() };
        let traj = simulate(&mech, &coulomb(&SEED001_FRICTION), &opts).unwrap();
        println!("stop={stop} latch_s {:?} end {}", traj.latch_s, traj.end_s);
    }
}
