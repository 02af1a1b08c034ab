//! Flexible panels (`docs/diagnosis.md`, "Flexible panels"): runs of a
//! wing whose panels bend are answered with the first mode named beside
//! the hidden effect, not with effects bent to absorb the bending; runs of
//! a rigid wing name no mode.
//!
//! The runs are our simulator's: a seed wing built with flexible panels
//! (`physics.md` §12; first mode drawn log-uniform in 4–15 Hz, damping
//! ratio in 1–3 %), and none or one effect of the stroke at one joint,
//! raised until it moves the runs of that flexible wing by ≥ 0.3° RMS; two
//! runs with the reference sensor's noise and rounding. The diagnosis is
//! given the runs and the drawing (rigid panels); it is not told the mode,
//! nor whether there is one.
//!
//! - `a_flexible_wing_is_named_beside_the_effect`: right in 85 % at least
//!   (the CI's 2 cases both): the hidden effect within 20 % alone (none:
//!   nothing claimed), the mode named within 10 % wherever the bending
//!   moves the runs by 0.1° RMS or more. `DEPLOYWATCH_FULL=1` runs 12:
//!   `DEPLOYWATCH_FULL=1 cargo test --release -p deploywatch-tests --test diagnosis_flexible_panels -- --nocapture`.
//! - `a_rigid_wing_names_no_mode`: the same cases on the rigid wing: no
//!   mode named.
//! - `simulate_from_gives_back_the_flexible_fit`: `deploywatch diagnose`
//!   writes the mode under `flexible_panels`, not `effects`, and `simulate
//!   --from d.json --at run.csv` gives back the RMS the diagnosis reported.

use deploywatch_sim::deployment::{self, SimOptions};
use deploywatch_sim::diagnose::{diagnose, Outcome};
use deploywatch_sim::effect::Effect;
use deploywatch_sim::findings::Findings;
use deploywatch_sim::flex::PanelFlex;
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::progress::quiet;
use deploywatch_tests::cli_run::{angles, deploywatch, rms_between};
use deploywatch_tests::data_dir;
use deploywatch_tests::hidden_effect::{moves_runs_deg, two_runs, SEED_WINGS, STROKE_KINDS};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::Path;

/// A case: the drawing, the wing as built (flexible), the hidden effects.
struct Case {
    drawn: Mechanism,
    built: Mechanism,
    truth: Vec<Effect>,
}

/// RMS \[deg\] by which the bending alone moves the runs of `c` (every
/// joint, over the samples both runs have, the runs not stopped when
/// deployed); 0 when either does not simulate.
fn bending_deg(c: &Case) -> f64 {
    let opts = SimOptions {
        stop_when_deployed: false,
        ..SimOptions::default()
    };
    let (Ok(a), Ok(b)) = (
        deployment::simulate(&c.drawn, &c.truth, &opts),
        deployment::simulate(&c.built, &c.truth, &opts),
    ) else {
        return 0.0;
    };
    rms_between(&a.phi_deg, &b.phi_deg)
}

/// Case `i`: a seed wing with flexible panels and none (every third case)
/// or one stroke effect at one joint.
fn case(i: usize) -> Case {
    let mut rng = ChaCha8Rng::seed_from_u64(6100 + i as u64);
    let drawn = Mechanism::load(&data_dir().join(format!("mechanisms/{}.toml", SEED_WINGS[i % 4])))
        .expect("bundled");
    let mut built = drawn.clone();
    built.flexible = Some(PanelFlex {
        first_mode_hz: (rng.gen_range(4f64.ln()..15f64.ln())).exp(),
        damping_ratio: rng.gen_range(0.01..0.03),
    });
    let truth = if i % 3 == 2 {
        Vec::new()
    } else {
        let kind = STROKE_KINDS[i % 3];
        let j = rng.gen_range(1..=drawn.joint_count());
        let mut e = Effect::joint(kind, j, 0.01);
        for _ in 0..40 {
            if moves_runs_deg(&built, &[e]) >= 0.3 {
                break;
            }
            e = e.with_value(e.value() * 1.25);
        }
        vec![e]
    };
    Case {
        drawn,
        built,
        truth,
    }
}

fn names(o: &Outcome) -> String {
    let e: Vec<String> = o.extended.effects().iter().map(|e| e.to_string()).collect();
    let mode = o.panel_mode.as_ref().map_or("no mode".to_string(), |m| {
        format!(
            "mode {:.2} Hz, {:.1} %",
            m.flex.first_mode_hz,
            100.0 * m.flex.damping_ratio
        )
    });
    format!("[{}] {mode}", e.join(" + "))
}

