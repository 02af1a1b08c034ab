//! EFT identification: the direct least-squares method and the
//! response surface of seed 000 on runs simulated here with known friction
//! and the reference sensor, and on example (a) of `shared/reference/examples`
//! (bundled at `data/examples/a_seed001_eft`), produced by the independent
//! reference implementation.
//!
//! Done when: `direct` recovers every EFT ≥ 0.1 N·m within 2 % and its 95 %
//! intervals contain the truth; `rsm` returns EFTs inside its design box,
//! reports R² for every response and lowers the trajectory RMS.

use deploywatch_sim::campaign::Campaign;
use deploywatch_sim::cli::identify::{run as run_cli, IdentifyArgs};
use deploywatch_sim::identify::by_rsm::identify_rsm;
use deploywatch_sim::identify::direct::identify_direct;
use deploywatch_sim::identify::{
    self, DirectOptions, Identification, Method, RsmOptions, RsmResponse,
};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::progress::quiet;
use deploywatch_tests::data_dir;
use std::path::{Path, PathBuf};

fn mechanism_path(name: &str) -> PathBuf {
    data_dir().join("mechanisms").join(format!("{name}.toml"))
}

/// Runs simulated with `truth` (coulomb_friction at joints 1..) on the
/// nominal bundled mechanisms, read by the reference sensor (seeded).
fn synthetic(names: &[&str], truth: &[f64], seeds: &[u64]) -> Campaign {
    let mechs: Vec<Mechanism> = names
        .iter()
        .map(|n| Mechanism::load(&mechanism_path(n)).expect("bundled mechanism"))
        .collect();
    identify::residual_check::synthetic_campaign(&mechs, truth, seeds).expect("simulate the truth")
}

/// Every EFT ≥ 0.1 N·m within 2 %, every interval contains the truth, the
/// RMS after is at the noise floor (σ = 0.02°, plus quantisation).
fn check_direct(case: &str, id: &Identification, truth: &[f64]) {
    assert_eq!(id.method, Method::Direct);
    assert_eq!(id.joints.len(), truth.len(), "{case}");
    for j in &id.joints {
        let t = truth[j.joint - 1];
        let [lo, hi] = j.ci95.expect("direct gives intervals");
        eprintln!(
            "{case}: joint {} truth {t} estimate {:.6} CI [{lo:.6}, {hi:.6}]",
            j.joint, j.coulomb_nm
        );
        if t >= 0.1 {
            let err = (j.coulomb_nm - t).abs() / t;
            assert!(
                err < 0.02,
                "{case}: joint {}: {} vs {t} ({:.2} %)",
                j.joint,
                j.coulomb_nm,
                100.0 * err
            );
        }
        assert!(
            j.coulomb_nm >= 0.0,
            "{case}: joint {}: negative EFT",
            j.joint
        );
        assert!(
            lo <= t && t <= hi,
            "{case}: joint {}: truth {t} outside [{lo}, {hi}]",
            j.joint
        );
    }
    assert!(
        id.rms_deg_after < 0.03,
        "{case}: RMS after {} deg, the noise floor is about 0.021 deg",
        id.rms_deg_after
    );
    assert!(id.rms_deg_after < id.rms_deg_before);
    assert!(id.simulations > 0 && id.deployments == id.simulations * id.before.runs.len());
}

