//! Runs of one configuration that cannot tell friction from a softened
//! spring or a harness (`docs/diagnosis.md`, "Ambiguity").
//!
//! A seeded generator draws each campaign: one ideal-latch mechanism (seed
//! 001 T01 or T02, seed 000 case 1 or 3), two runs of it (noise seeds
//! differ), Coulomb friction, spring softening or a harness hidden at a
//! drawn joint near the detectability bar (raised from a small value until
//! it moves the runs by ≥ 0.3° RMS), in half of them beside a harness at
//! another joint (the Coulomb at joint 2 with a harness at joint 1).
//! A campaign passes when the truth lies within what the report gives:
//! the set found, or a set of an ambiguity group (kinds and joints exact,
//! values within 20 %). The test prints how many reported an ambiguity.
//!
//! `DEPLOYWATCH_FULL=1` runs the 40 campaigns of the measured result; the
//! CI runs 3.
//!
//! The best set seen is the answer: a campaign whose
//! search ends on a worse set than one its ambiguity stage fits is answered
//! with the better one, and no set the report lists beats the answer by the
//! acceptance rule's BIC margin.

use deploywatch_sim::campaign::Campaign;
use deploywatch_sim::deployment::{self, SimOptions};
use deploywatch_sim::diagnose::{diagnose, FittedSet, Outcome, MIN_DELTA_BIC};
use deploywatch_sim::effect::{self, Effect, EffectKind};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::progress::{quiet, stderr, Progress};
use deploywatch_sim::sensor::{self, SensorModel};
use deploywatch_tests::data_dir;
use deploywatch_tests::hidden_effect::moves_runs_deg;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::Path;

const MECHS: [&str; 4] = [
    "seed001_T01",
    "seed001_T02",
    "seed000_case1",
    "seed000_case3",
];

const KINDS: [EffectKind; 3] = [
    EffectKind::CoulombFriction,
    EffectKind::SpringSoftening,
    EffectKind::HarnessStiffness,
];

fn sink() -> Progress<'static> {
    if std::env::var_os("DEPLOYWATCH_TRACE").is_some() {
        &stderr
    } else {
        &quiet
    }
}

/// Raises `e` from its small start until it moves the runs by ≥ 0.3°.
fn to_the_bar(m: &Mechanism, mut e: Effect) -> Effect {
    for _ in 0..40 {
        if moves_runs_deg(m, &[e]) >= 0.3 {
            break;
        }
        e = e.with_value(e.value() * 1.25);
    }
    e
}

fn generate(i: usize) -> (Mechanism, Vec<Effect>, Campaign) {
    let mut rng = ChaCha8Rng::seed_from_u64(9000 + i as u64);
    let m = Mechanism::load(&data_dir().join(format!("mechanisms/{}.toml", MECHS[i % 4])))
        .expect("bundled");
    let joints = m.joint_count();
    let kind = KINDS[(i / 4) % 3];
    let j = rng.gen_range(1..=joints);
    let start = match kind {
        EffectKind::CoulombFriction => 0.02,
        EffectKind::SpringSoftening => 0.01,
        _ => 0.01,
    };
    let mut truth = vec![to_the_bar(&m, Effect::joint(kind, j, start))];
    if i % 2 == 1 {
        let k = (j % joints) + 1;
        truth.push(to_the_bar(
            &m,
            Effect::joint(EffectKind::HarnessStiffness, k, 0.01),
        ));
    }
    let mut c = Campaign::default();
    for r in 0..2u64 {
        let traj = deployment::simulate(&m, &truth, &SimOptions::default()).expect("ideal latch");
        let off = effect::encoder_offsets_deg(&truth, joints);
        let mut run = sensor::measure(&traj, &off, &SensorModel::REFERENCE, 100 * i as u64 + r);
        run.set_meta("mechanism", &m.name);
        c.push(
            std::slice::from_ref(&m),
            run,
            Path::new(&format!("run{r}.csv")),
        )
        .expect("pairs");
    }
    (m, truth, c)
}

/// The set `f` names exactly the truth, values within 20 %.
fn is_truth(truth: &[Effect], f: &FittedSet) -> bool {
    let e = f.effects();
    e.len() == truth.len()
        && truth.iter().all(|t| {
            e.iter().any(|x| {
                x.kind() == t.kind()
                    && x.joint == t.joint
                    && (x.value() - t.value()).abs() <= 0.2 * t.value().abs()
            })
        })
}

fn within(truth: &[Effect], o: &Outcome) -> bool {
    is_truth(truth, &o.extended)
        || o.ambiguities
            .iter()
            .any(|g| g.sets.iter().any(|s| is_truth(truth, s)))
}

