//! Tests of the effect vocabulary and its syntax.

use super::*;

/// `EVERY` is the vocabulary: each kind once, and a kind added to the
/// enum does not compile here until it is listed (the match is
/// exhaustive) — so every test over `EVERY` covers it.
#[test]
fn every_lists_each_kind_once() {
    use EffectKind as K;
    let listed = |k: K| match k {
        K::CoulombFriction
        | K::ViscousDamping
        | K::QuadraticDamping
        | K::StribeckFriction
        | K::SpringSoftening
        | K::HarnessStiffness
        | K::LatchDetent
        | K::AirDrag
        | K::RigTilt
        | K::EncoderOffset
        | K::TorqueTable
        | K::PlungerWeakening
        | K::MagnetWeakening
        | K::RigFriction
        | K::WireLength
        | K::FrameOffset => K::EVERY.iter().filter(|e| **e == k).count(),
        #[cfg(feature = "demo-effect")]
        K::DemoDrag => K::EVERY.iter().filter(|e| **e == k).count(),
    };
    for k in K::EVERY {
        assert_eq!(listed(k), 1, "{k}");
        assert_eq!(k.name().parse::<K>().ok(), Some(k));
    }
}

#[test]
fn parses_the_cli_syntax() {
    let e: Effect = "coulomb_friction:joint=2:value=1.7".parse().unwrap();
    assert_eq!(e, Effect::joint(EffectKind::CoulombFriction, 2, 1.7));
    let e: Effect = "rig_tilt:value=0.05:alpha_deg=30".parse().unwrap();
    assert_eq!(
        e.law,
        Law::RigTilt {
            g_m_s2: 0.05,
            alpha_deg: 30.0
        }
    );
    assert!("friction:joint=1:value=1".parse::<Effect>().is_err());
    assert!("air_drag:value=abc".parse::<Effect>().is_err());
    assert!("air_drag".parse::<Effect>().is_err());
    let e: Effect = "air_drag:joint=1:value=0.2".parse().unwrap();
    assert!(e.validate(2).is_err());
    let e: Effect = "harness_stiffness:joint=3:value=0.2".parse().unwrap();
    assert!(e.validate(2).is_err());
    assert!(e.validate(3).is_ok());
    // Values that would turn the effect into another one are refused.
    for bad in [
        "coulomb_friction:joint=1:value=-1",
        "spring_softening:joint=1:value=1",
        "harness_stiffness:joint=1:value=-0.1",
    ] {
        let e: Effect = bad.parse().unwrap();
        assert!(
            matches!(e.validate(2), Err(EffectError::OutOfRange { .. })),
            "{bad}"
        );
    }
    let e: Effect = "spring_softening:joint=1:value=-0.2".parse().unwrap();
    assert!(e.validate(2).is_ok(), "a negative softening stiffens");
    // A key given twice would lose its first value without a word.
    for twice in [
        "coulomb_friction:joint=1:value=0.1:value=0.2",
        "coulomb_friction:joint=1:joint=3:value=0.1",
        "coulomb_friction:joint=1: value=0.1:value =0.2",
    ] {
        assert!(
            matches!(
                twice.parse::<Effect>(),
                Err(EffectError::RepeatedKey { .. })
            ),
            "{twice}"
        );
    }
}

#[test]
fn parses_and_prints_a_torque_table() {
    let text = "torque_table:joint=2:value=0.3:angle_deg=-90,0:torque_nm=0.3,0:rate_deg_s=0,50:rate_torque_nm=0,-0.1";
    let e: Effect = text.parse().unwrap();
    assert_eq!(e.kind(), EffectKind::TorqueTable);
    assert_eq!(e.value(), 0.3);
    assert_eq!(e.to_string(), text);
    assert!(e.validate(2).is_ok());
    assert!("torque_table:joint=1:angle_deg=0,1"
        .parse::<Effect>()
        .is_err());
    assert!("air_drag:value=1:angle_deg=0,1:torque_nm=1,1"
        .parse::<Effect>()
        .is_err());
}

#[test]
fn stribeck_and_quadratic_effects_parse_print_and_reach_the_core() {
    let text = "stribeck_friction:joint=2:value=0.3:excess_nm=0.4:stribeck_rad_s=0.05";
    let e: Effect = text.parse().unwrap();
    assert_eq!(
        e.law,
        Law::StribeckFriction {
            kinetic_nm: 0.3,
            excess_nm: 0.4,
            rate_rad_s: 0.05
        }
    );
    assert_eq!(e.to_string(), text);
    assert!("stribeck_friction:joint=2:value=0.3"
        .parse::<Effect>()
        .is_err());
    assert!(
        "stribeck_friction:joint=2:value=0.3:excess_nm=0.4:stribeck_rad_s=0"
            .parse::<Effect>()
            .is_err()
    );
    assert!("coulomb_friction:joint=2:value=0.3:excess_nm=0.4"
        .parse::<Effect>()
        .is_err());
    let q: Effect = "quadratic_damping:joint=1:value=0.5".parse().unwrap();
    let (je, _) = to_core(&[e, q], 2);
    assert_eq!(je[1].coulomb_nm, 0.3);
    assert_eq!(
        (je[1].stribeck_excess_nm, je[1].stribeck_rad_s),
        (0.4, 0.05)
    );
    assert_eq!(je[0].quadratic_nms2_per_rad2, 0.5);
    assert!(!EffectKind::ALL.contains(&EffectKind::QuadraticDamping));
    assert!(!EffectKind::ALL.contains(&EffectKind::StribeckFriction));
}
