//! Direct least squares vs the response-surface method of seed 000, side by
//! side: EFT per joint (truth, estimate, error), trajectory RMS before and
//! after compensation, simulations and wall time.
//!
//! ```text
//! cargo run --release -p deploywatch-sim --example identification_comparison
//! ```
//!
//! Cases:
//! 1. seed 001 T01 + T02 simulated here with the paper's EFT
//!    (2.63, 1.7, 0.001) N·m and the reference sensor (noise seeds 1, 2);
//! 2. seed 000 case 1 + case 3 simulated here with EFT (0.54, 0.472) N·m
//!    (noise seeds 3, 4);
//! 3. example (a) of `shared/reference/examples/` (bundled at
//!    `data/examples/a_seed001_eft`), produced by the independent reference
//!    implementation; its `truth.json` is read only after identifying.
//!
//! Prints a Markdown table on stdout (progress on stderr).

use deploywatch_sim::campaign::Campaign;
use deploywatch_sim::effect::{Effect, EffectKind};
use deploywatch_sim::identify::{
    self, identify_direct, identify_rsm, DirectOptions, Identification, RsmOptions, RsmResponse,
};
use deploywatch_sim::mechanism::Mechanism;
use std::path::{Path, PathBuf};

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../data")
}

fn mechanisms(names: &[&str]) -> Vec<Mechanism> {
    names
        .iter()
        .map(|n| Mechanism::load(&data().join("mechanisms").join(format!("{n}.toml"))).expect("bundled mechanism"))
        .collect()
}

/// Runs simulated here with the truth and the reference sensor.
fn synthetic(names: &[&str], truth: &[f64], seeds: &[u64]) -> Campaign {
    let mechs = mechanisms(names);
    let effects: Vec<Effect> = truth
        .iter()
        .enumerate()
        .map(|(j, &v)| Effect::joint(EffectKind::CoulombFriction, j + 1, v))
        .collect();
    let mut c = Campaign::default();
    for (m, (name, seed)) in mechs.iter().zip(names.iter().zip(seeds)) {
        let run = identify::synthetic_run(m, &effects, *seed).expect("simulation");
        c.push(&mechs, run, Path::new(&format!("{name}.csv"))).expect("pairing");
    }
    c
}

/// The truth of an example folder: the `coulomb_friction` values by joint.
fn example_truth(dir: &Path, joints: usize) -> Vec<f64> {
    let text = std::fs::read_to_string(dir.join("truth.json")).expect("truth.json");
    let v: serde_json::Value = serde_json::from_str(&text).expect("truth.json is JSON");
    let mut t = vec![0.0; joints];
    for e in v["effects"].as_array().expect("effects") {
        if e["name"] == "coulomb_friction" {
            let j = e["joint"].as_u64().expect("joint") as usize;
            t[j - 1] = e["value"].as_f64().expect("value");
        }
    }
    t
}

fn row(case: &str, label: &str, id: &Identification, truth: &[f64]) -> String {
    let efts: Vec<String> = id
        .joints
        .iter()
        .map(|j| {
            let t = truth[j.joint - 1];
            let err = if t >= 0.1 {
                format!("{:+.2} %", 100.0 * (j.coulomb_nm - t) / t)
            } else {
                format!("{:+.4} N·m", j.coulomb_nm - t)
            };
            let ci = match j.ci95 {
                Some([lo, hi]) => format!(" [{lo:.4}, {hi:.4}]"),
                None => String::new(),
            };
            format!("{t} → {:.4}{ci} ({err})", j.coulomb_nm)
        })
        .collect();
    format!(
        "| {case} | {label} | {} | {:.3} | {:.4} | {} | {:.2} |",
        efts.join("<br>"),
        id.rms_deg_before,
        id.rms_deg_after,
        id.simulations,
        id.wall_s
    )
}

fn main() {
    let progress = |m: &str| eprintln!("  {m}");
    let mut rows = Vec::new();
    let cases: Vec<(&str, Campaign, Option<Vec<f64>>)> = vec![
        (
            "seed001 T01+T02 (synthetic)",
            synthetic(&["seed001_T01", "seed001_T02"], &[2.63, 1.7, 0.001], &[1, 2]),
            Some(vec![2.63, 1.7, 0.001]),
        ),
        (
            "seed000 case1+case3 (synthetic)",
            synthetic(&["seed000_case1", "seed000_case3"], &[0.54, 0.472], &[3, 4]),
            Some(vec![0.54, 0.472]),
        ),
        (
            "example (a) a_seed001_eft",
            {
                let dir = data().join("examples/a_seed001_eft");
                let mechs: Vec<PathBuf> = ["seed001_T01", "seed001_T02"]
                    .iter()
                    .map(|n| data().join("mechanisms").join(format!("{n}.toml")))
                    .collect();
                let runs = vec![dir.join("seed001_T01.csv"), dir.join("seed001_T02.csv")];
                Campaign::load(&mechs, &runs).expect("example (a)")
            },
            None,
        ),
    ];
    for (case, campaign, truth) in cases {
        eprintln!("{case}:");
        let joints = identify::all_joints(&campaign);
        let direct = identify_direct(&campaign, &joints, &DirectOptions::default(), &progress).expect("direct");
        let te = identify_rsm(&campaign, &joints, &RsmOptions::default(), &progress).expect("rsm te");
        let mse = identify_rsm(
            &campaign,
            &joints,
            &RsmOptions {
                response: RsmResponse::Mse,
                ..RsmOptions::default()
            },
            &progress,
        )
        .expect("rsm mse");
        // The truth of the example is read only now, after identifying.
        let truth = truth.unwrap_or_else(|| example_truth(&data().join("examples/a_seed001_eft"), joints.len()));
        rows.push(row(case, "direct", &direct, &truth));
        for (label, id) in [("rsm (TE sum)", &te), ("rsm (MSE)", &mse)] {
            let r = id.rsm.as_ref().expect("rsm details");
            let r2: Vec<String> = r.responses.iter().map(|s| format!("{} {:.3}", s.name, s.r2)).collect();
            eprintln!("  {label}: R² {}; centre {:?} ± {:?}", r2.join(", "), r.centre_nm, r.half_range_nm);
            rows.push(row(case, label, id, &truth));
        }
    }
    println!("| case | method | EFT per joint [N·m]: truth → estimate [95 % CI] (error) | RMS before [deg] | RMS after [deg] | simulations | wall [s] |");
    println!("|---|---|---|---|---|---|---|");
    for r in rows {
        println!("{r}");
    }
}
