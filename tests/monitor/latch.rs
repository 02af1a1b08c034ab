//! The latch declarations on the reference mechanisms: within 30 ms of the true latch, never before.

use super::*;

/// Latch declarations on the four reference mechanisms, nominal and with
/// the papers' friction: within 30 ms after the true latch instant and never
/// before it; never for a joint that does not latch.
fn check_latch_timing<const N: usize>(name: &str, friction: &[f64]) {
    let mech = mechanism(name);
    let cfg = monitor_config::<N>(&mech).unwrap();
    for effects in [Vec::new(), coulomb(friction)] {
        for seed in 1..=3 {
            let (traj, run) = simulate_run(&mech, &effects, seed);
            let st = replay(&cfg, &run);
            for j in 0..N {
                let declared = st
                    .iter()
                    .find(|s| s.joints[j].latch == LatchState::Latched)
                    .map(|s| s.t_s as f64);
                match (traj.latch_s[j], declared) {
                    (Some(t), Some(d)) => {
                        println!("{name} friction {} seed {seed} joint {}: latch {t:.4} s, declared {d:.4} s (+{:.1} ms)", !effects.is_empty(), j + 1, 1e3 * (d - t));
                        assert!(
                            d >= t - 1e-6,
                            "{name} joint {}: declared at {d} before the latch at {t}",
                            j + 1
                        );
                        assert!(
                            d <= t + 0.030 + 1e-6,
                            "{name} joint {}: declared at {d}, latch at {t}",
                            j + 1
                        );
                    }
                    (None, None) => {}
                    (t, d) => panic!(
                        "{name} friction {} seed {seed} joint {}: latch {t:?}, declared {d:?}",
                        !effects.is_empty(),
                        j + 1
                    ),
                }
            }
        }
    }
}

#[test]
fn latched_within_30_ms_of_the_latch_never_before_never_falsely() {
    check_latch_timing::<2>("seed000_case1", &[0.54, 0.472]);
    check_latch_timing::<2>("seed000_case3", &[0.54, 0.472]);
    check_latch_timing::<3>("seed001_T01", &SEED001_FRICTION);
    check_latch_timing::<3>("seed001_T02", &SEED001_FRICTION);
}
