//! Tests of the physical latch: the torques against the potential, the
//! stop, the plunger, the magnet, the switch and bad parameters.

use super::*;

/// The latch of these tests in either float (`T::of` of the same
/// `f64` values, so the `f32` latch is the `f64` one rounded).
fn latch<T: Real>(side: T) -> PhysicalLatch<T> {
    let v = T::of;
    PhysicalLatch {
        side,
        stop: HertzStop {
            stiffness_n_per_mm1_5: v(37_000.0),
            damping_ns_per_mm1_25: v(3.7),
            radius_m: v(0.03),
        },
        plunger: Plunger {
            preload_n: v(20.0),
            stiffness_n_per_mm: v(10.0),
            radius_m: v(0.03),
            stroke_mm: v(1.0),
            crest_rad: v(1f64.to_radians()),
            entry_ramp_rad: v(30f64.to_radians()),
            hold_ramp_rad: v(50f64.to_radians()),
        },
        magnet: Magnet {
            force_n: v(10.0),
            decay_mm: v(0.5),
            reach_mm: v(2.0),
            radius_m: v(0.03),
        },
        switch_travel_rad: v(0.05f64.to_radians()),
        lock: Lock::Detent,
    }
}

#[test]
fn conservative_torque_is_minus_the_gradient_of_the_potential() {
    for side in [1.0, -1.0] {
        let l = latch(side);
        let mut u = -0.004;
        while u < 0.09 {
            let phi = side * u;
            // Away from the marks, where the law is smooth.
            let near = l.marks().iter().any(|&(_, m)| (u - m).abs() < 1e-5);
            if !near {
                let e = 1e-8;
                let grad = (l.potential_energy(phi + e) - l.potential_energy(phi - e)) / (2.0 * e);
                let f = l.stop_force(phi, 0.0).elastic_n;
                let tau = l.conservative_torque(phi) + l.stop_torque(f);
                assert!(
                    (tau + grad).abs() < 1e-5 * (1.0 + tau.abs()),
                    "u={u}: {tau} vs {}",
                    -grad
                );
            }
            u += 1.3e-4;
        }
    }
}

#[test]
fn stop_pushes_out_never_pulls_and_is_zero_outside() {
    let l = latch(-1.0);
    // side −1: inside the stop is φ > 0.
    assert_eq!(l.stop_force(-0.01, 5.0).applied_n(), 0.0);
    let f = l.stop_force(0.001, 0.0);
    let delta: f64 = 0.001 * 30.0;
    assert!((f.elastic_n - 37_000.0 * delta.powf(1.5)).abs() < 1e-9 * f.elastic_n);
    assert!(
        l.stop_torque(f.applied_n()) < 0.0,
        "pushes φ back towards the stowed side"
    );
    // Leaving fast: the raw force pulls, the applied one is zero.
    let leaving = l.stop_force(1e-6, -50.0);
    assert!(leaving.raw_n < 0.0 && leaving.applied_n() == 0.0);
    // Damping adds while going in.
    assert!(l.stop_force(0.001, 1.0).raw_n > f.raw_n);
}

#[test]
fn plunger_resists_on_entry_pushes_in_past_the_crest_and_stores_the_engagement() {
    let l = latch(1.0);
    let c = l.plunger.crest_rad;
    let on_entry = c + 0.5 * l.entry_width_rad();
    let on_hold = c - 0.5 * l.hold_width_rad();
    assert!(
        l.conservative_torque(on_entry) > 0.0,
        "resists the approach"
    );
    assert!(
        l.conservative_torque(on_hold) < 0.0,
        "pushes towards the stop"
    );
    let e = l.engagement_energy();
    assert!((e - (20.0 * 1.0 + 0.5 * 10.0) / 1000.0).abs() < 1e-15);
    let v_crest = l.potential_energy(c) - l.magnet_energy(c);
    assert!((v_crest - e).abs() < 1e-12);
    // The torque at the crest from the hold side is the holding torque.
    let just_in = l.plunger_torque_on(PlungerSegment::Hold, c);
    assert!((just_in + l.holding_torque()).abs() < 1e-12);
    let just_out = l.plunger_torque_on(PlungerSegment::Entry, c);
    assert!((just_out - l.entry_torque()).abs() < 1e-12);
    assert!(l.escape_energy() > 0.0);
}

#[test]
fn magnet_is_f0_at_contact_zero_at_its_reach_and_pulls_in() {
    let l = latch(1.0);
    assert!((l.magnet_force_on(true, 0.0) - 10.0).abs() < 1e-12);
    let reach = 2.0 / 30.0;
    assert!(l.magnet_force_on(true, reach).abs() < 1e-12);
    assert!(!l.magnet_within(reach * 1.01));
    assert!(l.magnet_energy(0.0) < 0.0 && l.magnet_energy(reach * 1.01) == 0.0);
    assert!(l.magnet_energy(reach * 0.999).abs() < 1e-6);
}

#[test]
fn switch_closes_at_its_travel_and_marks_are_ordered() {
    let l = latch(-1.0);
    assert!(!l.switch_closed(-0.06f64.to_radians()));
    assert!(l.switch_closed(-0.04f64.to_radians()));
    assert!(l.switch_closed(0.01));
    let m = l.marks();
    assert!(m[2].1 > m[1].1 && m[1].1 > m[3].1);
    assert_eq!(l.check(), Ok(()));
}

#[test]
fn bad_parameters_are_refused_and_never_panic() {
    let mut l = latch(1.0);
    l.plunger.hold_ramp_rad = 2.0;
    assert_eq!(l.check(), Err(LatchError::Ramp(LatchParam::HoldRamp)));
    let mut l = latch(1.0);
    l.stop.radius_m = 0.0;
    assert_eq!(
        l.check(),
        Err(LatchError::NotPositive(LatchParam::StopRadius))
    );
    let mut l = latch(0.5);
    assert_eq!(l.check(), Err(LatchError::Side));
    l.magnet.decay_mm = 0.0;
    for x in [f64::NAN, -1.0, 0.0, 1.0, f64::INFINITY] {
        let _ = l.torque(x, x);
        let _ = l.potential_energy(x);
    }
}

#[test]
fn f32_agrees_with_f64() {
    let l = latch(1.0f64);
    let l32 = latch(1.0f32);
    for phi in [-0.002, 0.005, 0.02, 0.04] {
        let a = l.torque(phi, 0.3);
        let b = l32.torque(phi as f32, 0.3) as f64;
        assert!((a - b).abs() < 1e-4 * (1.0 + a.abs()), "{phi}: {a} vs {b}");
    }
}