/// What the response surface honestly achieves: EFTs inside the box the
/// design spans, an R² for every response (TE per joint and MSE), the
/// surface minimum checked by simulation, and a lower RMS than before.
fn check_rsm(case: &str, id: &Identification, joints: usize) {
    assert_eq!(id.method, Method::Rsm);
    let r = id.rsm.as_ref().expect("rsm details");
    assert_eq!(
        r.points_nm.len(),
        (1 << joints) + 2 * joints + 1,
        "{case}: CCD size"
    );
    assert_eq!(r.responses.len(), joints + 1, "{case}: TE per joint + MSE");
    for s in &r.responses {
        assert!(
            s.r2.is_finite() && s.r2 <= 1.0,
            "{case}: {} R² {}",
            s.name,
            s.r2
        );
        assert_eq!(s.values.len(), r.points_nm.len());
    }
    for (j, b) in id.joints.iter().zip(&r.box_nm) {
        assert!(j.ci95.is_none());
        assert!(
            b[0] - 1e-12 <= j.coulomb_nm && j.coulomb_nm <= b[1] + 1e-12,
            "{case}: joint {} at {} outside the box {b:?}",
            j.joint,
            j.coulomb_nm
        );
        assert!(b[0] >= 0.0);
    }
    assert!(r.simulated.is_finite() && r.predicted.is_finite());
    assert!(
        id.rms_deg_after < id.rms_deg_before,
        "{case}: RMS {} -> {}",
        id.rms_deg_before,
        id.rms_deg_after
    );
    eprintln!(
        "{case}: rsm {:?} RMS {:.3} -> {:.3} deg, R² {:?}",
        id.joints.iter().map(|j| j.coulomb_nm).collect::<Vec<_>>(),
        id.rms_deg_before,
        id.rms_deg_after,
        r.responses
            .iter()
            .map(|s| (s.name.as_str(), s.r2))
            .collect::<Vec<_>>()
    );
}

#[test]
fn seed001_t01_t02_with_the_papers_eft() {
    let truth = [2.63, 1.7, 0.001];
    let c = synthetic(&["seed001_T01", "seed001_T02"], &truth, &[11, 12]);
    let joints = identify::all_joints(&c);
    assert_eq!(joints, [1, 2, 3]);
    let direct = identify_direct(&c, &joints, &DirectOptions::default(), &quiet).unwrap();
    check_direct("seed001", &direct, &truth);
    for response in [RsmResponse::TeSum, RsmResponse::Mse] {
        let o = RsmOptions {
            response,
            ..RsmOptions::default()
        };
        let rsm = identify_rsm(&c, &joints, &o, &quiet).unwrap();
        check_rsm("seed001", &rsm, 3);
    }
}

#[test]
fn seed000_case1_case3_with_the_papers_eft() {
    let truth = [0.54, 0.472];
    let c = synthetic(&["seed000_case1", "seed000_case3"], &truth, &[21, 22]);
    let joints = identify::all_joints(&c);
    let direct = identify_direct(&c, &joints, &DirectOptions::default(), &quiet).unwrap();
    check_direct("seed000", &direct, &truth);
    let rsm = identify_rsm(&c, &joints, &RsmOptions::default(), &quiet).unwrap();
    check_rsm("seed000", &rsm, 2);
    // seed 000 Table 9's design (joints O, I): centre (0.75, 0.60) ± (0.25, 0.30).
    let paper = RsmOptions {
        centre_nm: Some(vec![0.75, 0.60]),
        half_range_nm: Some(vec![0.25, 0.30]),
        ..RsmOptions::default()
    };
    let rsm = identify_rsm(&c, &joints, &paper, &quiet).unwrap();
    check_rsm("seed000, Table 9 design", &rsm, 2);
    let r = rsm.rsm.unwrap();
    assert_eq!(r.centre_nm, [0.75, 0.60]);
    assert!(
        (r.points_nm[4][0] - (0.75 - 0.25 * 2f64.sqrt())).abs() < 1e-12,
        "axial run at α = √2"
    );
}

