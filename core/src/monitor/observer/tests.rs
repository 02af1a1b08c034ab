//! Tests of `observer`.

use super::*;
use crate::monitor::rate_filter::{Fusion, JerkAdaptation, RateFilter};
use crate::{ChainState, Friction, GlobalEffects, Joint, JointEffects, Panel, Spring};

/// Three identical free panels without springs (also used by the
/// rollout's tests).
pub(crate) fn chain() -> Chain<f32, 3> {
    let p = Panel {
        length_m: 0.8,
        mass_kg: 3.5,
        com_m: 0.4,
        inertia_kgm2: 0.27,
    };
    let j = Joint {
        stowed_rad: 1.0,
        spring: Spring::None,
        friction: Friction::default(),
        effects: JointEffects::default(),
    };
    Chain::new([p; 3], [j; 3], GlobalEffects::default()).unwrap()
}

#[test]
fn momentum_terms_match_the_chain() {
    let c = chain();
    let phi = [0.3f32, -1.1, 0.7];
    let om = [0.5f32, -0.2, 1.3];
    let t = momentum_terms(&c, &phi, &om);
    let (m, beta) = (t.mass, t.beta);
    let m_ref = c.mass_matrix(&phi);
    // M φ̈ = rhs of chain.rs with no joint torques: rhs = −SᵀC.
    let x = ChainState {
        phi: phi.map(f64::from),
        phi_dot: om.map(f64::from),
    };
    let _ = x;
    let (_, rhs) = c.equations(&ChainState { phi, phi_dot: om }, &crate::Mode::default());
    for j in 0..3 {
        assert!(
            (rhs[j] - t.coriolis[j]).abs() < 1e-4,
            "{j}: {} vs {}",
            rhs[j],
            t.coriolis[j]
        );
    }
    for j in 0..3 {
        for k in 0..3 {
            assert!((m[j][k] - m_ref[j][k]).abs() < 1e-5, "{j}{k}");
        }
    }
    // β_j = ∂T/∂φ_j by central differences of the kinetic energy (f64).
    let c64 = {
        let p = Panel {
            length_m: 0.8,
            mass_kg: 3.5,
            com_m: 0.4,
            inertia_kgm2: 0.27,
        };
        let j = Joint {
            stowed_rad: 1.0,
            spring: Spring::None,
            friction: Friction::default(),
            effects: JointEffects::default(),
        };
        Chain::<f64, 3>::new([p; 3], [j; 3], GlobalEffects::default()).unwrap()
    };
    for j in 0..3 {
        let mut a = phi.map(f64::from);
        let mut b = a;
        a[j] += 1e-6;
        b[j] -= 1e-6;
        let w = om.map(f64::from);
        let ta = c64.kinetic_energy(&ChainState { phi: a, phi_dot: w });
        let tb = c64.kinetic_energy(&ChainState { phi: b, phi_dot: w });
        let fd = (ta - tb) / 2e-6;
        assert!(
            (f64::from(beta[j]) - fd).abs() < 1e-4,
            "β_{j}: {} vs {fd}",
            beta[j]
        );
    }
    // A rigid rotation of the whole chain does not change T.
    assert!(beta[0].abs() < 1e-5);
}

#[test]
fn momentum_rate_is_joint_torque_plus_beta() {
    // ṗ = Ṁ φ̇ + M φ̈ with φ̈ from the chain's own equations must equal
    // τ + β (Lagrange): checks β's sign against chain.rs's Coriolis terms.
    let p = Panel {
        length_m: 0.8,
        mass_kg: 3.5,
        com_m: 0.4,
        inertia_kgm2: 0.27,
    };
    let j = Joint {
        stowed_rad: 1.0,
        spring: Spring::Linear {
            preload_nm: 1.0,
            stiffness_nm_per_rad: 0.4,
            count: 2.0,
        },
        friction: Friction::coulomb(0.3),
        effects: JointEffects::default(),
    };
    let c64 = Chain::<f64, 3>::new([p; 3], [j; 3], GlobalEffects::default()).unwrap();
    let c32 = Chain::<f32, 3>::new(
        [Panel {
            length_m: 0.8f32,
            mass_kg: 3.5,
            com_m: 0.4,
            inertia_kgm2: 0.27,
        }; 3],
        [Joint {
            stowed_rad: 1.0f32,
            spring: Spring::None,
            friction: Friction::default(),
            effects: JointEffects::default(),
        }; 3],
        GlobalEffects::default(),
    )
    .unwrap();
    let phi = [-0.9f64, 2.1, -1.3];
    let w = [0.7f64, -1.9, 3.1];
    let x = ChainState { phi, phi_dot: w };
    let mode = crate::Mode::default();
    let acc = c64.acceleration(&x, &mode).unwrap();
    let eps = 1e-6;
    let mp = c64.mass_matrix(&core::array::from_fn(|k| phi[k] + eps * w[k]));
    let mm = c64.mass_matrix(&core::array::from_fn(|k| phi[k] - eps * w[k]));
    let m = c64.mass_matrix(&phi);
    let beta = momentum_terms(&c32, &phi.map(|v| v as f32), &w.map(|v| v as f32)).beta;
    for jj in 0..3 {
        let mut pdot = 0.0;
        for k in 0..3 {
            pdot += (mp[jj][k] - mm[jj][k]) / (2.0 * eps) * w[k] + m[jj][k] * acc[k];
        }
        let tau = c64.joint_torque(jj, phi[jj], w[jj], crate::Branch::Unfold);
        let want = tau + f64::from(beta[jj]);
        assert!(
            (pdot - want).abs() < 1e-3,
            "joint {jj}: ṗ = {pdot}, τ + β = {want}"
        );
    }
}

