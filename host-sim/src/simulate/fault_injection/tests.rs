//! Tests of `fault_injection`.

use super::readings::{corrupt_word, same};
use super::*;
use crate::simulate::sensor::RESOLUTION_DEG;
use deploywatch_core::monitor::encoder::{ERROR_FLAG_BIT, PARITY_BIT};

/// A 2-joint run at 100 Hz over 1 s: joint 1 moves from -90 to 0 and
/// latches at 0.5 s; joint 2 stays at 45 and never latches.
fn run() -> Run {
    let t: Vec<f64> = (0..=100).map(|i| i as f64 / 100.0).collect();
    let phi1: Vec<f64> = t.iter().map(|&t| (-90.0 + 180.0 * t).min(0.0)).collect();
    let latch1: Vec<bool> = t.iter().map(|&t| t >= 0.5 - 1e-12).collect();
    Run {
        metadata: vec![("mechanism".into(), "test".into())],
        phi_deg: vec![phi1, vec![45.0; t.len()]],
        latch: vec![latch1, vec![false; t.len()]],
        extra: Vec::new(),
        t_s: t,
    }
}

fn applied(spec: &str) -> (Run, usize) {
    let mut r = run();
    let f: SensorFault = spec.parse().unwrap();
    let rep = apply(&mut r, &[f], 7).unwrap();
    r.validate("test").unwrap();
    (r, rep[0].samples)
}

#[test]
fn cli_syntax_round_trips_and_rejects_with_what_was_expected() {
    for s in [
        "dropout:joint=1:start=0.5:duration=0.1:mode=stale",
        "dropout:joint=2:start=0:duration=1:mode=missing",
        "spike:joint=1:t=0.3:magnitude=-25",
        "spike:joint=1:t=0.3:magnitude=5:samples=3",
        "stuck:joint=1:start=0.2",
        "stuck:joint=1:start=0.2:value=-10",
        "parity:joint=2:rate=0.05",
        "parity:joint=2:rate=0.05:bits=2",
        "chatter:joint=1:bounce=0.02",
        "switch_stuck:joint=1:state=open",
        "switch_stuck:joint=1:state=closed",
        "jitter:sigma=0.002",
        "gap:start=0.4:duration=0.15",
    ] {
        let f: SensorFault = s.parse().unwrap_or_else(|e| panic!("{s}: {e}"));
        assert_eq!(f.to_string(), s);
    }
    let d: SensorFault = "dropout:joint=1:start=0.5:duration=0.1".parse().unwrap();
    assert!(matches!(
        d,
        SensorFault::Dropout {
            mode: DropoutMode::Missing,
            ..
        }
    ));
    for (bad, says) in [
        ("stall:joint=1", "expected one of dropout, spike"),
        ("dropout:joint=1:start=0.5", "missing duration=..."),
        (
            "dropout:joint=1:start=0.5:duration=0.1:mode=frozen",
            "expected stale or missing",
        ),
        ("spike:joint=0:t=1:magnitude=3", "joint 0 does not exist"),
        ("spike:joint=x:t=1:magnitude=3", "expected a joint number"),
        (
            "spike:joint=1:t=1:magnitude=nan",
            "expected a finite number",
        ),
        ("chatter:joint=1:bounce=0.05", "at most 0.02"),
        ("parity:joint=1:rate=1.5", "from 0 to 1"),
        ("parity:joint=1:rate=0.1:bits=0", "1 to 4"),
        ("gap:start=0.1:duration=0", "positive duration"),
        ("gap:start=0.1:duration=0.1:joint=1", "unknown key `joint`"),
        ("jitter:sigma=0.001:sigma=0.002", "given twice"),
        ("switch_stuck:joint=1:state=half", "expected open or closed"),
        ("stuck:joint=1:start=0:value=1000", "within ±720"),
        ("jitter", "missing sigma"),
        ("gap:0.1", "expected key=value"),
    ] {
        let e = bad.parse::<SensorFault>().unwrap_err().to_string();
        assert!(e.contains(says), "{bad}: {e}");
    }
    let f: SensorFault = "spike:joint=3:t=1:magnitude=3".parse().unwrap();
    assert!(f
        .validate(2)
        .unwrap_err()
        .to_string()
        .contains("joint 3 does not exist (expected a joint from 1 to 2)"));
}

#[test]
fn dropout_stale_repeats_the_last_reading_before_the_window() {
    // GIVEN joint 1 moving, WHEN its encoder freezes from 0.2 s for 0.1 s
    let (r, n) = applied("dropout:joint=1:start=0.2:duration=0.1:mode=stale");
    let before = run().phi_deg[0][19];
    // THEN samples 20..=29 read the value of sample 19, and only they
    assert_eq!(n, 10);
    for i in 20..30 {
        assert_eq!(r.phi_deg[0][i], before, "sample {i}");
    }
    assert_eq!(r.phi_deg[0][30], run().phi_deg[0][30]);
    assert_eq!(r.phi_deg[1], run().phi_deg[1]);
    assert!(r.meta(MISSING_SAMPLES_KEY).is_none());
    assert_eq!(
        r.meta("faults"),
        Some("dropout:joint=1:start=0.2:duration=0.1:mode=stale")
    );
}

