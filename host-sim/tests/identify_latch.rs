//! `deploywatch identify` on runs of a physical latch: the EFTs are fitted
//! on each run's free motion (up to the first instant a joint enters its
//! latch's reach), so the rebounds and escapes of a latch as built, which
//! no friction explains, do not bias them. The binary is run as a black box
//! on runs it simulated itself.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

fn mechanism(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../data/mechanisms")
        .join(name)
}

fn deploywatch(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_deploywatch"))
        .args(args)
        .output()
        .expect("run deploywatch")
}

fn ok(out: &Output) -> String {
    assert!(
        out.status.success(),
        "exit {:?}\n{}",
        out.status.code(),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Seed 001 T01 and T02 with physical latches, Coulomb friction 0.3 N·m
/// at joint 2, and joint 3's plunger weakened by half in the runs (a latch
/// as built that climbs back out more than drawn): identify finds the
/// friction at joint 2 within 5 % and next to none at the others, and says
/// which window it fitted.
#[test]
fn identify_fits_the_free_motion_of_physical_latch_runs() {
    let dir = std::env::temp_dir().join(format!("dw-identify-latch-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut runs = Vec::new();
    let mut mechs = Vec::new();
    for (k, m) in [
        "seed001_T01_physical_latch.toml",
        "seed001_T02_physical_latch.toml",
    ]
    .iter()
    .enumerate()
    {
        let m = mechanism(m);
        let out = dir.join(format!("run{k}.csv"));
        ok(&deploywatch(&[
            "simulate",
            m.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--seed",
            &k.to_string(),
            "--effect",
            "coulomb_friction:joint=2:value=0.3",
            "--effect",
            "plunger_weakening:joint=3:value=0.5",
            "-q",
        ]));
        runs.push(out.to_str().unwrap().to_string());
        mechs.push(m.to_str().unwrap().to_string());
    }
    let json = dir.join("id.json");
    let mut args = vec!["identify".to_string()];
    for m in &mechs {
        args.extend(["--mechanism".to_string(), m.clone()]);
    }
    args.extend(runs.iter().cloned());
    args.extend(["--json".to_string(), json.to_str().unwrap().to_string()]);
    let argv: Vec<&str> = args.iter().map(String::as_str).collect();
    let text = ok(&deploywatch(&argv));
    assert!(
        text.contains("free motion to") && text.contains("enters its latch's reach"),
        "{text}"
    );
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let eft = |j: usize| -> f64 {
        v["joints"]
            .as_array()
            .and_then(|a| a.iter().find(|x| x["joint"] == j))
            .and_then(|x| x["coulomb_nm"].as_f64())
            .unwrap_or_else(|| panic!("joint {j} in {v}"))
    };
    assert!((eft(2) - 0.3).abs() < 0.015, "joint 2: {} ({text})", eft(2));
    for j in [1, 3] {
        assert!(eft(j) < 0.03, "joint {j}: {} ({text})", eft(j));
    }
    std::fs::remove_dir_all(&dir).ok();
}
