//! The findings JSON (`docs/spec/formats.md`, "Findings JSON"): files that
//! `deploywatch identify` and `deploywatch diagnose` wrote (kept in
//! `tests/data/`) read through the one schema and write back byte for byte,
//! and `deploywatch margin --from` takes what they found.

use std::path::{Path, PathBuf};
use std::process::Command;

use deploywatch_sim::findings::{Findings, FindingsError};
use serde_json::Value;

fn here(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

const IDENTIFY: &str = "tests/data/identify_direct.json";
const DIAGNOSIS: &str = "tests/data/diagnosis_friction_harness.json";

fn read(rel: &str) -> String {
    std::fs::read_to_string(here(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

/// The text written back from what was read, as the commands write it.
fn written_back(f: &Findings) -> String {
    let text = match f {
        Findings::Identify(id) => serde_json::to_string_pretty(id),
        Findings::Diagnosis(d) => serde_json::to_string_pretty(d),
    };
    text.expect("serialisable") + "\n"
}

#[test]
fn a_written_identification_reads_and_writes_back_unchanged() {
    let text = read(IDENTIFY);
    let f = Findings::from_json_str(&text).expect("reads");
    let Findings::Identify(id) = &f else {
        panic!("read as a diagnosis")
    };
    assert_eq!(id.joints.len(), 3);
    assert_eq!(written_back(&f), text);
}

#[test]
fn a_written_diagnosis_reads_and_writes_back_unchanged() {
    let text = read(DIAGNOSIS);
    let f = Findings::from_json_str(&text).expect("reads");
    let Findings::Diagnosis(d) = &f else {
        panic!("read as an identification")
    };
    assert!(!d.effects.is_empty());
    assert_eq!(written_back(&f), text);
}

#[test]
fn minimal_files_read_and_others_are_refused() {
    let id = Findings::from_json_str(
        r#"{"method": "rsm", "joints": [{"joint": 2, "coulomb_nm": 0.5}]}"#,
    );
    assert!(matches!(id, Ok(Findings::Identify(_))), "{id:?}");
    let d = Findings::from_json_str(
        r#"{"effects": [{"name": "air_drag", "joint": null, "value": null}]}"#,
    );
    assert!(matches!(d, Ok(Findings::Diagnosis(_))), "{d:?}");
    let neither = Findings::from_json_str(r#"{"joints": 3}"#);
    assert!(
        matches!(neither, Err(FindingsError::Unknown)),
        "{neither:?}"
    );
    let wrong =
        Findings::from_json_str("{\"method\": \"direct\",\n\"joints\": [{\"joint\": \"one\"}]}");
    let Err(FindingsError::Json(e)) = wrong else {
        panic!("{wrong:?}")
    };
    assert_eq!(e.line(), 2, "{e}");
}

/// `margin --from FILE` for seed001_T01, its margins JSON.
fn margins_from(file: &Path, dir: &Path) -> Value {
    let out = dir.join("margins.json");
    let o = Command::new(env!("CARGO_BIN_EXE_deploywatch"))
        .args(["margin", "--quiet", "--mechanism"])
        .arg(here("../data/mechanisms/seed001_T01.toml"))
        .arg("--from")
        .arg(file)
        .arg("--json")
        .arg(&out)
        .output()
        .expect("runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_str(&std::fs::read_to_string(&out).expect("margins")).expect("JSON")
}

#[test]
fn margin_takes_the_friction_of_written_files() {
    let dir = tempfile::tempdir().expect("tempdir");
    let found: Value = serde_json::from_str(&read(IDENTIFY)).unwrap();
    let m = margins_from(&here(IDENTIFY), dir.path());
    for j in found["joints"].as_array().unwrap() {
        let k = j["joint"].as_u64().unwrap() as usize;
        // seed001_T01 has no friction of its own: T_R is the EFT found, at
        // the upper end of its 95 % interval where the file gives one.
        let eft = if j["ci95"].is_array() {
            &j["ci95"][1]
        } else {
            &j["coulomb_nm"]
        };
        assert_eq!(&m["joints"][k - 1]["coulomb_nm"], eft);
    }
    let found: Value = serde_json::from_str(&read(DIAGNOSIS)).unwrap();
    let m = margins_from(&here(DIAGNOSIS), dir.path());
    let mut named = 0;
    for e in found["effects"].as_array().unwrap() {
        if e["name"] == "coulomb_friction" {
            let k = e["joint"].as_u64().unwrap() as usize;
            let worst = if e["ci95"].is_array() {
                &e["ci95"][1]
            } else {
                &e["value"]
            };
            assert_eq!(&m["joints"][k - 1]["coulomb_nm"], worst);
            named += 1;
        }
    }
    assert!(named > 0, "the file names a friction");
    // Every named effect is counted (`margin_check.rs`): the harness at
    // its joint, nothing left out.
    assert_eq!(m["not_included"].as_array().expect("not_included").len(), 0);
    let harness = found["effects"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["name"] == "harness_stiffness")
        .expect("the file names a harness");
    let k = harness["joint"].as_u64().unwrap() as usize;
    let counted = m["joints"][k - 1]["counted"].as_array().expect("counted");
    assert!(
        counted.iter().any(|c| c["effect"] == "harness_stiffness"),
        "{counted:?}"
    );
}
