//! Unit tests of the latch tracker: the ideal latch and the physical one.

use super::*;

fn input(t: f32, switch: bool, deg: f32) -> LatchInput {
    LatchInput {
        t_s: t,
        switch,
        measured_deg: Some(deg),
        angle_deg: deg,
        rate_deg_s: -50.0,
        stowed_deg: 90.0,
        encoder_stuck: false,
        noise_sd_deg: 0.02,
        neighbour_impact: false,
    }
}

fn run(tr: &mut LatchTracker, samples: &[(bool, f32)]) -> LatchOutput {
    let cfg = LatchConfig::default();
    let mut out = None;
    for (i, &(sw, deg)) in samples.iter().enumerate() {
        out = Some(tr.step(&input(i as f32 * 0.01, sw, deg), &cfg));
    }
    out.unwrap()
}

#[test]
fn given_switch_and_encoder_agree_when_closed_twice_then_latched() {
    let mut tr = LatchTracker::new();
    let out = run(&mut tr, &[(false, 80.0), (false, 1.0), (true, 0.0)]);
    assert_eq!(
        out.state,
        LatchState::Latching,
        "one closed sample is not a latch"
    );
    let out = tr.step(&input(0.03, true, 0.01), &LatchConfig::default());
    assert!(out.newly_latched);
    assert_eq!(out.state, LatchState::Latched);
}

#[test]
fn given_switch_closed_far_from_latch_then_fault_not_latch() {
    let mut tr = LatchTracker::new();
    let out = run(
        &mut tr,
        &[(false, 60.0), (true, 59.0), (true, 58.0), (true, 57.0)],
    );
    assert_eq!(out.state, LatchState::Fault);
    assert!(out.faults.contains(Fault::SwitchEarly));
    assert!(!tr.is_latched());
}

#[test]
fn given_encoder_at_latch_with_switch_open_then_fault_not_latch() {
    let mut tr = LatchTracker::new();
    let samples: [(bool, f32); 20] = [(false, 0.01); 20];
    let out = run(&mut tr, &samples);
    assert_eq!(out.state, LatchState::Fault);
    assert!(out.faults.contains(Fault::SwitchOpenAtLatch));
    assert!(!tr.is_latched());
}

#[test]
fn given_confirmed_latch_when_switch_opens_then_latch_kept_and_flagged() {
    let mut tr = LatchTracker::new();
    run(&mut tr, &[(true, 0.0), (true, 0.0)]);
    assert!(tr.is_latched());
    let out = tr.step(&input(1.0, false, 0.0), &LatchConfig::default());
    assert_eq!(out.state, LatchState::Latched);
    assert!(out.faults.contains(Fault::LatchDisagree));
    let out = tr.step(
        &LatchInput {
            measured_deg: None,
            ..input(1.01, true, 0.0)
        },
        &LatchConfig::default(),
    );
    assert_eq!(out.state, LatchState::Latched);
}

#[test]
fn given_switch_open_when_encoder_at_latch_for_confirm_time_then_latched_and_flagged() {
    let mut tr = LatchTracker::new();
    let samples: [(bool, f32); 32] = [(false, 0.01); 32];
    let out = run(&mut tr, &samples);
    assert!(out.newly_latched && tr.is_latched());
    assert!(out.faults.contains(Fault::SwitchOpenAtLatch));
}

#[test]
fn given_switch_stuck_closed_then_no_latch_until_encoder_confirms() {
    let mut tr = LatchTracker::new();
    // Closed far from the latch for the debounce time: distrusted.
    let mut samples: std::vec::Vec<(bool, f32)> =
        (0..10).map(|i| (true, 60.0 - i as f32)).collect();
    // The encoder crosses the 2° window: not a latch with that switch.
    samples.extend([(true, 1.5), (true, 0.8), (true, 0.2)]);
    let out = run(&mut tr, &samples);
    assert!(tr.switch_suspect() && !tr.is_latched());
    assert_eq!(out.state, LatchState::Fault);
    // At the latch angle for the confirmation time: latched.
    samples.extend([(true, 0.0); 32]);
    let mut tr = LatchTracker::new();
    let out = run(&mut tr, &samples);
    assert!(tr.is_latched());
    assert_eq!(out.state, LatchState::Latched);
}

