//! `diagnose` on runs of physical latches that bounce and escape
//! (`docs/diagnosis.md`, "Runs of a physical latch").
//!
//! A seeded generator draws each campaign: a drawing (seed 001 T01 + T02,
//! or two runs of seed 000 case 1, all with physical latches), each run's
//! mechanism as built around it (`Mechanism::as_built` with the default
//! `LatchTolerance`: preload and rate ±20 %, magnet ±30 %, stop damping
//! ±30 %, crest ±0.1°), and zero or one named effect (kind, joint and value
//! drawn by `deploywatch_tests::hidden_effect`, as in `tests/diagnosis/`;
//! the value raised until it moves the ideal-latch twin's runs by ≥ 0.3°
//! RMS). The runs get the reference sensor noise. The diagnosis sees only the runs and the drawings; the
//! truth stays here until it has answered. Draws the simulator refuses are
//! skipped and counted.
//!
//! `DEPLOYWATCH_FULL=1` runs the 48 campaigns of the measured result; the
//! CI runs the first 2 of each family (`DEPLOYWATCH_TRACE=1` prints every
//! round).

// Per-joint series are indexed in lockstep with their offsets.
#![allow(clippy::needless_range_loop)]

use deploywatch_sim::campaign::Campaign;
use deploywatch_sim::deployment::{self, SimOptions};
use deploywatch_sim::diagnose::{diagnose, LatchCause, Outcome};
use deploywatch_sim::effect::{self, Effect, EffectKind};
use deploywatch_sim::latch::LatchTolerance;
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::progress::{quiet, stderr, Progress};
use deploywatch_sim::run::Run;
use deploywatch_sim::sensor::{self, SensorModel};
use deploywatch_tests::hidden_effect::{draw_effect, kinds};
use deploywatch_tests::holds_less;
use deploywatch_tests::{mechanism as load, PHYSICAL_LATCH_FAMILIES as FAMILIES};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::Path;

/// How far `e` moves the ideal-latch twins' runs [deg RMS], noise-free.
fn effect_size(twins: &[Mechanism], e: &Effect) -> f64 {
    let opts = SimOptions {
        stop_when_deployed: false,
        ..SimOptions::default()
    };
    let (mut sse, mut n) = (0.0, 0usize);
    for m in twins {
        let (Ok(a), Ok(b)) = (
            deployment::simulate(m, &[], &opts),
            deployment::simulate(m, &[*e], &opts),
        ) else {
            return 0.0;
        };
        let off = effect::encoder_offsets_deg(&[*e], m.joint_count());
        for j in 0..m.joint_count() {
            for i in 0..a.t_s.len().min(b.t_s.len()) {
                let d = b.phi_deg[j][i] + off[j] - a.phi_deg[j][i];
                sse += d * d;
                n += 1;
            }
        }
    }
    (sse / n.max(1) as f64).sqrt()
}

/// As-built draws tried per campaign before the generator gives up: a draw
/// the simulator refuses is redrawn, never without end.
const MAX_DRAWS: usize = 20;

/// One campaign: the drawings, the runs, the truth.
struct Case {
    drawings: Vec<Mechanism>,
    runs: Vec<Run>,
    truth: Vec<Effect>,
}