/// The hidden effect within 20 % is the only effect found (none found
/// where none is hidden).
fn effects_right(truth: &[Effect], o: &Outcome) -> bool {
    let e = o.extended.effects();
    e.len() == truth.len()
        && truth.iter().all(|t| {
            e.iter().any(|x| {
                x.kind() == t.kind()
                    && x.joint == t.joint
                    && (x.value() - t.value()).abs() <= 0.2 * t.value().abs()
            })
        })
}

fn cases() -> usize {
    if std::env::var_os("DEPLOYWATCH_FULL").is_some() {
        12
    } else {
        2
    }
}

#[test]
fn a_flexible_wing_is_named_beside_the_effect() {
    let n = cases();
    let opts = deploywatch_tests::diagnose_options();
    let mut failed = Vec::new();
    for i in 0..n {
        let c = case(i);
        let bending = bending_deg(&c);
        let o = diagnose(
            &two_runs(&c.drawn, &c.built, &c.truth, 10 * i as u64),
            &opts,
            &quiet,
        );
        let hz = c.built.flexible.map_or(0.0, |f| f.first_mode_hz);
        let mode_right = match &o.panel_mode {
            Some(m) => (m.flex.first_mode_hz - hz).abs() <= 0.1 * hz,
            None => bending < 0.1,
        };
        let ok = effects_right(&c.truth, &o) && mode_right;
        let hidden: Vec<String> = c.truth.iter().map(|e| e.to_string()).collect();
        println!(
            "case {i} {}: [{}] on panels of {hz:.2} Hz (bending moves the runs {bending:.3} deg) -> {}: {}",
            c.drawn.name,
            hidden.join(" + "),
            names(&o),
            if ok { "right" } else { "WRONG" }
        );
        if !ok {
            failed.push(i);
        }
    }
    println!("right: {} of {n}", n - failed.len());
    assert!(
        100 * failed.len() <= 15 * n,
        "cases {failed:?} (see the lines above)"
    );
}

#[test]
fn a_rigid_wing_names_no_mode() {
    let opts = deploywatch_tests::diagnose_options();
    for i in 0..cases() {
        let c = case(i);
        let o = diagnose(
            &two_runs(&c.drawn, &c.drawn, &c.truth, 10 * i as u64),
            &opts,
            &quiet,
        );
        println!("case {i} {} rigid -> {}", c.drawn.name, names(&o));
        assert!(o.panel_mode.is_none(), "case {i}: {}", names(&o));
    }
}

#[test]
fn simulate_from_gives_back_the_flexible_fit() {
    let c = case(0);
    let campaign = two_runs(&c.drawn, &c.built, &c.truth, 7);
    let dir = std::env::temp_dir().join(format!("dw-flexible-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    let mech = dir.join("wing.toml");
    std::fs::write(&mech, c.drawn.to_toml_string()).expect("writes the mechanism");
    let run = dir.join("run0.csv");
    campaign.runs[0].run.write(&run).expect("writes");
    let (json, model) = (dir.join("d.json"), dir.join("model.csv"));
    let s = |p: &Path| p.to_str().expect("UTF-8").to_string();
    let code = deploywatch(&[
        "diagnose",
        "--quiet",
        "--json",
        &s(&json),
        "--mechanism",
        &s(&mech),
        &s(&run),
    ]);
    assert_eq!(code, 0, "diagnose");
    let body = std::fs::read_to_string(&json).expect("the JSON");
    let Ok(Findings::Diagnosis(d)) = Findings::from_json_str(&body) else {
        panic!("not a diagnosis:\n{body}");
    };
    let flex = d
        .flexible_panels
        .as_ref()
        .unwrap_or_else(|| panic!("no flexible panels named:\n{body}"));
    let hz = c.built.flexible.map_or(0.0, |f| f.first_mode_hz);
    let found = flex.first_mode_hz.expect("a first mode");
    assert!((found - hz).abs() <= 0.1 * hz, "{found} Hz, built {hz} Hz");
    let code = deploywatch(&[
        "simulate",
        &s(&mech),
        "--from",
        &s(&json),
        "--at",
        &s(&run),
        "--out",
        &s(&model),
        "--quiet",
    ]);
    assert_eq!(code, 0, "simulate --from --at");
    let n = c.drawn.joint_count();
    let (a, r) = (angles(&model, n), angles(&run, n));
    let again = rms_between(&a, &r);
    let said = d.extended.rms_deg.expect("an extended RMS");
    // The model CSV's angles have 6 decimals: within their rounding.
    assert!(
        (again - said).abs() <= 1e-5,
        "re-simulated {again} deg, the diagnosis said {said}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
