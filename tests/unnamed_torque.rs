//! Hidden unnamed torques: torques of forms no named effect of
//! `physics.md` section 6 has, hidden in seeded campaigns, beside named
//! effects or alone, one or two per campaign.
//!
//! The generator writes its own forms as dense `torque_table`s (eight
//! points, unlike the five-knot tables the diagnosis fits, at other places):
//! - `rub`: a resisting bump over part of the stroke (a harness that rubs),
//!   `T exp(−((φ − φc)/w)²)`;
//! - `ramp`: a torque that grows linearly over the last part of the stroke
//!   (a cable pulled taut), driving or resisting;
//! - `rate`: a resisting torque `c √(|φ̇|/R)`, sub-linear in the rate (no
//!   named effect has that form);
//! - `rub+rate`: both at one joint.
//!
//! The seeds and the truth stay in this file; the diagnosis sees the runs
//! and the nominal mechanisms only. A case passes when every joint that
//! holds a hidden torque holds a found effect (a `torque_table`, or a named
//! effect that explains the data as well: a named effect wins over a table)
//! and the extended model, re-simulated, fits the runs within twice the
//! noise RMS; every other case must be reported `unexplained`, naming the
//! joint and the stroke region. The share found as tables is printed.

use deploywatch_sim::campaign::Campaign;
use deploywatch_sim::deployment::{self, SimOptions};
use deploywatch_sim::diagnose::diagnose;
use deploywatch_sim::effect::{Effect, EffectKind, Law};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::progress::quiet;
use deploywatch_sim::sensor::{self, SensorModel};
use deploywatch_sim::torque_table::{HostTable as Table, HostTorqueTable as TorqueTable};
use deploywatch_tests::data_dir;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::Path;

const PAIRS: [[&str; 2]; 2] = [
    ["seed001_T01", "seed001_T02"],
    ["seed000_case1", "seed000_case3"],
];

/// The unnamed forms drawn.
#[derive(Clone, Copy, Debug)]
enum Form {
    Rub,
    Ramp,
    Rate,
    RubRate,
}

fn mechanisms(pair: usize) -> Vec<Mechanism> {
    PAIRS[pair]
        .iter()
        .map(|m| Mechanism::load(&data_dir().join(format!("mechanisms/{m}.toml"))).unwrap())
        .collect()
}

/// Eight points of `y(x)` evenly over `[lo, hi]`.
fn table_of(lo: f64, hi: f64, y: impl Fn(f64) -> f64) -> Table {
    let xs: Vec<f64> = (0..8).map(|i| lo + (hi - lo) * i as f64 / 7.0).collect();
    let ys: Vec<f64> = xs.iter().map(|&x| y(x)).collect();
    Table::new(&xs, &ys).unwrap()
}

/// A table of form `form` at joint `j` (1-based) of a joint stowed at
/// `stowed` deg, with amplitude `amp` [N·m].
fn draw_table(rng: &mut ChaCha8Rng, form: Form, stowed: f64, amp: f64) -> TorqueTable {
    let motion = -stowed.signum(); // sign of φ̇ while deploying
    let (a, b) = (stowed.min(0.0), stowed.max(0.0));
    let at = |f: f64| stowed * (1.0 - f); // fraction f of the stroke done
    let rub = |rng: &mut ChaCha8Rng| {
        let c = at(rng.gen_range(0.2..0.8));
        let w = stowed.abs() * rng.gen_range(0.08..0.2);
        table_of((c - 2.0 * w).max(a), (c + 2.0 * w).min(b), move |x| {
            -motion * amp * (-((x - c) / w).powi(2)).exp()
        })
    };
    let rate = |rng: &mut ChaCha8Rng| {
        let r = rng.gen_range(100.0..400.0);
        let (lo, hi) = if motion > 0.0 { (0.0, r) } else { (-r, 0.0) };
        table_of(lo, hi, move |x| -motion * amp * (x.abs() / r).sqrt())
    };
    match form {
        Form::Rub => TorqueTable {
            angle: Some(rub(rng)),
            rate: None,
        },
        Form::Ramp => {
            let start = rng.gen_range(0.4..0.7);
            let s = if rng.gen::<bool>() { 1.0 } else { -1.0 };
            let (lo, hi) = (at(start).min(at(1.0)), at(start).max(at(1.0)));
            let x0 = at(start);
            TorqueTable {
                angle: Some(table_of(lo, hi, move |x| {
                    s * amp * ((x - x0) / (at(1.0) - x0)).clamp(0.0, 1.0)
                })),
                rate: None,
            }
        }
        Form::Rate => TorqueTable {
            angle: None,
            rate: Some(rate(rng)),
        },
        Form::RubRate => TorqueTable {
            angle: Some(rub(rng)),
            rate: Some(rate(rng)),
        },
    }
}

