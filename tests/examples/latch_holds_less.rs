//! A latch that holds less than drawn, where that plainly changes the runs
//! (`deploywatch_tests::holds_less`: one joint's plunger, magnet or both at
//! 15–50 % of the drawing, kept where, against the same as-built latches
//! without the weakening, the joint ends off its latch in a run or its
//! escapes double): how often `diagnose` names that joint's latch as
//! holding less than drawn, and where the joint's measured events fall in
//! the spread of the drawing itself over 40 as-built draws within its
//! tolerances (what two runs can tell: a count inside that spread is one
//! the drawing gives too). Prints a line per campaign; records its section
//! of `docs/measured.md` with `DEPLOYWATCH_FULL=1`:
//!
//! ```text
//! DEPLOYWATCH_FULL=1 cargo run --release -p deploywatch-tests --example latch_holds_less
//! ```
//!
//! `DEPLOYWATCH_CAMPAIGNS` sets how many campaigns are kept (default 24).

use deploywatch_sim::campaign::Campaign;
use deploywatch_sim::deployment::{self, SimOptions};
use deploywatch_sim::diagnose::{diagnose, LatchCause};
use deploywatch_sim::progress::quiet;
use deploywatch_tests::holds_less::{self, as_built, escapes_and_end, HoldsLess};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use std::path::Path;

/// As-built draws of the drawing whose spread the measured events are
/// placed in.
const DRAWS: u64 = 40;

/// The drawing's escapes and runs ending held at joint `j` (0-based) over
/// the campaign, for each of [`DRAWS`] as-built draws (noise-free).
fn spread(c: &HoldsLess, opts: &SimOptions) -> Vec<(usize, usize)> {
    (0..DRAWS)
        .into_par_iter()
        .filter_map(|k| {
            let mut rng = ChaCha8Rng::seed_from_u64(0x5eed_0000 + k);
            let mut uniform = || rng.gen::<f64>();
            let built = as_built(&c.drawings, &mut uniform);
            let (mut e, mut h) = (0, 0);
            for m in &built {
                let t = deployment::simulate(m, &[], opts).ok()?;
                let (a, b) = escapes_and_end(m, &t, c.joint - 1);
                e += a;
                h += usize::from(b);
            }
            Some((e, h))
        })
        .collect()
}

fn main() {
    let want: usize = std::env::var("DEPLOYWATCH_CAMPAIGNS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(24);
    let opts = SimOptions::default();
    let (mut kept, mut named, mut elsewhere, mut effects, mut inside) = (0, 0, 0, 0, 0);
    let mut rows = Vec::new();
    let mut seed = 7700u64;
    while kept < want && seed < 7700 + 100 * want as u64 {
        seed += 1;
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
        let here = o
            .latches
            .iter()
            .any(|l| l.joint == c.joint && l.cause == Some(LatchCause::HoldsLess));
        let other = o
            .latches
            .iter()
            .any(|l| l.joint != c.joint && !l.differs.is_empty());
        named += usize::from(here);
        elsewhere += usize::from(other);
        effects += usize::from(!o.extended.effects().is_empty() || o.unexplained.is_some());
        // Where the measured events fall among the drawing's: the runs'
        // own count, from their samples.
        let (mut esc, mut held) = (0, 0);
        for (m, run) in c.drawings.iter().zip(&c.runs) {
            let t = deploywatch_sim::deployment::Trajectory {
                phi_deg: run.phi_deg.clone(),
                latched: run.latch.clone(),
                ..deployment::simulate(m, &[], &opts).expect("the drawing runs")
            };
            let (e, h) = escapes_and_end(m, &t, c.joint - 1);
            esc += e;
            held += usize::from(h);
        }
        let s = spread(&c, &opts);
        let (lo_e, hi_e) = (s.iter().map(|x| x.0).min(), s.iter().map(|x| x.0).max());
        let (lo_h, hi_h) = (s.iter().map(|x| x.1).min(), s.iter().map(|x| x.1).max());
        let within = lo_e.is_some_and(|lo| esc >= lo)
            && hi_e.is_some_and(|hi| esc <= hi)
            && lo_h.is_some_and(|lo| held >= lo);
        inside += usize::from(within);
        let line = format!(
            "| {seed} | {:?} at {:.0} % at joint {} | {} → {}{} | {esc}, ends held in {held} | {}..{}, {}..{} | {} | {} |",
            c.what,
            100.0 * c.strength,
            c.joint,
            c.escapes.0,
            c.escapes.1,
            if c.opened { ", ends off its latch in a run" } else { "" },
            lo_e.unwrap_or(0),
            hi_e.unwrap_or(0),
            lo_h.unwrap_or(0),
            hi_h.unwrap_or(0),
            if here { "named" } else { "not named" },
            if other { "yes" } else { "no" },
        );
        println!("{line}");
        rows.push(line);
    }
    let body = format!(
        "## Diagnosis: a latch that holds less than drawn\n\n\
         `tests/examples/latch_holds_less.rs` (`docs/diagnosis.md`, \"Runs of a physical latch\"): \
         one joint's plunger, magnet or both at 15–50 % of the drawing, every latch as built, \
         kept where that plainly changes the runs against the same latches without the \
         weakening (ends off its latch in a run, or its escapes double): {kept} campaigns of \
         seeds 7701–{seed}. **Named at its joint in {named} of {kept}**; a latch at another joint \
         in {elsewhere}; an effect named in {effects}. The joint's measured escapes and runs \
         ending held lie within the drawing's own spread over {DRAWS} as-built draws in \
         {inside} of {kept}: there two runs cannot tell the weaker latch from the drawing's \
         tolerances.\n\n\
         | seed | latch | escapes without → with | measured | drawing, {DRAWS} draws: escapes, ends held | its joint | another joint |\n\
         |---|---|---|---|---|---|---|\n{}\n",
        rows.join("\n")
    );
    deploywatch_tests::record::record(
        "diagnosis-latch-holds-less",
        "DEPLOYWATCH_FULL=1 cargo run --release -p deploywatch-tests --example latch_holds_less",
        &body,
    )
    .expect("docs/measured.md written");
}
