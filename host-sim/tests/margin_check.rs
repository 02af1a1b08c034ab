//! `deploywatch margin`: every named effect a diagnosis finds enters the
//! margins (`docs/margin.md`, "Every diagnosed cause in the margin"), and
//! `--check` exits 1 when a joint fails.
mod common;

use common::{deploywatch, fails, s, t01_mechanism, write};
use deploywatch_sim::effect::EffectKind;
use serde_json::{json, Value};
use std::path::Path;

/// One effect of a diagnosis JSON: a named effect at joint 2 (or global),
/// with a value that is plainly not noise.
fn found(kind: EffectKind) -> Value {
    let joint = if kind.per_joint() {
        json!(2)
    } else {
        Value::Null
    };
    let value = match kind {
        EffectKind::CoulombFriction => 0.4,
        EffectKind::ViscousDamping => 0.2,
        EffectKind::SpringSoftening => 0.2,
        EffectKind::HarnessStiffness => 0.3,
        EffectKind::LatchDetent => 0.3,
        EffectKind::AirDrag => 0.5,
        EffectKind::RigTilt => 0.3,
        EffectKind::EncoderOffset => 0.5,
        _ => 0.2,
    };
    let mut e = json!({"name": kind.name(), "joint": joint, "value": value, "evidence": "test"});
    if kind == EffectKind::RigTilt {
        e["alpha_deg"] = json!(90.0);
    }
    if kind == EffectKind::TorqueTable {
        // Joint 2 deploys from 180° to 0: a positive torque resists it.
        e["angle_deg"] = json!([0.0, 90.0, 180.0]);
        e["torque_nm"] = json!([0.1, 0.3, 0.1]);
        e["rate_deg_s"] = json!([-100.0, 0.0, 100.0]);
        e["rate_torque_nm"] = json!([0.05, 0.0, -0.05]);
    }
    e
}

/// A diagnosis of seed001_T01 with a friction of 0.5 N·m at joints 1 and
/// 2, and `extra`.
fn diagnosis(dir: &Path, name: &str, extra: &[Value]) -> std::path::PathBuf {
    let mut effects = vec![
        json!({"name": "coulomb_friction", "joint": 1, "value": 0.5, "evidence": "test"}),
        json!({"name": "coulomb_friction", "joint": 2, "value": 0.5, "evidence": "test"}),
    ];
    effects.extend(extra.iter().cloned());
    let doc =
        json!({"mechanism": "seed001-T01", "mechanisms": ["seed001-T01"], "effects": effects});
    write(dir, name, serde_json::to_string_pretty(&doc).unwrap())
}

/// `margin --from FILE --json OUT` on seed001_T01: its JSON.
fn margins(file: &Path, dir: &Path, extra_args: &[&str]) -> Value {
    let out = dir.join("margins.json");
    let mech = t01_mechanism();
    let mut args = vec![
        "margin",
        "--quiet",
        "--mechanism",
        s(&mech),
        "--from",
        s(file),
        "--json",
        s(&out),
    ];
    args.extend_from_slice(extra_args);
    let run = deploywatch(&args);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    serde_json::from_str(&std::fs::read_to_string(&out).expect("margins")).expect("JSON")
}

/// `(torque, energy)` margins [%] of every joint.
fn pcts(m: &Value) -> Vec<(f64, f64)> {
    m["joints"]
        .as_array()
        .unwrap()
        .iter()
        .map(|j| {
            let f = |k: &str| j[k].as_f64().unwrap_or(f64::INFINITY);
            (f("torque_margin_pct"), f("energy_margin_pct"))
        })
        .collect()
}