/// How far effects move the pair of runs [deg RMS], noise-free.
fn effect_size(mechs: &[Mechanism], effects: &[Effect]) -> f64 {
    let opts = SimOptions {
        stop_when_deployed: false,
        ..SimOptions::default()
    };
    let (mut sse, mut n) = (0.0, 0usize);
    for m in mechs {
        let a = deployment::simulate(m, &[], &opts).unwrap();
        let b = deployment::simulate(m, effects, &opts).unwrap();
        for j in 0..m.joint_count() {
            for (x, y) in a.phi_deg[j].iter().zip(&b.phi_deg[j]) {
                sse += (x - y).powi(2);
                n += 1;
            }
        }
    }
    (sse / n as f64).sqrt()
}

/// One hidden torque at joint `j`, its amplitude raised until it moves the
/// runs by at least 0.3° RMS.
fn hidden_torque(seed: u64, form: Form, mechs: &[Mechanism], j: usize) -> Effect {
    let stowed = mechs[0].joints[j - 1].stowed_deg;
    let mut amp = 0.05;
    loop {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let table = draw_table(&mut rng, form, stowed, amp);
        let e = Effect {
            joint: Some(j),
            law: Law::TorqueTable(table),
        };
        if effect_size(mechs, &[e]) >= 0.3 || amp > 2.0 {
            return e;
        }
        amp *= 1.5;
    }
}

struct Case {
    pair: usize,
    truth: Vec<Effect>,
    runs: Vec<deploywatch_sim::run::Run>,
    noise_rms_deg: f64,
}

/// Simulates the truth and measures it with the reference sensor; returns
/// the runs and the RMS of the sensor noise they carry.
fn generate(seed: u64, pair: usize, truth: Vec<Effect>) -> Case {
    let mechs = mechanisms(pair);
    let (mut sse, mut n) = (0.0, 0usize);
    let runs = mechs
        .iter()
        .enumerate()
        .map(|(r, m)| {
            let traj = deployment::simulate(m, &truth, &SimOptions::default()).unwrap();
            let mut run = sensor::measure(
                &traj,
                &vec![0.0; m.joint_count()],
                &SensorModel::REFERENCE,
                seed * 10 + r as u64,
            );
            for j in 0..m.joint_count() {
                for (y, x) in run.phi_deg[j].iter().zip(&traj.phi_deg[j]) {
                    sse += (y - x).powi(2);
                    n += 1;
                }
            }
            run.set_meta("mechanism", &m.name);
            run
        })
        .collect();
    Case {
        pair,
        truth,
        runs,
        noise_rms_deg: (sse / n as f64).sqrt(),
    }
}

/// The hidden cases: a form alone, beside a named effect, and two tables.
fn cases() -> Vec<Case> {
    let mut out = Vec::new();
    let mut rng = ChaCha8Rng::seed_from_u64(1313);
    let forms = [Form::Rub, Form::Ramp, Form::Rate, Form::RubRate];
    for k in 0..12u64 {
        let seed = 7000 + k;
        let pair = (k % 2) as usize;
        let mechs = mechanisms(pair);
        let joints = mechs[0].joint_count();
        let j = rng.gen_range(1..=joints);
        let mut truth = vec![hidden_torque(seed, forms[k as usize % 4], &mechs, j)];
        match k / 4 {
            1 => truth.push(match rng.gen_range(0..3) {
                0 => Effect::joint(EffectKind::CoulombFriction, rng.gen_range(1..=joints), 0.3),
                1 => Effect::global(EffectKind::AirDrag, 0.3),
                _ => Effect {
                    joint: None,
                    law: Law::RigTilt {
                        g_m_s2: 0.08,
                        alpha_deg: rng.gen_range(0.0..360.0),
                    },
                },
            }),
            2 => {
                let other = 1 + j % joints;
                truth.push(hidden_torque(
                    seed + 100,
                    forms[(k as usize + 1) % 4],
                    &mechs,
                    other,
                ));
            }
            _ => {}
        }
        out.push(generate(seed, pair, truth));
    }
    out
}

