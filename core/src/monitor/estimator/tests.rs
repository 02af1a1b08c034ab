//! Tests of `estimator`.

use super::*;
use crate::monitor::faults::Fault;

fn config() -> MonitorConfig<1> {
    example_config()
}

#[test]
fn bad_time_stamps_are_flagged_and_resynchronised() {
    let mut m = Monitor::new(&config()).unwrap();
    m.update(&Sample::new(0.0, [90.0], [false]));
    m.update(&Sample::new(0.01, [90.0], [false]));
    let st = m.update(&Sample::new(f32::NAN, [90.0], [false]));
    assert!(st.joints[0].faults.contains(Fault::TimeInvalid));
    assert_eq!(st.samples, 2, "a sample with a bad time stamp is not used");
    // A clock that jumps ahead (a gap), then back to where it was: the
    // samples behind the jump are flagged and not used, until three in a
    // row are adopted as the new time base.
    let st = m.update(&Sample::new(5.0, [90.0], [false]));
    assert!(st.joints[0].faults.contains(Fault::TimeGap));
    assert_eq!(st.samples, 3);
    for (k, t) in [0.02f32, 0.03].iter().enumerate() {
        let st = m.update(&Sample::new(*t, [90.0], [false]));
        assert!(st.joints[0].faults.contains(Fault::TimeBackwards), "{k}");
        assert_eq!(st.samples, 3);
    }
    let st = m.update(&Sample::new(0.04, [90.0], [false]));
    assert!(st.joints[0].faults.contains(Fault::TimeBackwards));
    assert!(st.joints[0].faults.contains(Fault::TimeGap));
    assert_eq!(st.samples, 4, "adopted");
    let st = m.update(&Sample::new(0.05, [90.0], [false]));
    assert!(st.joints[0].faults.is_empty(), "{}", st.joints[0].faults);
}

/// A 1-joint deployment at 100 Hz: `φ = 90° − 20 t²` \[deg\].
fn swing(k: usize) -> Sample<1> {
    let t = 0.01 * k as f32;
    Sample::new(t, [90.0 - 20.0 * t * t], [false])
}

#[test]
fn a_starved_slow_path_drops_the_oldest_samples_and_says_so() {
    let mut m = Monitor::new(&config()).unwrap();
    for k in 0..100 {
        m.replay_step(&swing(k));
    }
    assert_eq!(m.learning_overruns(), 0, "the replay schedule keeps up");
    let learned = m.status().samples;
    assert!(m.status().joints[0].margin_pct.is_some(), "learned");
    // 10 samples with no slice of the slow path: the queue keeps the
    // last LEARNING_QUEUE of them and counts the rest.
    for k in 100..110 {
        m.update(&swing(k));
    }
    assert_eq!(m.learning_overruns() as usize, 10 - LEARNING_QUEUE);
    assert_eq!(m.status().samples, learned + 10, "every sample is used");
    // The next sample still finds the queue full (one more dropped);
    // then the slow path catches up and learns on, with finite
    // estimates.
    for k in 110..200 {
        let st = m.replay_step(&swing(k));
        let j = &st.joints[0];
        assert!(j.coulomb_nm.is_finite() && j.coulomb_sd_nm.is_finite());
        assert!(j.faults.is_empty(), "{k}: {}", j.faults);
    }
    assert_eq!(m.learning_overruns() as usize, 11 - LEARNING_QUEUE);
    assert!(m.status().joints[0].margin_pct.is_some());
}

#[test]
fn missing_reading_is_flagged_and_estimates_stay_finite() {
    let mut m = Monitor::new(&config()).unwrap();
    m.update(&Sample::new(0.0, [90.0], [false]));
    let st = m.update(&Sample::new(0.01, [f32::NAN], [false]));
    assert!(st.joints[0].faults.contains(Fault::EncoderMissing));
    let st = m.update(&Sample::new(0.02, [1e30], [false]));
    assert!(st.joints[0].faults.contains(Fault::EncoderRange));
    assert!(st.joints[0].phi_deg.is_finite() && (st.joints[0].phi_deg - 90.0).abs() < 1.0);
}

