//! Tests of `plausibility`.

use super::*;

const DEG: f32 = core::f32::consts::PI / 180.0;
const STEP: f32 = 360.0 / 16384.0 * DEG;

fn reading(t: f32, deg: f32, repeats: u16) -> Reading {
    Reading {
        t_s: t,
        angle: Some(deg * DEG),
        repeats,
        step: STEP,
        moving_checks: true,
        free: true,
        through_impact: false,
        follow: true,
    }
}

/// A joint at −100°/s from 10° at t = 0.
fn course(t: f32) -> Course {
    Course {
        t_s: t,
        angle: (10.0 - 100.0 * t) * DEG,
        rate: -100.0 * DEG,
        acc: 0.0,
    }
}

#[test]
fn a_two_sample_spike_that_returns_is_flagged_when_it_returns() {
    let mut c = ReadingCheck::new();
    // 0.01–0.03: on course; 0.04, 0.05: at 0° (a spike to the latch
    // angle); 0.06: back on course (4°).
    for (t, deg) in [
        (0.01, 9.0),
        (0.02, 8.0),
        (0.03, 7.0),
        (0.04, 0.0),
        (0.05, 0.0),
    ] {
        assert_eq!(
            c.check(&reading(t, deg, 0), &course(t - 0.01)),
            Verdict::Plausible
        );
    }
    assert_eq!(
        c.check(&reading(0.06, 4.0, 0), &course(0.05)),
        Verdict::SpikeReturned
    );
}

#[test]
fn a_rattle_at_the_nyquist_frequency_is_no_spike_a_spike_on_it_still_is() {
    // 100°/s with ±0.2° alternating every sample: the readings leave
    // and rejoin their line by 0.4° at every sample.
    let rattle = |k: usize| 10.0 - k as f32 + if k % 2 == 0 { 0.2 } else { -0.2 };
    let mut c = ReadingCheck::new();
    for k in 1..40 {
        let t = 0.01 * k as f32;
        let v = c.check(&reading(t, rattle(k), 0), &course(t - 0.01));
        assert_eq!(v, Verdict::Plausible, "sample {k}");
    }
    // The same departure on a smooth course is a spike when it returns.
    let mut c = ReadingCheck::new();
    let mut v = Vec::new();
    for k in 1..10 {
        let t = 0.01 * k as f32;
        let deg = 10.0 - k as f32 + if k == 6 { 0.4 } else { 0.0 };
        v.push(c.check(&reading(t, deg, 0), &course(t - 0.01)));
    }
    assert_eq!(v[6], Verdict::SpikeReturned, "{v:?}");
}

#[test]
fn a_whip_follows_the_cubic_through_four_readings_a_spike_does_not() {
    // The angle of a joint whose acceleration doubles every two samples.
    let whip = |k: f32| 0.2 * libm::powf(2.0, 0.5 * k) * DEG;
    let mut c = ReadingCheck::new();
    for k in 0..6 {
        let t = 0.01 * (k + 1) as f32;
        c.check(&reading(t, whip(k as f32) / DEG, 0), &course(t - 0.01));
    }
    let (next, tol) = (whip(6.0), 0.02 * DEG);
    let mut spiked = c;
    // The monitor asks after the reading's own checks.
    c.check(&reading(0.07, next / DEG, 0), &course(0.06));
    assert!(libm::fabsf(next - c.parabola) > tol, "the parabola lags");
    assert!(c.follows_readings(next, tol));
    let spike = next + 3.0 * DEG;
    spiked.check(&reading(0.07, spike / DEG, 0), &course(0.06));
    assert!(!spiked.follows_readings(spike, tol));
}

/// The readings of joint 6 of an eight-panel light wing at 100 Hz
/// (`tests/monitor/light_wings.rs`): its neighbour latches at 0.82 s, the
/// checks are off until 0.85 s, and the whip of the next latch bends its
/// course at 0.86 s by 2° from the parabola, 1.5° from the cubic.
const THROWN: [(f32, f32); 7] = [
    (0.80, 65.610),
    (0.81, 63.962),
    (0.82, 60.953),
    (0.83, 55.635),
    (0.84, 49.241),
    (0.85, 41.177),
    (0.86, 29.355),
];

#[test]
fn readings_through_an_impact_keep_the_course_for_the_first_checked_one() {
    let tol = 1.5 * DEG;
    let run = |through_impact: bool| {
        let mut c = ReadingCheck::new();
        for &(t, deg) in &THROWN[..6] {
            let mut r = reading(t, deg, 0);
            // The window of the latch at 0.82 s: no checks.
            r.moving_checks = !(0.82..=0.85).contains(&t);
            r.through_impact = through_impact && !r.moving_checks;
            c.check(&r, &course(t - 0.01));
        }
        let (t, deg) = THROWN[6];
        c.check(&reading(t, deg, 0), &course(t - 0.01));
        c.follows_readings(deg * DEG, tol)
    };
    assert!(run(true), "the readings since the impact give the cubic");
    assert!(!run(false), "a history begun afresh has no cubic yet");
}