/// The cases a test run without `DEPLOYWATCH_FULL` diagnoses: each form
/// (`k % 4`) and each composition (`k / 4`) at least once — 0 a rub alone,
/// 5 a ramp beside a named effect, 7 a rub + rate beside a named effect,
/// 10 a rate with a second table at another joint. The twelve are measured
/// with `DEPLOYWATCH_FULL=1` (docs/measured.md).
const CI_CASES: [usize; 4] = [0, 5, 7, 10];

#[test]
fn unnamed_torques_are_found_at_their_joint_or_reported_unexplained() {
    let all = cases();
    let (mut found_ok, mut unexplained_ok, mut tables_ok) = (0usize, 0usize, 0usize);
    let (mut ran, mut clean) = (0usize, 0usize);
    let mut bad = Vec::new();
    // `DEPLOYWATCH_CASE=k` runs only the k-th case; without
    // `DEPLOYWATCH_FULL` (a test run) the cases of [`CI_CASES`].
    let one: Option<usize> = std::env::var("DEPLOYWATCH_CASE")
        .ok()
        .and_then(|v| v.parse().ok());
    let full = std::env::var_os("DEPLOYWATCH_FULL").is_some();
    for (k, case) in all.iter().enumerate() {
        if one.map_or(!full && !CI_CASES.contains(&k), |o| o != k) {
            continue;
        }
        let mut campaign = Campaign::default();
        let mechs = mechanisms(case.pair);
        for (r, run) in case.runs.iter().enumerate() {
            campaign
                .push(&mechs, run.clone(), Path::new(&format!("run{r}.csv")))
                .unwrap();
        }
        let o = diagnose(&campaign, &deploywatch_tests::diagnose_options(), sink());
        // Only now the truth.
        let found = o.extended.effects();
        let table_joints = |v: &[Effect]| {
            let mut j: Vec<_> = v
                .iter()
                .filter(|e| e.kind() == EffectKind::TorqueTable)
                .map(|e| e.joint)
                .collect();
            j.sort();
            j
        };
        // The right joint: every joint that holds a hidden torque holds a
        // found effect, a table or a named effect that explains it as well
        // (a named effect that explains the data wins over a table).
        let found_joints: Vec<_> = found.iter().map(|e| e.joint).collect();
        let right_joint = table_joints(&case.truth)
            .iter()
            .all(|j| found_joints.contains(j));
        let as_table = table_joints(&case.truth)
            .iter()
            .all(|j| table_joints(&found).contains(j));
        let fits = o.extended.rms() <= 2.0 * case.noise_rms_deg;
        let ok = right_joint && fits && o.unexplained.is_none();
        // No claim at a joint that holds nothing: a joint holds its hidden
        // joint effects, and every joint holds a hidden global effect's
        // share (air drag and rig tilt act on every panel).
        let want = deploywatch_tests::hidden_torque::joints_of(&case.truth);
        let global = case.truth.iter().any(|e| e.joint.is_none());
        let spurious = !global
            && deploywatch_tests::hidden_torque::joints_of(&found)
                .iter()
                .any(|j| !want.contains(j));
        ran += 1;
        clean += usize::from(!spurious);
        let named_where = o.unexplained.as_ref().is_some_and(|u| u.joint().is_some());
        println!(
            "case {k}: truth {:?} found {:?}; RMS {:.4} -> {:.4} (noise {:.4}, {:.1} s){}",
            case.truth
                .iter()
                .map(|e| format!("{}@{:?}", e.kind(), e.joint))
                .collect::<Vec<_>>(),
            found
                .iter()
                .map(|e| format!("{}@{:?}", e.kind(), e.joint))
                .collect::<Vec<_>>(),
            o.baseline.rms(),
            o.extended.rms(),
            case.noise_rms_deg,
            o.wall_s,
            o.unexplained
                .as_ref()
                .map(|u| format!("; unexplained: {u}"))
                .unwrap_or_default()
        );
        if spurious {
            println!("  a claim at a joint that holds nothing");
        }
        if ok {
            found_ok += 1;
            tables_ok += usize::from(as_table);
        } else if named_where {
            unexplained_ok += 1;
        } else {
            bad.push(k);
        }
    }
    println!(
        "right joint and fit within 2x noise: {found_ok}/{ran} ({tables_ok} of them as torque_table at every hidden joint); unexplained with joint and region: {unexplained_ok}; neither: {bad:?}; no claim at a joint that holds nothing: {clean}/{ran}"
    );
    let body = format!(
        "## Diagnosis: unnamed torques (12 cases)\n\n\
         The seeded campaigns of `unnamed_torques_are_found_at_their_joint_or_reported_unexplained` \
         (`docs/diagnosis.md`, \"How well it works\"): torques of our own forms as dense \
         tables, alone, beside a named effect, two at two joints.\n\n\
         | criterion | required | measured |\n|---|---|---|\n\
         | right joint and fit within 2× the noise RMS | ≥ 80 % | {found_ok}/{ran} ({tables_ok} as `torque_table` at every hidden joint) |\n\
         | the rest reported `unexplained` with joint and region | 100 % | {unexplained_ok} of {} |\n\
         | no claim at a joint that holds nothing (a hidden global effect acts at every joint) | all | {clean}/{ran} |\n",
        ran - found_ok,
    );
    deploywatch_tests::record::record(
        "diagnosis-unnamed-torque",
        "DEPLOYWATCH_FULL=1 cargo test -p deploywatch-tests --test unnamed_torque unnamed_torques -- --nocapture",
        &body,
    )
    .expect("docs/measured.md written");
    assert!(ran > 0, "DEPLOYWATCH_CASE matches no case: zero cases ran");
    // The share found is a figure of the twelve (a rate of four would
    // move by a quarter with each case); every case, in any run, must be
    // found or reported unexplained with its joint and region.
    if full && one.is_none() {
        assert!(found_ok * 10 >= ran * 8, "only {found_ok}/{ran} found");
    }
    assert!(
        bad.is_empty(),
        "cases neither found nor reported unexplained: {bad:?}"
    );
}

