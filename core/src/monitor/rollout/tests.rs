//! Tests of `rollout`.

use super::*;
use crate::{Curve, Friction, GlobalEffects, Joint, JointEffects, Panel, Spring};

/// One panel on one hinge.
fn one_joint(stowed_rad: f32, spring: Spring<f32>) -> Chain<f32, 1> {
    let p = Panel {
        length_m: 0.8,
        mass_kg: 4.0,
        com_m: 0.4,
        inertia_kgm2: 0.3,
    };
    let j = Joint {
        stowed_rad,
        spring,
        friction: Friction::default(),
        effects: JointEffects::default(),
    };
    Chain::new([p], [j], GlobalEffects::default()).unwrap()
}

fn chain() -> Chain<f32, 1> {
    let spring = Spring::Linear {
        preload_nm: 1.0,
        stiffness_nm_per_rad: 0.5,
        count: 1.0,
    };
    one_joint(1.5, spring)
}

fn run(tc: f32) -> Rollout<1> {
    let cfg = RolloutConfig {
        dt_s: 0.02,
        bracket_dt_s: 0.02,
        glide_dt_s: 0.25,
        steps_per_slice: 255,
        slices_per_sample: 1,
        horizon_s: 20.0,
        coulomb_threshold_rad_s: 0.01,
    };
    let mut r = Rollout::new(RolloutStart {
        state: ChainState {
            phi: [1.5],
            phi_dot: [0.0],
        },
        latched: [false],
        coulomb_nm: [tc],
        viscous_nms: [0.0],
        spring_scale: [1.0],
        capture_rad: [0.0],
    });
    for _ in 0..100 {
        r.advance(&chain(), &cfg);
    }
    assert!(r.is_done());
    r
}

#[test]
fn latches_below_and_stalls_above_the_spring_torque() {
    // The spring gives 1 to 1.75 N·m: E_D = 2.06 J over 1.5 rad.
    let r = run(0.5);
    assert!(r.outcome()[0].latches);
    // I = 4·0.4² + 0.3 = 0.94; t ≈ √(2·1.5·I/(1.4 − 0.5)) ≈ 1.8 s.
    let t = r.outcome()[0].latch_after_s;
    assert!(t > 1.2 && t < 2.4, "{t}");
    // Friction above the preload: the joint stops short (creeps at rest).
    assert!(!run(1.6).outcome()[0].latches);
}

/// Three free panels without springs or friction: joint 3 swings into
/// its latch, the others coast on at the rates the impact left them.
fn coast(capture_3: f32, dt: f32) -> [JointOutcome; 3] {
    let chain = crate::monitor::observer::tests::chain();
    let cfg = RolloutConfig {
        dt_s: dt,
        bracket_dt_s: dt,
        glide_dt_s: dt,
        steps_per_slice: 255,
        slices_per_sample: 1,
        horizon_s: 10.0,
        coulomb_threshold_rad_s: 0.01,
    };
    let mut r = Rollout::new(RolloutStart {
        state: ChainState {
            phi: [-1.2, 2.0, -0.3],
            phi_dot: [0.5, -1.5, 5.0],
        },
        latched: [false; 3],
        coulomb_nm: [0.0; 3],
        viscous_nms: [0.0; 3],
        spring_scale: [1.0; 3],
        capture_rad: [0.0, 0.0, capture_3],
    });
    while !r.is_done() {
        r.advance(&chain, &cfg);
    }
    r.outcome()
}

#[test]
fn a_latch_at_the_capture_angle_keeps_the_other_joints_momenta() {
    // Reference: fine steps, joint 3 latching at 0 itself.
    let exact = coast(0.0, 1e-4);
    // Monitor-like steps, joint 3 caught 3° before its latch.
    let caught = coast(3f32.to_radians(), 0.01);
    // Joint 3 latches first; joint 1 then coasts in (the impact's
    // momentum decides when: 3.7 % late if taken after the jump to the
    // latch angle); joint 2 swings away.
    assert!(exact[0].latches && exact[2].latches && !exact[1].latches);
    for j in 0..3 {
        assert_eq!(exact[j].latches, caught[j].latches, "joint {}", j + 1);
        let (a, b) = (exact[j].latch_after_s, caught[j].latch_after_s);
        assert!(
            (a - b).abs() <= 0.002 * a,
            "joint {}: {a} s against {b} s",
            j + 1
        );
    }
}

/// A spring that stiffens towards the latch, as the tape springs of seed
/// 001 do over the second half of their stroke: `1.5 − 0.5|φ|` N·m.
const STIFFENING: Spring<f32> = Spring::Linear {
    preload_nm: 1.5,
    stiffness_nm_per_rad: -0.5,
    count: 1.0,
};

const WC: f32 = 0.01;

