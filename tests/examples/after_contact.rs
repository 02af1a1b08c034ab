//! How often `diagnose` finds a named effect that acts after the first
//! latch contact (`docs/diagnosis.md`, "Runs of a physical latch", 4), on
//! wings of four to six panels with mixed latches where the effect hardly
//! shows before that contact.
//!
//! Wings of `deploywatch_tests::wing_gen` (seeds from 9301 on) with 4–6
//! joints, no rig, half of the joints (drawn) with a physical latch and at
//! least one with the ideal latch; one named effect hidden at a drawn
//! joint (Coulomb friction, viscous damping or a harness, in turn), raised
//! until it moves the runs by 0.3° RMS or more, and kept only when, before
//! the first switch closing of any physical latch, it moves them by less
//! than 0.04° RMS (twice the sensor's noise): an effect that acts after the
//! first contact. Two runs of the drawing (reference sensor noise). Counted:
//! the effect claimed at its joint within 20 % with nothing else claimed
//! (found); claimed at its joint at all; another kind or joint claimed (a
//! wrong answer); a joint the whole-run check says
//! the model does not follow after the first contact (missed, any joint);
//! and the diagnosis's wall time.
//!
//! ```text
//! cargo run --release -p deploywatch-tests --example after_contact
//! ```
//!
//! `DEPLOYWATCH_CAMPAIGNS=N` sets the number of campaigns (20 by default).
//! The table goes to standard output (as `scripts/measured.py run` records
//! it), a line per campaign to standard error.

use deploywatch_sim::deployment::{self, SimOptions};
use deploywatch_sim::diagnose::diagnose;
use deploywatch_sim::effect::{Effect, EffectKind};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::progress::quiet;
use deploywatch_tests::hidden_effect::{moves_runs_deg, two_runs};
use deploywatch_tests::wing_gen::wing_toml;
use deploywatch_tests::SplitMix;
use std::time::Instant;

/// The kinds drawn in turn.
const KINDS: [EffectKind; 3] = [
    EffectKind::CoulombFriction,
    EffectKind::ViscousDamping,
    EffectKind::HarnessStiffness,
];

/// What the effect must move the runs by over the whole run \[deg\].
const WHOLE_DEG: f64 = 0.3;

/// What it may move them by before the first contact \[deg\]: twice the
/// reference sensor's noise.
const BEFORE_DEG: f64 = 0.04;

/// RMS \[deg\] by which `e` moves the runs of `m` before the first switch
/// closing of any physical latch (in the run without it), every joint.
fn moves_before_contact_deg(m: &Mechanism, physical: &[usize], e: &[Effect]) -> Option<f64> {
    let opts = SimOptions::default();
    let a = deployment::simulate(m, &[], &opts).ok()?;
    let b = deployment::simulate(m, e, &opts).ok()?;
    let first = physical
        .iter()
        .filter_map(|&j| a.latched.get(j - 1)?.iter().position(|&l| l))
        .min()?;
    let n = first.min(b.t_s.len());
    let (mut sse, mut k) = (0.0, 0usize);
    for j in 0..m.joint_count() {
        for i in 0..n {
            sse += (b.phi_deg[j][i] - a.phi_deg[j][i]).powi(2);
            k += 1;
        }
    }
    Some((sse / k.max(1) as f64).sqrt())
}

/// One campaign: the wing, its hidden effect, the first contact's share.
struct Case {
    seed: u64,
    wing: Mechanism,
    joints: usize,
    physical: Vec<usize>,
    truth: Effect,
    before_deg: f64,
}

