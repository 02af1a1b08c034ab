//! Hidden-effect tests of `diagnose`.
//!
//! A seeded generator draws each case: a mechanism pair (seed001 T01+T02 or
//! seed000 case1+case3), zero, one or two effects of the vocabulary (joint and
//! value drawn too, the value raised until the effect moves the runs by at
//! least 0.3° RMS), and simulates both runs with the reference sensor noise.
//! The diagnosis receives only the two runs and the nominal mechanisms: the
//! runs carry no metadata but the mechanism name, and the truth stays in
//! this file until the diagnosis has been made.
//!
//! `latch_detent` is not drawn: it does no net work and moves a run by under
//! 0.01°, below the sensor noise (`physics.md` section 6).
// Per-joint series are indexed in lockstep with their offsets.
#![allow(clippy::needless_range_loop)]

use deploywatch_sim::campaign::Campaign;
use deploywatch_sim::deployment::{self, SimOptions};
use deploywatch_sim::diagnose::{diagnose, DiagnoseOptions};
use deploywatch_sim::effect::{self, Effect, EffectKind};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::progress::quiet;
use deploywatch_sim::run::Run;
use deploywatch_sim::sensor::{self, SensorModel};
use deploywatch_tests::data_dir;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::BTreeMap;
use std::path::Path;

const PAIRS: [[&str; 2]; 2] = [
    ["seed001_T01", "seed001_T02"],
    ["seed000_case1", "seed000_case3"],
];

/// The kinds drawn (all but latch_detent).
const KINDS: [EffectKind; 7] = [
    EffectKind::CoulombFriction,
    EffectKind::ViscousDamping,
    EffectKind::SpringSoftening,
    EffectKind::HarnessStiffness,
    EffectKind::AirDrag,
    EffectKind::RigTilt,
    EffectKind::EncoderOffset,
];

struct Case {
    pair: usize,
    truth: Vec<Effect>,
    runs: Vec<Run>,
}

fn mechanisms(pair: usize) -> Vec<Mechanism> {
    PAIRS[pair]
        .iter()
        .map(|m| Mechanism::load(&data_dir().join(format!("mechanisms/{m}.toml"))).unwrap())
        .collect()
}

fn draw_effect(rng: &mut ChaCha8Rng, kind: EffectKind, joints: usize) -> Effect {
    let u = |rng: &mut ChaCha8Rng, lo: f64, hi: f64| lo * (hi / lo).powf(rng.gen::<f64>());
    let j = rng.gen_range(1..=joints);
    match kind {
        EffectKind::CoulombFriction => Effect::joint(kind, j, u(rng, 0.05, 1.0)),
        EffectKind::ViscousDamping => Effect::joint(kind, j, u(rng, 0.05, 1.5)),
        // Not candidates (not in `EffectKind::ALL`).
        EffectKind::QuadraticDamping | EffectKind::StribeckFriction => Effect::joint(kind, j, 0.0),
        EffectKind::SpringSoftening => Effect::joint(kind, j, u(rng, 0.05, 0.35)),
        EffectKind::HarnessStiffness => Effect::joint(kind, j, u(rng, 0.03, 0.5)),
        EffectKind::AirDrag => Effect::global(kind, u(rng, 0.05, 1.0)),
        EffectKind::RigTilt => Effect {
            alpha_deg: rng.gen_range(0.0..360.0),
            ..Effect::global(kind, u(rng, 0.01, 0.2))
        },
        EffectKind::EncoderOffset => {
            let s = if rng.gen::<bool>() { 1.0 } else { -1.0 };
            Effect::joint(kind, j, s * u(rng, 0.3, 2.0))
        }
        EffectKind::LatchDetent => Effect::joint(kind, j, u(rng, 0.5, 2.0)),
        // Not drawn here: tests/unnamed_torque.rs draws its own tables.
        EffectKind::TorqueTable => Effect::joint(kind, j, 0.0),
        // Never drawn: they act only on a physical latch (`EffectKind::LATCH`).
        EffectKind::PlungerWeakening | EffectKind::MagnetWeakening => Effect::joint(kind, j, 0.0),
        // Never drawn here: they act only on a rig (tests/diagnosis_rig.rs).
        EffectKind::RigFriction | EffectKind::WireLength | EffectKind::FrameOffset => {
            Effect::global(kind, 0.0)
        }
    }
}

