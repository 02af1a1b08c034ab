//! The switch faults of the fault campaign (chatter, stuck open, stuck
//! closed) on the ideal runs, with the physical latch configured.

use super::*;

/// The switch faults of the fault campaign on the ideal runs, with the
/// physical latch configured: flagged, no early latch, no latch undone.
fn switch_faults<const N: usize>(name: &str, tally: &mut Tally) {
    let mech = mechanism(name);
    let cfg = physical_config::<N>(&mech);
    let traj = simulate_ideal(&mech, 1.0);
    for seed in 1..=3u64 {
        let target = ((seed as usize - 1) % N) + 1;
        let faults = [
            SensorFault::SwitchChatter {
                joint: target,
                bounce_s: 0.02,
            },
            SensorFault::SwitchStuck {
                joint: target,
                closed: false,
            },
            SensorFault::SwitchStuck {
                joint: target,
                closed: true,
            },
        ];
        let clean = measure(&traj, &[], &SensorModel::REFERENCE, seed);
        let st = replay(&cfg, &clean);
        if st.iter().any(|s| !s.is_clean()) {
            tally
                .failures
                .push(format!("{name} seed {seed}: flags on the clean run"));
        }
        for fault in faults {
            let mut run = clean.clone();
            let touched: usize = apply(&mut run, &[fault], seed)
                .expect("fault")
                .iter()
                .map(|r| r.samples)
                .sum();
            let st = replay(&cfg, &run);
            tally.runs += 1;
            let label = format!("{name} seed {seed} {fault}");
            if touched > 0 && st.iter().all(|s| s.is_clean()) {
                tally.failures.push(format!("{label}: not flagged"));
            }
            for j in 0..N {
                let mut seen = false;
                for (i, s) in st.iter().enumerate() {
                    let latched = s.joints[j].latch == LatchState::Latched;
                    if latched && !traj.latched[j][i] {
                        tally.failures.push(format!(
                            "{label}: joint {} declared early at {:.3} s",
                            j + 1,
                            s.t_s
                        ));
                        break;
                    }
                    if seen && !latched {
                        tally.failures.push(format!(
                            "{label}: joint {} latch lost at {:.3} s",
                            j + 1,
                            s.t_s
                        ));
                        break;
                    }
                    seen |= latched;
                }
                let truly = traj.latch_s[j].is_some();
                if seen != truly {
                    tally.failures.push(format!(
                        "{label}: joint {} latched {seen}, truly {truly}",
                        j + 1
                    ));
                }
            }
        }
    }
}

#[test]
fn switch_faults_still_found_with_the_physical_latch() {
    let mut tally = Tally::default();
    switch_faults::<3>("seed001_T01", &mut tally);
    switch_faults::<3>("seed001_T02", &mut tally);
    switch_faults::<2>("seed000_case1", &mut tally);
    switch_faults::<2>("seed000_case3", &mut tally);
    println!(
        "switch faults with the physical latch: {} faulted runs, {} failures",
        tally.runs,
        tally.failures.len()
    );
    for f in &tally.failures {
        println!("FAIL {f}");
    }
    assert!(
        tally.failures.is_empty(),
        "{} failures",
        tally.failures.len()
    );
}