/// The search's progress: on stderr with `DEPLOYWATCH_TRACE` set, else none.
fn sink() -> deploywatch_sim::progress::Progress<'static> {
    if std::env::var_os("DEPLOYWATCH_TRACE").is_some() {
        &deploywatch_sim::progress::stderr
    } else {
        &quiet
    }
}

/// What one hidden-family campaign gave.
struct Verdict {
    /// Right joints, fit within 2× the noise RMS, nothing unexplained.
    found: bool,
    /// Reported `unexplained` with the joint and the stroke region.
    honest: bool,
    /// A claim at a joint that holds nothing.
    spurious: bool,
    /// The re-simulated angle RMS difference \[deg\] of each table that had
    /// to be compressed for the monitor.
    export_loss_deg: Vec<f64>,
}

fn judge_family_case(c: &deploywatch_tests::hidden_torque::Case) -> Verdict {
    use deploywatch_tests::hidden_torque::{joints_of, mechanisms};
    let mut campaign = Campaign::default();
    let mechs = mechanisms(c.pair);
    for (r, run) in c.runs.iter().enumerate() {
        campaign
            .push(&mechs, run.clone(), Path::new(&format!("run{r}.csv")))
            .unwrap();
    }
    let o = diagnose(&campaign, &deploywatch_tests::diagnose_options(), sink());
    // Only now the truth.
    let found = o.extended.effects();
    let (want, got) = (joints_of(&c.truth), joints_of(&found));
    let fits = o.extended.rms() <= 2.0 * c.noise_rms_deg;
    let verdict = Verdict {
        found: want == got && fits && o.unexplained.is_none(),
        honest: o.unexplained.as_ref().is_some_and(|u| u.joint().is_some()),
        spurious: got.iter().any(|j| !want.contains(j)),
        export_loss_deg: monitor_exports(&campaign, &found),
    };
    println!(
        "  {}: truth {:?} found {:?}; RMS {:.4} -> {:.4} (noise {:.4}, {:.1} s){}{}",
        c.family.name(),
        c.truth
            .iter()
            .map(|e| format!("{}@{:?}", e.kind(), e.joint))
            .collect::<Vec<_>>(),
        found
            .iter()
            .map(|e| format!("{}@{:?}", e.kind(), e.joint))
            .collect::<Vec<_>>(),
        o.baseline.rms(),
        o.extended.rms(),
        c.noise_rms_deg,
        o.wall_s,
        if verdict.found { " ok" } else { " MISS" },
        o.unexplained
            .as_ref()
            .map(|u| format!("; unexplained: {u}"))
            .unwrap_or_default()
    );
    verdict
}