/// How far an effect moves the pair of runs [deg RMS], noise-free.
fn effect_size(mechs: &[Mechanism], effects: &[Effect]) -> f64 {
    let (mut sse, mut n) = (0.0, 0usize);
    for m in mechs {
        let opts = SimOptions {
            stop_when_deployed: false,
            ..SimOptions::default()
        };
        let a = deployment::simulate(m, &[], &opts).unwrap();
        let b = deployment::simulate(m, effects, &opts).unwrap();
        let off = effect::encoder_offsets_deg(effects, m.joint_count());
        for j in 0..m.joint_count() {
            for i in 0..a.t_s.len() {
                let d = b.phi_deg[j][i] + off[j] - a.phi_deg[j][i];
                sse += d * d;
                n += 1;
            }
        }
    }
    (sse / n as f64).sqrt()
}

fn generate(seed: u64, kinds: &[EffectKind], pair: usize) -> Case {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mechs = mechanisms(pair);
    let joints = mechs[0].joint_count();
    let mut truth: Vec<Effect> = Vec::new();
    for &k in kinds {
        let mut e = draw_effect(&mut rng, k, joints);
        // Two effects of one kind go to different joints.
        while truth.iter().any(|t| t.kind == e.kind && t.joint == e.joint) {
            e = draw_effect(&mut rng, k, joints);
        }
        truth.push(e);
    }
    // Each effect on its own must move the runs by ≥ 0.3° RMS: its value is
    // raised up to six times by 1.5; an effect still below that (one that
    // barely acts where it was drawn) is drawn again.
    for i in 0..truth.len() {
        let mut raises = 0;
        for _ in 0..40 {
            if effect_size(&mechs, &truth[i..=i]) >= 0.3 {
                break;
            }
            if raises == 6 {
                let e = draw_effect(&mut rng, truth[i].kind, joints);
                if !truth.iter().any(|t| t.kind == e.kind && t.joint == e.joint) {
                    truth[i] = e;
                }
                raises = 0;
                continue;
            }
            truth[i].value *= 1.5;
            raises += 1;
        }
    }
    let runs = simulate_runs(&mechs, &truth, seed);
    Case { pair, truth, runs }
}

/// The measured runs of `truth` on each mechanism, with the reference
/// sensor noise drawn from `seed`.
fn simulate_runs(mechs: &[Mechanism], truth: &[Effect], seed: u64) -> Vec<Run> {
    mechs
        .iter()
        .enumerate()
        .map(|(r, m)| {
            let traj = deployment::simulate(m, truth, &SimOptions::default()).unwrap();
            let offsets = effect::encoder_offsets_deg(truth, m.joint_count());
            let mut run = sensor::measure(
                &traj,
                &offsets,
                &SensorModel::REFERENCE,
                seed * 10 + r as u64,
            );
            run.set_meta("mechanism", &m.name);
            run
        })
        .collect()
}

/// The cases: every kind alone three times, then 30 two-cause campaigns,
/// then 10 null campaigns (61 in all, half with two causes).
fn cases() -> Vec<(u64, Vec<EffectKind>, usize)> {
    let mut out = Vec::new();
    let mut rng = ChaCha8Rng::seed_from_u64(2026);
    let mut seed = 1000;
    for rep in 0..3 {
        for (k, kind) in KINDS.iter().enumerate() {
            seed += 1;
            out.push((seed, vec![*kind], (rep + k) % 2));
        }
    }
    for p in 0..30 {
        seed += 1;
        let a = KINDS[rng.gen_range(0..KINDS.len())];
        let mut b = KINDS[rng.gen_range(0..KINDS.len())];
        // A global effect (air drag, rig tilt) exists once: two of them
        // would be one.
        while b == a && !a.per_joint() {
            b = KINDS[rng.gen_range(0..KINDS.len())];
        }
        out.push((seed, vec![a, b], p % 2));
    }
    for p in 0..10 {
        seed += 1;
        out.push((seed, vec![], p % 2));
    }
    out
}

