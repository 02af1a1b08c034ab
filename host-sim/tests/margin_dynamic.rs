//! `deploywatch margin --deploy-time` (`docs/margin.md`, "The dynamic
//! margin"): the dynamic torque margin checked against a hand calculation
//! made here from the mechanism file's own numbers (the TOML read with
//! `toml_edit`, the inertia of the two-panel chain written out by hand, not
//! through the core chain), `--check` failing on a too-short deploy time,
//! and the line saying it is not computed without one.
mod common;

use common::{data, deploywatch, fails, s};
use serde_json::Value;
use std::path::Path;
use toml_edit::{DocumentMut, Item};

/// `margin --json` of `mech` with `args`: its JSON and its stdout.
fn margin_json(mech: &Path, args: &[&str]) -> (Value, String) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m.json");
    let mut all = vec!["margin", "--mechanism", s(mech), "--json", s(&out)];
    all.extend_from_slice(args);
    let run = deploywatch(&all);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let json = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    (json, String::from_utf8_lossy(&run.stdout).into_owned())
}

fn num(item: &Item) -> f64 {
    item.as_float()
        .or_else(|| item.as_integer().map(|i| i as f64))
        .unwrap_or_else(|| panic!("not a number: {item}"))
}

fn close(got: f64, want: f64, what: &str) {
    assert!(
        (got - want).abs() <= 1e-3 * want.abs(),
        "{what}: {got} from deploywatch, {want} by hand"
    );
}

/// The two-panel planar chain's inertias about each hinge, largest over
/// the stroke: joint 2 carries panel 2 alone, `I_2 + m_2 c_2²` at every
/// angle; joint 1 carries both panels, `I_1 + m_1 c_1² + I_2 + m_2 |L_1 +
/// c_2 e^{iφ_2}|²`, largest with the chain straight (`φ_2 = 0`, the
/// latched end of the stroke): `I_1 + m_1 c_1² + I_2 + m_2 (L_1 + c_2)²`.
fn hand_inertia(doc: &DocumentMut) -> [f64; 2] {
    let p = |j: usize, k: &str| num(&doc["panel"][j][k]);
    let own = |j: usize| p(j, "inertia_kgm2") + p(j, "mass_kg") * p(j, "com_m").powi(2);
    let outer = p(1, "inertia_kgm2") + p(1, "mass_kg") * (p(0, "length_m") + p(1, "com_m")).powi(2);
    [own(0) + outer, own(1)]
}

#[test]
fn seed000_case1_dynamic_margin_equals_a_hand_calculation() {
    let file = data().join("mechanisms/seed000_case1.toml");
    let doc: DocumentMut = std::fs::read_to_string(&file).unwrap().parse().unwrap();
    let inertia = hand_inertia(&doc);
    let t = 5.0;
    let friction = [0.54, 0.472];
    for (standard, check) in [("nasa-std-5017", "nasa"), ("aiaa-s-114", "aiaa")] {
        let (m, text) = margin_json(
            &file,
            &[
                "--quiet",
                "--friction",
                "0.54,0.472",
                "--standard",
                standard,
                "--deploy-time",
                "5",
            ],
        );
        assert!(text.contains("α = 2 S / T²"), "{text}");
        assert_eq!(m["deploy_time_s"].as_f64(), Some(t));
        for j in 0..2 {
            let joint = &doc["joint"][j];
            let stroke = num(&joint["stowed_deg"]).abs().to_radians();
            let alpha = 2.0 * stroke / (t * t);
            let spring = &joint["spring"];
            // A linear spring against a constant friction and inertia
            // torque: the worst position is the latch, where it gives its
            // preload.
            let d = num(&spring["preload_nm"]) * num(&spring["count"]);
            let ia = inertia[j] * alpha;
            let by_hand = if check == "nasa" {
                // NASA-STD-5017B Eq. 4-1, analysis row: friction 3, acceleration 1.25.
                (d / (3.0 * friction[j] + 1.25 * ia) - 1.0) * 100.0
            } else {
                // AIAA S-114: factor 2 on the resistances, 25 % on I α.
                ((d - 2.0 * friction[j]) / ia - 1.0) * 100.0
            };
            let dy = &m["joints"][j]["dynamic"];
            close(dy["inertia_kgm2"].as_f64().unwrap(), inertia[j], "I");
            close(dy["accel_rad_s2"].as_f64().unwrap(), alpha, "α");
            close(dy["margin_pct"].as_f64().unwrap(), by_hand, standard);
            assert_eq!(dy["worst_angle_deg"].as_f64(), Some(0.0));
            let printed = format!("margin {by_hand:.2} %");
            assert!(
                text.contains(&printed),
                "{standard}: lacks {printed}:\n{text}"
            );
        }
    }
    // Hand numbers of this wing, so the formula above is not vacuous.
    assert!((inertia[0] - 7.56).abs() < 1e-9 && (inertia[1] - 1.0448).abs() < 1e-9);
}

#[test]
fn check_fails_on_a_too_short_deploy_time_and_passes_on_a_long_one() {
    let file = data().join("mechanisms/seed000_case1.toml");
    let run = |t: &str| {
        deploywatch(&[
            "margin",
            "--quiet",
            "--mechanism",
            s(&file),
            "--standard",
            "nasa",
            "--check",
            "--deploy-time",
            t,
        ])
    };
    // 1 s: I α = 7.56 · π = 23.8 N·m at joint 1 against a 1.418 N·m preload.
    let short = run("1");
    fails(&short, 1, &["margin --check", "FAIL"]);
    assert!(String::from_utf8_lossy(&short.stdout).contains("FAIL (dynamic)"));
    let long = run("20");
    assert!(
        long.status.success(),
        "{}",
        String::from_utf8_lossy(&long.stderr)
    );
}

#[test]
fn without_a_deploy_time_the_output_says_it_is_not_computed() {
    let file = data().join("mechanisms/seed001_T01.toml");
    let (m, text) = margin_json(&file, &["--standard", "aiaa"]);
    assert!(
        text.contains("dynamic margin: not computed (no required deploy time"),
        "{text}"
    );
    assert!(m["deploy_time_s"].is_null());
    assert!(m["joints"][0]["dynamic"].is_null());
}
