//! Tests of the input checks of measured runs against their mechanism.
use super::*;
use std::path::PathBuf;

fn data(p: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../data")
        .join(p)
}

fn t01() -> (Run, Mechanism) {
    let run = Run::load(&data("examples/c_seed001_friction_harness/seed001_T01.csv")).unwrap();
    let m = Mechanism::load(&data("mechanisms/seed001_T01.toml")).unwrap();
    (run, m)
}

#[test]
fn the_bundled_run_has_no_finding() {
    let (run, m) = t01();
    assert_eq!(check(&run, &m, "r.csv").unwrap(), Vec::<String>::new());
}

#[test]
fn radians_are_told_from_one_corrupted_first_reading() {
    let (mut run, m) = t01();
    for x in run.phi_deg[0].iter_mut() {
        *x = x.to_radians();
    }
    let e = check(&run, &m, "r.csv").unwrap_err();
    assert!(
        matches!(e.kind, RunErrorKind::AnglesInRadians { joint: 1, .. }),
        "{e}"
    );
    // A spike at the first sample of a healthy run decides nothing.
    let (mut run, m) = t01();
    run.phi_deg[0][0] = 90.0;
    assert_eq!(check(&run, &m, "r.csv").unwrap(), Vec::<String>::new());
}

#[test]
fn a_run_sampled_at_2_hz_starts_where_it_starts() {
    // Every 50th sample of the 100 Hz run: five samples span 2 s of
    // the deployment, their median far from the stowed pose.
    let (run, m) = t01();
    let keep = |v: &[f64]| v.iter().step_by(50).copied().collect::<Vec<f64>>();
    let slow = Run {
        t_s: keep(&run.t_s),
        phi_deg: run.phi_deg.iter().map(|p| keep(p)).collect(),
        latch: run
            .latch
            .iter()
            .map(|l| l.iter().step_by(50).copied().collect())
            .collect(),
        ..run.clone()
    };
    assert!(slow.len() < 10);
    assert_eq!(check(&slow, &m, "r.csv").unwrap(), Vec::<String>::new());
}

#[test]
fn angles_counted_from_the_stowed_pose_are_told() {
    let (mut run, m) = t01();
    for (j, joint) in m.joints.iter().enumerate() {
        for x in run.phi_deg[j].iter_mut() {
            *x -= joint.stowed_deg;
        }
    }
    let e = check(&run, &m, "r.csv").unwrap_err();
    assert!(
        matches!(e.kind, RunErrorKind::AnglesFromStowed { joint: 1, .. }),
        "{e}"
    );
}

#[test]
fn angles_a_whole_turn_off_are_told_not_taken_for_a_mirrored_encoder() {
    let (mut run, m) = t01();
    for x in run.phi_deg[0].iter_mut() {
        *x += 360.0;
    }
    let e = check(&run, &m, "r.csv").unwrap_err();
    assert!(
        matches!(
            e.kind,
            RunErrorKind::AnglesWholeTurnsOff { joint: 1, turns, .. } if turns == 1.0
        ),
        "{e}"
    );
}

#[test]
fn a_start_far_from_the_stowed_angle_is_a_warning_within_it_none() {
    let (mut run, m) = t01();
    for x in run.phi_deg[0].iter_mut() {
        *x += 25.0;
    }
    let w = check(&run, &m, "r.csv").unwrap();
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("phi1_deg") && w[0].contains("stowed"),
        "{w:?}"
    );
    // An encoder offset of a few degrees is the diagnosis's business.
    let (mut run, m) = t01();
    for x in run.phi_deg[0].iter_mut() {
        *x += 3.0;
    }
    assert_eq!(check(&run, &m, "r.csv").unwrap(), Vec::<String>::new());
}

#[test]
fn a_failed_deployment_whose_latch_never_closes_is_no_finding() {
    // A bundled T02 run: joints 1 and 2 do not latch.
    let run = Run::load(&data("examples/a_seed001_eft/seed001_T02.csv")).unwrap();
    let m = Mechanism::load(&data("mechanisms/seed001_T02.toml")).unwrap();
    assert_eq!(run.latch[0].last(), Some(&false));
    assert_eq!(check(&run, &m, "r.csv").unwrap(), Vec::<String>::new());
}

/// Joint 1's switch opens at sample `from` for `open` samples and its
/// reading walks off the stop by `walk` deg over them.
fn opened(run: &mut Run, from: usize, open: usize, walk: f64) {
    let stop = run.phi_deg[0][from];
    for k in from..(from + open).min(run.len()) {
        run.latch[0][k] = false;
        run.phi_deg[0][k] = stop - walk * (k + 1 - from) as f64 / open as f64;
    }
}

/// `run` held at its last sample for `n` samples more, latched.
fn held_on(mut run: Run, n: usize) -> Run {
    let dt = run.t_s[1] - run.t_s[0];
    for _ in 0..n {
        let t = run.t_s[run.len() - 1] + dt;
        run.t_s.push(t);
        for p in run.phi_deg.iter_mut() {
            p.push(p[p.len() - 1]);
        }
        for l in run.latch.iter_mut() {
            l.push(l[l.len() - 1]);
        }
    }
    run
}