/// The monitor's export of every table found: at most the monitor's
/// points per axis; prints the fit loss and returns the re-simulated angle
/// loss \[deg\] of each compressed one.
fn monitor_exports(campaign: &Campaign, found: &[Effect]) -> Vec<f64> {
    use deploywatch_core::physics::TABLE_MAX_KNOTS;
    use deploywatch_sim::table_export::export_tables;
    let mut out = Vec::new();
    for x in export_tables(campaign, found) {
        for t in [&x.table.angle, &x.table.rate].into_iter().flatten() {
            assert!(t.xs().len() <= TABLE_MAX_KNOTS, "{:?}", x.table);
        }
        if x.compressed {
            let a = x.angle_rms_deg.expect("the export re-simulates");
            println!(
                "    monitor table at joint {}: torque difference RMS {:.4} N·m (max {:.4}), angles {:.4} deg",
                x.joint, x.torque_rms_nm, x.torque_max_nm, a
            );
            out.push(a);
        }
    }
    out
}

/// The set the search and the ambiguity stage found is the answer only when
/// it brings in no claim its joint shows no evidence of
/// (`Rejection::UnsupportedClaim`): on this narrow snag at one joint the
/// ambiguity stage fits a set with a harness stiffness beside it at a joint
/// whose residual torque shows nothing, better by BIC and held out; taking
/// it would claim an effect where none is. The campaign must be found, with
/// no claim elsewhere.
#[test]
fn an_alternative_brings_in_no_claim_its_joint_does_not_show() {
    use deploywatch_tests::hidden_torque::{case, families};
    let snag = families()
        .into_iter()
        .find(|f| f.name() == "Snag alone")
        .expect("the family of a snag alone");
    let v = judge_family_case(&case(snag, 1));
    assert!(!v.spurious, "a claim at a joint that holds nothing");
    assert!(v.found, "the snag not found at its joint");
}