#[test]
fn given_stuck_encoder_then_switch_alone_latches_after_debounce() {
    let cfg = LatchConfig::default();
    let mut tr = LatchTracker::new();
    let stuck = |t: f32, sw: bool| LatchInput {
        measured_deg: None,
        encoder_stuck: true,
        ..input(t, sw, 20.0)
    };
    tr.step(&stuck(0.0, false), &cfg);
    for k in 1..=3 {
        let out = tr.step(&stuck(0.01 * k as f32, true), &cfg);
        assert!(!tr.is_latched(), "{k}: {out:?}");
        // No reading that counts says the switch is early: it is waited for.
        assert!(!out.faults.contains(Fault::SwitchEarly), "{k}: {out:?}");
    }
    let out = tr.step(&stuck(0.04, true), &cfg);
    assert!(out.newly_latched);
    assert!(out.faults.is_empty(), "{out:?}");
}

#[test]
fn given_chatter_then_flagged() {
    let mut tr = LatchTracker::new();
    let out = run(&mut tr, &[(false, 50.0), (true, 49.0), (false, 48.0)]);
    assert!(out.faults.contains(Fault::SwitchChatter));
}

#[test]
fn names_round_trip() {
    for s in LatchState::ALL {
        assert_eq!(LatchState::from_name(s.as_str()), Some(s));
    }
}

/// The physical latch of the tests: 0.02° switch travel, crest at
/// 1.5°, ramp 0.6°, bounce window 30 ms.
fn physical() -> LatchConfig {
    LatchConfig {
        physical: Some(PhysicalLatch {
            switch_travel_deg: 0.02,
            crest_deg: 1.5,
            ramp_deg: 0.6,
            bounce_window_s: 0.03,
            lock: LockKind::Detent,
        }),
        ..LatchConfig::default()
    }
}

/// The latch of [`physical`] with a pawl for its lock.
fn pawl() -> LatchConfig {
    LatchConfig {
        physical: Some(PhysicalLatch {
            lock: LockKind::Pawl,
            ..physical().physical.unwrap()
        }),
        ..LatchConfig::default()
    }
}

fn run_with(tr: &mut LatchTracker, cfg: &LatchConfig, samples: &[(bool, f32)]) -> Vec<LatchOutput> {
    samples
        .iter()
        .enumerate()
        .map(|(i, &(sw, deg))| tr.step(&input(i as f32 * 0.01, sw, deg), cfg))
        .collect()
}

#[test]
fn given_physical_latch_when_joint_rebounds_then_no_chatter_and_latched_after_the_window() {
    let cfg = physical();
    let mut tr = LatchTracker::new();
    // In, contact, a 0.5° rebound over two samples, contact, a small
    // one-sample rebound, then held.
    let mut s = vec![
        (false, 3.0),
        (false, 1.2),
        (true, 0.0),
        (false, 0.45),
        (false, 0.3),
    ];
    s.extend([(true, 0.01), (false, 0.05), (true, 0.0), (true, 0.01)]);
    s.extend([(true, 0.0); 4]);
    let out = run_with(&mut tr, &cfg, &s);
    assert!(out.iter().all(|o| o.faults.is_empty()), "{out:?}");
    // Closed from sample 7: held for 30 ms at sample 10 (11 when the
    // time stamps' rounding makes it 29.99 ms).
    let first = out.iter().position(|o| o.newly_latched);
    assert!(matches!(first, Some(10 | 11)), "{first:?}: {out:?}");
}

#[test]
fn given_physical_latch_when_switch_toggles_at_rest_on_the_stop_then_chatter() {
    let cfg = physical();
    let mut tr = LatchTracker::new();
    let s = [
        (false, 3.0),
        (false, 1.2),
        (true, 0.0),
        (false, 0.01),
        (true, 0.0),
        (true, 0.0),
    ];
    let out = run_with(&mut tr, &cfg, &s);
    assert!(
        out.iter().any(|o| o.faults.contains(Fault::SwitchChatter)),
        "{out:?}"
    );
}