/// Draws a campaign of `family` with `kind` hidden (or none), redrawing an
/// as-built draw the simulator refuses (`refused` counts them) at most
/// [`MAX_DRAWS`] times; panics naming the seed and the last refusal when
/// every draw was refused.
fn generate(seed: u64, family: usize, kind: Option<EffectKind>, refused: &mut usize) -> Case {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let drawings: Vec<Mechanism> = FAMILIES[family].iter().map(|(d, _)| load(d)).collect();
    let twins: Vec<Mechanism> = FAMILIES[family].iter().map(|(_, t)| load(t)).collect();
    let joints = drawings[0].joint_count();
    let mut truth = Vec::new();
    if kind == Some(EffectKind::PlungerWeakening) {
        // The latch as built beyond its tolerance: no size to reach.
        let j = rng.gen_range(1..=joints);
        truth.push(Effect::joint(EffectKind::PlungerWeakening, j, 0.7));
    } else if let Some(k) = kind {
        let mut e = draw_effect(&mut rng, k, joints);
        for _ in 0..40 {
            if effect_size(&twins, &e) >= 0.3 {
                break;
            }
            e = e.with_value(e.value() * 1.5);
        }
        truth.push(e);
    }
    let tol = LatchTolerance::default();
    let mut last = String::new();
    for _ in 0..MAX_DRAWS {
        let mut uniform = || rng.gen::<f64>();
        // One as-built latch set per drawing: seed 000's two runs are of one
        // wing.
        let built: Vec<Mechanism> = if drawings[0].name == drawings[1].name {
            let b = drawings[0].as_built(&tol, &mut uniform);
            vec![b.clone(), b]
        } else {
            drawings
                .iter()
                .map(|d| d.as_built(&tol, &mut uniform))
                .collect()
        };
        let noise_seed = rng.gen::<u64>() % 1_000_000;
        let runs: Result<Vec<Run>, _> = built
            .iter()
            .enumerate()
            .map(|(r, m)| {
                let traj = deployment::simulate(m, &truth, &SimOptions::default())?;
                let off = effect::encoder_offsets_deg(&truth, m.joint_count());
                let mut run =
                    sensor::measure(&traj, &off, &SensorModel::REFERENCE, noise_seed + r as u64);
                run.set_meta("mechanism", &m.name);
                Ok::<Run, deployment::SimError>(run)
            })
            .collect();
        match runs {
            Ok(runs) => {
                return Case {
                    drawings,
                    runs,
                    truth,
                }
            }
            Err(e) => {
                *refused += 1;
                eprintln!("seed {seed}: the simulator refused an as-built draw: {e}");
                last = e.to_string();
            }
        }
    }
    panic!("seed {seed}: the simulator refused all {MAX_DRAWS} as-built draws; the last: {last}")
}

fn campaign_of(case: &Case) -> Campaign {
    let mut c = Campaign::default();
    for (r, run) in case.runs.iter().enumerate() {
        c.push(
            &case.drawings,
            run.clone(),
            Path::new(&format!("run{r}.csv")),
        )
        .expect("a generated run pairs with its drawing");
    }
    c
}

fn sink() -> Progress<'static> {
    if std::env::var_os("DEPLOYWATCH_TRACE").is_some() {
        &stderr
    } else {
        &quiet
    }
}

/// Exactly the hidden effects at their joints, each within 20 % (a rig
/// tilt by its magnitude), nothing unexplained; latch findings allowed.
fn named_exactly(truth: &[Effect], o: &Outcome) -> bool {
    let found = o.extended.effects();
    if found.len() != truth.len() || o.unexplained.is_some() {
        return false;
    }
    truth.iter().all(|t| {
        found.iter().any(|f| {
            f.kind() == t.kind()
                && f.joint == t.joint
                && (f.value() - t.value()).abs() <= 0.2 * t.value().abs()
        })
    })
}

/// The campaigns: per family, every kind three times and three clean.
fn specs(full: bool) -> Vec<(u64, usize, Option<EffectKind>)> {
    let mut out = Vec::new();
    for family in 0..2 {
        let mut list: Vec<Option<EffectKind>> = Vec::new();
        for rep in 0..3 {
            for (k, kind) in kinds().iter().enumerate() {
                if full || (rep == 0 && k % 4 == family) {
                    list.push(Some(*kind));
                }
            }
            if full || rep == 0 {
                list.push(None);
            }
        }
        for (i, kind) in list.into_iter().enumerate() {
            out.push((7000 + 100 * family as u64 + i as u64, family, kind));
        }
    }
    out
}

