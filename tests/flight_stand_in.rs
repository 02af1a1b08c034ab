//! A loss the runs cannot tell from the rig's (`docs/margin.md`, "On
//! orbit"; `docs/diagnosis.md`, "Ambiguity"): on a one-panel wing, air drag
//! on the panel and quadratic damping at its hinge have one law
//! (`c = k L⁴/4`), so two runs on the rig cannot say which it was. The
//! flight margin must then keep the hinge's loss, never credit the wing
//! with the air's.
//!
//! A seeded generator draws each wing (panel length, mass, linear spring,
//! stowed angle, hinge friction) and hides either air drag or quadratic
//! damping at the hinge (alternately; log-uniform, raised until it moves
//! the runs by ≥ 0.3° RMS), or nothing. Two runs are simulated with the
//! reference sensor and written as a user's files without the truth; the
//! CLI diagnoses them and computes the flight margin from the diagnosis.
//!
//! A case passes when
//! - with a loss hidden: the diagnosis's answer and its ambiguity group
//!   hold both readings, each value within 5 % of the truth's equivalent;
//!   `margin --flight` counts quadratic damping at joint 1 at least the
//!   truth's (the worst end of its interval), and says it was kept in the
//!   air's place; `reliability --flight` draws it;
//! - clean: nothing named, no ambiguity listed, nothing kept.
//!
//! `DEPLOYWATCH_FULL=1` runs 40 cases; the CI runs 12.

use deploywatch_sim::deployment::{self, SimOptions};
use deploywatch_sim::effect::{Effect, EffectKind};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::reliability::identified::from_findings_json;
use deploywatch_sim::reliability::params::Target;
use deploywatch_sim::sensor::{self, SensorModel};
use deploywatch_tests::cli_run::deploywatch;
use deploywatch_tests::hidden_effect::moves_runs_deg;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::Value;
use std::path::{Path, PathBuf};

/// What a case hides.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Hidden {
    Air,
    Hinge,
    Clean,
}

struct Case {
    toml: String,
    length_m: f64,
    truth: Vec<Effect>,
    hidden: Hidden,
}

fn log_uniform(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    lo * (hi / lo).powf(rng.gen::<f64>())
}

/// Case `i`: a one-panel wing drawn from seed `7100 + i`, hiding air drag,
/// hinge quadratic damping or nothing (`i % 3`).
fn case(i: u64) -> Case {
    let mut rng = ChaCha8Rng::seed_from_u64(7100 + i);
    let length_m: f64 = rng.gen_range(0.5..1.4);
    let mass_kg: f64 = rng.gen_range(1.0..5.0);
    let toml = format!(
        "name = \"one-panel-{i}\"\n\n[[panel]]\nlength_m = {length_m:.4}\nmass_kg = {mass_kg:.4}\n\
         com_m = {:.4}\ninertia_kgm2 = {:.5}\n\n[[joint]]\nstowed_deg = {:.1}\n\
         spring = {{ kind = \"linear\", preload_nm = {:.3}, stiffness_nm_per_rad = {:.3}, count = 1 }}\n\
         friction = {{ coulomb_nm = {:.3} }}\n\n[run]\nduration_s = 10.0\nsample_hz = 100.0\n",
        0.5 * length_m,
        mass_kg * length_m * length_m / 12.0,
        rng.gen_range(60.0..180.0),
        rng.gen_range(0.8..2.0),
        rng.gen_range(0.1..0.8),
        rng.gen_range(0.02..0.2),
    );
    let length_m = format!("{length_m:.4}").parse().expect("a number");
    let m = Mechanism::from_toml_str(&toml, "generated").expect("a valid wing");
    let hidden = [Hidden::Air, Hidden::Hinge, Hidden::Clean][(i % 3) as usize];
    let mut truth = match hidden {
        Hidden::Air => vec![Effect::global(
            EffectKind::AirDrag,
            log_uniform(&mut rng, 0.05, 1.0),
        )],
        Hidden::Hinge => vec![Effect::joint(
            EffectKind::QuadraticDamping,
            1,
            log_uniform(&mut rng, 0.005, 0.1),
        )],
        Hidden::Clean => Vec::new(),
    };
    for e in &mut truth {
        for _ in 0..12 {
            if moves_runs_deg(&m, std::slice::from_ref(e)) >= 0.3 {
                break;
            }
            *e = e.with_value(e.value() * 1.5);
        }
    }
    Case {
        toml,
        length_m,
        truth,
        hidden,
    }
}

/// The hinge's quadratic damping [N·m·s²/rad²] that acts as the truth does.
fn hinge_equivalent(c: &Case) -> Option<f64> {
    let e = c.truth.first()?;
    Some(match e.kind() {
        EffectKind::AirDrag => e.value() * c.length_m.powi(4) / 4.0,
        _ => e.value(),
    })
}

/// Writes the wing and its two runs into `dir`, as a user has them.
fn write_files(c: &Case, dir: &Path) -> (PathBuf, Vec<PathBuf>) {
    std::fs::create_dir_all(dir).expect("a folder");
    let wing = dir.join("wing.toml");
    std::fs::write(&wing, &c.toml).expect("written");
    let m = Mechanism::from_toml_str(&c.toml, "generated").expect("a valid wing");
    let traj = deployment::simulate(&m, &c.truth, &SimOptions::default()).expect("simulates");
    let runs = (0..2)
        .map(|r| {
            let mut run = sensor::measure(&traj, &[0.0], &SensorModel::REFERENCE, 40 + r);
            run.set_meta("mechanism", &m.name);
            let path = dir.join(format!("run{r}.csv"));
            run.write(&path).expect("written");
            path
        })
        .collect();
    (wing, runs)
}