#[test]
fn given_physical_latch_when_joint_goes_over_the_crest_then_escaped_not_latched() {
    let cfg = physical();
    let mut tr = LatchTracker::new();
    let mut s = vec![(false, 3.0), (false, 1.2), (true, 0.0)];
    s.extend((1..=20).map(|k| (false, 0.3 * k as f32)));
    let out = run_with(&mut tr, &cfg, &s);
    let last = out.last().unwrap();
    assert_eq!(last.state, LatchState::Escaped);
    assert!(
        out.iter().all(|o| o.faults.is_empty() && !o.newly_latched),
        "{out:?}"
    );
    // Back in and held: latched again.
    let t0 = s.len() as f32 * 0.01;
    let mut last = None;
    for k in 0..10 {
        last = Some(tr.step(&input(t0 + 0.01 * k as f32, true, 0.0), &cfg));
    }
    assert_eq!(last.unwrap().state, LatchState::Latched);
    // The switch opening after the declaration is a rebound (not
    // latched); over the crest, an escape.
    let t1 = t0 + 0.1;
    let a = tr.step(&input(t1, false, 0.5), &cfg);
    let b = tr.step(&input(t1 + 0.01, false, 2.5), &cfg);
    assert!(a.unlatched && a.state == LatchState::Latching, "{a:?}");
    assert_eq!(b.state, LatchState::Escaped, "{b:?}");
    assert!(a.faults.is_empty() && b.faults.is_empty());
}

#[test]
fn given_physical_latch_when_joint_rests_on_the_ramp_then_stopped_short() {
    let cfg = physical();
    let mut tr = LatchTracker::new();
    let mut s = vec![(false, 3.0), (false, 1.2), (false, 0.5)];
    s.extend([(false, 0.3); 150]);
    let out = run_with(&mut tr, &cfg, &s);
    let last = out.last().unwrap();
    assert_eq!(last.state, LatchState::StoppedShort, "{last:?}");
    assert!(out.iter().all(|o| o.faults.is_empty() && !o.newly_latched));
}

#[test]
fn physical_latch_config_is_validated() {
    let mut cfg = physical();
    assert!(cfg.is_valid());
    for bad in [
        PhysicalLatch {
            switch_travel_deg: -0.1,
            ..cfg.physical.unwrap()
        },
        PhysicalLatch {
            ramp_deg: 0.01,
            ..cfg.physical.unwrap()
        },
        PhysicalLatch {
            crest_deg: f32::NAN,
            ..cfg.physical.unwrap()
        },
        PhysicalLatch {
            bounce_window_s: 0.0,
            ..cfg.physical.unwrap()
        },
        PhysicalLatch {
            bounce_window_s: 0.2,
            ..cfg.physical.unwrap()
        },
    ] {
        cfg.physical = Some(bad);
        assert!(!cfg.is_valid(), "{bad:?}");
    }
}