#[test]
fn a_joint_moving_more_than_ten_degrees_a_reading_has_a_wider_tolerance() {
    let tol = 1.5 * DEG;
    // Joint 5 of the same wing, whipped to its latch: 16° then 22° a
    // reading, 2.3° off the cubic.
    let whipped = [-94.636, -87.891, -78.948, -67.567, -54.448, -38.518];
    let mut c = ReadingCheck::new();
    for (k, deg) in whipped.iter().enumerate() {
        let t = 0.80 + 0.01 * k as f32;
        c.check(&reading(t, *deg, 0), &course(t - 0.01));
    }
    // The monitor asks after the reading's own checks.
    let next = -16.436;
    c.check(&reading(0.86, next, 0), &course(0.85));
    let next = next * DEG;
    assert!(libm::fabsf(next - c.parabola - c.third) > tol);
    assert!(c.follows_readings(next, tol));
    // A reading 3° off the course of a joint moving 1° a reading is a
    // spike.
    let mut slow = ReadingCheck::new();
    for k in 0..6 {
        let t = 0.01 * (k + 1) as f32;
        slow.check(&reading(t, k as f32, 0), &course(t - 0.01));
    }
    slow.check(&reading(0.07, 9.0, 0), &course(0.06));
    assert!(!slow.follows_readings(9.0 * DEG, tol));
}

#[test]
fn a_stop_does_not_return_and_is_not_flagged() {
    let mut c = ReadingCheck::new();
    // The joint stops dead at 8° at 0.02 s and stays.
    let mut v = Vec::new();
    for (k, deg) in [9.0, 8.0, 8.01, 7.99, 8.0, 8.02].iter().enumerate() {
        let t = 0.01 * (k + 1) as f32;
        v.push(c.check(&reading(t, *deg, 0), &course(t - 0.01)));
    }
    assert!(v.iter().all(|x| *x == Verdict::Plausible), "{v:?}");
}

#[test]
fn repeats_are_stale_only_while_moving() {
    // Moving at 100°/s: the first repeat is fused (the filter slows
    // down), the second is judged against the readings' motion before
    // it.
    let mut c = ReadingCheck::new();
    for (k, deg) in [11.0, 10.0, 9.0].iter().enumerate() {
        let t = 0.01 * (k + 1) as f32;
        assert_eq!(
            c.check(&reading(t, *deg, 0), &course(t - 0.01)),
            Verdict::Plausible
        );
    }
    assert_eq!(
        c.check(&reading(0.04, 9.0, 1), &course(0.03)),
        Verdict::Plausible
    );
    let slowed = Course {
        rate: -DEG,
        ..course(0.04)
    };
    // Fast (45 steps per sample): the second repeat is stale.
    assert_eq!(c.check(&reading(0.05, 9.0, 2), &slowed), Verdict::Stale);
    // 0.15° (7 steps) per sample: two repeats may be a turn, the third
    // is stale.
    let mut c = ReadingCheck::new();
    let slow = |t: f32| Course {
        t_s: t,
        angle: (10.0 - 15.0 * t) * DEG,
        rate: -15.0 * DEG,
        acc: 0.0,
    };
    for (k, deg) in [9.85, 9.70, 9.55].iter().enumerate() {
        let t = 0.01 * (k + 1) as f32;
        assert_eq!(
            c.check(&reading(t, *deg, 0), &slow(t - 0.01)),
            Verdict::Plausible
        );
    }
    assert_eq!(
        c.check(&reading(0.04, 9.55, 1), &slow(0.03)),
        Verdict::Plausible
    );
    assert_eq!(
        c.check(&reading(0.05, 9.55, 2), &slow(0.03)),
        Verdict::Plausible
    );
    assert_eq!(
        c.check(&reading(0.06, 9.55, 3), &slow(0.03)),
        Verdict::Stale
    );
    // Before three readings there is no motion to judge a repeat by.
    let mut c = ReadingCheck::new();
    c.check(&reading(0.01, 9.0, 0), &course(0.0));
    c.check(&reading(0.02, 9.0, 1), &course(0.01));
    assert_eq!(
        c.check(&reading(0.03, 9.0, 2), &course(0.02)),
        Verdict::Plausible
    );
    // At rest, repeats are what a quantised encoder does.
    let rest = Course {
        t_s: 0.01,
        angle: 8.0 * DEG,
        rate: 0.001,
        acc: 0.0,
    };
    let mut c = ReadingCheck::new();
    for k in 0..5u16 {
        let t = 0.02 + 0.01 * f32::from(k);
        let at = Course {
            t_s: t - 0.01,
            ..rest
        };
        assert_eq!(c.check(&reading(t, 8.0, k), &at), Verdict::Plausible);
    }
    let mut off = reading(0.02, 8.0, 2);
    off.moving_checks = false;
    assert_eq!(c.check(&off, &course(0.01)), Verdict::Plausible);
}
