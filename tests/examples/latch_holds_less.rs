//! A latch that holds less than drawn, where that plainly changes the runs
//! (`deploywatch_tests::holds_less`: one joint's plunger, magnet or both at
//! 15–50 % of the drawing, every latch as built, kept where the joint's
//! escapes over the campaign exceed those of every one of 40 as-built
//! draws of the drawing, and of the same latches without the weakening, by
//! more than one, or fewer of its runs end held than in any of them, each
//! count as the measured runs show it): how often `diagnose` names that joint's latch as holding less
//! than drawn, how often it says the runs cannot tell it from the drawing,
//! and how often it names a latch at another joint or an effect. It also
//! counts the weakenings drawn that do not plainly change the runs (their
//! events within the drawing's own spread, where no method can tell them
//! from two runs). Prints a line per campaign; records its section of
//! `docs/measured.md` with `DEPLOYWATCH_FULL=1`:
//!
//! ```text
//! DEPLOYWATCH_FULL=1 cargo run --release -p deploywatch-tests --example latch_holds_less
//! ```
//!
//! `DEPLOYWATCH_CAMPAIGNS` sets how many campaigns are kept (default 24).

use deploywatch_sim::campaign::Campaign;
use deploywatch_sim::deployment::SimOptions;
use deploywatch_sim::diagnose::{diagnose, LatchCause, Outcome};
use deploywatch_sim::progress::quiet;
use deploywatch_tests::holds_less::{self, HoldsLess, SPREAD_DRAWS};
use std::path::Path;

/// What the diagnosis said of one campaign.
#[derive(Default)]
struct Said {
    named: bool,
    undecided: bool,
    elsewhere: bool,
    effect: bool,
}

fn said(o: &Outcome, c: &HoldsLess) -> Said {
    Said {
        named: o
            .latches
            .iter()
            .any(|l| l.joint == c.joint && l.cause == Some(LatchCause::HoldsLess)),
        undecided: o
            .latches
            .iter()
            .any(|l| l.joint == c.joint && l.cause.is_none() && !l.undecided.is_empty()),
        elsewhere: o
            .latches
            .iter()
            .any(|l| l.joint != c.joint && !l.differs.is_empty()),
        effect: !o.extended.effects().is_empty() || o.unexplained.is_some(),
    }
}

fn main() {
    let want: usize = std::env::var("DEPLOYWATCH_CAMPAIGNS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(24);
    let opts = SimOptions::default();
    let (mut kept, mut drawn, mut named, mut undecided, mut elsewhere, mut effects) =
        (0, 0, 0, 0, 0, 0);
    let mut rows = Vec::new();
    let mut seed = 7700u64;
    while kept < want && seed < 7700 + 100 * want as u64 {
        seed += 1;
        drawn += 1;
        let Some(c) = holds_less::generate(seed, (seed % 2) as usize, &opts) else {
            continue;
        };
        kept += 1;
        let mut campaign = Campaign::default();
        for (r, run) in c.runs.iter().enumerate() {
            campaign
                .push(&c.drawings, run.clone(), Path::new(&format!("run{r}.csv")))
                .expect("a generated run pairs with its drawing");
        }
        let o = diagnose(&campaign, &deploywatch_tests::diagnose_options(), &quiet);
        let s = said(&o, &c);
        named += usize::from(s.named);
        undecided += usize::from(s.undecided);
        elsewhere += usize::from(s.elsewhere);
        effects += usize::from(s.effect);
        let sp = c.spread;
        let line = format!(
            "| {seed} | {:?} at {:.0} % at joint {} | {}..{}, {}..{} | {} → {}{}, ends held in {} | {} | {} |",
            c.what,
            100.0 * c.strength,
            c.joint,
            sp.escapes[0],
            sp.escapes[1],
            sp.held[0],
            sp.held[1],
            c.escapes.0,
            c.escapes.1,
            if c.opened { " (ends off its latch in a run)" } else { "" },
            c.held,
            match (s.named, s.undecided) {
                (true, _) => "named",
                (false, true) => "cannot tell",
                (false, false) => "as the drawing",
            },
            if s.elsewhere { "yes" } else { "no" },
        );
        println!("{line}");
        rows.push(line);
    }
    let body = format!(
        "## Diagnosis: a latch that holds less than drawn\n\n\
         `tests/examples/latch_holds_less.rs` (`docs/diagnosis.md`, \"Runs of a physical latch\"): \
         one joint's plunger, magnet or both at 15–50 % of the drawing, every latch as built, \
         kept where that plainly changes the runs: the joint's escapes over the campaign beyond \
         those of every one of {SPREAD_DRAWS} as-built draws of the drawing, and of the same latches \
         without the weakening, by more than one (a count read at the encoder's resolution moves by \
         one), or fewer of its runs ending held than in any of them, each count as the measured runs show it (the \
         reference sensor's noise decides whether a rebound that stalls at the crest reads as \
         an escape). Of {drawn} weakenings drawn (seeds \
         7701–{seed}), {kept} are kept; the others leave the joint's events within the drawing's \
         own spread or one escape beyond it (or are draws the simulator refused), where two runs \
         cannot tell them from the drawing's tolerances. \
         **Named at its joint in {named} of {kept}**; the runs said not to tell it from the \
         drawing in {undecided}; a latch at another joint in {elsewhere}; an effect or \
         `unexplained` in {effects}.\n\n\
         | seed | latch | drawing, {SPREAD_DRAWS} draws and the same latches unweakened: escapes, ends held | escapes without → with the weakening | its joint | another joint |\n\
         |---|---|---|---|---|---|\n{}\n",
        rows.join("\n")
    );
    deploywatch_tests::record::record(
        "diagnosis-latch-holds-less",
        "DEPLOYWATCH_FULL=1 cargo run --release -p deploywatch-tests --example latch_holds_less",
        &body,
    )
    .expect("docs/measured.md written");
}