/// An ideal latch declared, then the switch opens and the encoder leaves
/// the latch (an as-built latch that escaped): never `latched` once both
/// have said so for the debounce time, flagged as a disagreement with the
/// drawing, and latched again when it comes back.
#[test]
fn given_ideal_latch_when_switch_opens_and_encoder_leaves_then_escaped_not_latched() {
    let cfg = LatchConfig::default();
    let mut tr = LatchTracker::new();
    let mut s = vec![(false, 3.0), (false, 1.2), (true, 0.0), (true, 0.0)];
    s.extend((1..=20).map(|k| (false, 0.5 * k as f32)));
    let out = run_with(&mut tr, &cfg, &s);
    assert!(out[3].newly_latched, "{out:?}");
    for (i, (o, &(sw, deg))) in out.iter().zip(&s).enumerate().skip(4) {
        // 0.5° a sample: beyond at_latch_deg (0.3°) from the first open
        // sample, 30 ms (3 samples, one more for the f32 time stamps) later
        // not latched.
        let t_out = 4;
        if i >= t_out + 4 {
            assert_eq!(o.state, LatchState::Escaped, "sample {i}: {o:?}");
            assert!(o.faults.contains(Fault::LatchDisagree), "{o:?}");
        }
        if o.state == LatchState::Latched {
            assert!(sw || deg <= cfg.at_latch_deg || i < t_out + 4, "{i}: {o:?}");
        }
    }
    assert_eq!(out.iter().filter(|o| o.unlatched).count(), 1);
    // Back in with the switch closed: latched again, no flag.
    let t0 = s.len() as f32 * 0.01;
    let mut last = None;
    for k in 0..4 {
        last = Some(tr.step(&input(t0 + 0.01 * k as f32, true, 0.0), &cfg));
    }
    let last = last.unwrap();
    assert_eq!(last.state, LatchState::Latched);
    assert!(last.faults.is_empty(), "{last:?}");
}

/// A rebound shorter than the debounce time, or an encoder spike with the
/// switch closed, does not undo an ideal latch.
#[test]
fn given_ideal_latch_when_a_short_rebound_or_a_spike_then_still_latched() {
    let cfg = LatchConfig::default();
    let mut tr = LatchTracker::new();
    let s = [
        (true, 0.0),
        (true, 0.0),
        (false, 3.0),
        (false, 2.5),
        (true, 0.0),
        (true, 9.0),
        (true, 9.0),
        (true, 9.0),
        (true, 9.0),
        (false, 0.1),
    ];
    let out = run_with(&mut tr, &cfg, &s);
    assert!(
        out[1..].iter().all(|o| o.state == LatchState::Latched),
        "{out:?}"
    );
    assert!(out.iter().all(|o| !o.unlatched));
}

/// An ideal latch's joint that friction stops 0.27° short (readings of
/// σ = 0.02° around it) with its switch open is not at the latch: the
/// encoder resolves the stop, switch and encoder agree, nothing is
/// flagged; one at rest within 5 σ (0.05°) with the switch open still is.
#[test]
fn given_ideal_latch_when_joint_stops_short_beyond_the_encoder_noise_then_no_switch_fault() {
    let wobble = |k: usize| 0.02 * [0.0, 1.0, -1.0, 0.5, -0.5][k % 5];
    let mut tr = LatchTracker::new();
    let mut s = vec![(false, 30.0), (false, 10.0), (false, 2.0)];
    s.extend((0..100).map(|k| (false, -0.27 + wobble(k))));
    let out = run_with(&mut tr, &LatchConfig::default(), &s);
    assert!(
        out.iter().all(|o| o.faults.is_empty() && !o.newly_latched),
        "{out:?}"
    );
    assert!(!tr.is_latched() && !tr.held_at_latch());
    let mut tr = LatchTracker::new();
    s.truncate(3);
    s.extend((0..100).map(|k| (false, 0.05 + wobble(k))));
    let out = run_with(&mut tr, &LatchConfig::default(), &s);
    assert!(
        out.iter()
            .any(|o| o.faults.contains(Fault::SwitchOpenAtLatch)),
        "{out:?}"
    );
}

/// A pawl's joint that comes within its notch's reach and goes back out
/// over it with the switch never closed was riding the cam, the pawl not
/// yet in its notch: not an escape, no flag. The same motion after the
/// switch closed at the stop is a broken pawl: escaped and flagged.
#[test]
fn given_pawl_when_joint_rides_the_cam_without_engaging_then_no_escape() {
    let cfg = pawl();
    let mut s = vec![(false, 3.0), (false, 2.0)];
    s.extend([1.6, 1.3, 1.1, 1.0, 1.1, 1.3, 1.6].map(|d| (false, d)));
    s.extend((1..=40).map(|k| (false, 1.6 + 0.1 * k as f32)));
    let mut tr = LatchTracker::new();
    let out = run_with(&mut tr, &cfg, &s);
    assert!(
        out.iter()
            .all(|o| o.faults.is_empty() && o.state != LatchState::Escaped),
        "{out:?}"
    );
    let mut s = vec![(false, 3.0), (false, 1.2), (true, 0.0)];
    s.extend((1..=20).map(|k| (false, 0.3 * k as f32)));
    let mut tr = LatchTracker::new();
    let out = run_with(&mut tr, &cfg, &s);
    let last = out.last().unwrap();
    assert_eq!(last.state, LatchState::Escaped, "{last:?}");
    assert!(last.faults.contains(Fault::LatchDisagree), "{last:?}");
}

