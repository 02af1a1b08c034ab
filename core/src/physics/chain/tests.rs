//! Tests of the chain's equations.

use super::*;

fn panel() -> Panel<f64> {
    Panel {
        length_m: 0.8,
        mass_kg: 3.5,
        com_m: 0.4,
        inertia_kgm2: 0.27,
    }
}

fn joint(stowed: f64) -> Joint<f64> {
    Joint {
        stowed_rad: stowed,
        spring: Spring::Linear {
            preload_nm: 1.0,
            stiffness_nm_per_rad: 0.5,
            count: 1.0,
        },
        friction: Friction::default(),
        effects: JointEffects::default(),
    }
}

fn chain3() -> Chain<f64, 3> {
    Chain::new(
        [panel(); 3],
        [joint(-1.0), joint(2.0), joint(-2.0)],
        GlobalEffects::default(),
    )
    .unwrap()
}

#[test]
fn mass_matrix_matches_kinetic_energy_by_finite_velocities() {
    // ½ φ̇ᵀ M φ̇ equals Σ ½ (m |ṙ|² + I θ̇²) computed from positions.
    let c = chain3();
    let phi = [0.3, -1.1, 0.7];
    let phid = [0.5, -0.2, 1.3];
    let x = ChainState { phi, phi_dot: phid };
    let ke = c.kinetic_energy(&x);
    let pos = |phi: &[f64; 3]| {
        let th = Chain::<f64, 3>::absolute(phi);
        let mut h = (0.0, 0.0);
        let mut r = [(0.0, 0.0); 3];
        for i in 0..3 {
            r[i] = (h.0 + 0.4 * th[i].cos(), h.1 + 0.4 * th[i].sin());
            h = (h.0 + 0.8 * th[i].cos(), h.1 + 0.8 * th[i].sin());
        }
        (r, th)
    };
    let eps = 1e-6;
    let mut p1 = phi;
    let mut p0 = phi;
    for j in 0..3 {
        p1[j] += eps * phid[j];
        p0[j] -= eps * phid[j];
    }
    let (r1, t1) = pos(&p1);
    let (r0, t0) = pos(&p0);
    let mut ke2 = 0.0;
    for i in 0..3 {
        let vx = (r1[i].0 - r0[i].0) / (2.0 * eps);
        let vy = (r1[i].1 - r0[i].1) / (2.0 * eps);
        let w = (t1[i] - t0[i]) / (2.0 * eps);
        ke2 += 0.5 * (3.5 * (vx * vx + vy * vy) + 0.27 * w * w);
    }
    assert!((ke - ke2).abs() < 1e-8 * ke2, "{ke} vs {ke2}");
}

#[test]
fn latch_impulse_stops_the_joint_and_keeps_the_others_momentum() {
    let c = chain3();
    let x = ChainState {
        phi: [0.0, -0.4, 0.9],
        phi_dot: [1.5, -0.8, 0.6],
    };
    let after = c.latch_impulse(&x, &[true, false, false]).unwrap();
    assert_eq!(after[0], 0.0);
    let m = c.mass_matrix(&x.phi);
    let p0 = mat_vec(&m, &x.phi_dot);
    let p1 = mat_vec(&m, &after);
    assert!((p0[1] - p1[1]).abs() < 1e-12 && (p0[2] - p1[2]).abs() < 1e-12);
    // A plastic impact never adds energy.
    let x1 = ChainState {
        phi: x.phi,
        phi_dot: after,
    };
    assert!(c.kinetic_energy(&x1) < c.kinetic_energy(&x));
}

#[test]
fn tilt_force_is_minus_the_potential_gradient() {
    let mut c = chain3();
    c.global_mut().tilt_m_s2 = 0.3;
    c.global_mut().tilt_alpha_rad = 0.7;
    for j in 0..3 {
        c.joint_mut(j).unwrap().spring = Spring::None;
    }
    let phi = [0.2, -0.5, 1.0];
    let x = ChainState {
        phi,
        phi_dot: [0.0; 3],
    };
    let (_, rhs) = c.equations(&x, &Mode::default());
    for j in 0..3 {
        let mut a = phi;
        let mut b = phi;
        a[j] += 1e-6;
        b[j] -= 1e-6;
        let grad = (c.potential_energy(&a) - c.potential_energy(&b)) / 2e-6;
        assert!((rhs[j] + grad).abs() < 1e-7, "{j}: {} vs {}", rhs[j], -grad);
    }
}