/// What the diagnosis sees of a case: the nominal mechanisms and the runs
/// (`keep` selects which runs).
fn campaign_of(case: &Case, keep: impl Fn(usize) -> bool) -> Campaign {
    let mut campaign = Campaign::default();
    let mechs = mechanisms(case.pair);
    for (r, run) in case.runs.iter().enumerate().filter(|(r, _)| keep(*r)) {
        campaign
            .push(&mechs, run.clone(), Path::new(&format!("run{r}.csv")))
            .unwrap();
    }
    campaign
}

/// The progress sink of a test's diagnoses: every round on standard error
/// with `DEPLOYWATCH_TRACE`, nothing otherwise.
fn trace_sink() -> deploywatch_sim::progress::Progress<'static> {
    if std::env::var_os("DEPLOYWATCH_TRACE").is_some() {
        &deploywatch_sim::progress::stderr
    } else {
        &quiet
    }
}

fn key(e: &Effect) -> (EffectKind, Option<usize>) {
    (e.kind, e.joint)
}

#[test]
fn hidden_effects_are_named_and_measured() {
    let specs = cases();
    assert!(specs.len() >= 60);
    assert!(specs.iter().filter(|s| s.1.len() == 2).count() * 2 >= specs.len() - 1);
    assert!(specs.iter().filter(|s| s.1.is_empty()).count() >= 10);
    let (mut correct, mut total) = (0usize, 0usize);
    let (mut correct2, mut total2) = (0usize, 0usize);
    let mut failures = Vec::new();
    let mut confusion: BTreeMap<(String, String), usize> = BTreeMap::new();
    let mut value_errors = Vec::new();
    let mut gains = Vec::new();
    let mut false_claims_in_null = 0;
    for (seed, kinds, pair) in specs {
        let case = generate(seed, &kinds, pair);
        eprintln!("seed {seed}: diagnosing ({} hidden)", case.truth.len());
        let campaign = campaign_of(&case, |_| true);
        let outcome = diagnose(&campaign, &DiagnoseOptions::default(), trace_sink());
        let found = outcome.extended.effects();

        // Only now compare with the truth.
        total += 1;
        let mut want: Vec<_> = case.truth.iter().map(key).collect();
        let mut got: Vec<_> = found.iter().map(key).collect();
        want.sort();
        got.sort();
        let ok = want == got && outcome.unexplained.is_none();
        eprintln!(
            "case {total:>2} seed {seed}: {} truth [{}] found [{}] RMS {:.3} -> {:.4} ({} sims, {:.1} s)",
            if ok { "ok  " } else { "MISS" },
            case.truth.iter().map(|e| e.to_string()).collect::<Vec<_>>().join("; "),
            found.iter().map(|e| e.to_string()).collect::<Vec<_>>().join("; "),
            outcome.baseline.rms(),
            outcome.extended.rms(),
            outcome.simulations,
            outcome.wall_s
        );
        if case.truth.len() == 2 {
            total2 += 1;
            correct2 += usize::from(ok);
        }
        if ok {
            correct += 1;
        } else {
            failures.push(format!(
                "seed {seed}: truth {:?} found {:?} (RMS {:.4} -> {:.4}){}",
                case.truth.iter().map(|e| e.to_string()).collect::<Vec<_>>(),
                found.iter().map(|e| e.to_string()).collect::<Vec<_>>(),
                outcome.baseline.rms(),
                outcome.extended.rms(),
                outcome
                    .unexplained
                    .as_deref()
                    .map(|u| format!(", unexplained: {u}"))
                    .unwrap_or_default()
            ));
        }
        let truth_name = if case.truth.is_empty() {
            "(none)".to_string()
        } else {
            case.truth
                .iter()
                .map(|e| e.kind.name())
                .collect::<Vec<_>>()
                .join("+")
        };
        let found_name = if found.is_empty() {
            "(none)".to_string()
        } else {
            let mut f: Vec<_> = found.iter().map(|e| e.kind.name()).collect();
            f.sort();
            f.join("+")
        };
        *confusion.entry((truth_name, found_name)).or_default() += 1;
        if case.truth.is_empty() {
            if !found.is_empty() || outcome.unexplained.is_some() {
                false_claims_in_null += 1;
            }
            continue;
        }
        let gain = outcome.baseline.rms() / outcome.extended.rms().max(1e-12);
        gains.push((seed, gain));
        if ok {
            for t in &case.truth {
                let f = found.iter().find(|f| key(f) == key(t)).unwrap();
                let err = (f.value - t.value).abs() / t.value.abs();
                value_errors.push((seed, t.to_string(), f.value, err));
            }
        }
    }

    println!("\nconfusion (truth -> found):");
    for ((t, f), n) in &confusion {
        println!("  {t:<40} -> {f:<40} {n}");
    }
    println!("\ncorrect set of names and joints: {correct}/{total}");
    println!("  of which two-cause campaigns: {correct2}/{total2}");
    for f in &failures {
        println!("  MISS {f}");
    }
    let worst_value = value_errors.iter().map(|v| v.3).fold(0.0, f64::max);
    println!(
        "value error of the effects named right: worst {:.2} %",
        100.0 * worst_value
    );
    let min_gain = gains.iter().map(|g| g.1).fold(f64::INFINITY, f64::min);
    println!("RMS gain: smallest x{min_gain:.1}");
    let body = format!(
        "## Diagnosis: the hidden-set suite\n\n\
         {total} seeded campaigns of `tests/diagnosis.rs` (`docs/diagnosis.md`, \
         \"How well it works\"): every effect alone, two causes, null campaigns; \
         reference sensor noise.\n\n\
         | criterion | required | measured |\n|---|---|---|\n\
         | exact set of names and joints | ≥ 95 % | {correct}/{total} ({:.1} %) |\n\
         | of which two-cause campaigns | (reported) | {correct2}/{total2} |\n\
         | value error of every effect named right | ≤ 5 % | worst {:.2} % |\n\
         | RMS gain whenever an effect was hidden | ≥ 5× | smallest {min_gain:.1}× |\n\
         | effects claimed in null campaigns | 0 | {false_claims_in_null} |\n",
        100.0 * correct as f64 / total.max(1) as f64,
        100.0 * worst_value,
    );
    deploywatch_tests::record::record(
        "diagnosis-hidden-set",
        "DEPLOYWATCH_FULL=1 cargo test -p deploywatch-tests --test diagnosis hidden_effects -- --nocapture",
        &body,
    )
    .expect("docs/measured.md written");

    assert!(
        correct * 100 >= total * 95,
        "only {correct}/{total} correct"
    );
    for (seed, t, v, err) in &value_errors {
        assert!(
            *err <= 0.05,
            "seed {seed}: {t} estimated {v} ({:.1} % off)",
            100.0 * err
        );
    }
    for (seed, g) in &gains {
        assert!(*g >= 5.0, "seed {seed}: RMS gain only x{g:.2}");
    }
    assert_eq!(false_claims_in_null, 0, "effects claimed in null cases");
}