/// A pawl that breaks locks nothing again: a joint whose pawl was declared
/// latched and then went out beyond its notch is escaped and flagged, and
/// stays so when its spring brings it back onto its stop with the switch
/// closed for far longer than the bounce window (a plunger's joint is
/// latched again there, `..._goes_over_the_crest_then_escaped_not_latched`).
#[test]
fn given_pawl_when_it_breaks_then_never_latched_again() {
    let cfg = pawl();
    let mut s = vec![(false, 3.0), (false, 1.2)];
    s.extend([(true, 0.0); 8]);
    let mut tr = LatchTracker::new();
    let out = run_with(&mut tr, &cfg, &s);
    assert_eq!(out.last().unwrap().state, LatchState::Latched, "{out:?}");
    // Out over the notch (1.5° plus the contact's give), then back on the
    // stop, switch closed, for a second.
    let t0 = s.len() as f32 * 0.01;
    let back = (0..20)
        .map(|k| (false, 0.3 * k as f32))
        .chain((0..100).map(|_| (true, 0.0)));
    let out: Vec<LatchOutput> = back
        .enumerate()
        .map(|(k, (sw, deg))| tr.step(&input(t0 + 0.01 * k as f32, sw, deg), &cfg))
        .collect();
    let broke = out
        .iter()
        .position(|o| o.state == LatchState::Escaped)
        .expect("the break is an escape");
    assert!(
        out[broke..].iter().all(|o| o.state == LatchState::Escaped
            && o.faults.contains(Fault::LatchDisagree)
            && !o.newly_latched),
        "{:?}",
        &out[broke..]
    );
    assert!(!tr.is_latched());
}

/// A joint that stops short of its ideal latch inside `latching_deg` (a
/// jam 2° short, the switch rightly open) is `Stalled` once its readings
/// have stayed within the rest band for `stall_time_s`, whatever its
/// filtered rate (inside the snap zone the rate of a joint at rest swings
/// by tens of degrees per second; here it reads -50 deg/s throughout). A
/// joint still creeping through the same zone is not.
#[test]
fn given_ideal_latch_when_joint_rests_short_within_the_latching_zone_then_stalled() {
    let wobble = |k: usize| 0.02 * [0.0, 1.0, -1.0, 0.5, -0.5][k % 5];
    let cfg = LatchConfig::default();
    let mut s = vec![(false, 30.0), (false, 10.0)];
    s.extend((0..150).map(|k| (false, -2.0 + wobble(k))));
    let out = run_with(&mut LatchTracker::new(), &cfg, &s);
    // Sample 2 starts the rest at t = 0.02 s; stalled from t = 1.02 s.
    let first = out.iter().position(|o| o.state == LatchState::Stalled);
    assert_eq!(first, Some(102), "{:?}", &out[95..110]);
    assert!(out[102..].iter().all(|o| o.state == LatchState::Stalled));
    assert!(out.iter().all(|o| o.faults.is_empty()));
    // Creeping at 0.5 deg/s from -2.5 deg: leaves the band every 0.3 s.
    let mut s = vec![(false, 30.0), (false, 10.0)];
    s.extend((0..150).map(|k| (false, -2.5 + 0.005 * k as f32 + wobble(k))));
    let out = run_with(&mut LatchTracker::new(), &cfg, &s);
    assert!(
        out.iter().all(|o| o.state != LatchState::Stalled),
        "{out:?}"
    );
}
