//! Tests of the stick–slip transitions (`cargo test -p deploywatch-core stick`).

use super::*;
use crate::physics::chain::{GlobalEffects, Joint, JointEffects, Panel};
use crate::physics::friction::Friction;
use crate::physics::spring::Spring;

fn one(friction: f64, preload: f64) -> Chain<f64, 1> {
    let panel = Panel {
        length_m: 1.0,
        mass_kg: 2.0,
        com_m: 0.5,
        inertia_kgm2: 0.2,
    };
    let joint = Joint {
        stowed_rad: 1.0,
        spring: Spring::Linear {
            preload_nm: preload,
            stiffness_nm_per_rad: 0.0,
            count: 1.0,
        },
        friction: Friction::coulomb(friction),
        effects: JointEffects::default(),
    };
    Chain::new([panel], [joint], GlobalEffects::default()).unwrap()
}

#[test]
fn a_spring_weaker_than_the_friction_is_held_and_a_stronger_one_is_not() {
    for (friction, preload, held) in [(1.0, 0.5, true), (1.0, 1.5, false)] {
        let c = one(friction, preload);
        let band = c.stick_band(0, 0.5);
        let (m, rhs) = c.equations(
            &crate::ChainState {
                phi: [0.5],
                phi_dot: [0.0],
            },
            &crate::Mode {
                latched: [true],
                ..Default::default()
            },
        );
        let r = holding_torques(&m, &rhs, &[true]).unwrap()[0];
        // Nothing else acts: the holding torque is zero, the band is the
        // spring's −preload ± friction.
        assert!(r.abs() < 1e-12);
        assert!((band.lo - (-preload - friction)).abs() < 1e-12);
        assert_eq!(band.holds(r), held, "{band:?}");
        if !held {
            assert_eq!(band.slip_direction(r), -1.0);
        }
    }
}

#[test]
fn stribeck_effect_peaks_at_its_excess_and_raises_the_static_level() {
    let mut c = one(0.0, 0.0);
    if let Some(jt) = c.joint_mut(0) {
        jt.effects.coulomb_nm = 0.3;
        jt.effects.stribeck_excess_nm = 0.4;
        jt.effects.stribeck_rad_s = 0.05;
        jt.effects.quadratic_nms2_per_rad2 = 2.0;
    }
    let w = 0.05 / 2f64.sqrt();
    let t = c.joint_torque(0, 0.5, w, Branch::Fold);
    let expect = 0.3 * (w / 0.01).tanh() + 0.4 + 2.0 * w * w;
    assert!((t + expect).abs() < 1e-9, "{t} vs {}", -expect);
    // Far past ω_st the excess is gone: kinetic + quadratic only.
    let t = c.joint_torque(0, 0.5, 1.0, Branch::Fold);
    assert!((t + 0.3 + 2.0).abs() < 1e-6, "{t}");
    assert!((c.static_friction_nm(0) - 0.7).abs() < 1e-12);
    // The kinetic level leaves the excess out: its band is the static
    // band narrowed by 0.4 N·m on each side.
    assert!((c.kinetic_friction_nm(0) - 0.3).abs() < 1e-12);
    let (s, k) = (c.stick_band(0, 0.5), c.kinetic_band(0, 0.5));
    assert!((k.lo - (s.lo + 0.4)).abs() < 1e-12 && (k.hi - (s.hi - 0.4)).abs() < 1e-12);
}
