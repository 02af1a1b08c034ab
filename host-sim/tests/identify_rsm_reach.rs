//! `identify --method rsm` on runs whose friction its default design does
//! not reach (`docs/identification.md`, the warning after the fit): the
//! CLI says that friction alone explains them, with least squares' EFTs
//! and the `--center` to use, never "friction alone does not explain";
//! `margin --from` that file says its EFTs are the surface's.
//! `cargo test -p deploywatch-sim --test identify_rsm_reach`.
mod common;

use common::{data, deploywatch, s};
use serde_json::Value;

#[test]
fn friction_the_design_did_not_reach_is_said_and_carried_to_the_margin() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mech = data().join("mechanisms/seed001_T01.toml");
    let mut runs = Vec::new();
    for seed in ["1", "2"] {
        let run = dir.path().join(format!("run{seed}.csv"));
        let out = deploywatch(&[
            "simulate",
            s(&mech),
            "-o",
            s(&run),
            "--seed",
            seed,
            "--effect",
            "coulomb_friction:joint=1:value=0.3",
            "-q",
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        runs.push(run);
    }
    let json = dir.path().join("rsm.json");
    let out = deploywatch(&[
        "identify",
        s(&runs[0]),
        s(&runs[1]),
        "--mechanism",
        s(&mech),
        "--method",
        "rsm",
        "--json",
        s(&json),
        "-q",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let v: Value =
        serde_json::from_str(&std::fs::read_to_string(&json).expect("json")).expect("JSON");
    let rms_after = v["rms_deg_after"].as_f64().expect("rms");
    let b = &v["rsm"]["beyond_design"];
    // The precondition: the surface's own EFTs leave the runs unexplained.
    assert!(
        rms_after > 0.1,
        "the default design reached it: {rms_after} deg"
    );
    assert!(err.contains("friction alone explains these runs"), "{err}");
    assert!(!err.contains("does not explain"), "{err}");
    assert!(err.contains("--center"), "{err}");
    let got: Vec<f64> = b["coulomb_nm"]
        .as_array()
        .expect("beyond_design.coulomb_nm")
        .iter()
        .map(|c| c.as_f64().expect("a number"))
        .collect();
    for (g, want) in got.iter().zip([0.3, 0.0, 0.0]) {
        assert!((g - want).abs() < 0.01, "{got:?}");
    }
    assert!(b["rms_deg"].as_f64().expect("rms") < 0.05, "{b}");
    let out = deploywatch(&["margin", "--mechanism", s(&mech), "--from", s(&json), "-q"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        text.contains("these are the response surface's EFTs")
            && text.contains("rsm.beyond_design"),
        "{text}"
    );
}

/// A design the user's numbers cannot make is refused by its option (exit
/// 2) before any simulation: `--center 0` without `--range` (the default
/// half-range is half the centre), and a centre whose factorial points go
/// below 0 N·m, said with the point's own coded level (1 there).
#[test]
fn a_design_below_zero_is_refused_by_its_option() {
    let mech = data().join("mechanisms/seed001_T01.toml");
    let run = data().join("examples/a_seed001_eft/seed001_T01.csv");
    let identify = |extra: &[&str]| {
        let mut args = vec![
            "identify",
            "--mechanism",
            s(&mech),
            s(&run),
            "--method",
            "rsm",
            "-q",
        ];
        args.extend_from_slice(extra);
        deploywatch(&args)
    };
    let out = identify(&["--center", "0,1,1"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("--center 0") && err.contains("--range"),
        "{err}"
    );
    let out = identify(&["--center", "0.01,1,1", "--range", "0.5,0.5,0.5"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    // The first point below 0 is the factorial one: 0.01 − 1 × 0.5.
    assert!(
        err.contains("EFT -0.4900") && err.contains("1.000 × half-range 0.5"),
        "{err}"
    );
}