#[test]
fn rate_filter_tracks_a_ramp() {
    let adapt = JerkAdaptation {
        q_min: 1e-3,
        q_max: 1e4,
        high: 2.0,
        low: 1.2,
        weight: 0.05,
    };
    let mut f = RateFilter::new(1.0, 1e-3, 1.0, 10.0);
    let mut noise = 0x1234_5678u32;
    for i in 1..=400 {
        let t = i as f32 * 0.01;
        f.predict(0.01, 0.0);
        noise = noise.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        let n = ((noise >> 8) as f32 / (1u32 << 24) as f32 - 0.5) * 6e-4;
        assert_eq!(
            f.update(1.0 - 0.2 * t + n, 3e-8, 36.0, &adapt),
            Fusion::Accepted
        );
    }
    assert!((f.rate() + 0.2).abs() < 2e-3, "{}", f.rate());
    assert!(
        f.jerk_psd() < 0.1,
        "a steady ramp needs little process noise: {}",
        f.jerk_psd()
    );
    assert!(f.is_healthy());
    // A spike is gated out.
    f.predict(0.01, 0.0);
    assert_eq!(
        f.update(f.angle() + 0.1, 3e-8, 36.0, &adapt),
        Fusion::Rejected
    );
}

/// Observer tuning for noise-free data: no random walk.
fn exact_data_tuning() -> ObserverTuning {
    ObserverTuning {
        bandwidth_per_s: 10.0,
        coulomb_threshold_rad_s: 0.01,
        coulomb_walk: 0.0,
        viscous_walk: 0.0,
        residual_var_floor: 1e-4,
    }
}

#[test]
fn observer_recovers_coulomb_friction_of_a_single_body() {
    // I ω̇ = τ_s + d with d = −T_C tanh(ω/ω_c), τ_s = 3 N·m: exact data,
    // the default-like prior.
    let tc = 1.2f32;
    let (o, _) = single_body(0.05, 0.05, tc, 0.0, 0.0);
    let e = o.estimate();
    assert!((e.coulomb_nm - tc).abs() < 0.05 * tc, "{e:?}");
    assert!(o.is_healthy());
}

/// A single body `I ω̇ = 3 − 0.5 ω − T_C tanh(ω/ω_c) − f ω` (the
/// `−0.5 ω` known), started at rate `w0` [rad/s], exact data at 100 Hz
/// for 3 s, observed under a viscous prior `f = 0 ± viscous_sd` and a
/// spring-scale spread `spring_sd_rel`; returns the observer and the
/// final rate [rad/s].
fn single_body(
    viscous_sd: f32,
    spring_sd_rel: f32,
    tc: f32,
    f: f32,
    w0: f32,
) -> (FrictionObserver, f32) {
    let inertia = 2.0f32;
    let mut o = FrictionObserver::new(
        FrictionPrior {
            coulomb_nm: 0.0,
            coulomb_sd_nm: 2.0,
            viscous_nms: 0.0,
            viscous_sd_nms: viscous_sd,
        },
        spring_sd_rel,
    );
    let (mut w, dt) = (w0, 0.01f32);
    for _ in 0..300 {
        // Fine sub-steps of the true motion.
        for _ in 0..100 {
            let d = -tc * libm::tanhf(w / 0.01) - f * w;
            w += (dt / 100.0) * (3.0 - 0.5 * w + d) / inertia;
        }
        o.step(
            &ObserverInput {
                momentum: inertia * w,
                spring_torque_nm: 3.0,
                beta_nm: -0.5 * w,
                rate_rad_s: w,
                rate_var: 0.0,
                dt_s: dt,
                learn: true,
            },
            &exact_data_tuning(),
        );
    }
    (o, w)
}

