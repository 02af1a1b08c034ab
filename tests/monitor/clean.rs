//! Clean runs raise no fault flag: the reference and example runs, Monte-Carlo at 100 Hz and 1 kHz.

use super::*;

/// Fault flags raised over a replay: (samples with a flag, the flags' names
/// with the first time and joint each was seen).
fn flags_raised<const N: usize>(st: &[Status<N>]) -> (usize, Vec<String>) {
    let mut count = 0;
    let mut seen: Vec<String> = Vec::new();
    for s in st {
        for (j, js) in s.joints.iter().enumerate() {
            if js.faults.is_empty() {
                continue;
            }
            count += 1;
            let name = js.faults.to_string();
            if !seen.iter().any(|x| x.starts_with(&name)) {
                seen.push(format!("{name} (first at {:.3} s, joint {})", s.t_s, j + 1));
            }
        }
    }
    (count, seen)
}

/// Replays `run` with the monitor of `mech` and asserts no fault flag.
fn assert_clean<const N: usize>(label: &str, mech: &Mechanism, run: &Run) {
    let cfg = monitor_config::<N>(mech).unwrap();
    let st = replay(&cfg, run);
    let (count, seen) = flags_raised(&st);
    assert_eq!(count, 0, "{label}: fault flags on a clean run: {seen:?}");
}

/// Every bundled reference and example run (no fault injected) replays
/// without a single fault flag: a flight monitor that cries wolf on every
/// deployment is ignored.
#[test]
fn clean_reference_and_example_runs_raise_no_fault_flag() {
    let data = data_dir();
    let mut files = Vec::new();
    for dir in [
        "reference",
        "examples/a_seed001_eft",
        "examples/b_seed000_eft_air_drag",
        "examples/c_seed001_friction_harness",
        "examples/wing4",
        "examples/wing6",
    ] {
        for e in std::fs::read_dir(data.join(dir)).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "csv") {
                files.push(p);
            }
        }
    }
    files.sort();
    assert!(files.len() >= 18, "{files:?}");
    for p in &files {
        let run = Run::load(p).unwrap();
        let name = run.mechanism().unwrap().replace('-', "_");
        let name = name.trim_end_matches("_open");
        let mech = mechanism(name);
        let label = p.display().to_string();
        match mech.joint_count() {
            2 => assert_clean::<2>(&label, &mech, &run),
            3 => assert_clean::<3>(&label, &mech, &run),
            4 => assert_clean::<4>(&label, &mech, &run),
            6 => assert_clean::<6>(&label, &mech, &run),
            n => panic!("{label}: {n} joints"),
        }
        println!("{label}: no fault flag");
    }
}

/// Clean Monte-Carlo runs (the friction and spring scatter of
/// [`monte_carlo_prediction_at_half_stroke`], reference sensor, no fault)
/// at `sample_hz`: no fault flag in any status, and every latch declared
/// within 30 ms after the switch closes, never before. The runs go on for
/// [`HOLD_S`] (the `settle_s` of `formats.md`) after the last latch.
fn clean_monte_carlo(sample_hz: f64, runs: usize, draws: u64, sensor: u64) {
    let mut mech = mechanism("seed001_T01");
    mech.sample_hz = sample_hz;
    let cfg = monitor_config::<3>(&mech).unwrap();
    let mut rng = SplitMix(draws);
    let (mut flagged, mut latches, mut worst_ms) = (0, 0, 0.0f64);
    for k in 0..runs {
        let effects = scatter(&mut rng);
        let seed = sensor + k as u64;
        // formats.md: a run goes on for settle_s after the last latch, or
        // ends at duration_s when a joint never latches.
        let mut traj = simulate_truth(&mech, &effects);
        if traj.latch_s.iter().all(Option::is_some) {
            hold_at_rest(&mut traj, HOLD_S, 1.0 / mech.sample_hz);
        }
        let run = measure(&traj, &[], &SensorModel::REFERENCE, seed);
        let st = replay(&cfg, &run);
        let (count, seen) = flags_raised(&st);
        if count > 0 {
            flagged += 1;
            println!("{sample_hz} Hz seed {seed}: {count} flagged statuses: {seen:?}");
        }
        for j in 0..3 {
            let declared = st
                .iter()
                .find(|s| s.joints[j].latch == LatchState::Latched)
                .map(|s| s.t_s as f64);
            // The switch closes at the first sample at or after the latch.
            let switch =
                traj.latch_s[j].and_then(|t| run.t_s.iter().copied().find(|&s| s >= t - 1e-9));
            match (switch, declared) {
                (Some(t), Some(d)) => {
                    latches += 1;
                    worst_ms = worst_ms.max(1e3 * (d - t));
                    assert!(d >= t - 1e-6, "{sample_hz} Hz seed {seed} joint {}: declared at {d} before the switch at {t}", j + 1);
                    assert!(
                        d <= t + 0.030 + 1e-6,
                        "{sample_hz} Hz seed {seed} joint {}: declared at {d}, switch at {t}",
                        j + 1
                    );
                }
                (None, None) => {}
                (t, d) => panic!(
                    "{sample_hz} Hz seed {seed} joint {}: switch {t:?}, declared {d:?}",
                    j + 1
                ),
            }
        }
    }
    println!("{sample_hz} Hz: {runs} clean runs, {flagged} with a fault flag; {latches} latches declared, the latest {worst_ms:.1} ms after the switch");
    assert_eq!(
        flagged, 0,
        "{sample_hz} Hz: {flagged}/{runs} clean runs raised a fault flag"
    );
}

/// 200 clean Monte-Carlo runs at 100 Hz: zero fault flags, latches declared
/// within 30 ms of the switch. Rerun with `cargo test -p deploywatch-tests
/// --test monitor clean_monte_carlo -- --nocapture`.
#[test]
fn clean_monte_carlo_at_100_hz_raises_no_fault_flag() {
    clean_monte_carlo(100.0, MC_RUNS, 2024, 1000);
}

/// The same at 1 kHz.
#[test]
fn clean_monte_carlo_at_1_khz_raises_no_fault_flag() {
    clean_monte_carlo(1000.0, MC_RUNS, 7, 5000);
}