/// The three example campaigns of `data/examples/` (copied from
/// `shared/reference/examples/`), diagnosed from the runs and the nominal
/// mechanisms; `truth.json` is read only afterwards.
///
/// "Correct" means: every disclosed effect that on its own moves the runs by
/// at least 0.3° RMS (the detectability bar of the hidden-effect suite) is
/// named with its joint and its value within 10 %; an effect below that bar
/// (example (a)'s 0.001 N·m at joint 3, which moves the runs by about the
/// sensor noise) need not be; anything else reported is below that
/// detectability bar by a factor of three (without it the extended model's
/// RMS stays under 0.1°: it stands in for an effect the data cannot name);
/// and the extended model reaches the disclosed noise floor
/// (`truth_rms_deg`) within 20 %.
#[test]
fn bundled_examples_are_diagnosed_correctly() {
    let examples = [
        ("a_seed001_eft", ["seed001_T01", "seed001_T02"]),
        ("b_seed000_eft_air_drag", ["seed000_case1", "seed000_case3"]),
        ("c_seed001_friction_harness", ["seed001_T01", "seed001_T02"]),
    ];
    let mut rows = Vec::new();
    for (dir, mechs) in examples {
        let mech_paths: Vec<_> = mechs
            .iter()
            .map(|m| data_dir().join(format!("mechanisms/{m}.toml")))
            .collect();
        let run_paths: Vec<_> = mechs
            .iter()
            .map(|m| data_dir().join(format!("examples/{dir}/{m}.csv")))
            .collect();
        let campaign = Campaign::load(&mech_paths, &run_paths).unwrap();
        let outcome = diagnose(&campaign, &DiagnoseOptions::default(), trace_sink());
        let found = outcome.extended.effects();

        // Now the truth.
        let truth_json: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(data_dir().join(format!("examples/{dir}/truth.json")))
                .unwrap(),
        )
        .unwrap();
        let truth: Vec<Effect> = truth_json["effects"]
            .as_array()
            .unwrap()
            .iter()
            .map(|e| {
                let joint = e["joint"]
                    .as_u64()
                    .map(|j| format!(":joint={j}"))
                    .unwrap_or_default();
                format!(
                    "{}{joint}:value={}",
                    e["name"].as_str().unwrap(),
                    e["value"]
                )
                .parse()
                .unwrap()
            })
            .collect();
        let floor = truth_json["runs"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| r["truth_rms_deg"].as_f64().unwrap())
            .fold(0.0, f64::max);
        let mechanisms: Vec<Mechanism> = mech_paths
            .iter()
            .map(|p| Mechanism::load(p).unwrap())
            .collect();
        println!(
            "{dir}: found {:?}, RMS {:.4} -> {:.4} (floor {floor})",
            found.iter().map(|e| e.to_string()).collect::<Vec<_>>(),
            outcome.baseline.rms(),
            outcome.extended.rms()
        );
        let list = |v: &[Effect]| {
            v.iter()
                .map(|e| match e.joint {
                    Some(j) => format!("{} j{j} {:.5}", e.kind.name(), e.value),
                    None => format!("{} {:.5}", e.kind.name(), e.value),
                })
                .collect::<Vec<_>>()
                .join(", ")
        };
        rows.push(format!(
            "| {dir} | {} | {} | {:.2}° → {:.4}° ({floor:.4}°) |",
            list(&truth),
            list(&found),
            outcome.baseline.rms(),
            outcome.extended.rms()
        ));
        for t in &truth {
            let others: Vec<Effect> = truth.iter().filter(|o| *o != t).copied().collect();
            let full = effect_size_between(&mechanisms, &others, &truth);
            let hit = found.iter().find(|f| key(f) == key(t));
            println!(
                "  truth {t}: moves the runs by {full:.3} deg; found {:?}",
                hit.map(|h| h.value)
            );
            if full >= 0.3 {
                let h = hit.unwrap_or_else(|| panic!("{dir}: {t} not found"));
                assert!(
                    (h.value - t.value).abs() <= 0.1 * t.value.abs(),
                    "{dir}: {t} estimated {}",
                    h.value
                );
            }
        }
        for (k, f) in found.iter().enumerate() {
            if !truth.iter().any(|t| key(t) == key(f)) {
                let without = outcome.strength_rms_deg[k];
                println!("  extra {f}: RMS without it {without:.4} deg");
                assert!(
                    without < 0.1,
                    "{dir}: {f} is not in the truth and not below the bar"
                );
            }
        }
        assert!(
            outcome.unexplained.is_none(),
            "{dir}: {:?}",
            outcome.unexplained
        );
        assert!(
            outcome.extended.rms() <= 1.2 * floor,
            "{dir}: extended RMS {} above the noise floor {floor}",
            outcome.extended.rms()
        );
    }
    let body = format!(
        "## Diagnosis: the bundled examples\n\n\
         `data/examples/` diagnosed from the runs and the nominal mechanisms \
         (`bundled_examples_are_diagnosed_correctly`; `truth.json` read after the \
         diagnosis; the floor is its noise RMS).\n\n\
         | example | truth | found | RMS before → after (floor) |\n|---|---|---|---|\n{}\n",
        rows.join("\n")
    );
    deploywatch_tests::record::record(
        "diagnosis-bundled-examples",
        "DEPLOYWATCH_FULL=1 cargo test -p deploywatch-tests --test diagnosis bundled_examples -- --nocapture",
        &body,
    )
    .expect("docs/measured.md written");
}