/// The response surface's default design (centred on the start scan's
/// per-joint best) can miss a friction at one joint by far; where its
/// minimum leaves residuals above the warning level, least squares from it
/// (or from the direct method's own start) must say that friction alone
/// explains the runs, at the truth — never send the user to `diagnose` for
/// a cause that is not there. Friction of 0.3 N·m at one joint of three
/// bundled wings, each joint in turn; then a harness beside the friction,
/// which friction alone cannot explain.
#[test]
fn the_response_surface_says_when_friction_explains_what_its_design_missed() {
    use deploywatch_sim::identify::residual_check::residual_warnings;
    let mut missed = 0;
    for (names, joints) in [
        (&["seed001_T01", "seed001_T02"][..], 3),
        (&["seed000_case1", "seed000_case3"][..], 2),
        (&["wing4_ideal"][..], 4),
    ] {
        for at in 0..joints.min(2) {
            let mut truth = vec![0.0; joints];
            truth[at] = 0.3;
            let c = synthetic(names, &truth, &[31, 32]);
            let js = identify::all_joints(&c);
            let rsm = identify_rsm(&c, &js, &RsmOptions::default(), &quiet).unwrap();
            let beyond = rsm.rsm.as_ref().and_then(|r| r.beyond_design.clone());
            if residual_warnings(&c, &rsm).is_empty() {
                assert!(
                    beyond.is_none(),
                    "{names:?} {truth:?}: checked though explained"
                );
                continue;
            }
            missed += 1;
            let b = beyond
                .unwrap_or_else(|| panic!("{names:?} {truth:?}: friction explains these runs"));
            for (got, want) in b.coulomb_nm.iter().zip(&truth) {
                assert!(
                    (got - want).abs() < 0.01,
                    "{names:?} {truth:?}: {:?}",
                    b.coulomb_nm
                );
            }
            assert!(b.rms_deg < 0.05 && b.simulations > 0, "{names:?}: {b:?}");
        }
    }
    assert!(
        missed > 0,
        "no case where the default design misses the friction"
    );
    // A harness at joint 2 beside friction at joint 1: not friction alone.
    let mechs = [Mechanism::load(&mechanism_path("seed001_T01")).unwrap()];
    let effects = [
        deploywatch_sim::effect::Effect::joint(
            deploywatch_sim::effect::EffectKind::CoulombFriction,
            1,
            0.3,
        ),
        deploywatch_sim::effect::Effect::joint(
            deploywatch_sim::effect::EffectKind::HarnessStiffness,
            2,
            0.5,
        ),
    ];
    let mut c = Campaign::default();
    for seed in [41, 42] {
        let run = identify::residual_check::synthetic_run(&mechs[0], &effects, seed).unwrap();
        c.push(&mechs, run, Path::new(&format!("harness{seed}.csv")))
            .unwrap();
    }
    let js = identify::all_joints(&c);
    let rsm = identify_rsm(&c, &js, &RsmOptions::default(), &quiet).unwrap();
    assert!(
        !residual_warnings(&c, &rsm).is_empty(),
        "a harness leaves residuals"
    );
    assert!(
        rsm.rsm.unwrap().beyond_design.is_none(),
        "friction alone cannot explain a harness"
    );
}

/// The default design (the scan's centre, half of it as half-range) is
/// one the plan accepts for any number of identified joints: a rotatable
/// CCD's α = (2^k)^(1/4) passes 2 at five joints, where half the centre
/// would take the axial points below 0 N·m; there the half-range is
/// centre / α and the lowest design point is 0 N·m exactly.
#[test]
fn the_default_design_stays_at_or_above_zero_for_any_number_of_joints() {
    for k in 1..=6 {
        // Friction added at the identified joints only, so they can explain it.
        let truth: Vec<f64> = (1..=6).map(|j| if j <= k { 0.2 } else { 0.0 }).collect();
        let c = synthetic(&["wing6_ideal"], &truth, &[51]);
        let js: Vec<usize> = (1..=k).collect();
        let case = format!("wing6_ideal, joints 1..={k}");
        let id = identify_rsm(&c, &js, &RsmOptions::default(), &quiet)
            .unwrap_or_else(|e| panic!("{case}: {e}"));
        check_rsm(&case, &id, k);
        let r = id.rsm.as_ref().unwrap();
        let alpha = f64::powf(f64::powi(2.0, k as i32), 0.25);
        assert!((r.alpha - alpha).abs() < 1e-12, "{case}: α {}", r.alpha);
        for i in 0..k {
            let lowest = r
                .points_nm
                .iter()
                .map(|p| p[i])
                .fold(f64::INFINITY, f64::min);
            let (c, h) = (r.centre_nm[i], r.half_range_nm[i]);
            assert!(lowest >= 0.0, "{case}: joint {}: {lowest}", i + 1);
            if 0.5 * alpha <= 1.0 {
                assert_eq!(h, 0.5 * c, "{case}: joint {}", i + 1);
            } else {
                assert!((h - c / alpha).abs() <= 1e-12 * c, "{case}: {h} vs {c}");
                assert!(lowest <= 1e-12 * c, "{case}: joint {}: {lowest}", i + 1);
            }
        }
    }
}

