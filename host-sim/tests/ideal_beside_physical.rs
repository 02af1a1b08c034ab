//! Ideal latches beside a physical one on the six-panel wing: the ball
//! plunger and magnet of `wing6_mixed.toml`'s joint 5 put at joint 3 or 6
//! of `wing6_ideal.toml`, the other joints' latches ideal. Every ideal
//! joint that reaches its latch angle latches there: from its latch instant
//! on the switch is closed and the angle 0, never past it, and a joint with
//! no latch instant never reaches 0 (`docs/spec/physics.md` §5) — nominal
//! and with extra friction at a joint (the issue-38 wing's "NOT latched at
//! 0.00 deg" came from such a run).

use deploywatch_sim::deployment::{simulate, SimOptions, Trajectory};
use deploywatch_sim::effect::{Effect, EffectKind};
use deploywatch_sim::mechanism::Mechanism;
use std::path::PathBuf;

fn data() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../data/mechanisms")
}

/// `wing6_ideal.toml` with `wing6_mixed.toml`'s joint-5 latch table (the
/// ball plunger and magnet) at joint `j` (1-based).
fn wing(j: usize) -> Mechanism {
    let ideal = std::fs::read_to_string(data().join("wing6_ideal.toml")).expect("wing6_ideal");
    let mixed = std::fs::read_to_string(data().join("wing6_mixed.toml")).expect("wing6_mixed");
    // The plunger's table: the second `[joint.latch]` of the mixed wing.
    let start = mixed
        .match_indices("[joint.latch]")
        .nth(1)
        .expect("plunger")
        .0;
    let end = mixed[start..]
        .find("\n\n")
        .map_or(mixed.len(), |e| start + e);
    let table = &mixed[start..end];
    assert!(table.contains("plunger"), "{table}");
    let mut parts: Vec<String> = ideal.split("[[joint]]").map(str::to_string).collect();
    assert_eq!(parts.len(), 7, "six joints");
    let body = &parts[j];
    let cut = body.find("\n\n").expect("joint's keys end");
    parts[j] = format!("{}\n\n{table}\n{}", &body[..cut], &body[cut..]);
    let text = parts.join("[[joint]]");
    Mechanism::from_toml_str(&text, &format!("wing6_plunger_at_{j}.toml")).expect("wing parses")
}

/// The ideal joint `j` (0-based) of `traj`: latched at 0 from its latch
/// instant on, never past its latch, and never at 0 without one.
fn check_ideal(mech: &Mechanism, traj: &Trajectory, j: usize, what: &str) {
    let side = mech.joints[j].stowed_deg.signum();
    let phi = &traj.phi_deg[j];
    let past = phi.iter().map(|p| -side * p).fold(f64::MIN, f64::max);
    assert!(
        past <= 1e-6,
        "{what}: joint {} passes its latch by {past} deg",
        j + 1
    );
    match traj.latch_s[j] {
        Some(t) => {
            for (i, &ts) in traj.t_s.iter().enumerate() {
                if ts >= t + 1e-9 {
                    assert!(traj.latched[j][i], "{what}: joint {} open at {ts} s", j + 1);
                    assert!(
                        phi[i].abs() <= 1e-6,
                        "{what}: joint {} at {} deg",
                        j + 1,
                        phi[i]
                    );
                }
            }
        }
        None => {
            let closest = phi.iter().map(|p| p.abs()).fold(f64::MAX, f64::min);
            assert!(
                closest > 1e-3,
                "{what}: joint {} reaches its latch ({closest} deg) and is not latched",
                j + 1
            );
            assert!(
                traj.latched[j].iter().all(|l| !l),
                "{what}: switch without a latch"
            );
        }
    }
}

#[test]
fn ideal_joints_beside_a_plunger_at_joint_3_or_6_latch_where_they_reach_their_latch() {
    let opts = SimOptions::default();
    for j in [3, 6] {
        let mech = wing(j);
        assert!(mech.latches[j - 1].is_some(), "joint {j}: the plunger");
        for extra in [None, Some((2, 0.2)), Some((4, 0.5)), Some((1, 1.2))] {
            let effects: Vec<Effect> = extra
                .map(|(k, v)| Effect::joint(EffectKind::CoulombFriction, k, v))
                .into_iter()
                .collect();
            let what = format!("plunger at joint {j}, extra friction {extra:?}");
            let traj = simulate(&mech, &effects, &opts).unwrap_or_else(|e| panic!("{what}: {e}"));
            let ideal = (0..6).filter(|&k| k != j - 1);
            for k in ideal {
                check_ideal(&mech, &traj, k, &what);
            }
            let latched = (0..6).filter(|&k| traj.latch_s[k].is_some()).count();
            assert_eq!(latched, 6, "{what}: every joint latches on this wing");
        }
    }
}