#[test]
fn config_errors_name_the_parameter() {
    let mut c = config();
    c.joints[0].prior.coulomb_sd_nm = f32::NAN;
    assert_eq!(
        Monitor::new(&c).err(),
        Some(ConfigError::Joint {
            index: 0,
            what: JointParam::CoulombPriorSd
        })
    );
    let mut c = config();
    c.margin.confidence = 1.5;
    assert_eq!(
        Monitor::new(&c).err(),
        Some(ConfigError::Parameter(TuningParam::Confidence))
    );
    let mut c = config();
    c.panels[0].mass_kg = 0.0;
    assert!(matches!(Monitor::new(&c), Err(ConfigError::Chain(_))));
}

#[test]
fn prediction_names_round_trip() {
    for p in Prediction::ALL {
        assert_eq!(Prediction::from_name(p.as_str()), Some(p));
    }
}

/// [`swing`] shaken from sample 100 to 129 as a rattling neighbour shakes
/// a joint near the Nyquist frequency: ±0.3° about its course, alternating
/// every sample (its rate alternates by ±60°/s about the swing's).
fn shaken(k: usize) -> Sample<1> {
    let mut s = swing(k);
    if (100..130).contains(&k) {
        s.phi_deg[0] += if k % 2 == 0 { 0.3 } else { -0.3 };
    }
    s
}

/// [`config`] with a ball plunger at the joint (a wing with a physical
/// latch: the resolution is followed).
fn plunger_config() -> MonitorConfig<1> {
    let mut c = config();
    c.joints[0].physical = Some(crate::monitor::latch::PhysicalLatch {
        switch_travel_deg: 0.02,
        crest_deg: 1.5,
        ramp_deg: 0.6,
        bounce_window_s: 0.03,
        lock: crate::monitor::bounce::LockKind::Detent,
    });
    c
}

#[test]
fn a_shaken_joint_is_unresolved_without_a_flag_a_spike_on_a_quiet_one_is_flagged() {
    let mut m = Monitor::new(&plunger_config()).unwrap();
    let mut unresolved = Vec::new();
    for k in 0..200 {
        let st = m.update(&shaken(k));
        let j = &st.joints[0];
        assert!(j.faults.is_empty(), "sample {k}: {}", j.faults);
        if j.resolution == Resolution::Unresolved {
            unresolved.push(k);
        }
    }
    // Unresolved while shaken (once the readings have shown the shaking
    // both ways), resolved again within a few quiet readings after it.
    let (first, last) = (unresolved[0], unresolved[unresolved.len() - 1]);
    assert!((101..=106).contains(&first), "{unresolved:?}");
    assert!((130..=137).contains(&last), "{unresolved:?}");
    assert_eq!(unresolved.len(), last - first + 1, "{unresolved:?}");
    assert_eq!(m.status().joints[0].resolution, Resolution::Resolved);
    // A 3° spike on the joint, quiet again: flagged within three samples.
    let mut flagged = false;
    for k in 200..204 {
        let mut s = swing(k);
        if k == 201 {
            s.phi_deg[0] += 3.0;
        }
        let j = m.update(&s).joints[0];
        flagged |= j.faults.contains(Fault::EncoderOutlier);
        assert_eq!(j.resolution, Resolution::Resolved, "sample {k}");
    }
    assert!(flagged);
    // The same spike during the shaking is not flagged: it cannot be told
    // from the motion.
    let mut m = Monitor::new(&plunger_config()).unwrap();
    for k in 0..120 {
        let mut s = shaken(k);
        if k == 115 {
            s.phi_deg[0] += 3.0;
        }
        let j = m.update(&s).joints[0];
        assert!(j.faults.is_empty(), "sample {k}: {}", j.faults);
    }
}

#[test]
fn resolution_names_round_trip() {
    for r in Resolution::ALL {
        assert_eq!(Resolution::from_name(r.as_str()), Some(r));
    }
}

#[test]
fn on_a_wing_of_ideal_latches_every_joint_is_resolved() {
    // The shaking is not followed there (no physical latch to shake a
    // joint): the reading checks judge every reading as before.
    let mut m = Monitor::new(&config()).unwrap();
    for k in 0..200 {
        let j = m.update(&shaken(k)).joints[0];
        assert_eq!(j.resolution, Resolution::Resolved, "sample {k}");
    }
}
