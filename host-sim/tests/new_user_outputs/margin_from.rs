//! margin reads what identify and diagnose found.

use super::*;

/// `margin --mechanism seed001_T01 --from FILE --json OUT`: its stdout and
/// the margins JSON it wrote (beside FILE).
fn margin_from(file: &Path, extra: &[&str]) -> (String, Value) {
    let text = succeeds(&run_margin_from(file, extra));
    let margins = file.with_file_name("margins.json");
    let m = serde_json::from_str(&std::fs::read_to_string(&margins).expect("margins"))
        .expect("margins JSON");
    (text, m)
}

#[test]
fn margin_from_an_identify_json_uses_the_identified_friction() {
    let dir = tempfile::tempdir().expect("tempdir");
    let eft = dir.path().join("eft.json");
    succeeds(&identify_a(&["--quiet", "--json", s(&eft)]));
    let (text, m) = margin_from(&eft, &[]);
    assert!(text.contains("identify"), "{text}");
    let id: Value = serde_json::from_str(&std::fs::read_to_string(&eft).expect("eft")).unwrap();
    let joints = m["joints"].as_array().expect("joints");
    assert_eq!(joints.len(), 3);
    for found in id["joints"].as_array().expect("identified joints") {
        let j = found["joint"].as_u64().expect("joint") as usize;
        let row = &joints[j - 1];
        let t_r = row["coulomb_nm"].as_f64().expect("T_R");
        // seed001_T01 has no friction of its own: T_R is the EFT found, at
        // the upper end of its 95 % interval where the file gives one.
        let eft = found["ci95"][1]
            .as_f64()
            .or(found["coulomb_nm"].as_f64())
            .expect("EFT");
        assert_eq!(t_r, eft);
        let t_d = row["driving_torque_nm"].as_f64().expect("T_D");
        let tm = row["torque_margin_pct"].as_f64().expect("finite margin");
        assert!((tm - (t_d / t_r - 1.0) * 100.0).abs() < 1e-9 * tm.abs().max(1.0));
    }
}

#[test]
fn margin_from_a_diagnose_json_takes_friction_and_damping_and_counts_the_rest() {
    let dir = tempfile::tempdir().expect("tempdir");
    // The diagnosis format of docs/spec/formats.md.
    let diagnosis = dir.path().join("diagnosis.json");
    std::fs::write(
        &diagnosis,
        r#"{
  "mechanism": "seed001-T01",
  "runs": ["t01.csv"],
  "baseline": { "rms_deg": 6.41, "trajectory_error_pct": [31.2, 18.0, 4.1] },
  "effects": [
    { "name": "coulomb_friction", "joint": 1, "value": 0.8, "unit": "N·m", "ci95": [0.79, 0.81], "evidence": "..." },
    { "name": "viscous_damping", "joint": 2, "value": 0.05, "unit": "N·m·s/rad", "ci95": [0.04, 0.06], "evidence": "..." },
    { "name": "harness_stiffness", "joint": 3, "value": 0.1, "unit": "N·m/rad", "ci95": [0.09, 0.11], "evidence": "..." }
  ],
  "extended": { "rms_deg": 0.031, "trajectory_error_pct": [0.4, 0.3, 0.2] },
  "gain": { "rms_ratio": 206.8, "held_out_rms_deg": null }
}"#,
    )
    .expect("write");
    let (text, m) = margin_from(&diagnosis, &["--quiet"]);
    // The harness is a resistance: counted under its joint with its factor,
    // each effect at the upper end of its 95 % interval.
    assert!(
        text.contains("harness_stiffness 0.11 N·m/rad (harness"),
        "{text}"
    );
    let j = &m["joints"];
    assert_eq!(j[0]["coulomb_nm"].as_f64(), Some(0.81));
    assert_eq!(j[1]["viscous_nms"].as_f64(), Some(0.06));
    let e_visc = j[1]["viscous_energy_j"].as_f64().expect("E_visc");
    assert!(e_visc > 0.0, "the damping dissipates energy on the way");
    assert_eq!(j[0]["viscous_energy_j"].as_f64(), Some(0.0));
    // E_R = T_R · stroke + E_visc.
    for row in j.as_array().expect("joints") {
        let stroke = row["stowed_deg"].as_f64().unwrap().abs().to_radians();
        let want = row["coulomb_nm"].as_f64().unwrap() * stroke
            + row["viscous_energy_j"].as_f64().unwrap();
        let got = row["resisting_energy_j"].as_f64().unwrap();
        assert!((got - want).abs() < 1e-12 + 1e-12 * want, "{got} vs {want}");
    }
    // Every effect found is counted: nothing is left out.
    let left_out = m["not_included"].as_array().map_or(0, Vec::len);
    assert_eq!(left_out, 0, "{}", m["not_included"]);
}

#[test]
fn margin_from_a_file_that_is_neither_says_what_it_expected() {
    let run = data("examples/a_seed001_eft/seed001_T01.csv");
    let out = deploywatch(&["margin", "--mechanism", s(&data(T01)), "--from", s(&run)]);
    fails(&out, 2, &["--from", "seed001_T01.csv", "not JSON"]);
    let dir = tempfile::tempdir().expect("tempdir");
    let other = dir.path().join("other.json");
    std::fs::write(&other, r#"{"joints": 3}"#).expect("write");
    let out = deploywatch(&["margin", "--mechanism", s(&data(T01)), "--from", s(&other)]);
    fails(&out, 2, &["deploywatch identify", "deploywatch diagnose"]);
    let far = dir.path().join("far.json");
    std::fs::write(
        &far,
        r#"{"method": "direct", "joints": [{"joint": 4, "coulomb_nm": 1.0}]}"#,
    )
    .expect("write");
    let out = deploywatch(&["margin", "--mechanism", s(&data(T01)), "--from", s(&far)]);
    fails(&out, 2, &["joint 4", "joints 1 to 3"]);
}