#[test]
fn hidden_effects_are_named_on_runs_of_physical_latches() {
    let full = std::env::var_os("DEPLOYWATCH_FULL").is_some();
    let specs = specs(full);
    assert!(!specs.is_empty());
    let (mut ok, mut hidden_ok, mut hidden, mut clean_ok, mut clean) = (0, 0, 0, 0, 0);
    let mut refused = 0usize;
    let mut walls = Vec::new();
    let mut latch_found = 0usize;
    let (mut latch_joints, mut outside_by_one, mut outside_more) = (0usize, 0usize, 0usize);
    for (seed, family, kind) in &specs {
        let case = generate(*seed, *family, *kind, &mut refused);
        let o = diagnose(
            &campaign_of(&case),
            &deploywatch_tests::diagnose_options(),
            sink(),
        );
        let good = named_exactly(&case.truth, &o);
        walls.push(o.wall_s);
        let latch: Vec<String> = o
            .latches
            .iter()
            .filter(|l| !l.differs.is_empty())
            .map(|l| format!("joint {}: {:?}", l.joint, l.differs))
            .collect();
        latch_found += usize::from(!latch.is_empty());
        // How far each joint's measured escapes lie outside the range the
        // drawing's latch gives over its ensemble (the finding's margin).
        for l in &o.latches {
            let x: usize = l.measured.iter().map(|e| e.escapes).sum();
            let [lo, hi] = l.spread.escapes;
            let gap = x.saturating_sub(hi).max(lo.saturating_sub(x));
            latch_joints += 1;
            outside_by_one += usize::from(gap == 1);
            outside_more += usize::from(gap > 1);
        }
        eprintln!(
            "seed {seed} family {family}: {} truth [{}] found [{}] RMS {:.4} -> {:.4}{} latch [{}] ({:.1} s)",
            if good { "ok  " } else { "MISS" },
            case.truth.iter().map(|e| e.to_string()).collect::<Vec<_>>().join("; "),
            o.extended.effects().iter().map(|e| e.to_string()).collect::<Vec<_>>().join("; "),
            o.baseline.rms(),
            o.extended.rms(),
            o.unexplained.as_ref().map(|u| format!(" unexplained: {u}")).unwrap_or_default(),
            latch.join(" | "),
            o.wall_s
        );
        ok += usize::from(good);
        if case.truth.is_empty() {
            clean += 1;
            clean_ok += usize::from(good);
        } else {
            hidden += 1;
            hidden_ok += usize::from(good);
        }
    }
    walls.sort_by(f64::total_cmp);
    let median = walls[walls.len() / 2];
    println!(
        "named exactly: {ok}/{} (hidden {hidden_ok}/{hidden}, clean {clean_ok}/{clean}); refused draws {refused}; diagnose wall time median {median:.1} s, max {:.1} s",
        specs.len(),
        walls.last().copied().unwrap_or(0.0)
    );
    let max = walls.last().copied().unwrap_or(0.0);
    let pct = |a: usize, b: usize| 100.0 * a as f64 / b.max(1) as f64;
    let body = format!(
        "## Diagnosis on runs of physical latches\n\n\
         {n} campaigns of `tests/diagnosis_physical_latch.rs` (`docs/diagnosis.md`, \
         \"Runs of a physical latch\"): each run's latches as built, one named \
         effect or none, the diagnosis given the drawings.\n\n\
         | criterion | required | measured |\n|---|---|---|\n\
         | named exactly (within 20 %) | ≥ 90 % | {ok}/{n} ({:.1} %): hidden {hidden_ok}/{hidden}, clean {clean_ok}/{clean} |\n\
         | clean campaign names no joint or global effect | all | {clean_ok}/{clean} |\n\
         | campaigns with a latch finding (as-built latches within tolerance) | (reported) | {latch_found}/{n} |\n\
         | joints whose measured escapes lie outside the drawing's range over its ensemble | (reported) | {outside_by_one} by one, {outside_more} by more, of {latch_joints} |\n\
         | `diagnose` wall time, two runs | ≤ 30 s median | median {median:.1} s, max {max:.1} s |\n\
         | draws the simulator refused (skipped, redrawn) | (counted) | {refused} |\n",
        pct(ok, specs.len()),
        n = specs.len(),
    );
    deploywatch_tests::record::record(
        "diagnosis-physical-latch",
        "DEPLOYWATCH_FULL=1 cargo test -p deploywatch-tests --test diagnosis_physical_latch -- --nocapture",
        &body,
    )
    .expect("docs/measured.md written");
    assert_eq!(clean_ok, clean, "a clean campaign named an effect");
    assert!(
        10 * ok >= 9 * specs.len(),
        "{ok}/{} named exactly, expected ≥ 90 %",
        specs.len()
    );
}

