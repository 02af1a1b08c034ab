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
//! first contact. Two runs of the drawing (reference sensor noise).
//!
//! Two rows, one per rule of drawing:
//! - **every draw**: as above;
//! - **same latch history**: only draws where each joint's switch closes
//!   as many times with the effect as without it. Where the counts differ,
//!   the effect changed which impacts happen (a rebound more or less at a
//!   plunger), and the 0.3° is that split of the runs, not the effect's
//!   torque: any other small change (a restitution, a latch within its
//!   tolerances) splits them the same way, and no diagnosis can name its
//!   cause. The row gives how many draws were left out so.
//!
//! Counted in each row: the effect claimed at its joint within 20 % with
//! nothing else claimed (found); claimed at its joint at all; another kind
//! or joint claimed (a wrong answer); a joint the whole-run check says the
//! model does not follow after the first contact (missed, any joint); no
//! shot of that check after the first contact (every stretch after it has
//! a joint in a contact transient: a pawl within its reach, a plunger
//! rattling); the campaigns fitted on the whole runs (the model closes
//! each switch as often as the runs do: "Runs of a physical latch", 5);
//! the campaigns fitted on each run up to where the model stops following
//! it (beyond the free motion: "Runs of a physical latch", 6); and the
//! diagnosis's wall time.
//!
//! ```text
//! cargo run --release -p deploywatch-tests --example after_contact
//! ```
//!
//! `DEPLOYWATCH_CAMPAIGNS=N` sets the number of campaigns of each row (20
//! by default). The table goes to standard output (as `scripts/measured.py
//! run` records it), a line per campaign to standard error.

use deploywatch_sim::diagnose::diagnose;
use deploywatch_sim::effect::EffectKind;
use deploywatch_sim::progress::quiet;
use deploywatch_tests::after_contact::{case, Case, BEFORE_DEG, WHOLE_DEG};
use deploywatch_tests::hidden_effect::two_runs;
use std::time::Instant;

/// The kinds drawn in turn.
const KINDS: [EffectKind; 3] = [
    EffectKind::CoulombFriction,
    EffectKind::ViscousDamping,
    EffectKind::HarnessStiffness,
];

/// What one row counted.
#[derive(Default)]
struct Row {
    kept: usize,
    found: usize,
    at_joint: usize,
    other: usize,
    missed: usize,
    /// Campaigns with no shot after the first contact.
    no_shot: usize,
    /// Campaigns fitted on the whole runs.
    whole: usize,
    /// Campaigns fitted up to where the model follows the runs.
    to_horizon: usize,
    /// Draws left out because the effect changed the latch history.
    split: usize,
    walls: Vec<f64>,
}

impl Row {
    /// Diagnoses case `c` (the row's `kept`-th) and counts it.
    fn count(&mut self, c: &Case) {
        self.kept += 1;
        let campaign = two_runs(&c.wing, &c.wing, &[c.truth], 1000 + c.seed);
        let t0 = Instant::now();
        let o = diagnose(&campaign, &deploywatch_tests::diagnose_options(), &quiet);
        let wall = t0.elapsed().as_secs_f64();
        self.walls.push(wall);
        let claimed = o.extended.effects();
        let here = claimed
            .iter()
            .find(|x| x.kind() == c.truth.kind() && x.joint == c.truth.joint);
        let right = claimed.len() == 1
            && here.is_some_and(|x| (x.value() - c.truth.value()).abs() <= 0.2 * c.truth.value());
        self.found += usize::from(right);
        self.at_joint += usize::from(here.is_some());
        self.other += usize::from(
            claimed
                .iter()
                .any(|x| x.kind() != c.truth.kind() || x.joint != c.truth.joint),
        );
        let miss = o
            .whole_run
            .as_ref()
            .and_then(|w| w.missed())
            .map(|m| m.joint);
        self.missed += usize::from(miss.is_some());
        self.no_shot += usize::from(o.whole_run.as_ref().is_none_or(|w| w.shots.is_empty()));
        self.whole += usize::from(o.fitted_whole);
        self.to_horizon += usize::from(o.fitted_to.is_some());
        let names: Vec<String> = claimed.iter().map(|x| x.to_string()).collect();
        eprintln!(
            "{:>3} seed {} ({} joints, physical {:?}): {} (before contact {:.3} deg) -> [{}]{}{}{}{} ({wall:.1} s)",
            self.kept,
            c.seed,
            c.joints,
            c.physical,
            c.truth,
            c.before_deg,
            names.join(" + "),
            if o.unexplained.is_some() { " + unexplained" } else { "" },
            if o.fitted_whole { ", fitted whole" } else { "" },
            if o.fitted_to.is_some() { ", fitted up to where the model follows the runs" } else { "" },
            miss.map_or(String::new(), |j| format!("; joint {j} not followed after contact")),
        );
    }

    /// The row's line of the table.
    fn line(&self, rule: &str) -> String {
        let mut w = self.walls.clone();
        w.sort_by(f64::total_cmp);
        let median = w.get(w.len() / 2).copied().unwrap_or(f64::NAN);
        let pct = |k: usize| 100.0 * k as f64 / self.kept.max(1) as f64;
        format!(
            "| {rule} | {} | {} | {} ({:.0} %) | {} ({:.0} %) | {} ({:.0} %) | {} ({:.0} %) | {} ({:.0} %) | {} ({:.0} %) | {} ({:.0} %) | {median:.1} s |",
            self.kept,
            self.split,
            self.found,
            pct(self.found),
            self.at_joint,
            pct(self.at_joint),
            self.other,
            pct(self.other),
            self.missed,
            pct(self.missed),
            self.no_shot,
            pct(self.no_shot),
            self.whole,
            pct(self.whole),
            self.to_horizon,
            pct(self.to_horizon),
        )
    }
}

/// The first `want` campaigns from seed 9301 on, every draw when `same`
/// is false, else only those of the same latch history.
fn row(want: usize, same: bool) -> Row {
    let mut r = Row::default();
    let mut seed = 9300u64;
    eprintln!(
        "{}",
        if same {
            "same latch history:"
        } else {
            "every draw:"
        }
    );
    while r.kept < want && seed < 9300 + 400 * want as u64 {
        seed += 1;
        let kind = KINDS[(r.kept + r.split) % KINDS.len()];
        let Some(c) = case(seed, kind) else { continue };
        if same && !c.same_history {
            r.split += 1;
            continue;
        }
        r.count(&c);
    }
    r
}

fn main() {
    let want: usize = std::env::var("DEPLOYWATCH_CAMPAIGNS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(20);
    let started = Instant::now();
    let every = row(want, false);
    let same = row(want, true);
    println!(
        "Wings of 4–6 joints with mixed latches (seeds 9301 on), one named effect hidden that moves the runs by ≥ {WHOLE_DEG}° RMS and by < {BEFORE_DEG}° before the first latch contact; two runs each.\n"
    );
    println!("| draws | campaigns | left out: the effect changed the latch history | found (its joint, within 20 %, nothing else) | its kind claimed at its joint, any value | another kind or joint claimed | a joint not followed after contact | no shot after the first contact | fitted on the whole runs | fitted up to where the model follows the runs | median diagnose |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    println!("{}", every.line("every draw"));
    println!("{}", same.line("same latch history"));
    println!(
        "\n{} campaigns in {:.0} s (load average {}).",
        every.kept + same.kept,
        started.elapsed().as_secs_f64(),
        std::fs::read_to_string("/proc/loadavg")
            .ok()
            .and_then(|s| s.split_whitespace().next().map(str::to_owned))
            .unwrap_or_else(|| "unknown".into())
    );
}