/// RMS difference \[deg\] between two effect sets on the mechanisms, noise-free.
fn effect_size_between(mechs: &[Mechanism], a: &[Effect], b: &[Effect]) -> f64 {
    let (mut sse, mut n) = (0.0, 0usize);
    for m in mechs {
        let opts = SimOptions {
            stop_when_deployed: false,
            ..SimOptions::default()
        };
        let x = deployment::simulate(m, a, &opts).unwrap();
        let y = deployment::simulate(m, b, &opts).unwrap();
        let (oa, ob) = (
            effect::encoder_offsets_deg(a, m.joint_count()),
            effect::encoder_offsets_deg(b, m.joint_count()),
        );
        for j in 0..m.joint_count() {
            for i in 0..x.t_s.len() {
                let d = (x.phi_deg[j][i] + oa[j]) - (y.phi_deg[j][i] + ob[j]);
                sse += d * d;
                n += 1;
            }
        }
    }
    (sse / n as f64).sqrt()
}

/// A campaign answer is never worse than the answers of its runs
/// taken alone. Two causes (rig tilt and Coulomb friction at joint 1) on
/// seed 001 T01 + T02: when each run alone is explained to the noise, the
/// two runs together must be too, with the same causes.
#[test]
fn a_campaign_is_never_worse_than_its_runs_alone() {
    for seed in [7u64, 8, 9] {
        let truth = vec![
            Effect {
                alpha_deg: 30.0,
                ..Effect::global(EffectKind::RigTilt, 0.05)
            },
            Effect::joint(EffectKind::CoulombFriction, 1, 0.8),
        ];
        let case = Case {
            pair: 0,
            runs: simulate_runs(&mechanisms(0), &truth, seed),
            truth,
        };
        let alone: Vec<_> = (0..2)
            .map(|r| {
                diagnose(
                    &campaign_of(&case, |i| i == r),
                    &DiagnoseOptions::default(),
                    &quiet,
                )
            })
            .collect();
        let both = diagnose(
            &campaign_of(&case, |_| true),
            &DiagnoseOptions::default(),
            &quiet,
        );
        let names = |o: &deploywatch_sim::diagnose::Outcome| {
            let mut k: Vec<_> = o.extended.effects().iter().map(key).collect();
            k.sort();
            k
        };
        println!(
            "seed {seed}: alone {:?} / {:?}, together {:?} (RMS {:.4})",
            names(&alone[0]),
            names(&alone[1]),
            names(&both),
            both.extended.rms()
        );
        let worst_alone = alone.iter().map(|o| o.extended.rms()).fold(0.0, f64::max);
        if alone.iter().all(|o| o.unexplained.is_none()) {
            assert!(
                both.unexplained.is_none(),
                "seed {seed}: {:?}",
                both.unexplained
            );
            assert!(both.extended.rms() <= 1.2 * worst_alone);
        }
        let mut want: Vec<_> = case.truth.iter().map(key).collect();
        want.sort();
        assert_eq!(names(&both), want, "seed {seed}");
    }
}