/// How a latch as built differs from its drawing beyond its tolerances,
/// at one joint, nothing else hidden.
#[derive(Clone, Copy, Debug)]
enum LatchFault {
    /// The plunger's preload and rate at 30 % of the drawing's.
    Plunger,
    /// The magnet's pull at 30 % of the drawing's.
    Magnet,
    /// The stop's contact damping 3 times the drawing's (its tolerance:
    /// ±30 %).
    StopDamping,
}

/// The simulator's options for the weakened-latch runs: the mechanisms'
/// own sample rate (100 Hz), or `DEPLOYWATCH_LATCH_HZ` to ask what a
/// faster rig would show.
fn latch_sim_options() -> SimOptions {
    SimOptions {
        sample_hz: std::env::var("DEPLOYWATCH_LATCH_HZ")
            .ok()
            .and_then(|v| v.parse().ok()),
        ..SimOptions::default()
    }
}

/// A campaign of `family` whose latch at one drawn joint differs by
/// `fault` (every latch also as built within its tolerances); the truth is
/// that joint.
fn generate_latch(seed: u64, family: usize, fault: LatchFault) -> (Case, usize) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let drawings: Vec<Mechanism> = FAMILIES[family].iter().map(|(d, _)| load(d)).collect();
    let j = rng.gen_range(1..=drawings[0].joint_count());
    let effects = match fault {
        LatchFault::Plunger => vec![Effect::joint(EffectKind::PlungerWeakening, j, 0.7)],
        LatchFault::Magnet => vec![Effect::joint(EffectKind::MagnetWeakening, j, 0.7)],
        LatchFault::StopDamping => Vec::new(),
    };
    let tol = LatchTolerance::default();
    let mut uniform = || rng.gen::<f64>();
    let mut built: Vec<Mechanism> = if drawings[0].name == drawings[1].name {
        let b = drawings[0].as_built(&tol, &mut uniform);
        vec![b.clone(), b]
    } else {
        drawings
            .iter()
            .map(|d| d.as_built(&tol, &mut uniform))
            .collect()
    };
    if let LatchFault::StopDamping = fault {
        for m in built.iter_mut() {
            if let Some(Some(l)) = m.latches.get_mut(j - 1) {
                l.stop.damping_ns_per_mm1_25 *= 3.0;
            }
        }
    }
    let noise_seed = rng.gen::<u64>() % 1_000_000;
    let runs = built
        .iter()
        .enumerate()
        .map(|(r, m)| {
            let traj = deployment::simulate(m, &effects, &latch_sim_options())
                .expect("an as-built draw the simulator runs");
            let mut run = sensor::measure(
                &traj,
                &vec![0.0; m.joint_count()],
                &SensorModel::REFERENCE,
                noise_seed + r as u64,
            );
            run.set_meta("mechanism", &m.name);
            run
        })
        .collect();
    let case = Case {
        drawings,
        runs,
        truth: Vec::new(),
    };
    (case, j)
}

