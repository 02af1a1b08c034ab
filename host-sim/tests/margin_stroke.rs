//! `deploywatch margin` along the stroke (`docs/margin.md`, "Along the
//! stroke"): the static torque margin at every position, checked against
//! hand calculations made here from the mechanism files' own numbers (the
//! TOML read with `toml_edit`, not through deploywatch's loader), and
//! `--check` failing on a negative margin at any position.
mod common;

use common::{data, deploywatch, fails, s};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Output;
use toml_edit::{DocumentMut, Item};

/// `margin --json` of `mech` with `args`; its JSON.
fn margin_json(mech: &Path, args: &[&str]) -> Value {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m.json");
    let mut all = vec![
        "margin",
        "--quiet",
        "--mechanism",
        s(mech),
        "--json",
        s(&out),
    ];
    all.extend_from_slice(args);
    let run = deploywatch(&all);
    assert!(
        run.status.success(),
        "{}: {}",
        mech.display(),
        String::from_utf8_lossy(&run.stderr)
    );
    serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap()
}

/// `deploywatch margin --quiet` of seed 000 case 1 with its identified
/// friction (0.54 and 0.472 N·m) by ECSS, and the `more` arguments.
fn case1_ecss(more: &[&str]) -> Output {
    let file = data().join("mechanisms/seed000_case1.toml");
    let mut args = vec![
        "margin",
        "--quiet",
        "--mechanism",
        s(&file),
        "--friction",
        "0.54,0.472",
        "--standard",
        "ecss",
    ];
    args.extend(more);
    deploywatch(&args)
}

fn toml(path: &Path) -> DocumentMut {
    std::fs::read_to_string(path).unwrap().parse().unwrap()
}

fn num(item: &Item) -> f64 {
    item.as_float()
        .or_else(|| item.as_integer().map(|i| i as f64))
        .unwrap_or_else(|| panic!("not a number: {item}"))
}

/// The margin [%] the JSON gives at joint angle `deg` of joint `j`.
fn margin_at(m: &Value, j: usize, deg: f64) -> f64 {
    let points = m["joints"][j]["stroke"]["points"].as_array().unwrap();
    let p = points
        .iter()
        .find(|p| (p["angle_deg"].as_f64().unwrap() - deg).abs() < 1e-9)
        .unwrap_or_else(|| panic!("joint {}: no position at {deg}°", j + 1));
    p["margin_pct"].as_f64().unwrap()
}

/// `(D / (f · T) − 1) · 100` [%], the hand calculation.
fn hand(driving_nm: f64, factor: f64, friction_nm: f64) -> f64 {
    (driving_nm / (factor * friction_nm) - 1.0) * 100.0
}

fn close(got: f64, want: f64, what: &str) {
    assert!(
        (got - want).abs() <= 1e-3 * want.abs().max(1.0),
        "{what}: {got} % from deploywatch, {want} % by hand"
    );
}

#[test]
fn seed000_case1_fails_at_the_latch_end_with_its_identified_friction() {
    let file = data().join("mechanisms/seed000_case1.toml");
    let doc = toml(&file);
    let m = margin_json(
        &file,
        &["--friction", "0.54,0.472", "--standard", "ecss-e-st-33-01c"],
    );
    for (j, eft) in [(0, 0.54), (1, 0.472)] {
        let spring = &doc["joint"][j]["spring"];
        // At the latch (|φ| = 0) a linear spring gives its preload.
        let by_hand = hand(num(&spring["preload_nm"]) * num(&spring["count"]), 3.0, eft);
        let stroke = &m["joints"][j]["stroke"];
        assert!(by_hand < 0.0, "joint {}: {by_hand}", j + 1);
        assert_eq!(stroke["worst_angle_deg"].as_f64(), Some(0.0));
        assert_eq!(stroke["pass"], false);
        let worst = stroke["worst_margin_pct"].as_f64().unwrap();
        assert!(
            (worst - by_hand).abs() <= 1e-3 * by_hand.abs(),
            "joint {}: {worst} vs {by_hand}",
            j + 1
        );
        // The stowed-angle margin passes: only the stroke shows the failure.
        assert!(m["joints"][j]["torque_margin_pct"].as_f64().unwrap() > 0.0);
    }
    let run = case1_ecss(&["--check"]);
    fails(&run, 1, &["margin --check", "FAIL"]);
    let out = String::from_utf8_lossy(&run.stdout);
    assert!(out.contains("worst at φ = 0.00°"), "{out}");
    assert!(out.contains("-12.47"), "{out}");
    assert!(out.contains("-66.48"), "{out}");
}