/// The campaign of `seed`, `kind` hidden, or `None` when the wing or the
/// effect does not qualify.
fn case(seed: u64, kind: EffectKind) -> Option<Case> {
    let w = wing_toml(seed, 0.5);
    if !(4..=6).contains(&w.joints) || w.rig || w.physical.is_empty() {
        return None;
    }
    if w.physical.len() == w.joints || !w.effects.is_empty() {
        return None;
    }
    let wing = Mechanism::from_toml_str(&w.toml, &format!("random-{seed}")).ok()?;
    let mut r = SplitMix(seed ^ 0xaf7e_c047);
    let joint = 1 + ((r.next_f64() * w.joints as f64) as usize).min(w.joints - 1);
    let mut e = Effect::joint(kind, joint, 0.01);
    for _ in 0..40 {
        if moves_runs_deg(&wing, &[e]) >= WHOLE_DEG {
            let before = moves_before_contact_deg(&wing, &w.physical, &[e])?;
            return (before < BEFORE_DEG).then_some(Case {
                seed,
                wing,
                joints: w.joints,
                physical: w.physical,
                truth: e,
                before_deg: before,
            });
        }
        e = e.with_value(e.value() * 1.3);
    }
    None
}

fn main() {
    let want: usize = std::env::var("DEPLOYWATCH_CAMPAIGNS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(20);
    let started = Instant::now();
    let (mut found, mut at_joint, mut other, mut missed, mut kept) = (0, 0, 0, 0, 0);
    let mut walls = Vec::new();
    let mut seed = 9300u64;
    while kept < want && seed < 9300 + 400 * want as u64 {
        seed += 1;
        let kind = KINDS[kept % KINDS.len()];
        let Some(c) = case(seed, kind) else { continue };
        kept += 1;
        let campaign = two_runs(&c.wing, &c.wing, &[c.truth], 1000 + seed);
        let t0 = Instant::now();
        let o = diagnose(&campaign, &deploywatch_tests::diagnose_options(), &quiet);
        let wall = t0.elapsed().as_secs_f64();
        walls.push(wall);
        let claimed = o.extended.effects();
        let here = claimed
            .iter()
            .find(|x| x.kind() == c.truth.kind() && x.joint == c.truth.joint);
        let right = claimed.len() == 1
            && here.is_some_and(|x| (x.value() - c.truth.value()).abs() <= 0.2 * c.truth.value());
        found += usize::from(right);
        at_joint += usize::from(here.is_some());
        other += usize::from(
            claimed
                .iter()
                .any(|x| x.kind() != c.truth.kind() || x.joint != c.truth.joint),
        );
        let miss = o
            .whole_run
            .as_ref()
            .and_then(|w| w.missed())
            .map(|m| m.joint);
        missed += usize::from(miss.is_some());
        let names: Vec<String> = claimed.iter().map(|x| x.to_string()).collect();
        eprintln!(
            "{kept:>3} seed {} ({} joints, physical {:?}): {} (before contact {:.3} deg) -> [{}]{}{} ({wall:.1} s)",
            c.seed,
            c.joints,
            c.physical,
            c.truth,
            c.before_deg,
            names.join(" + "),
            if o.unexplained.is_some() { " + unexplained" } else { "" },
            miss.map_or(String::new(), |j| format!("; joint {j} not followed after contact")),
        );
    }
    walls.sort_by(f64::total_cmp);
    let median = walls.get(walls.len() / 2).copied().unwrap_or(f64::NAN);
    let pct = |k: usize| 100.0 * k as f64 / kept.max(1) as f64;
    println!(
        "Wings of 4–6 joints with mixed latches (seeds 9301 on), one named effect hidden that moves the runs by ≥ {WHOLE_DEG}° RMS and by < {BEFORE_DEG}° before the first latch contact; two runs each.\n"
    );
    println!("| campaigns | found (its joint, within 20 %, nothing else) | its kind claimed at its joint, any value | another kind or joint claimed | a joint not followed after contact | median diagnose |");
    println!("|---|---|---|---|---|---|");
    println!(
        "| {kept} | {found} ({:.0} %) | {at_joint} ({:.0} %) | {other} ({:.0} %) | {missed} ({:.0} %) | {median:.1} s |",
        pct(found),
        pct(at_joint),
        pct(other),
        pct(missed)
    );
    println!(
        "\n{kept} campaigns in {:.0} s (load average {}).",
        started.elapsed().as_secs_f64(),
        std::fs::read_to_string("/proc/loadavg")
            .ok()
            .and_then(|s| s.split_whitespace().next().map(str::to_owned))
            .unwrap_or_else(|| "unknown".into())
    );
}
