//! Every finding survives its JSON (`docs/spec/formats.md`, "Diagnosis:
//! JSON"), for every kind of the effect vocabulary ([`EffectKind::EVERY`]:
//! a kind added to it is covered here without editing this file; a kind
//! needs a line in [`sample`], whose match is exhaustive).
//!
//! - `every_kind_survives_its_json` (proptest): an effect with generated
//!   parameters written as `deploywatch diagnose --json` writes it
//!   ([`FoundEffect::of_effect`]) and read back as `simulate --from`,
//!   `margin --from` and `reliability --from` read it
//!   ([`Diagnosis::extended_effects`]) is the same effect, bit for bit
//!   (the model's parameters are written in full).
//! - `simulate_diagnose_resimulate_every_kind`: for each kind, a run
//!   simulated with the effect, diagnosed, the extended model re-simulated
//!   from the JSON alone (`simulate --from d.json --at run.csv`): its RMS
//!   against the run, recomputed here from the two CSVs, equals the
//!   extended RMS the diagnosis wrote within 1e-6 deg (the JSON's RMS has
//!   6 decimals and the CSV's angles too: at most 5e-7 deg each);
//!   `margin --from` counts each effect at the value fitted or an end of
//!   its interval (which end: `host-sim/tests/margin_ends.rs`), and
//!   `reliability --from` centres each law on it (a table fixed, each
//!   knot as fitted or at an end of its band).
//! - `formats_md_names_every_key_of_every_kind`: every key an entry
//!   carries is named in formats.md's "Diagnosis: JSON" section.
//!
//!     cargo test --release -p deploywatch-tests --test findings_roundtrip

use deploywatch_sim::effect::{Effect, EffectKind, Law};
use deploywatch_sim::findings::{Diagnosis, Findings, FoundEffect};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::reliability::identified::from_findings_json;
use deploywatch_sim::reliability::params::{Dist, Target};
use deploywatch_sim::torque_table::TablePoints;
use deploywatch_tests::cli_run::{angles, deploywatch};
use proptest::prelude::*;
use std::path::{Path, PathBuf};

/// Every kind the effect syntax knows.
fn kinds() -> Vec<EffectKind> {
    EffectKind::EVERY.to_vec()
}

/// An effect of `kind` from generated numbers `u` (each in 0..1).
fn sample(kind: EffectKind, joint: usize, u: [f64; 4]) -> Effect {
    // The first of these values the kind allows ([`EffectKind::allowed`];
    // every kind allows the last).
    let value = [4.0 * u[0] - 2.0, 2.0 * u[0], 0.9 * u[0]]
        .into_iter()
        .find(|&x| kind.allowed().contains(x))
        .expect("a fraction below 0.9 is allowed");
    let law = match Law::of_value(kind, value) {
        Law::StribeckFriction { .. } => Law::StribeckFriction {
            kinetic_nm: u[0],
            excess_nm: u[1],
            rate_rad_s: 0.01 + u[2],
        },
        Law::RigTilt { g_m_s2, .. } => Law::RigTilt {
            g_m_s2,
            alpha_deg: 360.0 * u[3] - 180.0,
        },
        Law::TorqueTable(_) => {
            let points = TablePoints {
                angle_deg: Some(vec![0.0, 45.0 + 40.0 * u[1], 180.0]),
                torque_nm: Some(vec![u[0], -u[2], 0.5 * u[3]]),
                rate_deg_s: Some(vec![0.0, 10.0 + u[3]]),
                rate_torque_nm: Some(vec![0.0, u[1]]),
            };
            Law::TorqueTable(points.build().expect("increasing knots"))
        }
        law => law,
    };
    Effect {
        joint: kind.per_joint().then_some(joint),
        law,
    }
}

/// The diagnosis JSON of one effect, as `diagnose --json` writes it.
fn json_of(e: &Effect) -> String {
    let d = Diagnosis {
        effects: vec![FoundEffect::of_effect(e)],
        ..Diagnosis::default()
    };
    serde_json::to_string_pretty(&d).expect("serialises")
}