/// The `--center` the warning offers is a new design, never the one that
/// just missed: EFTs below the least default centre (0.025 N·m) give that
/// centre, and when it is the design's own, none is offered.
#[test]
fn the_centre_offered_beyond_the_design_is_a_new_one() {
    use deploywatch_sim::identify::by_rsm::centre_beyond;
    use deploywatch_sim::identify::BeyondDesign;
    let least = identify::SCAN_GRID_NM[1];
    let b = |c: Vec<f64>| BeyondDesign {
        coulomb_nm: c,
        rms_deg: 0.02,
        simulations: 10,
        start: "the surface's minimum".into(),
    };
    assert_eq!(
        centre_beyond(&b(vec![0.3, 0.0]), &[least, least]),
        Some(vec![0.3, least])
    );
    assert_eq!(centre_beyond(&b(vec![0.0, 1e-4]), &[least, least]), None);
    assert_eq!(centre_beyond(&b(vec![0.3, 0.6]), &[0.3002, 0.5999]), None);
    assert!(centre_beyond(&b(vec![0.3, 0.6]), &[0.3, 0.601]).is_some());
}

#[test]
fn a_subset_of_joints_keeps_the_others_as_given() {
    // Joint 2 only: joint 1 has no friction in the truth, so the nominal
    // mechanism is exact there and joint 2 alone is identified.
    let c = synthetic(&["seed000_case1"], &[0.0, 0.472], &[31]);
    let id = identify_direct(&c, &[2], &DirectOptions::default(), &quiet).unwrap();
    assert_eq!(id.joints.len(), 1);
    assert_eq!(id.joints[0].joint, 2);
    let [lo, hi] = id.joints[0].ci95.unwrap();
    assert!(lo <= 0.472 && 0.472 <= hi, "[{lo}, {hi}]");
    assert!(matches!(
        identify_direct(&c, &[3], &DirectOptions::default(), &quiet),
        Err(identify::IdentifyError::BadJoint {
            joint: 3,
            joints: 2
        })
    ));
    assert!(matches!(
        identify_direct(&c, &[2, 2], &DirectOptions::default(), &quiet),
        Err(identify::IdentifyError::DuplicateJoint(2))
    ));
}