/// `∫ dφ / (ω_c artanh(τ(φ)/T_C))` from `from` to 0 for [`STIFFENING`]
/// by a fine midpoint rule (f64).
fn creep_reference(from: f64, tc: f64) -> f64 {
    let n = 100_000;
    let h = from / n as f64;
    (0..n)
        .map(|k| {
            let abs = from - (k as f64 + 0.5) * h;
            h / (f64::from(WC) * ((1.5 - 0.5 * abs) / tc).atanh())
        })
        .sum()
}

fn joint(from_rad: f32, coulomb_nm: f32) -> CreepJoint {
    CreepJoint {
        from_rad,
        capture_rad: 0.0,
        spring_scale: 1.0,
        coulomb_nm,
        viscous_nms: 0.0,
        inertia_kgm2: 1.0,
    }
}

#[test]
fn creep_time_is_the_quasi_static_quadrature() {
    // Constant spring: ω = ω_c artanh(1/2), 0.5 rad in 91.0 s.
    let flat = Spring::Linear {
        preload_nm: 1.0,
        stiffness_nm_per_rad: 0.0,
        count: 1.0,
    };
    let expect = 0.5 / (WC * 0.5f32.atanh());
    match creep(&flat, &joint(0.5, 2.0), WC, f32::INFINITY) {
        Creep::Covers(t) => assert!((t / expect - 1.0).abs() < 1e-4, "{t} vs {expect}"),
        other => panic!("{other:?}"),
    }
    // Viscous friction slows the creep: T_C tanh(ω/ω_c) + f ω = τ.
    let w = {
        let (mut lo, mut hi) = (0.0f64, 0.1f64);
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if 2.0 * (mid / 0.01).tanh() + 5.0 * mid > 1.0 {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        lo
    };
    let viscous = CreepJoint {
        viscous_nms: 5.0,
        ..joint(0.5, 2.0)
    };
    match creep(&flat, &viscous, WC, f32::INFINITY) {
        Creep::Covers(t) => {
            let expect = 0.5 / w;
            assert!(
                (f64::from(t) / expect - 1.0).abs() < 0.01,
                "{t} vs {expect}"
            );
        }
        other => panic!("{other:?}"),
    }
    // Stiffening spring: 8 panels against a fine quadrature.
    let expect = creep_reference(1.0, 1.6);
    match creep(&STIFFENING, &joint(1.0, 1.6), WC, f32::INFINITY) {
        Creep::Covers(t) => assert!(
            (f64::from(t) / expect - 1.0).abs() < 0.01,
            "{t} vs {expect}"
        ),
        other => panic!("{other:?}"),
    }
    // The spring scale counts: 1.2 × 1.45 > 1.6 before the latch.
    let stronger = CreepJoint {
        spring_scale: 1.2,
        ..joint(1.0, 1.6)
    };
    assert!(matches!(
        creep(&STIFFENING, &stronger, WC, f32::INFINITY),
        Creep::BreaksFree(t) if t > 0.0
    ));
    assert_eq!(
        creep(&Spring::None, &joint(1.0, 1.6), WC, f32::INFINITY),
        Creep::Stops
    );
    assert_eq!(
        creep(&STIFFENING, &joint(0.0, 1.6), WC, f32::INFINITY),
        Creep::Covers(0.0)
    );
}

/// A snap-through peak inside the capture angle: 1 N·m down to 2°,
/// rising to 20 N·m at 0.5°. A joint that creeps in at 1.2 N·m of
/// friction breaks free where the peak passes 1.2 N·m and accelerates
/// from its creep rate; the one-joint integration agrees with a fine
/// explicit one (f64, 10 µs steps).
#[test]
fn a_creep_into_the_capture_angle_snaps_through_in_its_own_time() {
    let pts = [(0.0f32, 0.0f32), (0.5, 20.0), (2.0, 1.0), (90.0, 1.0)];
    let curve = Curve::new(&pts, crate::physics::spring::Interp::Linear).unwrap();
    let spring = Spring::Curve {
        unfold: curve,
        fold: crate::physics::spring::Fold::SameAsUnfold,
        count: 1.0,
    };
    let (tc, inertia) = (1.2f64, 3.0f64);
    let capture = 2.0f32.to_radians();
    let j = CreepJoint {
        from_rad: capture,
        capture_rad: capture,
        spring_scale: 1.0,
        coulomb_nm: tc as f32,
        viscous_nms: 0.0,
        inertia_kgm2: inertia as f32,
    };
    let Creep::Covers(t) = creep(&spring, &j, WC, f32::INFINITY) else {
        panic!("no snap-through");
    };
    // Reference: from the creep rate at the capture angle.
    let wc = f64::from(WC);
    let torque = |abs: f64| f64::from(curve.eval(abs.to_degrees() as f32));
    let (mut abs, mut w, mut t_ref) = (f64::from(capture), wc * (1.0 / tc).atanh(), 0.0);
    let h = 1e-5;
    while abs > 0.0 {
        let a = (torque(abs) - tc * (w / wc).tanh()) / inertia;
        abs -= h * w;
        w += h * a;
        t_ref += h;
    }
    assert!(t_ref > 0.1, "a slow snap: {t_ref} s");
    assert!((f64::from(t) - t_ref).abs() < 0.01, "{t} vs {t_ref}");
}

/// A joint held by its friction that creeps ever faster towards the
/// latch: the rollout latches it when the creep gets there before the
/// horizon (a constant-rate extrapolation from the start would take
/// 1.3 times as long and call a stall), and stalls it when not.
#[test]
fn a_creep_that_speeds_up_is_followed_to_the_latch() {
    let chain = one_joint(1.0, STIFFENING);
    let t_creep = creep_reference(1.0, 1.6) as f32;
    let t_const = 1.0 / (WC * (1.0f32 / 1.6).atanh());
    assert!(t_const > 1.3 * t_creep, "{t_const} vs {t_creep}");
    let run = |horizon_s: f32| {
        let cfg = RolloutConfig {
            dt_s: 0.01,
            bracket_dt_s: 0.01,
            glide_dt_s: 0.25,
            steps_per_slice: 255,
            slices_per_sample: 1,
            horizon_s,
            coulomb_threshold_rad_s: WC,
        };
        let mut r = Rollout::new(RolloutStart {
            state: ChainState {
                phi: [1.0],
                phi_dot: [0.0],
            },
            latched: [false],
            coulomb_nm: [1.6],
            viscous_nms: [0.0],
            spring_scale: [1.0],
            capture_rad: [0.0],
        });
        for _ in 0..10 {
            r.advance(&chain, &cfg);
        }
        assert!(r.is_done(), "a creep ends by quadrature");
        r.outcome()[0]
    };
    let out = run(1.2 * t_creep);
    assert!(out.latches);
    assert!(
        (out.latch_after_s / t_creep - 1.0).abs() < 0.02,
        "{} vs {t_creep}",
        out.latch_after_s
    );
    assert!(!run(0.9 * t_creep).latches);
}

#[test]
fn quantile_inverts_the_cdf() {
    assert!((normal_quantile(0.9) - 1.281_551_6).abs() < 1e-4);
    assert_eq!(normal_quantile(0.5), 0.0);
}

/// A viscous creep: spring `1.2 + 0.5 φ` N·m against `T_C` = 1 N·m and
/// `f` = 2 N·m·s/rad, from rest at 1.5 rad: the rate settles (in
/// `I/f` ≈ 0.5 s) to the balance of spring and friction, slow and smooth.
/// The lengthened steps find the latch time of fixed 10 ms steps within
/// 3 % in under a fifth of the steps. Here `h f ≈ I` (steps as long as the
/// relaxation time), where a linearly implicit step tracks the balance to
/// first order only: 2.4 % early (`docs/monitor.md` §6, the glide).
#[test]
fn a_glide_takes_long_steps_and_keeps_the_latch_time() {
    let spring = Spring::Linear {
        preload_nm: 1.2,
        stiffness_nm_per_rad: 0.5,
        count: 1.0,
    };
    let chain = one_joint(1.5, spring);
    let run = |glide_dt_s: f32| {
        let cfg = RolloutConfig {
            dt_s: 0.01,
            bracket_dt_s: 0.01,
            glide_dt_s,
            steps_per_slice: 1,
            slices_per_sample: 1,
            horizon_s: 20.0,
            coulomb_threshold_rad_s: 0.01,
        };
        let mut r = Rollout::new(RolloutStart {
            state: ChainState {
                phi: [1.5],
                phi_dot: [0.0],
            },
            latched: [false],
            coulomb_nm: [1.0],
            viscous_nms: [2.0],
            spring_scale: [1.0],
            capture_rad: [0.0],
        });
        let mut steps = 0;
        while !r.is_done() && steps < 10_000 {
            r.advance(&chain, &cfg);
            steps += 1;
        }
        assert!(r.is_done() && r.outcome()[0].latches);
        (r.outcome()[0].latch_after_s, steps)
    };
    let (t_fixed, n_fixed) = run(0.01);
    let (t_glide, n_glide) = run(0.5);
    assert!(t_fixed > 4.0 && t_fixed < 8.0, "{t_fixed}");
    assert!(
        (t_glide - t_fixed).abs() <= 0.03 * t_fixed,
        "{t_glide} s against {t_fixed} s"
    );
    assert!(5 * n_glide < n_fixed, "{n_glide} steps against {n_fixed}");
}