#[test]
fn missing_torque_is_the_torque_an_extra_effect_adds() {
    // Accelerations of a chain with a viscous damper at joint 2, seen by
    // the chain without it: the missing torque is −f φ̇₂ at joint 2 only.
    let plain = chain3();
    let mut damped = plain;
    damped.joint_mut(1).unwrap().effects.viscous_nms = 0.7;
    let x = ChainState {
        phi: [0.2, -0.5, 1.0],
        phi_dot: [0.4, -1.0, 2.0],
    };
    let mode = Mode::default();
    let acc = damped.acceleration(&x, &mode).unwrap();
    let tau = plain.missing_torque(&x, &acc, &mode);
    assert!(tau[0].abs() < 1e-12 && tau[2].abs() < 1e-12, "{tau:?}");
    assert!((tau[1] - 0.7).abs() < 1e-12, "{tau:?}");
    let latched = Mode {
        latched: [true, false, false],
        ..Mode::default()
    };
    let acc = damped.acceleration(&x, &latched).unwrap();
    let tau = plain.missing_torque(&x, &acc, &latched);
    assert_eq!(tau[0], 0.0);
    assert!((tau[1] - 0.7).abs() < 1e-12, "{tau:?}");
}

#[test]
fn air_drag_dissipates() {
    let mut c = chain3();
    c.global_mut().air_drag_kg_m2 = 0.25;
    for j in 0..3 {
        c.joint_mut(j).unwrap().spring = Spring::None;
    }
    let x = ChainState {
        phi: [0.2, -0.5, 1.0],
        phi_dot: [0.4, -1.0, 2.0],
    };
    let (_, rhs) = c.equations(&x, &Mode::default());
    // Power of the drag forces: Σ τ_j φ̇_j < 0 (Coriolis does no work).
    let m = c.mass_matrix(&x.phi);
    let _ = m;
    let cor_free = {
        let mut c2 = c;
        c2.global_mut().air_drag_kg_m2 = 0.0;
        c2.equations(&x, &Mode::default()).1
    };
    let power: f64 = (0..3).map(|j| (rhs[j] - cor_free[j]) * x.phi_dot[j]).sum();
    assert!(power < 0.0);
}

#[test]
fn bad_panel_is_an_error() {
    let mut p = [panel(); 3];
    p[1].mass_kg = 0.0;
    assert_eq!(
        Chain::new(p, [joint(1.0); 3], GlobalEffects::default()).err(),
        Some(ChainError::BadPanel { index: 1 })
    );
}

#[test]
fn acceleration_with_torques_is_acceleration_to_the_bit() {
    // With friction, a softened spring, a harness and a latched joint: the
    // same accelerations as `acceleration`, each free joint's total the
    // bits of `joint_torque`, its spring term the softened spring's, and
    // the latched joint's torques zero.
    let mut c = chain3();
    let j = c.joint_mut(1).unwrap();
    j.friction = Friction::coulomb(0.3);
    j.effects.spring_softening = 0.25;
    j.effects.harness_nm_per_rad = 0.4;
    c.joint_mut(2).unwrap().effects.viscous_nms = 0.7;
    let x = ChainState {
        phi: [0.2, -0.5, 1.0],
        phi_dot: [0.4, -1.0, 2.0],
    };
    let mode = Mode {
        latched: [true, false, false],
        branch: [Branch::Unfold, Branch::Fold, Branch::Unfold],
    };
    let plain = c.acceleration(&x, &mode).unwrap();
    let (acc, torques) = c.acceleration_with_torques(&x, &mode).unwrap();
    assert_eq!(plain.map(f64::to_bits), acc.map(f64::to_bits));
    assert_eq!(torques[0], JointTorque::default());
    for j in 1..3 {
        let total = c.joint_torque(j, x.phi[j], x.phi_dot[j], mode.branch[j]);
        assert_eq!(torques[j].total.to_bits(), total.to_bits(), "joint {j}");
    }
    let spring = c.joints()[1].spring.torque(x.phi[1], Branch::Fold) * 0.75;
    assert_eq!(torques[1].spring.to_bits(), spring.to_bits());
    let spring = c.joints()[2].spring.torque(x.phi[2], Branch::Unfold);
    assert_eq!(torques[2].spring.to_bits(), spring.to_bits());
}
