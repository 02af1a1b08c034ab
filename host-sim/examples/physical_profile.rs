//! Where a physical-latch deployment's work goes, and why its verdict
//! fails: the draws of `examples/physical_verdicts.rs` (seed 001 T01 with
//! its ball plungers and with its pawls, friction with a 5 % normal
//! dispersion, `--fail not_latched`, crude Monte-Carlo draws of seed 0),
//! each simulated as `reliability` does (`Keep::Ledger`, rtol = atol =
//! 1e-6, one sample at `T`) on one thread.
//!
//! The first table splits the evaluations of the equations of motion of a
//! run (rejected and retaken steps included) at two instants read from its
//! events (`LatchEvent::evaluations`): the first arrival of any joint on its
//! stop, and the instant every latch has been in once (every pawl dropped
//! into its notch, every plunger's crest passed inwards; a plunger may
//! escape again after; a draw where some latch never is counts its rest to
//! the middle column). It gives the mean
//! evaluations, steps, retaken or rejected steps and stop arrivals per
//! deployment, the deployments per core-second (CPU time of the process,
//! `/proc/self/stat`) and the evaluations a deployment could take at the
//! same CPU per evaluation to reach 2,000 deployments per core-second.
//!
//! The second table takes the joints that failed (`not_latched`: switch
//! open at `T`) and says where each ended (`LatchRun::outcome`), whether
//! its travel at `T` is beyond its pawl's notch (`u > u_n`: pressing the
//! notch's wall, the switch opened by that contact's compression), and how
//! many of those draws change their verdict when the same draw is
//! simulated at rtol = atol = 1e-7.
//!
//! `cargo run --release -p deploywatch-sim --example physical_profile -- [DRAWS]`
//! (default 100).

use deploywatch_core::physics::latch_contact::LatchMark;
use deploywatch_sim::deployment::SimOptions;
use deploywatch_sim::latch_deployment::{latches, simulate_with, Keep, LatchEventKind, LatchRun};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::reliability::mc::draw;
use deploywatch_sim::reliability::Problem;
use deploywatch_sim::trajectory::Samples;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// The wings and the 5 % dispersions of their friction [N·m], as
/// `examples/physical_verdicts.rs`.
const WINGS: [(&str, [f64; 3]); 2] = [
    ("seed001_T01_physical_latch", [0.1315, 0.085, 0.00005]),
    ("seed001_T01_pawl", [0.1315, 0.085, 0.00005]),
];

/// Issue 42's target for a physical-latch deployment [per core-second].
const TARGET_PER_CORE_S: f64 = 2000.0;

/// The joints of these wings.
const JOINTS: usize = 3;

#[path = "common/cpu.rs"]
mod cpu;
use cpu::cpu_s;

/// The mechanism and effects of one draw.
fn at(p: &Problem, x: &[f64]) -> (Mechanism, Vec<deploywatch_sim::effect::Effect>) {
    let mut mech = p.mech.clone();
    let mut effects = Vec::new();
    for (v, &x) in p.vary.iter().zip(x) {
        v.apply(x, &mut mech, &mut effects);
    }
    (mech, effects)
}

/// One draw's run at tolerance `tol`, as `Problem::deploy` runs it.
fn deploy(p: &Problem, x: &[f64], tol: f64) -> Result<LatchRun, String> {
    let (mech, effects) = at(p, x);
    let end = [mech.duration_s];
    let opts = SimOptions {
        duration_s: Some(mech.duration_s),
        settle_s: Some(0.0),
        rtol: tol,
        atol: tol,
        ..SimOptions::default()
    };
    simulate_with(&mech, &effects, &opts, Samples::Listed(&end), Keep::Ledger)
        .map_err(|e| e.to_string())
}

/// The joints (from 0) whose `not_latched` failed: switch open at `T`.
fn failed_joints(run: &LatchRun, duration_s: f64) -> Vec<usize> {
    (0..run.traj.latch_s.len())
        .filter(|&j| run.traj.latch_s[j].is_none_or(|t| t >= duration_s))
        .collect()
}

/// Evaluations by the first stop arrival and by the instant every latch is
/// in (`None`: never).
fn split(run: &LatchRun) -> (usize, Option<usize>) {
    let total = run.traj.stats.evaluations;
    let first_impact = run
        .events
        .iter()
        .find(|e| e.kind == LatchEventKind::Mark(LatchMark::Stop) && e.rate_rad_s < 0.0)
        .map_or(total, |e| e.evaluations);
    let is_in = |k: LatchEventKind, rate: f64| {
        k == LatchEventKind::PawlDrop || (k == LatchEventKind::Mark(LatchMark::Crest) && rate < 0.0)
    };
    let firsts: Option<Vec<usize>> = (1..=JOINTS)
        .map(|j| {
            run.events
                .iter()
                .find(|e| e.joint == j && is_in(e.kind, e.rate_rad_s))
                .map(|e| e.evaluations)
        })
        .collect();
    (first_impact, firsts.and_then(|f| f.into_iter().max()))
}