fn close(a: f64, b: f64) -> bool {
    a == b || (a.is_nan() && b.is_nan())
}

fn same_tables(a: &Effect, b: &Effect) -> bool {
    let knots = |e: &Effect| {
        let mut k: Vec<Vec<f64>> = Vec::new();
        let t = e.table().copied().unwrap_or_default();
        for t in [&t.angle, &t.rate].into_iter().flatten() {
            k.push(t.xs().to_vec());
            k.push(t.ys().to_vec());
        }
        (t.angle.is_some(), t.rate.is_some(), k)
    };
    knots(a) == knots(b)
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 64,
        failure_persistence: None,
        rng_seed: proptest::test_runner::RngSeed::Fixed(20_261_129),
        ..ProptestConfig::default()
    })]

    /// Every kind, generated parameters: the effect read back from the JSON
    /// alone is the effect written, bit for bit.
    #[test]
    fn every_kind_survives_its_json(joint in 1usize..4, u in proptest::array::uniform4(0.0f64..1.0)) {
        for kind in kinds() {
            let e = sample(kind, joint, u);
            let text = json_of(&e);
            let Ok(Findings::Diagnosis(d)) = Findings::from_json_str(&text) else {
                panic!("{kind}: not read back as a diagnosis:\n{text}");
            };
            let back = d.extended_effects().map_err(|x| TestCaseError::fail(format!("{kind}: {x}")))?;
            prop_assert_eq!(back.len(), 1, "{}: {}", kind, text);
            let b = &back[0];
            prop_assert_eq!(b.kind(), e.kind());
            prop_assert_eq!(b.joint, e.joint);
            prop_assert!(close(b.value(), e.value()), "{}: value {} vs {}", kind, b.value(), e.value());
            // Every parameter of the law, bit for bit (a table's knots below).
            if e.table().is_none() {
                prop_assert_eq!(b.law, e.law, "{}: parameters", kind);
            }
            prop_assert!(same_tables(b, &e), "{}: tables", kind);
        }
    }
}

/// The "Diagnosis: JSON" section of formats.md.
fn formats_diagnosis_section() -> String {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/spec/formats.md");
    let text = std::fs::read_to_string(path).expect("docs/spec/formats.md");
    let start = text
        .find("## Diagnosis: JSON")
        .expect("a Diagnosis: JSON section");
    let rest = &text[start + 3..];
    let end = rest.find("\n## ").unwrap_or(rest.len());
    rest[..end].to_string()
}

/// Every key an effect entry carries, for every kind, is named in
/// formats.md's diagnosis section (as `"key"` or in the JSON example), and
/// its `name` in physics.md (formats.md: "a name from `physics.md` section 6").
#[test]
fn formats_md_names_every_key_of_every_kind() {
    let doc = formats_diagnosis_section();
    let physics = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../docs/spec/physics.md"
    ))
    .expect("docs/spec/physics.md");
    for kind in kinds() {
        let e = sample(kind, 1, [0.3, 0.4, 0.5, 0.6]);
        let v: serde_json::Value = serde_json::from_str(&json_of(&e)).expect("JSON");
        let entry = v["effects"][0].as_object().expect("an effect entry");
        for key in entry.keys() {
            assert!(
                doc.contains(&format!("\"{key}\"")),
                "{kind}: key \"{key}\" of its JSON entry is not in formats.md's Diagnosis: JSON section"
            );
        }
        assert!(
            physics.contains(&format!("`{}`", kind.name())),
            "{kind}: the entry's name is not in physics.md, where formats.md says the names are"
        );
    }
}

/// `deploywatch ARGS...` in this process (the CLI's own parser and `run`):
/// its exit code, 0 on success.
fn data(rel: &str) -> String {
    format!("{}/../data/{rel}", env!("CARGO_MANIFEST_DIR"))
}

fn text(p: &Path) -> &str {
    p.to_str().expect("a UTF-8 path")
}

