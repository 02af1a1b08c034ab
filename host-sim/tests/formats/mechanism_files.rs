//! The bundled mechanisms load, and a mechanism written reads back unchanged.

use super::*;

#[test]
fn the_four_bundled_mechanisms_load() {
    let ms = mechanisms();
    let names: Vec<&str> = ms.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "seed000-case1-open",
            "seed000-case3-open",
            "seed001-T01",
            "seed001-T02"
        ]
    );
    let case3 = &ms[1];
    assert_eq!(case3.joint_count(), 2);
    assert_eq!(case3.panels[1].mass_kg, 4.28);
    assert_eq!(case3.joints[0].stowed_deg, 90.0);
    assert_eq!(
        case3.joints[1].spring,
        SpringSpec::Linear {
            preload_nm: 0.711942,
            stiffness_nm_per_rad: 0.909758,
            count: 1
        }
    );
    let t02 = &ms[3];
    assert_eq!(t02.joint_count(), 3);
    assert_eq!(t02.duration_s, 12.0);
    assert_eq!(t02.sample_hz, 100.0);
    assert_eq!(t02.joints[2].stowed_deg, -180.0);
    let SpringSpec::Tape {
        type_name,
        points,
        count,
    } = &t02.joints[0].spring
    else {
        panic!("T02 joint 1 is a tape spring")
    };
    assert_eq!((type_name.as_str(), *count), ("TS-3", 2));
    assert_eq!(points.a, (1.08, 33.43));
    assert_eq!(points.b, (1.15, 0.46));
    assert_eq!(points.d, (0.29, 11.07));
    assert_eq!((points.m_90, points.c_180), (0.385, 0.74));
    for m in &ms {
        assert_eq!(m.joints.len(), m.panels.len());
        for j in &m.joints {
            assert_eq!(
                j.friction,
                Default::default(),
                "{}: nominal, no friction",
                m.name
            );
        }
    }
}

#[test]
fn bundled_mechanisms_round_trip() {
    for m in mechanisms() {
        let text = m.to_toml_string();
        let back = Mechanism::from_toml_str(&text, "written.toml")
            .unwrap_or_else(|e| panic!("{}: {e}\n{text}", m.name));
        assert_eq!(back, m, "{}", m.name);
        assert_eq!(back.to_toml_string(), text, "{}: writing is stable", m.name);
    }
}

#[test]
fn a_declared_free_play_is_read_and_written_back() {
    let text = t01_text().replacen(
        "stowed_deg = -90.0",
        "stowed_deg = -90.0\nfree_play_deg = 0.15",
        1,
    );
    let m = Mechanism::from_toml_str(&text, "play.toml").unwrap_or_else(|e| panic!("{e}"));
    let plays: Vec<f64> = m.joints.iter().map(|j| j.free_play_deg).collect();
    assert_eq!(plays[0], 0.15);
    assert!(plays[1..].iter().all(|&p| p == 0.0), "{plays:?}");
    let back = Mechanism::from_toml_str(&m.to_toml_string(), "back.toml").expect("written");
    assert_eq!(back, m);
}

#[test]
fn a_declared_spring_tolerance_is_read_and_written_back() {
    let text = t01_text().replacen(
        "stowed_deg = -90.0",
        "stowed_deg = -90.0\nspring_tolerance_pct = 3",
        1,
    );
    let m = Mechanism::from_toml_str(&text, "spring.toml").unwrap_or_else(|e| panic!("{e}"));
    let tol: Vec<f64> = m.joints.iter().map(|j| j.spring_tolerance_pct).collect();
    assert_eq!(tol[0], 3.0);
    assert!(tol[1..].iter().all(|&p| p == 0.0), "{tol:?}");
    let written = m.to_toml_string();
    assert!(written.contains("spring_tolerance_pct = 3"), "{written}");
    let back = Mechanism::from_toml_str(&written, "back.toml").expect("written");
    assert_eq!(back, m);
}

#[test]
fn declared_mass_tolerances_are_read_and_written_back() {
    let text = t01_text().replacen(
        "inertia_kgm2 = 0.27",
        "inertia_kgm2 = 0.27\nmass_tolerance_pct = 0.5\ninertia_tolerance_pct = 2",
        2,
    );
    let m = Mechanism::from_toml_str(&text, "tol.toml").unwrap_or_else(|e| panic!("{e}"));
    let tol: Vec<(f64, f64)> = (0..3)
        .map(|i| {
            (
                m.mass_tolerance(i).mass_pct,
                m.mass_tolerance(i).inertia_pct,
            )
        })
        .collect();
    assert_eq!(tol, [(0.5, 2.0), (0.5, 2.0), (0.0, 0.0)]);
    let back = Mechanism::from_toml_str(&m.to_toml_string(), "back.toml").expect("written");
    assert_eq!(back, m);
}

