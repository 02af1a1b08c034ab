//! A campaign is never worse than its runs alone.

use super::*;

/// A campaign answer is never worse than the answers of its runs
/// taken alone. Two causes (rig tilt and Coulomb friction at joint 1) on
/// seed 001 T01 + T02: when each run alone is explained to the noise, the
/// two runs together must be too, with the same causes.
#[test]
fn a_campaign_is_never_worse_than_its_runs_alone() {
    for seed in [7u64, 8, 9] {
        let truth = vec![
            Effect {
                joint: None,
                law: Law::RigTilt {
                    g_m_s2: 0.05,
                    alpha_deg: 30.0,
                },
            },
            Effect::joint(EffectKind::CoulombFriction, 1, 0.8),
        ];
        let case = Case {
            pair: 0,
            runs: simulate_runs(&mechanisms(0), &truth, seed),
            truth,
        };
        let alone: Vec<_> = (0..2)
            .map(|r| {
                diagnose(
                    &campaign_of(&case, |i| i == r),
                    &deploywatch_tests::diagnose_options(),
                    &quiet,
                )
            })
            .collect();
        let both = diagnose(
            &campaign_of(&case, |_| true),
            &deploywatch_tests::diagnose_options(),
            &quiet,
        );
        let names = |o: &deploywatch_sim::diagnose::Outcome| {
            let mut k: Vec<_> = o.extended.effects().iter().map(key).collect();
            k.sort();
            k
        };
        println!(
            "seed {seed}: alone {:?} / {:?}, together {:?} (RMS {:.4})",
            names(&alone[0]),
            names(&alone[1]),
            names(&both),
            both.extended.rms()
        );
        let worst_alone = alone.iter().map(|o| o.extended.rms()).fold(0.0, f64::max);
        if alone.iter().all(|o| o.unexplained.is_none()) {
            assert!(
                both.unexplained.is_none(),
                "seed {seed}: {:?}",
                both.unexplained.as_ref().map(ToString::to_string)
            );
            assert!(both.extended.rms() <= 1.2 * worst_alone);
        }
        let mut want: Vec<_> = case.truth.iter().map(key).collect();
        want.sort();
        assert_eq!(names(&both), want, "seed {seed}");
    }
}