/// The pairs of causes at one joint drawn by
/// [`two_causes_at_one_joint_are_named_and_measured`]: the second is at the
/// first's joint (rig tilt has none; its partner takes a drawn joint).
const ONE_JOINT_PAIRS: [[EffectKind; 2]; 4] = [
    [EffectKind::SpringSoftening, EffectKind::CoulombFriction],
    [EffectKind::SpringSoftening, EffectKind::HarnessStiffness],
    [EffectKind::ViscousDamping, EffectKind::CoulombFriction],
    [EffectKind::RigTilt, EffectKind::CoulombFriction],
];

/// Two causes at one joint, each moving the runs by 0.3° to 0.6° RMS on its
/// own (near the detectability bar): drawn like [`generate`]'s, then moved
/// to one joint. Noise seeds differ from the main suite's.
fn generate_one_joint(seed: u64, kinds: [EffectKind; 2], pair: usize) -> Case {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mechs = mechanisms(pair);
    let joints = mechs[0].joint_count();
    let mut truth: Vec<Effect> = kinds
        .iter()
        .map(|&k| draw_effect(&mut rng, k, joints))
        .collect();
    let joint = truth.iter().find_map(|e| e.joint);
    for e in truth.iter_mut().filter(|e| e.kind.per_joint()) {
        e.joint = joint;
    }
    // Near the detectability bar: each effect brought to 0.3–0.6° RMS.
    for i in 0..truth.len() {
        for _ in 0..20 {
            let size = effect_size(&mechs, &truth[i..=i]);
            if size < 0.3 {
                truth[i].value *= 1.5;
            } else if size > 0.6 {
                truth[i].value /= 1.5;
            } else {
                break;
            }
        }
    }
    let runs = simulate_runs(&mechs, &truth, seed);
    Case { pair, truth, runs }
}