/// A latch that differs at one joint beyond its tolerances (plunger or
/// magnet at 30 %, or a stop damping 3 times its drawing's), nothing else
/// hidden: never an effect (no joint friction, table or global stand-in);
/// the test prints how often the latch finding names that joint, and
/// whether any other joint's latch was named. `DEPLOYWATCH_FULL=1`: 8
/// campaigns of each, alternating the two families; the CI the first of
/// the plunger (seed 001 T01 + T02; a weakened latch of seed 000 case 1
/// is the CI's in `a_latch_that_holds_less_is_named_at_its_joint_never_an_effect`).
#[test]
fn a_weakened_latch_is_a_latch_finding_never_an_effect() {
    let full = std::env::var_os("DEPLOYWATCH_FULL").is_some();
    let faults: &[LatchFault] = if full {
        &[
            LatchFault::Plunger,
            LatchFault::Magnet,
            LatchFault::StopDamping,
        ]
    } else {
        &[LatchFault::Plunger]
    };
    let n = if full { 8 } else { 1 };
    let mut clean_all = 0;
    let mut rows = Vec::new();
    for fault in faults {
        let (mut clean, mut flagged, mut elsewhere) = (0, 0, 0);
        for i in 0..n {
            let seed = 7500 + i as u64;
            let (case, joint) = generate_latch(seed, i % 2, *fault);
            let o = diagnose(
                &campaign_of(&case),
                &deploywatch_tests::diagnose_options(),
                sink(),
            );
            let named = o.extended.effects();
            let hit = o
                .latches
                .iter()
                .any(|l| l.joint == joint && !l.differs.is_empty());
            let other = o
                .latches
                .iter()
                .any(|l| l.joint != joint && !l.differs.is_empty());
            clean += usize::from(named.is_empty() && o.unexplained.is_none());
            flagged += usize::from(hit);
            elsewhere += usize::from(other);
            let latch: Vec<String> = o
                .latches
                .iter()
                .filter(|l| l.joint == joint || !l.differs.is_empty())
                .map(|l| {
                    let esc: usize = l.measured.iter().map(|e| e.escapes).sum();
                    format!(
                        "joint {}: {esc} escapes, restitution {:?}, deceleration {:?}; drawing {:?}; {:?}",
                        l.joint,
                        l.restitution.map(|a| (a.median, a.ci95)),
                        l.hold_accel.map(|a| (a.median, a.ci95, a.impacts)),
                        l.spread,
                        l.differs
                    )
                })
                .collect();
            eprintln!(
                "seed {seed} {fault:?} at joint {joint}: effects [{}] latch [{}]",
                named
                    .iter()
                    .map(|e| e.to_string())
                    .collect::<Vec<_>>()
                    .join("; "),
                latch.join(" | ")
            );
        }
        println!("{fault:?}: no effect named in {clean}/{n}; latch finding at its joint in {flagged}/{n}; a latch finding at another joint in {elsewhere}/{n}");
        rows.push(format!(
            "| {fault:?} | {}/{n} | {flagged}/{n} | {elsewhere}/{n} |",
            n - clean
        ));
        clean_all += usize::from(clean == n);
    }
    if full {
        let body = format!(
            "## Diagnosis: a latch that differs from its drawing\n\n\
             Per fault {n} campaigns of `a_weakened_latch_is_a_latch_finding_never_an_effect` \
             (`docs/diagnosis.md`, \"Physical-latch campaigns\"): a plunger or magnet at 30 %, or a \
             stop damping 3 × drawn, at one drawn joint, nothing else hidden, every latch as built.\n\n\
             | latch at one joint | named as an effect (or unexplained) | latch finding at that joint | latch finding at another joint |\n\
             |---|---|---|---|\n{}\n",
            rows.join("\n")
        );
        deploywatch_tests::record::record(
            "diagnosis-latch-faults",
            "DEPLOYWATCH_FULL=1 cargo test -p deploywatch-tests --test diagnosis_physical_latch a_weakened -- --nocapture",
            &body,
        )
        .expect("docs/measured.md written");
    }
    assert_eq!(
        clean_all,
        faults.len(),
        "a latch fault was named as an effect"
    );
}

