//! The residual torque from the data (`analysis::residual_torque`) against
//! the baseline: on hidden campaigns (`deploywatch_tests::hidden_torque`)
//! the joints that hold a hidden torque show a significant residual torque,
//! and on null campaigns no joint does. (Against a baseline far from the
//! truth, a joint beside a large hidden torque may show one too: the
//! diagnosis re-estimates it beside each table it takes.) The test sees the
//! truth only after the estimate.

use deploywatch_sim::campaign::Campaign;
use deploywatch_sim::effect::EffectKind;
use deploywatch_sim::residual_torque::residual_torque;
use deploywatch_tests::hidden_torque::{case, mechanisms, Case, Family};
use std::path::Path;

fn campaign_of(c: &Case) -> Campaign {
    let mut campaign = Campaign::default();
    let mechs = mechanisms(c.pair);
    for (r, run) in c.runs.iter().enumerate() {
        campaign
            .push(&mechs, run.clone(), Path::new(&format!("run{r}.csv")))
            .unwrap();
    }
    campaign
}

/// (every hidden torque's joint significant, no significant joint on a
/// null campaign).
fn judge(c: &Case) -> (bool, bool) {
    let campaign = campaign_of(c);
    let res = residual_torque(&campaign, &[]);
    // Only now the truth: joints that hold anything per-joint.
    let tables: Vec<usize> = c
        .truth
        .iter()
        .filter(|e| e.kind() == EffectKind::TorqueTable)
        .filter_map(|e| e.joint)
        .collect();
    for jt in &res {
        println!("  {}", jt.describe());
    }
    let found = tables
        .iter()
        .all(|j| res.iter().any(|r| r.joint == *j && r.significant));
    let clean = !c.truth.is_empty() || res.iter().all(|r| !r.significant);
    (found, clean)
}

#[test]
fn residual_torque_is_significant_where_a_torque_is_hidden_and_nowhere_else() {
    let families = [
        Family::Alone(0),
        Family::Alone(1),
        Family::Alone(2),
        Family::Alone(3),
        Family::TwoJoints,
        Family::Null,
    ];
    let per = if std::env::var_os("DEPLOYWATCH_FULL").is_some() {
        6
    } else {
        2
    };
    let (mut found, mut clean, mut nulls, mut with_torque) = (0, 0, 0, 0);
    for f in families {
        for k in 0..per {
            let c = case(f, k);
            println!(
                "{} {k}: truth {:?}",
                f.name(),
                c.truth
                    .iter()
                    .map(|e| format!("{}@{:?}", e.kind(), e.joint))
                    .collect::<Vec<_>>()
            );
            let (a, b) = judge(&c);
            if f == Family::Null {
                nulls += 1;
                clean += usize::from(b);
            } else {
                with_torque += 1;
                found += usize::from(a);
            }
        }
    }
    println!(
        "against the baseline: every hidden torque's joint significant in {found}/{with_torque}; null campaigns with no significant joint {clean}/{nulls}"
    );
    assert!(found * 10 >= with_torque * 6, "{found}/{with_torque}");
    assert_eq!(clean, nulls, "a significant joint on a null campaign");
}