/// Two causes at ONE joint (spring softening with Coulomb friction or with
/// a harness, viscous damping with Coulomb friction, rig tilt with Coulomb
/// friction): each pair twice, on both mechanism pairs, with the joint and
/// the values drawn by a seeded generator; the diagnosis sees only the runs
/// and the nominal mechanisms. A case is right when named exactly (names
/// and joints, nothing unexplained) with every value within 5 %. The
/// target (95 % named) is for the hidden sets together: with
/// [`hidden_effects_are_named_and_measured`]'s 61 it needs at least 5 of
/// these 8; the test asks for the 7 measured (`docs/diagnosis.md`, "Two
/// causes at one joint").
#[test]
fn two_causes_at_one_joint_are_named_and_measured() {
    let mut rng = ChaCha8Rng::seed_from_u64(4242);
    let (mut ok, mut total, mut worst) = (0usize, 0usize, 0.0f64);
    let mut misses = Vec::new();
    for rep in 0..2u64 {
        for (p, kinds) in ONE_JOINT_PAIRS.iter().enumerate() {
            let seed = 5200 + rng.gen_range(0..1000) + 1000 * rep;
            let case = generate_one_joint(seed, *kinds, (p + rep as usize) % 2);
            let outcome = diagnose(
                &campaign_of(&case, |_| true),
                &DiagnoseOptions::default(),
                trace_sink(),
            );
            // Only now the truth.
            let found = outcome.extended.effects();
            let mut want: Vec<_> = case.truth.iter().map(key).collect();
            let mut got: Vec<_> = found.iter().map(key).collect();
            want.sort();
            got.sort();
            let named = want == got && outcome.unexplained.is_none();
            let err = case
                .truth
                .iter()
                .filter_map(|t| {
                    let f = found.iter().find(|f| key(f) == key(t))?;
                    Some((f.value - t.value).abs() / t.value.abs())
                })
                .fold(0.0, f64::max);
            let right = named && err <= 0.05;
            println!(
                "seed {seed}: {} truth [{}] found [{}] RMS {:.3} -> {:.4}, worst value error {:.2} % ({:.1} s)",
                if right { "ok  " } else { "MISS" },
                case.truth.iter().map(|e| e.to_string()).collect::<Vec<_>>().join("; "),
                found.iter().map(|e| e.to_string()).collect::<Vec<_>>().join("; "),
                outcome.baseline.rms(),
                outcome.extended.rms(),
                100.0 * err,
                outcome.wall_s
            );
            total += 1;
            if right {
                ok += 1;
                worst = worst.max(err);
            } else {
                misses.push(seed);
            }
        }
    }
    println!(
        "two causes at one joint: {ok}/{total} named with values within 5 % (worst {:.2} %)",
        100.0 * worst
    );
    let body = format!(
        "## Diagnosis: two causes at one joint\n\n\
         {total} seeded campaigns of `two_causes_at_one_joint_are_named_and_measured` \
         (`docs/diagnosis.md`, \"How well it works\"): two causes at one drawn joint, \
         each near the detectability bar.\n\n\
         | criterion | required | measured |\n|---|---|---|\n\
         | exact names and joints, values within 5 % | ≥ 7/8 (test) | {ok}/{total} (worst value error {:.2} %) |\n\
         | misses (seeds) | (reported) | {} |\n",
        100.0 * worst,
        if misses.is_empty() {
            "none".to_string()
        } else {
            format!("{misses:?}")
        },
    );
    deploywatch_tests::record::record(
        "diagnosis-two-causes",
        "DEPLOYWATCH_FULL=1 cargo test -p deploywatch-tests --test diagnosis two_causes -- --nocapture",
        &body,
    )
    .expect("docs/measured.md written");
    assert!(ok * 8 >= total * 7, "{ok}/{total}; misses: {misses:?}");
}