#[test]
fn dropout_missing_makes_nan_and_declares_it() {
    let (r, n) = applied("dropout:joint=2:start=0.5:duration=0.05:mode=missing");
    assert_eq!(n, 5);
    assert!((50..55).all(|i| r.phi_deg[1][i].is_nan()));
    assert_eq!(r.phi_deg[1].iter().filter(|x| x.is_nan()).count(), 5);
    assert_eq!(r.meta(MISSING_SAMPLES_KEY), Some(MISSING_SAMPLES_VALUE));
    // The switch and the time stamps are untouched.
    assert_eq!(r.latch, run().latch);
    assert_eq!(r.t_s, run().t_s);
}

#[test]
fn spike_offsets_the_given_number_of_samples() {
    let (r, n) = applied("spike:joint=1:t=0.305:magnitude=30:samples=2");
    assert_eq!(n, 2);
    let base = run();
    for i in 0..r.len() {
        let d = r.phi_deg[0][i] - base.phi_deg[0][i];
        let want = if i == 31 || i == 32 { 30.0 } else { 0.0 };
        assert!((d - want).abs() < 1e-9, "sample {i}: {d}");
    }
    // A spike after the end of the run would do nothing: refused, the
    // run unchanged.
    let mut r = run();
    let late = "spike:joint=1:t=5:magnitude=30".parse().unwrap();
    let e = apply(&mut r, &[late], 0).unwrap_err();
    assert!(matches!(e, FaultError::AfterEnd { .. }), "{e}");
    assert!(e.to_string().contains("after the run ends (1 s)"), "{e}");
    assert_eq!(r, run());
}

#[test]
fn stuck_holds_a_value_to_the_end() {
    let (r, n) = applied("stuck:joint=1:start=0.1");
    let held = run().phi_deg[0][9];
    assert!(r.phi_deg[0][10..].iter().all(|&x| x == held));
    assert_eq!(n, 91);
    let (r, _) = applied("stuck:joint=1:start=0.1:value=-12.5");
    assert!(r.phi_deg[0][10..].iter().all(|&x| x == -12.5));
    assert_eq!(r.phi_deg[0][9], run().phi_deg[0][9]);
}

#[test]
fn one_flipped_bit_fails_the_parity_and_two_pass_it() {
    // GIVEN a reading on the 14-bit grid
    let deg = 1234.0 * RESOLUTION_DEG;
    // WHEN one bit (any, data, error flag or parity) flips
    for b in 0..16 {
        // THEN the driver rejects the word
        assert!(corrupt_word(deg, 1 << b).is_nan(), "bit {b}");
    }
    // WHEN two data bits flip, THEN the parity passes and the angle is wrong
    let x = corrupt_word(deg, 0b1_0000_0001);
    assert!(
        (x - f64::from(1234 ^ 0b1_0000_0001) * RESOLUTION_DEG).abs() < 1e-9,
        "{x}"
    );
    // WHEN a data bit and the parity bit flip, THEN a wrong angle passes too
    let x = corrupt_word(deg, PARITY_BIT | 2);
    assert!(
        (x - f64::from(1234 ^ 2) * RESOLUTION_DEG).abs() < 1e-9,
        "{x}"
    );
    // WHEN the error flag is one of two flips, THEN the driver rejects it
    assert!(corrupt_word(deg, ERROR_FLAG_BIT | 1).is_nan());
    // Negative and multi-turn readings keep their turn.
    let deg = -180.0 + 3.0 * RESOLUTION_DEG;
    let x = corrupt_word(deg, 0b11);
    assert!((x - deg).abs() < 4.0 * RESOLUTION_DEG && x < 0.0, "{x}");
}

#[test]
fn parity_errors_hit_about_the_rate_and_depend_on_the_seed_only() {
    let f: SensorFault = "parity:joint=1:rate=0.2".parse().unwrap();
    let mut a = run();
    let ra = apply(&mut a, &[f], 1).unwrap();
    let nan = a.phi_deg[0].iter().filter(|x| x.is_nan()).count();
    // One flipped bit: every corrupted word is rejected.
    assert_eq!(nan, ra[0].samples);
    assert!((8..=35).contains(&nan), "{nan} of 101 at rate 0.2");
    assert_eq!(a.meta(MISSING_SAMPLES_KEY), Some(MISSING_SAMPLES_VALUE));
    let mut b = run();
    apply(&mut b, &[f], 1).unwrap();
    assert!(a.phi_deg[0]
        .iter()
        .zip(&b.phi_deg[0])
        .all(|(x, y)| same(*x, *y)));
    let mut c = run();
    apply(&mut c, &[f], 2).unwrap();
    assert!(!a.phi_deg[0]
        .iter()
        .zip(&c.phi_deg[0])
        .all(|(x, y)| same(*x, *y)));
    // Two bits: no missing sample, but wrong readings (or EF rejections).
    let mut d = run();
    let f2: SensorFault = "parity:joint=1:rate=0.2:bits=2".parse().unwrap();
    let rd = apply(&mut d, &[f2], 1).unwrap();
    let wrong = d.phi_deg[0]
        .iter()
        .zip(&run().phi_deg[0])
        .filter(|(x, y)| !same(**x, **y))
        .count();
    assert!(wrong > 0 && wrong <= rd[0].samples);
    assert!(d.phi_deg[0]
        .iter()
        .any(|x| x.is_finite() && !run().phi_deg[0].contains(x)));
}