/// The problem of wing `mech`, its friction dispersed by `sd`.
fn problem(mech: Mechanism, sd: [f64; 3]) -> Result<Problem, String> {
    Ok(Problem {
        mech,
        vary: (0..3)
            .map(|j| format!("coulomb_friction:joint={}:normal(0,{})", j + 1, sd[j]).parse())
            .collect::<Result<_, _>>()
            .map_err(|e| format!("{e}"))?,
        fail: vec!["not_latched".parse().map_err(|e| format!("{e}"))?],
        corr: Vec::new(),
        fixed: Vec::new(),
    })
}

/// Sums over the draws of a wing.
#[derive(Default)]
struct Tally {
    evaluations: usize,
    before_impact: usize,
    after_in: usize,
    all_in: usize,
    steps: usize,
    retaken: usize,
    impacts: usize,
    cpu_s: f64,
    /// (joint, where it ended, beyond its notch) → (failed joints, of
    /// their draws, verdicts that differ at 1e-7).
    ends: BTreeMap<(usize, String, bool), (usize, usize)>,
    failed: usize,
    flips: usize,
}

impl Tally {
    /// Adds one draw's run (and its failure classes).
    fn add(&mut self, run: &LatchRun, cpu_s: f64) {
        let total = run.traj.stats.evaluations;
        let (first_impact, all_in) = split(run);
        self.evaluations += total;
        self.before_impact += first_impact;
        if let Some(e) = all_in {
            self.all_in += 1;
            self.after_in += total - e;
        }
        self.steps += run.traj.stats.steps;
        self.retaken += run.traj.stats.rejected;
        self.impacts += run
            .events
            .iter()
            .filter(|e| e.kind == LatchEventKind::Mark(LatchMark::Stop) && e.rate_rad_s < 0.0)
            .count();
        self.cpu_s += cpu_s;
    }
}

/// Runs the draws of one wing; returns its tally.
fn wing(p: &Problem, draws: u64) -> Result<Tally, String> {
    let duration = p.mech.duration_s;
    let mut tally = Tally::default();
    for i in 0..draws {
        let x = p.x_of(&draw(0, 0, i, 3));
        let t0 = cpu_s();
        let run = deploy(p, &x, 1e-6)?;
        tally.add(&run, cpu_s() - t0);
        let failed = failed_joints(&run, duration);
        if failed.is_empty() {
            continue;
        }
        let tighter = deploy(p, &x, 1e-7)?;
        let flip = failed_joints(&tighter, duration).is_empty();
        tally.failed += 1;
        tally.flips += usize::from(flip);
        let (mech, effects) = at(p, &x);
        let ls = latches::<JOINTS>(&mech, &effects);
        for j in failed {
            let Some(l) = &ls[j] else { continue };
            let Some(o) = run.outcome(j + 1, l) else {
                continue;
            };
            let beyond = l.pawl().is_some() && o.end_travel_deg.to_radians() > l.plunger.crest_rad;
            let e = tally
                .ends
                .entry((j + 1, o.end.to_string(), beyond))
                .or_default();
            e.0 += 1;
            e.1 += usize::from(flip);
        }
    }
    Ok(tally)
}

fn main() -> Result<(), String> {
    let draws: u64 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(100);
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    let load: Vec<&str> = load.split_whitespace().take(3).collect();
    println!(
        "{draws} draws a wing (seed 0), one thread; load average at the start {}.\n",
        load.join(", ")
    );
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../data/mechanisms");
    let mut tallies = Vec::new();
    for (name, sd) in WINGS {
        let mech =
            Mechanism::load(&root.join(format!("{name}.toml"))).map_err(|e| e.to_string())?;
        tallies.push((name, wing(&problem(mech, sd)?, draws)?));
    }
    println!("| wing | evaluations | before the first stop arrival | until every latch was first in | after (draws where every latch was in) | steps | retaken or rejected | stop arrivals | per core-second | evaluations a deployment may take for 2,000 per core-second at this CPU per evaluation |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let n = draws as f64;
    for (name, t) in &tallies {
        let share = |x: usize| 100.0 * x as f64 / t.evaluations.max(1) as f64;
        let middle = t.evaluations - t.before_impact - t.after_in;
        println!(
            "| {name} | {:.0} | {:.1} % | {:.1} % | {:.1} % ({}) | {:.0} | {:.0} | {:.1} | {:.1} | {:.0} |",
            t.evaluations as f64 / n,
            share(t.before_impact),
            share(middle),
            share(t.after_in),
            t.all_in,
            t.steps as f64 / n,
            t.retaken as f64 / n,
            t.impacts as f64 / n,
            n / t.cpu_s.max(1e-9),
            t.evaluations as f64 / t.cpu_s.max(1e-9) / TARGET_PER_CORE_S,
        );
    }
    println!("\n| wing | draws failed | of them, verdict differs at 1e-7 | failed joint | where it ended | beyond its notch at `T` | joints | of their draws, verdict differs at 1e-7 |");
    println!("|---|---|---|---|---|---|---|---|");
    for (name, t) in &tallies {
        for ((j, end, beyond), (count, flips)) in &t.ends {
            println!(
                "| {name} | {} | {} | {j} | {end} | {} | {count} | {flips} |",
                t.failed,
                t.flips,
                if *beyond { "yes" } else { "no" }
            );
        }
    }
    Ok(())
}