#[test]
fn a_latch_that_lets_go_is_said_and_a_chatter_is_not() {
    let (run, m) = t01();
    let run = held_on(run, 100);
    let closed = run.latch[0].iter().position(|&l| l).unwrap();
    let from = closed + 50;
    let mut gone = run.clone();
    let rest = gone.len() - from;
    opened(&mut gone, from, rest, 8.0);
    let g = let_go(&gone, 0).expect("let go");
    assert_eq!((g.closed, g.opened), (closed, from));
    assert!((g.left_deg - 8.0).abs() < 0.1, "{g:?}");
    let w = check(&gone, &m, "r.csv").unwrap();
    let line = format!("r.csv:{}: column `latch1`", line_of_sample(&gone, from));
    assert!(
        w.len() == 1 && w[0].starts_with(&line) && w[0].contains("let go"),
        "{w:?}"
    );
    // Two samples open with the panel 2 deg off, then closed again: a
    // chatter; five open with the panel on its stop: no letting go.
    let mut chatter = run.clone();
    opened(&mut chatter, from, LET_GO_SAMPLES - 1, 2.0);
    let mut on_stop = run.clone();
    opened(&mut on_stop, from, 5, 0.05);
    for r in [&chatter, &on_stop] {
        assert_eq!(let_go(r, 0), None);
        assert_eq!(check(r, &m, "r.csv").unwrap(), Vec::<String>::new());
    }
}

#[test]
fn a_gap_longer_than_a_tenth_of_the_duration_is_said() {
    let (run, m) = t01();
    // 0.7 s of samples lost at 1 s (duration_s 6 s).
    let keep: Vec<usize> = (0..run.len())
        .filter(|&i| !(100..170).contains(&i))
        .collect();
    let pick = |v: &[f64]| keep.iter().map(|&i| v[i]).collect::<Vec<f64>>();
    let gap = Run {
        t_s: pick(&run.t_s),
        phi_deg: run.phi_deg.iter().map(|p| pick(p)).collect(),
        latch: run
            .latch
            .iter()
            .map(|l| keep.iter().map(|&i| l[i]).collect())
            .collect(),
        ..run.clone()
    };
    let w = check(&gap, &m, "r.csv").unwrap();
    assert!(
        w.len() == 1 && w[0].contains("no sample for 0.7100 s, from t = 0.99 s to t = 1.7 s"),
        "{w:?}"
    );
}

#[test]
fn an_encoder_that_wraps_at_180_deg_is_told_at_its_line() {
    // Joint 2 of T01 is stowed at 180 deg: two readings written -180.
    let (mut run, m) = t01();
    let i = run.phi_deg[1].iter().position(|&x| x > 179.9).unwrap() + 2;
    run.phi_deg[1][i] -= 360.0;
    let e = check(&run, &m, "r.csv").unwrap_err();
    assert!(
        matches!(e.kind, RunErrorKind::AnglesWrap { joint: 2, .. }),
        "{e}"
    );
    assert!(
        e.to_string()
            .contains(&format!("r.csv:{}:", line_of_sample(&run, i))),
        "{e}"
    );
}

#[test]
fn a_mirrored_encoder_at_180_deg_is_refused_once_the_joint_has_moved() {
    // Joint 2 of T01 is stowed at 180 deg: mirrored, it reads -180 and
    // moves towards 0 through negative readings, never jumping a turn.
    let (mut run, m) = t01();
    for x in run.phi_deg[1].iter_mut() {
        *x = -*x;
    }
    let e = check(&run, &m, "r.csv").unwrap_err();
    assert!(
        matches!(e.kind, RunErrorKind::MirroredEncoder { joint: 2, .. }),
        "{e}"
    );
    // Before it has moved 10 deg, -180 is the stowed pose as an encoder
    // wrapping at ±180 deg reads it: a warning.
    let (mut run, m) = t01();
    let k = run.phi_deg[1]
        .iter()
        .position(|&x| x < 175.0)
        .expect("joint 2 moves");
    run.truncate(k);
    for x in run.phi_deg[1].iter_mut() {
        *x = -*x;
    }
    let w = check(&run, &m, "r.csv").unwrap();
    assert!(w.iter().any(|w| w.contains("mirrored")), "{w:?}");
}

#[test]
fn columns_swapped_between_joints_stowed_at_180_and_minus_180_are_refused() {
    // Joints 2 and 3 of T01 are stowed at 180 and -180 deg: swapped, each
    // column starts at the other's stowed angle (its own pose a turn off)
    // and moves towards 0 on that side.
    let (mut run, m) = t01();
    run.phi_deg.swap(1, 2);
    let e = check(&run, &m, "r.csv").unwrap_err();
    assert!(
        matches!(
            e.kind,
            RunErrorKind::SwappedOrMirrored { joints: [2, 3], .. }
        ),
        "{e}"
    );
    let text = e.to_string();
    assert!(
        text.contains("swap the columns") && text.contains("negate both"),
        "{text}"
    );
}