fn read(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).expect("written")).expect("JSON")
}

/// `(name, joint, value)` of each effect of a JSON list, its name under
/// `key` (`name` in a diagnosis, `effect` in a margin's `counted`).
fn effects_by(list: &Value, key: &str) -> Vec<(String, Option<u64>, f64)> {
    list.as_array()
        .into_iter()
        .flatten()
        .map(|e| {
            (
                e[key].as_str().unwrap_or_default().to_string(),
                e["joint"].as_u64(),
                e["value"].as_f64().unwrap_or(f64::NAN),
            )
        })
        .collect()
}

/// `(name, joint, value)` of each effect of a diagnosis's JSON list.
fn effects(list: &Value) -> Vec<(String, Option<u64>, f64)> {
    effects_by(list, "name")
}

/// Every set the diagnosis reports: its answer, then each set of each
/// ambiguity group.
fn reported_sets(d: &Value) -> Vec<Vec<(String, Option<u64>, f64)>> {
    let mut out = vec![effects(&d["effects"])];
    for g in d["ambiguities"].as_array().into_iter().flatten() {
        for s in g["sets"].as_array().into_iter().flatten() {
            out.push(effects(&s["effects"]));
        }
    }
    out
}

fn check(i: u64) -> Result<(), String> {
    let c = case(i);
    let dir = std::env::temp_dir().join(format!("dw-flight-stand-in-{}-{i}", std::process::id()));
    let (wing, runs) = write_files(&c, &dir);
    let (w, d, m) = (
        wing.display().to_string(),
        dir.join("d.json"),
        dir.join("m.json"),
    );
    let mut args = vec!["diagnose", "-q", "--mechanism", &w, "--json"];
    let d_s = d.display().to_string();
    args.push(&d_s);
    let run_s: Vec<String> = runs.iter().map(|p| p.display().to_string()).collect();
    args.extend(run_s.iter().map(String::as_str));
    let code = deploywatch(&args);
    if code != 0 {
        return Err(format!("diagnose exited {code}"));
    }
    let diag = read(&d);
    let m_s = m.display().to_string();
    let code = deploywatch(&[
        "margin",
        "-q",
        "--mechanism",
        &w,
        "--from",
        &d_s,
        "--flight",
        "--json",
        &m_s,
    ]);
    if code != 0 {
        return Err(format!("margin --flight exited {code}"));
    }
    let margin = read(&m);
    let counted = effects_by(&margin["joints"][0]["counted"], "effect");
    let source = margin["resistances_from"].as_str().unwrap_or_default();
    let sets = reported_sets(&diag);
    let Some(c_true) = hinge_equivalent(&c) else {
        // Clean: nothing named, nothing listed, nothing kept.
        let clean = sets.len() == 1 && sets[0].is_empty() && counted.is_empty();
        return clean
            .then_some(())
            .ok_or_else(|| format!("clean wing: reported {sets:?}, counted {counted:?}"));
    };
    let k_true = 4.0 * c_true / c.length_m.powi(4);
    let near = |v: f64, t: f64| (v / t - 1.0).abs() <= 0.05;
    let air = sets
        .iter()
        .any(|s| s.len() == 1 && s[0].0 == "air_drag" && near(s[0].2, k_true));
    let hinge = sets.iter().any(|s| {
        s.len() == 1 && s[0].0 == "quadratic_damping" && s[0].1 == Some(1) && near(s[0].2, c_true)
    });
    if !(air && hinge) {
        return Err(format!(
            "{:?} hidden (hinge equivalent {c_true:.5}, air {k_true:.5}): reported {sets:?}",
            c.hidden
        ));
    }
    let kept = counted
        .iter()
        .find(|e| e.0 == "quadratic_damping")
        .map(|e| e.2);
    if !kept.is_some_and(|v| v >= c_true * 0.999) {
        return Err(format!(
            "margin --flight counts {counted:?} for the hinge's {c_true:.5} ({source})"
        ));
    }
    if counted.iter().any(|e| e.0 == "air_drag") || !source.contains("kept in place of air_drag") {
        return Err(format!("margin --flight: {counted:?}, source {source}"));
    }
    let m_loaded = Mechanism::from_toml_str(&c.toml, "generated").expect("a valid wing");
    let mut found = from_findings_json(&std::fs::read_to_string(&d).expect("written"), &m_loaded)
        .map_err(|e| e.to_string())?;
    let (out, kept) = found.take_out_the_rig();
    let drawn = found.vary.iter().any(|v| {
        matches!(v.target, Target::Effect(e) if e.kind() == EffectKind::QuadraticDamping && e.joint == Some(1))
    });
    let air_drawn = found
        .vary
        .iter()
        .any(|v| matches!(v.target, Target::Effect(e) if e.kind() == EffectKind::AirDrag));
    if !drawn || air_drawn || kept.len() != 1 {
        return Err(format!(
            "reliability --flight: took out {out:?}, kept {kept:?}, draws {:?}",
            found.vary
        ));
    }
    let _ = std::fs::remove_dir_all(&dir);
    Ok(())
}

#[test]
fn the_flight_margin_keeps_a_loss_the_runs_cannot_tell_from_the_air() {
    let n = if std::env::var_os("DEPLOYWATCH_FULL").is_some() {
        40
    } else {
        12
    };
    let failures: Vec<String> = (0..n)
        .filter_map(|i| check(i).err().map(|e| format!("case {i}: {e}")))
        .collect();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