#[test]
fn every_named_effect_is_counted_in_the_margins() {
    let dir = tempfile::tempdir().unwrap();
    let base = margins(&diagnosis(dir.path(), "base.json", &[]), dir.path(), &[]);
    let before = pcts(&base);
    let kinds = EffectKind::ALL.into_iter().chain([EffectKind::TorqueTable]);
    for kind in kinds {
        let file = diagnosis(dir.path(), "one.json", &[found(kind)]);
        let m = margins(&file, dir.path(), &["--standard", "nasa-std-5017"]);
        let base_f = margins(
            &diagnosis(dir.path(), "base.json", &[]),
            dir.path(),
            &["--standard", "nasa-std-5017"],
        );
        assert_eq!(
            m["not_included"].as_array().unwrap().len(),
            0,
            "{kind}: {}",
            m["not_included"]
        );
        let on: Vec<usize> = m["joints"]
            .as_array()
            .unwrap()
            .iter()
            .enumerate()
            .filter(|(_, j)| match kind {
                // Friction and damping have columns of their own.
                EffectKind::CoulombFriction => j["coulomb_nm"].as_f64() == Some(0.9),
                EffectKind::ViscousDamping => j["viscous_nms"] == 0.2,
                _ => j["counted"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .any(|c| c["effect"] == kind.name()),
            })
            .map(|(i, _)| i)
            .collect();
        let expect: Vec<usize> = if kind.per_joint() {
            vec![1]
        } else {
            vec![0, 1, 2]
        };
        assert_eq!(on, expect, "{kind} counted at the joints it acts on");
        let (after, prior) = (pcts(&m), pcts(&base_f));
        let lower = after
            .iter()
            .zip(&prior)
            .any(|(a, b)| a.0 < b.0 - 1e-9 || a.1 < b.1 - 1e-9);
        if kind.is_sensor() {
            assert_eq!(after, prior, "{kind}: a sensor effect moves no margin");
        } else {
            assert!(
                lower,
                "{kind}: some margin must drop: {prior:?} -> {after:?}"
            );
        }
        assert!(after
            .iter()
            .zip(&prior)
            .all(|(a, b)| a.0 <= b.0 + 1e-9 && a.1 <= b.1 + 1e-9));
    }
    // The unfactored baseline is the mechanism with the friction alone.
    assert!(before[1].0.is_finite() && before[2].0.is_infinite());
}

#[test]
fn harness_and_softening_count_as_the_hand_calculation() {
    let dir = tempfile::tempdir().unwrap();
    let file = diagnosis(
        dir.path(),
        "two.json",
        &[
            found(EffectKind::HarnessStiffness),
            json!({"name": "spring_softening", "joint": 1, "value": 0.25, "evidence": "test"}),
        ],
    );
    let plain = margins(&diagnosis(dir.path(), "base.json", &[]), dir.path(), &[]);
    let m = margins(&file, dir.path(), &["--standard", "ecss-e-st-33-01c"]);
    // Joint 1: spring × 0.75, friction 0.5 × 3.
    let j1 = &m["joints"][0];
    let td = plain["joints"][0]["driving_torque_nm"].as_f64().unwrap();
    let want = (0.75 * td / (3.0 * 0.5) - 1.0) * 100.0;
    assert!((j1["torque_margin_pct"].as_f64().unwrap() - want).abs() < 1e-6);
    // Joint 2: friction 0.5 N·m and harness 0.3 N·m/rad over the 180°
    // stroke, both factor 3: the harness torque at the latch k_h·π, its
    // energy ½ k_h π².
    let j2 = &m["joints"][1];
    let td2 = j2["driving_torque_nm"].as_f64().unwrap();
    let ed2 = j2["driving_energy_j"].as_f64().unwrap();
    let pi = std::f64::consts::PI;
    let t_want = (td2 / (3.0 * 0.5 + 3.0 * 0.3 * pi) - 1.0) * 100.0;
    let e_want = (ed2 / (3.0 * 0.5 * pi + 3.0 * 0.5 * 0.3 * pi * pi) - 1.0) * 100.0;
    assert!((j2["torque_margin_pct"].as_f64().unwrap() - t_want).abs() < 1e-6);
    assert!((j2["energy_margin_pct"].as_f64().unwrap() - e_want).abs() < 1e-6);
}

#[test]
fn check_exits_1_when_a_joint_fails_and_0_when_all_pass() {
    let dir = tempfile::tempdir().unwrap();
    let mech = common::data().join("mechanisms/seed001_T02.toml");
    // T02 with seed 001's identified friction: joint 1 fails (Table 5).
    let fail = [
        "margin",
        "--mechanism",
        s(&mech),
        "--friction",
        "2.63,1.7,0.001",
    ];
    let out = deploywatch(&fail);
    assert_eq!(
        out.status.code(),
        Some(0),
        "without --check: the table only"
    );
    let mut with_check = fail.to_vec();
    with_check.push("--check");
    let out = deploywatch(&with_check);
    fails(&out, 1, &["joint(s) 1", "FAIL"]);
    assert!(String::from_utf8_lossy(&out.stdout).contains("FAIL"));
    // T01 with seed 001's friction passes unfactored at the stowed angle
    // and in the energy form, but not along the stroke: joint 2's unfolding
    // branch (2 × TS-2, an Akima spline through B and M) dips below its
    // 1.7 N·m of friction in mid-stroke.
    let t01 = t01_mechanism();
    let json_out = dir.path().join("t01.json");
    let args = [
        "margin",
        "--mechanism",
        s(&t01),
        "--friction",
        "2.63,1.7,0.001",
        "--json",
        s(&json_out),
        "--check",
    ];
    fails(&deploywatch(&args), 1, &["joint(s) 2 of"]);
    let m: Value = serde_json::from_str(&std::fs::read_to_string(&json_out).unwrap()).unwrap();
    for j in m["joints"].as_array().unwrap() {
        assert!(j["torque_margin_pct"].as_f64().unwrap() > 0.0);
        assert!(j["energy_margin_pct"].as_f64().unwrap() > 0.0);
        let worst = j["stroke"]["worst_margin_pct"].as_f64().unwrap();
        let stroke_deg = j["stowed_deg"].as_f64().unwrap().abs();
        let at = j["stroke"]["worst_angle_deg"].as_f64().unwrap().abs();
        assert_eq!(j["stroke"]["pass"], worst >= 0.0);
        if j["joint"] == 2 {
            assert!(worst < 0.0 && at > 1.0 && at < stroke_deg, "{j}");
        }
    }
    // A harness found by a diagnosis can tip a passing joint into a FAIL.
    let file = diagnosis(
        dir.path(),
        "harness.json",
        &[json!({"name": "harness_stiffness", "joint": 3, "value": 2.0, "evidence": "test"})],
    );
    let out = deploywatch(&[
        "margin",
        "--mechanism",
        s(&t01),
        "--from",
        s(&file),
        "--check",
    ]);
    fails(&out, 1, &["joint(s) 3"]);
}

#[test]
fn flight_leaves_out_what_only_the_rig_has() {
    let dir = tempfile::tempdir().unwrap();
    let drag = found(EffectKind::AirDrag);
    let tilt = found(EffectKind::RigTilt);
    let harness = found(EffectKind::HarnessStiffness);
    let file = diagnosis(dir.path(), "rig.json", &[drag, tilt, harness]);
    let ground = margins(&file, dir.path(), &[]);
    let flight = margins(&file, dir.path(), &["--flight"]);
    let counted = |m: &Value, j: usize| -> Vec<String> {
        m["joints"][j]["counted"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c["effect"].as_str().unwrap().to_string())
            .collect()
    };
    assert!(counted(&ground, 0).contains(&"air_drag".to_string()));
    assert_eq!(counted(&flight, 0), Vec::<String>::new());
    assert_eq!(counted(&flight, 1), vec!["harness_stiffness".to_string()]);
    assert!(flight["resistances_from"]
        .as_str()
        .unwrap()
        .contains("rig-only: air_drag, rig_tilt"));
    // What flies is the same; the rig's share is gone from the margin.
    let (g, f) = (pcts(&ground), pcts(&flight));
    assert!(g.iter().zip(&f).all(|(g, f)| f.1 >= g.1 && f.0 >= g.0));
    assert!(g.iter().zip(&f).any(|(g, f)| f.1 > g.1));
}

#[test]
fn the_rig_causes_are_left_to_the_rig_and_out_of_flight() {
    // `rig_friction`, `wire_length`, `frame_offset` (physics.md §11.7): a
    // diagnosis's rig causes are read, not dropped as unknown; they add
    // nothing to a hinge's margin (their share is the rig split's) and
    // `--flight` names them as rig-only.
    let dir = tempfile::tempdir().unwrap();
    let rig: Vec<Value> = EffectKind::RIG.into_iter().map(found).collect();
    let file = diagnosis(dir.path(), "rig.json", &rig);
    let ground = margins(&file, dir.path(), &[]);
    let flight = margins(&file, dir.path(), &["--flight"]);
    let base = margins(&diagnosis(dir.path(), "base.json", &[]), dir.path(), &[]);
    assert_eq!(
        ground["not_included"].as_array().unwrap().len(),
        0,
        "{}",
        ground["not_included"]
    );
    let from = flight["resistances_from"].as_str().unwrap();
    for k in EffectKind::RIG {
        assert!(from.contains(k.name()), "{k}: {from}");
    }
    assert_eq!(pcts(&ground), pcts(&base));
    assert_eq!(pcts(&flight), pcts(&base));
}

/// The row of factors a reviewer signs is the one used: NASA-STD-5017B's
/// clause line names the `--data-source` row its factors come from;
/// ECSS-E-ST-33-01C and AIAA S-114, with one row here, keep their factors
/// and say that the source changed nothing; `--all-standards` shows each
/// standard's own factors, so a `--factor` beside it is refused.
#[test]
fn the_clause_names_the_row_of_factors_used() {
    let m = t01_mechanism();
    let dir = tempfile::tempdir().unwrap();
    let json_of = |standard: &str, source: &str| {
        let out = dir.path().join(format!("{standard}-{source}.json"));
        let run = deploywatch(&[
            "margin",
            "--mechanism",
            s(&m),
            "--friction",
            "2.63,1.7,0.001",
            "--standard",
            standard,
            "--data-source",
            source,
            "--json",
            s(&out),
        ]);
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        let doc: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
        (doc, String::from_utf8_lossy(&run.stderr).into_owned())
    };
    let (nasa, said) = json_of("nasa-std-5017", "test");
    let reference = nasa["standard_reference"].as_str().unwrap();
    assert!(
        reference.contains("row: development, qualification"),
        "{reference}"
    );
    assert_eq!(nasa["factors"]["friction"], json!(2.5));
    assert!(!said.contains("one row of factors"), "{said}");
    for standard in ["ecss-e-st-33-01c", "aiaa-s-114"] {
        let (analysis, _) = json_of(standard, "analysis");
        for source in ["test", "acceptance-extremes"] {
            let (doc, said) = json_of(standard, source);
            assert_eq!(doc["factors"], analysis["factors"], "{standard} {source}");
            assert_eq!(doc["joints"], analysis["joints"], "{standard} {source}");
            assert!(
                said.contains(&format!(
                    "--data-source {source}: {standard} has one row of factors"
                )) && said.contains("--factor KIND=VALUE"),
                "{standard} {source}: {said}"
            );
        }
    }
    fails(
        &deploywatch(&[
            "margin",
            "--mechanism",
            s(&m),
            "--all-standards",
            "--factor",
            "friction=2",
        ]),
        2,
        &["--all-standards", "--factor"],
    );
}

/// A wing with nothing resisting any joint (seed 001 T01 as bundled, no
/// friction) has infinite margins: said, so that no one signs a pass on
/// no data; with the friction given, not.
#[test]
fn margins_on_no_resistance_are_said_to_be_on_no_data() {
    let m = t01_mechanism();
    let said = "nothing resists any joint";
    let bare = deploywatch(&["margin", "--mechanism", s(&m), "-q"]);
    assert!(bare.status.success() && String::from_utf8_lossy(&bare.stderr).contains(said));
    let given = deploywatch(&[
        "margin",
        "--mechanism",
        s(&m),
        "--friction",
        "2.63,1.7,0.001",
        "-q",
    ]);
    assert!(given.status.success() && !String::from_utf8_lossy(&given.stderr).contains(said));
}