/// A wing on which `kind` acts: the rig's causes need a `[rig]`, the
/// latch's a physical latch, every other kind seed 001's T01.
fn wing_for(kind: EffectKind) -> String {
    if kind.is_rig() {
        data("mechanisms/seed001_T01_rig.toml")
    } else if EffectKind::LATCH.contains(&kind) {
        data("mechanisms/seed001_T01_physical_latch.toml")
    } else {
        data("mechanisms/seed001_T01.toml")
    }
}

/// The angle columns of a run CSV, `[joint][sample]` (comment lines and
/// the header skipped; `t_s` first, then one `phiJ_deg` per joint).
/// RMS of model minus run over the first `samples` samples of each joint.
fn rms(model: &[Vec<f64>], run: &[Vec<f64>], samples: usize) -> f64 {
    let (mut sse, mut m) = (0.0, 0usize);
    for (a, b) in model.iter().zip(run) {
        for (x, y) in a.iter().zip(b).take(samples) {
            sse += (x - y) * (x - y);
            m += 1;
        }
    }
    (sse / m.max(1) as f64).sqrt()
}

/// One kind through simulate, diagnose, `simulate --from --at`, `margin
/// --from` and `reliability --from`; `Err` says what differs.
fn round_trip(kind: EffectKind, dir: &Path) -> Result<(), String> {
    let effect = sample(kind, 2, [0.05, 0.4, 0.3, 0.6]);
    // The numbers give the rig's kinds 1.8 of their unit: a tilt of
    // 1.8 m/s², under which seed 001 T01's rig never deploys, a wire
    // length and a frame offset of -1.8 m — runs no model here follows,
    // which the search spends minutes on. The round trip is about a rig
    // as tested: each at a size of the hidden-set suite's campaigns
    // (`tests/diagnosis_rig.rs`).
    let effect = match kind {
        EffectKind::RigTilt => effect.with_value(0.1),
        EffectKind::WireLength => effect.with_value(-0.12),
        EffectKind::FrameOffset => effect.with_value(0.025),
        _ => effect,
    };
    let mech = wing_for(kind);
    let (run, json, model) = (
        dir.join("run.csv"),
        dir.join("d.json"),
        dir.join("model.csv"),
    );
    let e = effect.to_string();
    let code = deploywatch(&[
        "simulate",
        &mech,
        "--out",
        text(&run),
        "--effect",
        &e,
        "--quiet",
    ]);
    if code != 0 {
        return Err(format!("simulate with {e}: exit {code}"));
    }
    let code = deploywatch(&[
        "diagnose",
        "--quiet",
        "--max-effects",
        "1",
        "--json",
        text(&json),
        "--mechanism",
        &mech,
        text(&run),
    ]);
    if code != 0 {
        return Err(format!("diagnose: exit {code}"));
    }
    let body = std::fs::read_to_string(&json).map_err(|x| x.to_string())?;
    let Ok(Findings::Diagnosis(d)) = Findings::from_json_str(&body) else {
        return Err(format!("not a diagnosis:\n{body}"));
    };
    let code = deploywatch(&[
        "simulate",
        &mech,
        "--from",
        text(&json),
        "--at",
        text(&run),
        "--out",
        text(&model),
        "--quiet",
    ]);
    if code != 0 {
        return Err(format!("simulate --from --at: exit {code}"));
    }
    intervals_bracket_the_values(&d)?;
    let joints = d.extended.trajectory_error_pct.len();
    let measured = angles(&run, joints);
    // The window the diagnosis fitted: up to where the model follows the
    // run, its free motion, or the whole run.
    let window = match (d.fitted_window.first(), d.fitted_whole) {
        (Some(w), _) => Some(w),
        (None, false) => d.free_window.first(),
        (None, true) => None,
    };
    let samples = window.map_or(measured[0].len(), |w| w.samples);
    let again = rms(&angles(&model, joints), &measured, samples);
    let said = d.extended.rms_deg.ok_or("no extended RMS in the JSON")?;
    if (again - said).abs() > 1e-6 {
        return Err(format!(
            "found {:?}: re-simulated RMS {again} deg, the diagnosis said {said}",
            names(&d)
        ));
    }
    margin_uses_the_fitted(&mech, &json, &d, dir)?;
    let wing = Mechanism::load(Path::new(&mech)).map_err(|x| x.to_string())?;
    reliability_uses_the_fitted(&body, &d, &wing)
}