/// Campaigns whose latch at one joint holds less than drawn where that
/// plainly changes the runs (`deploywatch_tests::holds_less`: beyond the
/// drawing's spread over 40 as-built draws; the first kept from seed 7701,
/// the first 2 with `DEPLOYWATCH_FULL=1`): the diagnosis names that
/// joint's latch as holding less than drawn, no effect for it and no latch
/// at another joint. How often over
/// 24 campaigns, and how few weakenings plainly change two runs:
/// `DEPLOYWATCH_FULL=1 cargo run --release -p deploywatch-tests --example
/// latch_holds_less` (docs/measured.md).
#[test]
fn a_latch_that_holds_less_is_named_at_its_joint_never_an_effect() {
    let want = if std::env::var_os("DEPLOYWATCH_FULL").is_some() {
        2
    } else {
        1
    };
    let mut kept = 0;
    for seed in 7701u64..7900 {
        let Some(c) = holds_less::generate(seed, (seed % 2) as usize, &latch_sim_options()) else {
            continue;
        };
        let case = Case {
            drawings: c.drawings,
            runs: c.runs,
            truth: Vec::new(),
        };
        let o = diagnose(
            &campaign_of(&case),
            &deploywatch_tests::diagnose_options(),
            sink(),
        );
        let others: Vec<usize> = o
            .latches
            .iter()
            .filter(|l| l.joint != c.joint && !l.differs.is_empty())
            .map(|l| l.joint)
            .collect();
        assert!(
            o.extended.effects().is_empty() && o.unexplained.is_none(),
            "seed {seed}: {:?} at {:.0} % at joint {} named as an effect",
            c.what,
            100.0 * c.strength,
            c.joint
        );
        assert!(
            others.is_empty(),
            "seed {seed}: a latch named at joints {others:?}, not {}",
            c.joint
        );
        assert!(
            o.latches
                .iter()
                .any(|l| l.joint == c.joint && l.cause == Some(LatchCause::HoldsLess)),
            "seed {seed}: {:?} at {:.0} % at joint {} not named as holding less: {:?}",
            c.what,
            100.0 * c.strength,
            c.joint,
            o.latches
                .iter()
                .find(|l| l.joint == c.joint)
                .map(|l| (&l.differs, &l.undecided))
        );
        kept += 1;
        if kept == want {
            return;
        }
    }
    panic!("only {kept} of {want} campaigns kept of seeds 7701..7900");
}

/// The whole-run check (`docs/diagnosis.md`, "Runs of a physical latch",
/// 4) on seed 001 T01 + T02 with the drawing's latches: without a hidden
/// effect every joint's shots after the first contact are followed by the
/// model found (no joint above the check's factor); with a harness of
/// 0.5 N·m/rad hidden at the slow root joint, which acts mostly after the
/// first contact, either the harness is named at joint 1 or the check
/// finds a joint the model does not follow.
#[test]
fn an_effect_after_the_first_contact_shows_in_the_whole_run() {
    let drawings: Vec<Mechanism> = FAMILIES[0].iter().map(|(d, _)| load(d)).collect();
    let harness = vec![Effect::joint(EffectKind::HarnessStiffness, 1, 0.5)];
    for truth in [Vec::new(), harness] {
        let runs: Vec<Run> = drawings
            .iter()
            .enumerate()
            .map(|(r, m)| {
                let traj = deployment::simulate(m, &truth, &SimOptions::default())
                    .expect("the wing simulates");
                let mut run = sensor::measure(&traj, &[], &SensorModel::REFERENCE, 77 + r as u64);
                run.set_meta("mechanism", &m.name);
                run
            })
            .collect();
        let case = Case {
            drawings: drawings.clone(),
            runs,
            truth: truth.clone(),
        };
        let o = diagnose(
            &campaign_of(&case),
            &deploywatch_tests::diagnose_options(),
            sink(),
        );
        let w = o
            .whole_run
            .as_ref()
            .expect("runs that go on after their free window are checked whole");
        assert!(!w.shots.is_empty(), "no shot after the free windows");
        // Only now the truth.
        if truth.is_empty() {
            assert!(
                w.missed().is_none(),
                "a clean campaign not followed: {:?}",
                w.joints
            );
        } else {
            let named = o
                .extended
                .effects()
                .iter()
                .any(|e| e.kind() == EffectKind::HarnessStiffness && e.joint == Some(1));
            assert!(
                named || w.missed().is_some(),
                "the harness neither named nor the motion after contact missed: {:?}, {:?}",
                o.extended.effects(),
                w.joints
            );
        }
    }
}
