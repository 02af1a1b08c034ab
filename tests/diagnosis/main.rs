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
//! 0.01°, below the sensor noise (`physics.md` section 6).//!
//! One module per suite: `hidden` (the generated cases), `bundled` (the
//! example campaigns), `campaign` (a campaign against its runs alone),
//! `one_joint` (two causes at one joint), `coverage` (the reported
//! intervals hold the truth); the generator is here (the kinds
//! and each effect's joint and value from `deploywatch_tests::hidden_effect`).
// Per-joint series are indexed in lockstep with their offsets.
#![allow(clippy::needless_range_loop)]
mod bundled;
mod campaign;
mod coverage;
mod hidden;
mod one_joint;

use deploywatch_sim::campaign::Campaign;
use deploywatch_sim::deployment::{self, SimOptions};
use deploywatch_sim::diagnose::diagnose;
use deploywatch_sim::effect::{self, Effect, EffectKind, Law};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::progress::quiet;
use deploywatch_sim::run::Run;
use deploywatch_sim::sensor::{self, SensorModel};
use deploywatch_tests::data_dir;
use deploywatch_tests::hidden_effect::{draw_effect, kinds};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::BTreeMap;
use std::path::Path;

const PAIRS: [[&str; 2]; 2] = [
    ["seed001_T01", "seed001_T02"],
    ["seed000_case1", "seed000_case3"],
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
        while truth
            .iter()
            .any(|t| t.kind() == e.kind() && t.joint == e.joint)
        {
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
                let e = draw_effect(&mut rng, truth[i].kind(), joints);
                if !truth
                    .iter()
                    .any(|t| t.kind() == e.kind() && t.joint == e.joint)
                {
                    truth[i] = e;
                }
                raises = 0;
                continue;
            }
            truth[i] = truth[i].with_value(truth[i].value() * 1.5);
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
    let kinds = kinds();
    for rep in 0..3 {
        for (k, kind) in kinds.iter().enumerate() {
            seed += 1;
            out.push((seed, vec![*kind], (rep + k) % 2));
        }
    }
    for p in 0..30 {
        seed += 1;
        let a = kinds[rng.gen_range(0..kinds.len())];
        let mut b = kinds[rng.gen_range(0..kinds.len())];
        // A global effect (air drag, rig tilt) exists once: two of them
        // would be one.
        while b == a && !a.per_joint() {
            b = kinds[rng.gen_range(0..kinds.len())];
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
    (e.kind(), e.joint)
}