/// Every parameter of a finding comes with its 95 % interval around it
/// (formats.md): the value's `ci95`, and `stribeck_friction`'s two others.
fn intervals_bracket_the_values(d: &Diagnosis) -> Result<(), String> {
    let inside = |x: Option<f64>, ci: Option<[Option<f64>; 2]>, key: &str| match (x, ci) {
        (Some(x), Some([Some(lo), Some(hi)])) if lo <= x + 1e-6 && x <= hi + 1e-6 => Ok(()),
        other => Err(format!(
            "{key}: {other:?} is not a value inside its interval"
        )),
    };
    for e in d
        .effects
        .iter()
        .filter(|e| e.name != "unexplained" && e.name != "torque_table")
    {
        inside(e.value, e.ci95, &format!("{} value", e.name))?;
        if e.name == EffectKind::StribeckFriction.name() {
            inside(e.excess_nm, e.excess_ci95_nm, "excess_nm")?;
            inside(e.stribeck_rad_s, e.stribeck_ci95_rad_s, "stribeck_rad_s")?;
        }
    }
    Ok(())
}

fn names(d: &Diagnosis) -> Vec<String> {
    d.effects
        .iter()
        .map(|e| format!("{}@{:?}", e.name, e.joint))
        .collect()
}

/// `margin --from`: every named effect counted at the value fitted or the
/// end of its 95 % interval that lowers the margin (the friction and
/// damping added to their joint's own; `tests/margin_ends.rs` in
/// deploywatch-sim checks which end).
fn margin_uses_the_fitted(
    mech: &str,
    json: &Path,
    d: &Diagnosis,
    dir: &Path,
) -> Result<(), String> {
    let out = dir.join("margin.json");
    let code = deploywatch(&[
        "margin",
        "--quiet",
        "--mechanism",
        mech,
        "--from",
        text(json),
        "--json",
        text(&out),
    ]);
    if code != 0 {
        return Err(format!("margin --from: exit {code}"));
    }
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).map_err(|x| x.to_string())?)
            .map_err(|x| x.to_string())?;
    let base: serde_json::Value = {
        let plain = dir.join("margin0.json");
        if deploywatch(&[
            "margin",
            "--quiet",
            "--mechanism",
            mech,
            "--json",
            text(&plain),
        ]) != 0
        {
            return Err("margin without --from failed".into());
        }
        serde_json::from_str(&std::fs::read_to_string(&plain).map_err(|x| x.to_string())?)
            .map_err(|x| x.to_string())?
    };
    for (i, f) in d.effects.iter().enumerate() {
        let Some(e) = f.to_effect(i).map_err(|x| x.to_string())? else {
            continue;
        };
        // At the end of its interval that lowers the margin (or its
        // estimate, docs/margin.md): one of the three.
        let ends: Vec<f64> = match f.ci95 {
            Some([Some(lo), Some(hi)]) => vec![e.value(), lo, hi],
            _ => vec![e.value()],
        };
        let j = e.joint.unwrap_or(1) - 1;
        let at =
            |v: &serde_json::Value, key: &str| v["joints"][j][key].as_f64().unwrap_or(f64::NAN);
        let ok = match e.kind() {
            EffectKind::CoulombFriction => ends
                .iter()
                .any(|x| at(&m, "coulomb_nm") == at(&base, "coulomb_nm") + x),
            EffectKind::ViscousDamping => ends
                .iter()
                .any(|x| at(&m, "viscous_nms") == at(&base, "viscous_nms") + x),
            _ => m["joints"]
                .as_array()
                .into_iter()
                .flatten()
                .flat_map(|jt| jt["counted"].as_array().into_iter().flatten())
                .chain(m["not_included"].as_array().into_iter().flatten())
                .any(|c| {
                    c["effect"].as_str() == Some(e.kind().name())
                        && (e.kind() == EffectKind::TorqueTable
                            || c["value"].as_f64().is_some_and(|v| ends.contains(&v))
                            || c["value"].is_null())
                }),
        };
        if !ok {
            return Err(format!(
                "margin --from: {e} not counted at its estimate or an end of its interval:\n{m:#}"
            ));
        }
    }
    Ok(())
}

