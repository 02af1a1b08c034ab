//! Light wings: panels of 0.6 kg and 0.3 m on linear springs (2 N·m at the
//! root down to 0.3 N·m at the tip), ideal latches, 0.03 N·m of friction.
//! They deploy in about a second, the outer joints at up to 2,000°/s, and
//! each latch's impulse throws the neighbours: the rollout's base step has
//! to follow that (`docs/monitor.md` §6, "The base step"), and the rate
//! filters must take a neighbour's impact and the whip before a latch as
//! motion (§6.2). Rerun with `cargo test -p deploywatch-tests --test
//! monitor light_wing -- --nocapture`.

use super::*;

/// A light wing of `panels` panels sampled at `sample_hz`.
fn light_wing(panels: usize, sample_hz: f64) -> Mechanism {
    let mut t = format!("name = \"light-{panels}\"\n");
    for _ in 0..panels {
        t += "[[panel]]\nlength_m = 0.3\nmass_kg = 0.6\ncom_m = 0.15\ninertia_kgm2 = 0.0045\n";
    }
    for k in 0..panels {
        let stowed = match k {
            0 => -90.0,
            _ if k % 2 == 1 => 180.0,
            _ => -180.0,
        };
        let preload = 2.05 - 0.25 * k as f64;
        t += &format!(
            "[[joint]]\nstowed_deg = {stowed}\nspring = {{ kind = \"linear\", preload_nm = {preload}, \
             stiffness_nm_per_rad = 0.2, count = 1 }}\nfriction = {{ coulomb_nm = 0.03 }}\n"
        );
    }
    t += &format!("[run]\nduration_s = 10.0\nsample_hz = {sample_hz}\n");
    Mechanism::from_toml_str(&t, "light.toml").expect("light wing")
}

/// Worst error of the predicted latch times against the simulation over
/// the starts every 50 ms until the last latch, of each joint not latched
/// at the start \[s\] (infinite when a joint's outcome is wrong).
fn rollout_errors<const N: usize>(mech: &Mechanism) -> Vec<f64> {
    let traj = simulate_truth(mech, &[]);
    let last = traj
        .latch_s
        .iter()
        .map(|t| t.expect("every joint latches"))
        .fold(0.0, f64::max);
    let every = (0.05 * mech.sample_hz).round() as usize;
    let mut worst = Vec::new();
    for i in (every..traj.t_s.len()).step_by(every) {
        if traj.t_s[i] >= last {
            break;
        }
        let cfg = monitor_config::<N>(mech).unwrap();
        let coulomb = std::array::from_fn(|q| mech.joints[q].friction.coulomb_nm as f32);
        let predicted = rollout_latches(&cfg, cfg.margin.rollout, &traj, i, coulomb, [1.0; N]);
        let w = predicted
            .iter()
            .zip(&traj.latch_s)
            .enumerate()
            .filter(|(q, _)| !traj.latched[*q][i])
            .map(|(_, (p, t))| p.map_or(f64::INFINITY, |p| (p - t.unwrap()).abs()))
            .fold(0.0f64, f64::max);
        worst.push(w);
    }
    worst
}

// doc-figures: not measured (the test's limits)
/// From the true state every 50 ms, the rollout predicts every joint of
/// the 6-, 7- and 8-panel light wings to latch within 0.1 s of the
/// simulation, the median of the worst errors within 30 ms. (A fixed 20 ms
/// step turns each joint by up to 8° a step and spreads joint 1's latch
/// time of the 8-panel wing over 0.65–2.6 s for 1.38 s.)
#[test]
fn a_light_wing_rollout_from_the_truth_keeps_its_latch_times() {
    for panels in 6..=8 {
        let mech = light_wing(panels, 100.0);
        let mut worst = match panels {
            6 => rollout_errors::<6>(&mech),
            7 => rollout_errors::<7>(&mech),
            _ => rollout_errors::<8>(&mech),
        };
        worst.sort_by(f64::total_cmp);
        let (median, max) = (worst[worst.len() / 2], worst[worst.len() - 1]);
        println!(
            "{panels} panels: {} starts, worst latch-time error median {median:.3} s, max {max:.3} s",
            worst.len()
        );
        assert!(max <= 0.1, "{panels} panels: a latch time {max:.3} s off");
        assert!(
            median <= 0.03,
            "{panels} panels: median of the worst errors {median:.3} s"
        );
    }
}

/// Clean runs of the light wings of 2 to 8 panels at 100 Hz and 1 kHz
/// (reference sensor, two sensor seeds): no fault flag, and no joint, all
/// of which latch, ever predicted to stall.
#[test]
fn clean_runs_of_light_wings_raise_no_flag_and_predict_no_stall() {
    for panels in 2..=8 {
        for sample_hz in [100.0, 1000.0] {
            let mech = light_wing(panels, sample_hz);
            for seed in 1..=2 {
                let (traj, run) = simulate_run(&mech, &[], seed);
                assert!(traj.latch_s.iter().all(Option::is_some), "{panels} panels");
                let (flags, stalls) = match panels {
                    2 => clean_replay::<2>(&mech, &run),
                    3 => clean_replay::<3>(&mech, &run),
                    4 => clean_replay::<4>(&mech, &run),
                    5 => clean_replay::<5>(&mech, &run),
                    6 => clean_replay::<6>(&mech, &run),
                    7 => clean_replay::<7>(&mech, &run),
                    _ => clean_replay::<8>(&mech, &run),
                };
                let label = format!("{panels} panels, {sample_hz} Hz, sensor seed {seed}");
                assert!(
                    flags.is_empty(),
                    "{label}: fault flags on a clean run: {flags:?}"
                );
                assert!(stalls.is_empty(), "{label}: a stall predicted: {stalls:?}");
                println!("{label}: no flag, no stall predicted");
            }
        }
    }
}

/// The fault flags raised on `run` and the stall (or ramp-stop)
/// predictions made, each as (time, joint, what).
fn clean_replay<const N: usize>(mech: &Mechanism, run: &Run) -> (Vec<String>, Vec<String>) {
    let st = replay(&monitor_config::<N>(mech).unwrap(), run);
    let (mut flags, mut stalls) = (Vec::new(), Vec::new());
    for s in &st {
        for (j, js) in s.joints.iter().enumerate() {
            if !js.faults.is_empty() {
                flags.push(format!("{:.3} s joint {}: {}", s.t_s, j + 1, js.faults));
            }
            if matches!(js.prediction, Prediction::Stall | Prediction::RampStop) {
                stalls.push(format!("{:.3} s joint {}: {}", s.t_s, j + 1, js.prediction));
            }
        }
    }
    (flags, stalls)
}