#[test]
fn chatter_bounces_after_the_closing_then_stays_closed() {
    let (r, n) = applied("chatter:joint=1:bounce=0.02");
    // Closing at sample 50: 50 closed, 51 open, 52 random, 53.. closed.
    assert!(!r.latch[0][49] && r.latch[0][50] && !r.latch[0][51]);
    assert!(r.latch[0][53..].iter().all(|&l| l));
    assert!((1..=2).contains(&n));
    // A switch that never closes has nothing to bounce.
    let (r, n) = applied("chatter:joint=2:bounce=0.02");
    assert_eq!((n, r.latch), (0, run().latch));
}

#[test]
fn switch_stuck_reads_one_state_throughout() {
    let (r, n) = applied("switch_stuck:joint=1:state=open");
    assert!(r.latch[0].iter().all(|&l| !l));
    assert_eq!(n, 51);
    let (r, n) = applied("switch_stuck:joint=2:state=closed");
    assert!(r.latch[1].iter().all(|&l| l));
    assert_eq!(n, 101);
    assert_eq!(r.phi_deg, run().phi_deg);
}

#[test]
fn jitter_keeps_times_increasing_and_the_first_at_zero() {
    // A jitter far larger than the sample interval is clipped.
    let (r, n) = applied("jitter:sigma=1");
    assert_eq!(r.t_s[0], 0.0);
    assert_eq!(n, 100);
    for w in r.t_s.windows(2) {
        assert!(w[1] - w[0] >= 0.1 * 0.01 - 1e-12, "{w:?}");
    }
    let (r, _) = applied("jitter:sigma=0.0005");
    let err: f64 = r
        .t_s
        .iter()
        .zip(&run().t_s)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(err > 0.0 && err <= 0.0045 + 1e-12);
    assert_eq!(r.phi_deg, run().phi_deg);
}

#[test]
fn gap_removes_rows_and_never_all_of_them() {
    let (r, n) = applied("gap:start=0.45:duration=0.1");
    assert_eq!(n, 10);
    assert_eq!(r.len(), 91);
    assert!(r
        .t_s
        .iter()
        .all(|&t| !(0.45 - 1e-9..0.55 - 1e-9).contains(&t)));
    // The latch happened in the gap: the next row already reads latched.
    let i = r.t_s.iter().position(|&t| t > 0.5).unwrap();
    assert!(r.latch[0][i] && !r.latch[0][i - 1]);
    let mut r = run();
    let e = apply(&mut r, &["gap:start=0:duration=2".parse().unwrap()], 0)
        .unwrap_err()
        .to_string();
    assert!(e.contains("remove every sample"), "{e}");
    assert_eq!(r, run());
}

#[test]
fn faults_combine_deterministically_and_windows_use_the_original_times() {
    let faults: Vec<SensorFault> = [
        "jitter:sigma=0.002",
        "gap:start=0.2:duration=0.05",
        "dropout:joint=1:start=0.6:duration=0.03:mode=missing",
        "chatter:joint=1:bounce=0.02",
    ]
    .iter()
    .map(|s| s.parse().unwrap())
    .collect();
    let mut a = run();
    let rep = apply(&mut a, &faults, 11).unwrap();
    assert_eq!(
        rep.iter().map(|r| r.samples).collect::<Vec<_>>()[1..3],
        [5, 3]
    );
    assert_eq!(a.len(), 96);
    assert_eq!(a.phi_deg[0].iter().filter(|x| x.is_nan()).count(), 3);
    let mut b = run();
    apply(&mut b, &faults, 11).unwrap();
    assert_eq!(a.to_csv_string(), b.to_csv_string());
    // Adding a fault does not change what the others drew.
    let mut c = run();
    let mut more = faults.clone();
    more.push("spike:joint=2:t=0.9:magnitude=4".parse().unwrap());
    apply(&mut c, &more, 11).unwrap();
    assert_eq!(a.t_s, c.t_s);
    assert_eq!(a.latch, c.latch);
    // The faulted run is writable and declares what was done to it.
    a.validate("a").unwrap();
    assert!(a
        .meta("faults")
        .unwrap()
        .starts_with("jitter:sigma=0.002; gap:"));
}

#[test]
fn a_fault_that_does_not_fit_the_run_leaves_it_unchanged() {
    let mut r = run();
    let e = apply(&mut r, &["stuck:joint=3:start=0".parse().unwrap()], 0)
        .unwrap_err()
        .to_string();
    assert!(e.contains("joint 3 does not exist"), "{e}");
    assert_eq!(r, run());
}