/// True when the table `fixed` is the fitted `t` (same kind, joint and
/// knots), each knot's torque the fitted one or an end of its band in the
/// diagnosis's `entry`.
fn table_as_fitted(fixed: &Effect, t: &Effect, entry: &FoundEffect) -> bool {
    let knots = |a: &Effect| {
        let t = a.table().copied().unwrap_or_default();
        [t.angle, t.rate].map(|x| x.as_ref().map(|x| (x.xs().to_vec(), x.ys().to_vec())))
    };
    let bands = [&entry.torque_ci95_nm, &entry.rate_torque_ci95_nm];
    let on_band = |band: &Option<[Vec<Option<f64>>; 2]>, i: usize, y: f64| {
        band.as_ref()
            .is_some_and(|b| b.iter().any(|end| end.get(i) == Some(&Some(y))))
    };
    fixed.kind() == t.kind()
        && fixed.joint == t.joint
        && knots(fixed)
            .into_iter()
            .zip(knots(t))
            .zip(bands)
            .all(|((a, b), band)| match (a, b) {
                (Some((ax, ay)), Some((bx, by))) => {
                    ax == bx
                        && ay
                            .iter()
                            .zip(&by)
                            .enumerate()
                            .all(|(i, (y, fitted))| y == fitted || on_band(band, i, *y))
                }
                (a, b) => a.is_none() && b.is_none(),
            })
}

/// `reliability --from`: a law centred on each effect's value fitted, its
/// other parameters as fitted; a table fixed as fitted, each knot's torque
/// the fitted one or an end of its band (which end:
/// `host-sim/tests/margin_ends.rs`).
fn reliability_uses_the_fitted(body: &str, d: &Diagnosis, mech: &Mechanism) -> Result<(), String> {
    let found = from_findings_json(body, mech)?;
    let (tables, effects): (Vec<Effect>, Vec<Effect>) = d
        .extended_effects()
        .map_err(|x| x.to_string())?
        .into_iter()
        .partition(|e| e.kind() == EffectKind::TorqueTable);
    let entries = d.effects.iter().filter(|f| f.name == "torque_table");
    if found.fixed.len() != tables.len() {
        return Err(format!(
            "{} fixed for {} tables",
            found.fixed.len(),
            tables.len()
        ));
    }
    for ((f, t), entry) in found.fixed.iter().zip(&tables).zip(entries) {
        let fixed = &f.effect;
        let ok = table_as_fitted(fixed, t, entry);
        if !ok {
            return Err(format!("reliability --from: {fixed} fixed for {t}"));
        }
    }
    let laws = found.vary;
    if laws.len() != effects.len() {
        return Err(format!("{} laws for {} effects", laws.len(), effects.len()));
    }
    for (v, e) in laws.iter().zip(&effects) {
        let Dist::Normal { mean, .. } = v.dist else {
            return Err(format!("{}: not a normal law", v.label()));
        };
        let same = matches!(v.target, Target::Effect(t) if t.with_value(0.0) == e.with_value(0.0));
        if mean != e.value() || !same {
            return Err(format!("reliability --from: {v} for {e}"));
        }
    }
    Ok(())
}

/// Every kind of the vocabulary through the whole chain; every kind that
/// fails is named before the test fails.
#[test]
fn simulate_diagnose_resimulate_every_kind() {
    let root = std::env::temp_dir().join(format!("dw-roundtrip-{}", std::process::id()));
    let mut failed = Vec::new();
    for kind in kinds() {
        let dir: PathBuf = root.join(kind.name());
        std::fs::create_dir_all(&dir).expect("temp dir");
        let t0 = std::time::Instant::now();
        let r = round_trip(kind, &dir);
        eprintln!("{kind}: {:.1} s", t0.elapsed().as_secs_f64());
        if let Err(m) = r {
            failed.push(format!("{kind}: {m}"));
        }
    }
    let _ = std::fs::remove_dir_all(&root);
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}