#[test]
fn the_truth_lies_within_what_one_configuration_reports() {
    let n = if std::env::var_os("DEPLOYWATCH_FULL").is_some() {
        40
    } else {
        3
    };
    let (mut inside, mut reported, mut reported_inside, mut ran) = (0, 0, 0, 0);
    // `DEPLOYWATCH_CASE=k` runs only the k-th case.
    let one: Option<usize> = std::env::var("DEPLOYWATCH_CASE")
        .ok()
        .and_then(|v| v.parse().ok());
    for i in (0..n).filter(|i| one.is_none_or(|o| o == *i)) {
        let (m, truth, c) = generate(i);
        let o = diagnose(&c, &deploywatch_tests::diagnose_options(), sink());
        let ok = within(&truth, &o);
        ran += 1;
        inside += usize::from(ok);
        reported += usize::from(!o.ambiguities.is_empty());
        reported_inside += usize::from(ok && !o.ambiguities.is_empty());
        let groups: Vec<String> = o
            .ambiguities
            .iter()
            .map(|g| {
                let sets: Vec<String> = g
                    .sets
                    .iter()
                    .map(|s| {
                        s.effects()
                            .iter()
                            .map(|e| e.to_string())
                            .collect::<Vec<_>>()
                            .join(" + ")
                    })
                    .collect();
                format!("joint {}: {{{}}}", g.joint, sets.join("} | {"))
            })
            .collect();
        eprintln!(
            "case {i} {}: {} truth [{}] found [{}] RMS {:.4}; ambiguity [{}] ({:.1} s)",
            m.name,
            if ok { "ok  " } else { "MISS" },
            truth
                .iter()
                .map(|e| e.to_string())
                .collect::<Vec<_>>()
                .join("; "),
            o.extended
                .effects()
                .iter()
                .map(|e| e.to_string())
                .collect::<Vec<_>>()
                .join("; "),
            o.extended.rms(),
            groups.join(" ; "),
            o.wall_s
        );
    }
    println!(
        "truth within the reported set: {inside}/{ran}; ambiguity reported: {reported}/{ran}, with the truth inside: {reported_inside}"
    );
    let body = format!(
        "## Diagnosis: the truth within the reported ambiguity\n\n\
         {ran} campaigns of `tests/diagnosis_ambiguity.rs` (`docs/diagnosis.md`, \
         \"Ambiguity\"): two runs of one ideal-latch configuration, a cause at the \
         detectability bar, half of them beside a harness at another joint.\n\n\
         | criterion | required | measured |\n|---|---|---|\n\
         | the truth is the set found or a set of an ambiguity group | all | {inside}/{ran} |\n\
         | an ambiguity reported | (reported) | {reported}/{ran}, the truth inside in {reported_inside} |\n"
    );
    deploywatch_tests::record::record(
        "diagnosis-ambiguity",
        "DEPLOYWATCH_FULL=1 cargo test -p deploywatch-tests --test diagnosis_ambiguity -- --nocapture",
        &body,
    )
    .expect("docs/measured.md written");
    assert!(ran > 0, "DEPLOYWATCH_CASE matches no case: zero cases ran");
    assert_eq!(inside, ran, "the truth outside what the report gives");
}

/// Issue 40, item 5: seed 000 case 1 + case 3 with Coulomb 0.06 N·m at
/// joint 2 and a rig tilt of 0.1 m/s² (noise seed 3, as `deploywatch
/// simulate --seed 3` draws it). The stepwise search ends on rig tilt,
/// Coulomb friction and a softened spring at joint 1 (RMS 0.0239°), while
/// the ambiguity stage fits rig tilt + Coulomb at joint 2 at 0.0209° with a
/// BIC better by about 270: that set is the answer, and no set the report
/// lists beats the answer by more than the acceptance rule's BIC margin.
#[test]
fn the_best_set_seen_is_the_answer() {
    let truth: Vec<Effect> = [
        "coulomb_friction:joint=2:value=0.06",
        "rig_tilt:value=0.1:alpha_deg=0",
    ]
    .iter()
    .map(|e| e.parse().expect("effect syntax"))
    .collect();
    let mut c = Campaign::default();
    let mechs: Vec<Mechanism> = ["seed000_case1", "seed000_case3"]
        .iter()
        .map(|m| {
            Mechanism::load(&data_dir().join(format!("mechanisms/{m}.toml"))).expect("bundled")
        })
        .collect();
    for (r, m) in mechs.iter().enumerate() {
        let traj = deployment::simulate(m, &truth, &SimOptions::default()).expect("ideal latch");
        let off = effect::encoder_offsets_deg(&truth, m.joint_count());
        let mut run = sensor::measure(&traj, &off, &SensorModel::REFERENCE, 3);
        run.set_meta("mechanism", &m.name);
        c.push(&mechs, run, Path::new(&format!("run{r}.csv")))
            .expect("pairs");
    }
    let o = diagnose(&c, &deploywatch_tests::diagnose_options(), sink());
    let words = |f: &FittedSet| {
        f.effects()
            .iter()
            .map(|e| e.to_string())
            .collect::<Vec<_>>()
            .join(" + ")
    };
    eprintln!(
        "found [{}] RMS {:.4} deg, BIC {:.1}",
        words(&o.extended),
        o.extended.rms(),
        o.extended.bic()
    );
    for s in o.ambiguities.iter().flat_map(|g| g.sets.iter()) {
        eprintln!(
            "  listed [{}] RMS {:.4} deg, BIC {:.1}",
            words(s),
            s.rms(),
            s.bic()
        );
        assert!(
            s.bic() > o.extended.bic() - MIN_DELTA_BIC,
            "listed as an alternative, better by the rule's margin: [{}] (BIC {:.1}) against the answer [{}] (BIC {:.1})",
            words(s),
            s.bic(),
            words(&o.extended),
            o.extended.bic()
        );
    }
    assert!(
        is_truth(&truth, &o.extended),
        "answered [{}] (RMS {:.4} deg) for [{}]",
        words(&o.extended),
        o.extended.rms(),
        truth
            .iter()
            .map(|e| e.to_string())
            .collect::<Vec<_>>()
            .join(" + ")
    );
}