/// [`single_body`] under a wide viscous prior `f = 0 ± 1` and a spring
/// scale fixed at 1 (the spring torque is a constant, collinear with
/// the Coulomb regressor).
fn single_body_with_wide_viscous_prior(tc: f32, f: f32, w0: f32) -> (FrictionObserver, f32) {
    single_body(1.0, 0.0, tc, f, w0)
}

#[test]
fn a_damping_of_zero_under_a_wide_prior_leaves_the_coulomb_estimate_alone() {
    // From rest, no damping: f sits at its bound 0, met in the metric
    // Σ⁻¹, and the Coulomb estimate stays on the truth. (Noisy data
    // press f against the bound much harder: on T01 with the sensor
    // model, `tests/monitor/refresh.rs` viscous, a clamp of f alone let joint
    // 3's Coulomb estimate drift to 21.8 N·m against 0.001.)
    let (o, _) = single_body_with_wide_viscous_prior(1.2, 0.0, 0.0);
    let e = o.estimate();
    assert!((e.coulomb_nm - 1.2).abs() < 0.05 * 1.2, "{e:?}");
    assert!(e.viscous_nms <= 2.0 * libm::sqrtf(e.viscous_var), "{e:?}");
    assert!(o.is_healthy());
}

#[test]
fn conditioned_on_no_damping_the_coulomb_torque_holds_the_friction_seen() {
    // Started at its terminal rate (3 − 0.5 ω − 1.2 − 0.3 ω = 0 at
    // 2.25 rad/s) the body never changes rate: the data fix T_C + f ω
    // there and nothing of the split, and f stays unresolved.
    // Conditioned on f = 0 the Coulomb torque is that friction, with no
    // viscous term and a smaller variance.
    let (tc, f) = (1.2f32, 0.3f32);
    let (o, w) = single_body_with_wide_viscous_prior(tc, f, 2.25);
    let seen = tc + f * w;
    let e = o.estimate();
    assert!(e.viscous_var > 0.25, "f is not resolved: {e:?}");
    assert!(
        (e.coulomb_nm + e.viscous_nms * w - seen).abs() < 0.05 * seen,
        "{e:?}"
    );
    let c = o.estimate_given_viscous(0.0);
    assert!((c.coulomb_nm - seen).abs() < 0.05 * seen, "{c:?} vs {seen}");
    assert_eq!((c.viscous_nms, c.viscous_var, c.cov), (0.0, 0.0, 0.0));
    assert!(
        c.coulomb_var > 0.0 && c.coulomb_var < e.coulomb_var,
        "{c:?} {e:?}"
    );
    // Conditioned on the estimate itself nothing moves.
    let same = o.estimate_given_viscous(e.viscous_nms);
    assert!(
        (same.coulomb_nm - e.coulomb_nm).abs() < 1e-4,
        "{same:?} {e:?}"
    );
}

#[test]
fn observer_separates_a_spring_error_from_friction_when_the_torque_varies() {
    // I φ̈ = (1 + κ) τ_s(φ) − T_C tanh(φ̇/ω_c), τ_s = 3 − 1.2 φ N·m over
    // φ = 0 … 1.5 rad (the torque falls to 40 %): the spring is 8 %
    // stronger than its curve.
    let (inertia, tc, kappa) = (2.0f32, 1.0f32, 0.08f32);
    let tuning = exact_data_tuning();
    let prior = FrictionPrior {
        coulomb_nm: 0.0,
        coulomb_sd_nm: 2.0,
        viscous_nms: 0.0,
        viscous_sd_nms: 0.05,
    };
    let mut o = FrictionObserver::new(prior, 0.05);
    let spring = |phi: f32| 3.0 - 1.2 * phi;
    let (mut phi, mut w, dt) = (0.0f32, 0.0f32, 0.01f32);
    while phi < 1.5 {
        for _ in 0..100 {
            let h = dt / 100.0;
            let d = -tc * libm::tanhf(w / 0.01);
            w += h * ((1.0 + kappa) * spring(phi) + d) / inertia;
            phi += h * w;
        }
        o.step(
            &ObserverInput {
                momentum: inertia * w,
                spring_torque_nm: spring(phi),
                beta_nm: 0.0,
                rate_rad_s: w,
                rate_var: 0.0,
                dt_s: dt,
                learn: true,
            },
            &tuning,
        );
    }
    let e = o.estimate();
    assert!((e.spring_scale_err - kappa).abs() < 0.02, "{e:?}");
    assert!((e.coulomb_nm - tc).abs() < 0.05 * tc, "{e:?}");
}