/// Three positions of joint `j` of `doc` and the driving torque by hand
/// there: `(joint angle [deg], torque [N·m])`.
fn hand_positions(doc: &DocumentMut, j: usize) -> Vec<(f64, f64)> {
    let joint = &doc["joint"][j];
    let stowed = num(&joint["stowed_deg"]);
    let (sign, stroke) = (stowed.signum(), stowed.abs());
    let spring = &joint["spring"];
    let count = num(&spring["count"]);
    match spring["kind"].as_str().unwrap() {
        "linear" => {
            let (t0, k) = (
                num(&spring["preload_nm"]),
                num(&spring["stiffness_nm_per_rad"]),
            );
            [0.0, stroke / 2.0, stroke]
                .map(|d| (sign * d + 0.0, count * (t0 + k * d.to_radians())))
                .to_vec()
        }
        "tape" => {
            // The unfolding branch passes through (0, 0), D, B, (90, M),
            // (180, C) (physics.md 3.2); below D its torque falls to 0 at
            // the latch, where the latching margin applies instead.
            let ty = spring["type"].as_str().unwrap();
            let t = &doc["tape"][ty];
            let pt = |k: &str| (num(&t[k][0]), num(&t[k][1]));
            let mut knots = vec![pt("d"), pt("b")];
            knots.push((90.0, num(&t["m_90"])));
            knots.push((180.0, num(&t["c_180"])));
            knots
                .into_iter()
                .filter(|(d, _)| *d <= stroke)
                .take(3)
                .map(|(d, m)| (sign * d + 0.0, count * m))
                .collect()
        }
        other => panic!("a spring of kind {other}"),
    }
}

/// A physical latch's entry ramp on joint `j` by hand: its torque
/// `(P0 + k h) r tan α_e` [N·m] over `[crest, crest + h / (r tan α_e)]`
/// \[deg\] of travel from the stop (a pawl: its spring on its cam, `lift`
/// and `notch` for `h` and the crest; `physics.md` §10).
fn hand_latch(doc: &DocumentMut, j: usize) -> Option<(f64, f64, f64)> {
    let latch = doc["joint"][j].get("latch")?;
    let (t, stroke, crest, ramp) = match latch.get("plunger") {
        Some(p) => (p, "stroke_mm", "crest_deg", "entry_ramp_deg"),
        None => (&latch["pawl"], "lift_mm", "notch_deg", "cam_ramp_deg"),
    };
    let (p0, k, r_mm, h) = (
        num(&t["preload_n"]),
        num(&t["stiffness_n_per_mm"]),
        num(&t["radius_mm"]),
        num(&t[stroke]),
    );
    let tan_e = num(&t[ramp]).to_radians().tan();
    let from = num(&t[crest]);
    let to = from + (h / (r_mm * tan_e)).to_degrees();
    Some(((p0 + k * h) * r_mm / 1000.0 * tan_e, from, to))
}