/// Hidden torques of forms unlike the diagnosis's knots
/// (`deploywatch_tests::hidden_torque`): narrow features, torques
/// proportional to the spring's, rate laws peaked at low rate and
/// quadratic (`φ̇|φ̇|`), a break-away falling with rate, narrow snags, each
/// friction form also beside named effects, a torque beside named effects,
/// two torques at two joints, null campaigns; each family's pass rate
/// printed, and each friction form's (≥ 80 % asserted on the full run). A
/// case not found must be `unexplained` with its joint and stroke region.
/// The CI runs one campaign per family (12); `DEPLOYWATCH_FULL=1` runs six
/// per family (72).
#[test]
fn hidden_torque_families_are_found_or_reported_unexplained() {
    use deploywatch_tests::hidden_torque::{case, families, friction_form, Family};
    use std::collections::BTreeMap;
    let per = if std::env::var_os("DEPLOYWATCH_FULL").is_some() {
        6
    } else {
        1
    };
    let (mut found, mut with, mut clean, mut total, mut bad) = (0, 0, 0, 0, Vec::new());
    let mut losses = Vec::new();
    let mut rows = Vec::new();
    // Found / campaigns of each friction form, alone and beside named.
    let mut friction: BTreeMap<String, (usize, usize)> = BTreeMap::new();
    // `DEPLOYWATCH_FAMILY=two` runs only the families whose name holds it;
    // a filter that matches none fails (a suite of zero cases proves nothing).
    let only = std::env::var("DEPLOYWATCH_FAMILY").unwrap_or_default();
    let chosen: Vec<Family> = families()
        .into_iter()
        .filter(|f| f.name().contains(&only))
        .collect();
    assert!(
        !chosen.is_empty(),
        "DEPLOYWATCH_FAMILY={only:?} matches no family (families: {}): zero cases would run",
        families()
            .iter()
            .map(|f| f.name())
            .collect::<Vec<_>>()
            .join(", ")
    );
    for f in chosen {
        let (mut ok, mut n) = (0, 0);
        // `DEPLOYWATCH_CASE=k` runs only the k-th campaign of each family.
        let one: Option<u64> = std::env::var("DEPLOYWATCH_CASE")
            .ok()
            .and_then(|v| v.parse().ok());
        for k in (0..per).filter(|k| one.is_none_or(|o| o == *k)) {
            let c = case(f, k);
            let v = judge_family_case(&c);
            losses.extend(v.export_loss_deg.iter().copied());
            n += 1;
            total += 1;
            ok += usize::from(v.found);
            clean += usize::from(!v.spurious);
            if f != Family::Null {
                with += 1;
                found += usize::from(v.found);
            }
            if !v.found && !v.honest {
                bad.push(format!("{} {k}", f.name()));
            }
            if let Some(form) = friction_form(f) {
                let e = friction.entry(format!("{form:?}")).or_default();
                e.0 += usize::from(v.found);
                e.1 += 1;
            }
        }
        println!("family {}: {ok}/{n}", f.name());
        rows.push(format!("| {} | {ok}/{n} |", f.name()));
    }
    println!(
        "hidden torques found: {found}/{with}; no claim at a joint that holds nothing: {clean}/{total}; neither found nor unexplained: {bad:?}"
    );
    for (form, (ok, n)) in &friction {
        println!("friction form {form} (alone and beside named): {ok}/{n}");
    }
    losses.sort_by(f64::total_cmp);
    println!(
        "monitor exports compressed: {}; re-simulated angle loss median {:.4} deg, largest {:.4} deg",
        losses.len(),
        losses.get(losses.len() / 2).copied().unwrap_or(0.0),
        losses.last().copied().unwrap_or(0.0)
    );
    let forms: Vec<String> = friction
        .iter()
        .map(|(form, (ok, n))| format!("| {form} (alone and beside named) | ≥ 80 % | {ok}/{n} |"))
        .collect();
    let body = format!(
        "## Diagnosis: hidden-torque families\n\n\
         {per} campaign(s) per family of `hidden_torque_families_are_found_or_reported_unexplained` \
         (`tests/src/hidden_torque.rs`; `docs/diagnosis.md`, \"How well it works\"); \
         found: the right joints, a fit within 2× the noise RMS, nothing `unexplained`.\n\n\
         | family | found |\n|---|---|\n{}\n\n\
         | criterion | required | measured |\n|---|---|---|\n{}\n\
         | hidden torques found | ≥ 60 % (CI) | {found}/{with} |\n\
         | no claim at a joint that holds nothing | all (the CI's one per family: ≥ 85 %) | {clean}/{total} |\n\
         | neither found nor `unexplained` with joint and region | none | {} |\n\
         | monitor exports compressed; re-simulated angle loss median, largest | (reported) | {}; {:.4}°, {:.4}° |\n",
        rows.join("\n"),
        forms.join("\n"),
        if bad.is_empty() { "none".to_string() } else { bad.join(", ") },
        losses.len(),
        losses.get(losses.len() / 2).copied().unwrap_or(0.0),
        losses.last().copied().unwrap_or(0.0),
    );
    deploywatch_tests::record::record(
        "diagnosis-hidden-torque-families",
        "DEPLOYWATCH_FULL=1 cargo test -p deploywatch-tests --test unnamed_torque hidden_torque_families -- --nocapture",
        &body,
    )
    .expect("docs/measured.md written");
    assert!(total > 0, "zero cases ran");
    assert!(found * 100 >= with * 60, "only {found}/{with} found");
    assert!(
        clean * 100 >= total * 85,
        "spurious claims: {clean}/{total} clean"
    );
    assert!(
        bad.is_empty(),
        "neither found nor unexplained with joint and region: {bad:?}"
    );
    // The bar for each friction form, on the full experiment (12
    // campaigns each); the CI's two per form are too few to measure it.
    if per >= 6 {
        assert_eq!(clean, total, "claims at a joint that holds nothing");
        for (form, (ok, n)) in &friction {
            assert!(ok * 100 >= n * 80, "{form}: only {ok}/{n} found");
        }
    }
}