/// The `coulomb_friction` truth of an example folder, by joint.
fn example_truth(dir: &Path, joints: usize) -> Vec<f64> {
    let text = std::fs::read_to_string(dir.join("truth.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let mut t = vec![0.0; joints];
    for e in v["effects"].as_array().unwrap() {
        if e["name"] == "coulomb_friction" {
            t[e["joint"].as_u64().unwrap() as usize - 1] = e["value"].as_f64().unwrap();
        }
    }
    t
}

#[test]
fn example_a_is_identified_by_both_methods() {
    let dir = data_dir().join("examples/a_seed001_eft");
    let mechs = [mechanism_path("seed001_T01"), mechanism_path("seed001_T02")];
    let runs = [dir.join("seed001_T01.csv"), dir.join("seed001_T02.csv")];
    let c = Campaign::load(&mechs, &runs).unwrap();
    let joints = identify::all_joints(&c);
    let direct = identify_direct(&c, &joints, &DirectOptions::default(), &quiet).unwrap();
    let rsm = identify_rsm(&c, &joints, &RsmOptions::default(), &quiet).unwrap();
    // Only now look at the truth.
    let truth = example_truth(&dir, joints.len());
    assert_eq!(truth, [2.63, 1.7, 0.001]);
    check_direct("example (a)", &direct, &truth);
    check_rsm("example (a)", &rsm, 3);
    // The RMS before is the truth file's baseline_rms_deg per run.
    for (s, want) in direct.before.runs.iter().zip([44.6515, 42.7104]) {
        assert!(
            (s.rms_deg - want).abs() < 1e-3,
            "{}: {} vs {want}",
            s.run,
            s.rms_deg
        );
    }
}

#[test]
fn cli_writes_the_json_and_the_plot() {
    let dir = data_dir().join("examples/a_seed001_eft");
    let out = std::env::temp_dir().join(format!("deploywatch-identify-{}", std::process::id()));
    std::fs::create_dir_all(&out).unwrap();
    let json = out.join("a.json");
    let args = IdentifyArgs {
        mechanisms: vec![mechanism_path("seed001_T01"), mechanism_path("seed001_T02")],
        runs: vec![dir.join("seed001_T01.csv"), dir.join("seed001_T02.csv")],
        method: Method::Direct,
        joints: Some(vec![1, 2, 3]),
        json: Some(json.clone()),
        plot: None,
        start: None,
        center: None,
        range: None,
        response: RsmResponse::TeSum,
        rounds: None,
        quiet: true,
    };
    run_cli(&args).unwrap();
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(v["method"], "direct");
    let joints = v["joints"].as_array().unwrap();
    assert_eq!(joints.len(), 3);
    for (i, j) in joints.iter().enumerate() {
        assert_eq!(j["joint"].as_u64(), Some(i as u64 + 1));
        assert!(j["coulomb_nm"].as_f64().is_some());
        let ci = j["ci95"].as_array().unwrap();
        assert_eq!(ci.len(), 2);
        assert!(ci[0].as_f64().unwrap() <= j["coulomb_nm"].as_f64().unwrap());
    }
    for key in ["rms_deg_before", "rms_deg_after", "wall_s"] {
        assert!(v[key].as_f64().is_some(), "{key}");
    }
    assert!(v["simulations"].as_u64().unwrap() > 0);
    let png = std::fs::read(out.join("a.png")).expect("the PNG beside the JSON");
    assert_eq!(&png[1..4], b"PNG");

    // rsm through the CLI: no intervals.
    let rsm_json = out.join("rsm.json");
    let args = IdentifyArgs {
        method: Method::Rsm,
        joints: Some(vec![1, 2, 3]),
        json: Some(rsm_json.clone()),
        plot: Some(out.join("rsm-plot.png")),
        ..args
    };
    run_cli(&args).unwrap();
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&rsm_json).unwrap()).unwrap();
    assert_eq!(v["method"], "rsm");
    assert!(v["joints"][0]["ci95"].is_null());
    assert!(out.join("rsm-plot.png").exists());

    // Bad input: a run whose mechanism is not given, an option of the wrong method.
    let bad = IdentifyArgs {
        mechanisms: vec![mechanism_path("seed001_T01")],
        ..args
    };
    let e = run_cli(&bad).unwrap_err();
    assert_eq!(e.code, 2);
    assert!(
        e.message.contains("seed001_T02.csv") && e.message.contains("seed001-T02"),
        "{}",
        e.message
    );
    let bad = IdentifyArgs {
        mechanisms: vec![mechanism_path("seed001_T01"), mechanism_path("seed001_T02")],
        method: Method::Direct,
        center: Some(vec![1.0, 1.0, 0.1]),
        ..bad
    };
    let e = run_cli(&bad).unwrap_err();
    assert_eq!(e.code, 2);
    assert!(e.message.contains("--center"), "{}", e.message);
    let bad = IdentifyArgs {
        method: Method::Rsm,
        center: Some(vec![1.0, 1.0]),
        ..bad
    };
    let e = run_cli(&bad).unwrap_err();
    assert_eq!(e.code, 2, "{}", e.message);
    assert!(e.message.contains("centre"), "{}", e.message);
    let bad = IdentifyArgs {
        method: Method::Direct,
        center: None,
        rounds: Some(3),
        ..bad
    };
    let e = run_cli(&bad).unwrap_err();
    assert_eq!(e.code, 2, "{}", e.message);
    assert!(e.message.contains("--rounds"), "{}", e.message);
    let bad = IdentifyArgs {
        method: Method::Rsm,
        rounds: Some(0),
        ..bad
    };
    let e = run_cli(&bad).unwrap_err();
    assert_eq!(e.code, 2, "{}", e.message);
    assert!(e.message.contains("rounds 0"), "{}", e.message);
    let _ = std::fs::remove_dir_all(&out);
}