#[test]
fn every_bundled_mechanism_agrees_with_a_hand_calculation_at_three_positions() {
    let mut files: Vec<PathBuf> = std::fs::read_dir(data().join("mechanisms"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 20, "{files:?}");
    let friction = 0.2;
    for file in &files {
        let doc = toml(file);
        let n = doc["joint"].as_array_of_tables().unwrap().len();
        let list = vec![friction.to_string(); n].join(",");
        let m = margin_json(file, &["--friction", &list, "--standard", "nasa-std-5017"]);
        for j in 0..n {
            let positions = hand_positions(&doc, j);
            assert_eq!(positions.len(), 3, "{}: joint {}", file.display(), j + 1);
            let latch = hand_latch(&doc, j);
            let stroke = &m["joints"][j]["stroke"];
            let from = stroke["static_from_deg"].as_f64().unwrap();
            let first = stroke["points"][0]["angle_deg"].as_f64().unwrap().abs();
            assert_eq!(first, from);
            let tape = doc["joint"][j]["spring"]["kind"].as_str() == Some("tape");
            let d = positions[0].0.abs();
            assert_eq!(from, if tape { d } else { 0.0 }, "{}", file.display());
            for (deg, driving) in positions {
                let entry = match latch {
                    Some((t, from, to)) if deg.abs() >= from && deg.abs() <= to => t,
                    _ => 0.0,
                };
                let want = (driving / (3.0 * friction + 3.0 * entry) - 1.0) * 100.0;
                let what = format!("{} joint {} at {deg}°", file.display(), j + 1);
                close(margin_at(&m, j, deg), want, &what);
            }
        }
    }
}

#[test]
fn a_plunger_entry_ramp_counts_on_its_width_only() {
    // (P0 + k_p h) r_p tan α_e over crest … crest + h / (r_p tan α_e).
    let file = data().join("mechanisms/one_panel_physical_latch.toml");
    let doc = toml(&file);
    let p = &doc["joint"][0]["latch"]["plunger"];
    let (p0, kp, r_mm, h) = (
        num(&p["preload_n"]),
        num(&p["stiffness_n_per_mm"]),
        num(&p["radius_mm"]),
        num(&p["stroke_mm"]),
    );
    let tan_e = num(&p["entry_ramp_deg"]).to_radians().tan();
    let crest = num(&p["crest_deg"]);
    let entry = (p0 + kp * h) * r_mm / 1000.0 * tan_e;
    let spring = &doc["joint"][0]["spring"];
    let (t0, k, count) = (
        num(&spring["preload_nm"]),
        num(&spring["stiffness_nm_per_rad"]),
        num(&spring["count"]),
    );
    let sign = num(&doc["joint"][0]["stowed_deg"]).signum();
    let m = margin_json(&file, &["--friction", "0.2", "--standard", "nasa-std-5017"]);
    let drive = |deg: f64| count * (t0 + k * f64::to_radians(deg));
    let at_crest = (drive(crest) / (3.0 * 0.2 + 3.0 * entry) - 1.0) * 100.0;
    close(margin_at(&m, 0, sign * crest), at_crest, "at the crest");
    let end = crest + (h / (r_mm * tan_e)).to_degrees();
    let past = (end + 1.0).floor();
    close(
        margin_at(&m, 0, sign * past),
        hand(drive(past), 3.0, 0.2),
        "past the ramp",
    );
    close(
        margin_at(&m, 0, 0.0),
        hand(drive(0.0), 3.0, 0.2),
        "at the stop",
    );
}

/// `--plot FILE.png` writes the margin along the stroke as a PNG beside
/// the JSON (the data it draws is held against the table in
/// `report::margin_plot`'s unit test); a folder that does not exist is
/// refused before anything is computed (exit 2).
#[test]
fn plot_writes_the_margin_along_the_stroke() {
    let file = data().join("mechanisms/seed000_case1.toml");
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("margin.png");
    let run = case1_ecss(&["--plot", s(&png)]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let bytes = std::fs::read(&png).expect("the plot is written");
    assert!(bytes.starts_with(b"\x89PNG\r\n\x1a\n"), "a PNG");
    let missing = dir.path().join("no_such_folder/margin.png");
    let run = deploywatch(&["margin", "--mechanism", s(&file), "--plot", s(&missing)]);
    fails(&run, 2, &["--plot", "does not exist"]);
}

/// A joint's `spring_tolerance_pct` in the mechanism file lowers its
/// minimum driving spring as `--spring-tolerance` of the same figure does
/// (a margin from the nominal spring would overstate it by the whole
/// band); of the two, the larger holds, joint by joint, and the JSON says
/// which each joint took.
#[test]
fn a_spring_tolerance_declared_in_the_file_lowers_the_driving_spring() {
    let file = data().join("mechanisms/seed001_T01.toml");
    let dir = tempfile::tempdir().unwrap();
    let mut doc = toml(&file);
    doc["joint"][0]["spring_tolerance_pct"] = toml_edit::value(5.0);
    let declared = dir.path().join("declared.toml");
    std::fs::write(&declared, doc.to_string()).unwrap();
    let std = [
        "--friction",
        "2.63,1.7,0.001",
        "--standard",
        "nasa-std-5017",
    ];
    let nominal = margin_json(&file, &std);
    let from_file = margin_json(&declared, &std);
    let flag = |pct: &'static str| [&std[..], &["--spring-tolerance", pct]].concat();
    let by_flag = margin_json(&file, &flag("5"));
    let pct = |m: &Value, j: usize, key: &str| m["joints"][j][key].as_f64().unwrap();
    for key in ["torque_margin_pct", "energy_margin_pct"] {
        assert_eq!(pct(&from_file, 0, key), pct(&by_flag, 0, key), "{key}");
        assert!(pct(&from_file, 0, key) < pct(&nominal, 0, key), "{key}");
        assert_eq!(
            pct(&from_file, 1, key),
            pct(&nominal, 1, key),
            "{key}: joint 2 declares none"
        );
    }
    assert_eq!(pct(&from_file, 0, "spring_tolerance_pct"), 5.0);
    assert_eq!(pct(&from_file, 1, "spring_tolerance_pct"), 0.0);
    // A smaller figure for every joint keeps joint 1's 5 % and gives the
    // others 2 %.
    let both = margin_json(&declared, &flag("2"));
    assert_eq!(pct(&both, 0, "spring_tolerance_pct"), 5.0);
    assert_eq!(pct(&both, 1, "spring_tolerance_pct"), 2.0);
    assert_eq!(
        pct(&both, 0, "torque_margin_pct"),
        pct(&by_flag, 0, "torque_margin_pct")
    );
}