#[test]
fn mechanism_with_curve_spring_friction_and_defaults_round_trips() {
    let text = r#"
name = "one panel"

[[panel]]
length_m = 1
mass_kg = 2.0
com_m = 0.5
inertia_kgm2 = 0.2

[[joint]]
stowed_deg = 120
spring = { kind = "curve", unfold = [[0.0, 0.0], [10.0, 1.5], [180.0, 2.0]], fold = [[0, 0], [5, 3], [180, 2.5]], interp = "linear", count = 2 }
friction = { coulomb_nm = 0.3, viscous_nms = 0.01, breakaway_nm = 0.5, stribeck_rad_s = 0.02 }
"#;
    let m = Mechanism::from_toml_str(text, "curve.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(m.description, "");
    assert_eq!(m.duration_s, 6.0, "default duration");
    assert_eq!(m.sample_hz, 100.0, "default sample rate");
    assert_eq!(m.panels[0].length_m, 1.0, "integers read as numbers");
    let j = &m.joints[0];
    assert_eq!(
        j.spring,
        SpringSpec::Curve {
            unfold: vec![(0.0, 0.0), (10.0, 1.5), (180.0, 2.0)],
            fold: Some(vec![(0.0, 0.0), (5.0, 3.0), (180.0, 2.5)]),
            interp: Interp::Linear,
            count: 2
        }
    );
    assert_eq!(j.friction.coulomb_nm, 0.3);
    assert_eq!(j.friction.viscous_nms, 0.01);
    assert_eq!(
        j.friction.coulomb_threshold_rad_s, 0.01,
        "default threshold"
    );
    assert_eq!(j.friction.stribeck, Some((0.5, 0.02)));
    let back =
        Mechanism::from_toml_str(&m.to_toml_string(), "w.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(back, m);

    // A curve spring without fold or interp: no hysteresis, Akima.
    let plain = text
        .replace(", fold = [[0, 0], [5, 3], [180, 2.5]]", "")
        .replace(", interp = \"linear\"", "");
    let m = Mechanism::from_toml_str(&plain, "plain.toml").unwrap_or_else(|e| panic!("{e}"));
    assert!(matches!(
        m.joints[0].spring,
        SpringSpec::Curve {
            fold: None,
            interp: Interp::Akima,
            ..
        }
    ));
}

#[test]
fn mechanism_written_to_a_file_reads_back() {
    let dir = tempfile::tempdir().expect("tempdir");
    for m in mechanisms() {
        let path = dir.path().join("m.toml");
        m.write(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(Mechanism::load(&path).unwrap_or_else(|e| panic!("{e}")), m);
    }
}

#[test]
fn run_settle_s_defaults_to_two_tenths_is_read_checked_and_written_back() {
    use deploywatch_sim::mechanism_toml::DEFAULT_SETTLE_S;
    let m = Mechanism::from_toml_str(&t01_text(), "t01.toml").expect("T01");
    assert_eq!(m.settle_s, DEFAULT_SETTLE_S);
    assert_eq!(DEFAULT_SETTLE_S, 0.2);
    let text = t01_with("sample_hz = 100.0", "sample_hz = 100.0\nsettle_s = 0.0");
    let m = Mechanism::from_toml_str(&text, "t01.toml").expect("settle_s = 0");
    assert_eq!(m.settle_s, 0.0);
    let back = Mechanism::from_toml_str(&m.to_toml_string(), "back.toml").expect("written");
    assert_eq!(back, m);
    let text = t01_with("sample_hz = 100.0", "sample_hz = 100.0\nsettle_s = -1");
    let e = bad_mech(&text);
    assert_eq!(e.line, Some(line_of(&text, "settle_s")));
    assert_eq!(e.key(), Some("run.settle_s"));
    assert!(e.to_string().contains("a finite number ≥ 0 [s]"), "{e}");
}

#[test]
fn a_spring_scaled_gives_its_torque_times_the_scale_at_every_angle() {
    let curve = SpringSpec::Curve {
        unfold: vec![(0.0, 0.4), (45.0, 0.9), (120.0, 1.3), (180.0, 2.2)],
        fold: Some(vec![(0.0, 0.3), (60.0, 0.8), (180.0, 1.9)]),
        interp: Interp::Akima,
        count: 2,
    };
    let springs = mechanisms()
        .into_iter()
        .flat_map(|m| m.joints.into_iter().map(|j| j.spring))
        .chain([curve]);
    for spec in springs {
        let scale = 1.03;
        let drawn = spec.to_spring::<f64>().expect("a spring");
        let built = spec.scaled(scale).to_spring::<f64>().expect("scaled");
        assert_eq!(spec.scaled(1.0), spec);
        for k in 0..=36 {
            let phi = -(k as f64) * 5.0_f64.to_radians();
            for branch in [
                deploywatch_core::Branch::Fold,
                deploywatch_core::Branch::Unfold,
            ] {
                let (a, b) = (drawn.torque(phi, branch), built.torque(phi, branch));
                assert!(
                    (b - scale * a).abs() <= 1e-9 * a.abs().max(1.0),
                    "{spec:?} at {phi} rad {branch:?}: {b} against {scale} × {a}"
                );
            }
        }
    }
}
