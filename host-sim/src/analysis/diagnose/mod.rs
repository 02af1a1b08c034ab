//! Diagnosis: what the simulation gets wrong, and which named effect of
//! `docs/spec/physics.md` section 6 explains it.
//!
//! Method (details and rationale in `docs/diagnosis.md`):
//! 1. Baseline: the mechanisms as given, residuals per run and joint.
//! 2. Noise floor σ̂ estimated from the data alone (third differences).
//! 3. Candidates: every effect, per joint where it has one. Each is fitted to
//!    all runs at once: a coarse scan for a start, then Levenberg–Marquardt
//!    ([`crate::analysis::fit`]); candidates are fitted in parallel.
//! 4. Stepwise selection: a loop over the moves of [`policy::STEPWISE`]
//!    (an addition; when none passes, a pair fitted jointly; then a swap,
//!    and a swap for a pair; the named pairs the residual torque proposes
//!    and those at a joint), each judged by the one acceptance policy
//!    ([`policy`]: BIC better by more than [`MIN_DELTA_BIC`], every added
//!    effect's 95 % interval excludes zero, and, with two or more runs, the
//!    held-out RMS of the resulting set — fit on all runs but one, predict
//!    that one — improves), which returns a typed [`policy::Verdict`]; effects that
//!    no longer earn their keep are dropped again ([`Move::Drop`], judged
//!    by the same rule). At most three named effects; stop at the noise
//!    floor 1.2 σ̂ (σ̂ estimated once and carried). Each proposed set
//!    carries the start values of its screen; the settings come in through
//!    [`DiagnoseOptions`].
//! 5. Discovery ([`discover`]): when the named effects leave a residual
//!    above the noise floor, a `torque_table` fitted at each joint is judged
//!    like any candidate; a named effect that fits as well replaces it.
//! 6. A clear residual that nothing explains is reported as `unexplained`
//!    (how large, which joint, which part of the stroke), never forced onto
//!    a name. Where a global effect stands in for a joint torque, a table
//!    at that joint in its place is tried first (`stand_in`).
//! 7. Claims within the discrepancy ([`discrepancy`]): while the set found
//!    stays clearly above the noise, a claim that accounts for less than
//!    the residual the set leaves above the noise is set aside
//!    ([`Move::SetAside`]) and reported as such.
//! 8. The drawing's declared tolerances of mass, inertia and spring torque:
//!    a named effect they alone could make is taken out, and they widen the
//!    reported intervals by what they move the estimates ([`tolerance`]).

pub mod ambiguity;
mod candidate;
pub mod discover;
mod discrepancy;
pub mod encoder_delay;
pub mod evidence;
mod evidence_search;
pub mod free_play;
mod friction_forms;
mod halt;
pub mod latch_finding;
pub mod latch_window;
mod moves;
mod outcome;
pub mod panel_mode;
mod policy;
mod refine;
pub mod residual_named;
pub mod residual_shape;
pub mod residual_torque;
mod restart;
mod screen;
mod shared_torque;
pub mod smoothing;
mod stand_in;
mod step;
pub mod table_export;
mod table_form;
pub mod tolerance;
pub mod whole_fit;
pub mod whole_run;

pub use candidate::Candidate;
use candidate::{effects_of, labels, ParamBound};
pub use outcome::{
    DiagnoseOptions, FitStats, FittedEffect, FittedSet, FreePlayOffset, HaltReason, Outcome,
    PanelMode, Round, SeparatingTest, SetAside, StopFlag, ToleranceShare, Unexplained,
    UnexplainedShape, WithinTolerance,
};
pub use policy::{Kept, Move, Rejection, Verdict, MIN_DELTA_BIC};

use crate::analysis::campaign_sim::CampaignSim;
use crate::analysis::fit::{self, FitOptions};
use crate::data::campaign::{Campaign, CampaignRun};
use crate::model::effect::EffectKind;
use crate::report::progress::Progress;
use evidence::noise_sigma_deg;
use halt::Halt;
use rayon::prelude::*;
use std::time::Instant;

/// The residual is "down to the sensor noise" below this multiple of σ̂.
pub const NOISE_FLOOR_FACTOR: f64 = 1.2;

/// A residual is "clearly above the noise" beyond this multiple of σ̂ \[1\]
/// (and beyond [`ABOVE_NOISE_MARGIN_DEG`] over σ̂).
pub const ABOVE_NOISE_FACTOR: f64 = 1.5;

/// A residual clearly above the noise also exceeds σ̂ by this \[deg\] (the encoder's step, 0.022°,
/// rounded down: below it a residual is quantisation).
pub const ABOVE_NOISE_MARGIN_DEG: f64 = 0.01;

/// Levenberg–Marquardt iterations without progress before a fit stops
/// ([`FitOptions::patience`]).
const FIT_PATIENCE: usize = 12;

/// How many candidates of a round, best by their coarse scan, are fitted
/// fully (the others keep their scan score).
pub const SCREEN_KEEP: usize = 8;

struct Engine<'a> {
    campaign: &'a Campaign,
    progress: Progress<'a>,
    sims: std::sync::atomic::AtomicUsize,
    /// When and on what the search stops early ([`Halt`]).
    halt: Halt,
    /// What the progress traces beside its usual lines
    /// ([`DiagnoseOptions::trace`], [`DiagnoseOptions::trace_forms`]).
    trace: Trace,
}

/// What the progress traces beside its usual lines (the search's
/// settings, from [`DiagnoseOptions`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Trace {
    /// Every score of a round and the verdicts of the first judged.
    scores: bool,
    /// The friction forms' residual-torque evidence, on stderr.
    forms: bool,
}

impl Engine<'_> {
    fn say(&self, msg: impl AsRef<str>) {
        (self.progress)(msg.as_ref());
    }

    fn residuals(&self, c: &Campaign, set: &[Candidate], p: &[f64]) -> Option<Vec<f64>> {
        if self.halt.now() {
            return None;
        }
        self.sims.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        c.residual_vector(&effects_of(set, p))
    }

    fn sse(&self, c: &Campaign, set: &[Candidate], p: &[f64]) -> Option<(f64, usize)> {
        let r = self.residuals(c, set, p)?;
        Some((r.iter().map(|x| x * x).sum(), r.len()))
    }

    /// Fits `set` on campaign `c`, starting from `p0`.
    fn fit(&self, c: &Campaign, set: &[Candidate], p0: &[f64]) -> Option<FittedSet> {
        if set.is_empty() {
            let (sse, m) = self.sse(c, set, &[])?;
            return Some(FittedSet {
                members: Vec::new(),
                stats: Some(FitStats {
                    sse,
                    m,
                    evaluations: 1,
                }),
            });
        }
        let b: Vec<ParamBound> = set.iter().flat_map(|c| c.bounds()).collect();
        let opts = FitOptions {
            lower: b.iter().map(|x| x.lower).collect(),
            upper: b.iter().map(|x| x.upper).collect(),
            min_step: b.iter().map(|x| x.min_step).collect(),
            patience: FIT_PATIENCE,
        };
        let model = |p: &[f64]| self.residuals(c, set, p);
        let model = fit::InSeries {
            model: &model,
            lengths: c.series_lengths(),
        };
        let r = fit::least_squares(&model, p0, &opts).ok()?;
        let stats = FitStats {
            sse: r.sse,
            m: r.residuals,
            evaluations: r.evaluations,
        };
        Some(
            FittedSet::from_flat(set, &r.params, Some(&r.ci95), Some(stats))
                .with_search_intervals(&r.ci95_ols),
        )
    }

    /// Refits `start` on campaign `c` from its parameters.
    fn refit(&self, c: &Campaign, start: &FittedSet) -> Option<FittedSet> {
        self.fit(c, &start.candidates(), &start.params())
    }

    /// SSE and number of residuals of `f` at its parameters on `c`.
    fn sse_of(&self, c: &Campaign, f: &FittedSet) -> Option<(f64, usize)> {
        self.sse(c, &f.candidates(), &f.params())
    }

    /// Held-out RMS \[deg\] of a set: fit on all runs but one (from the
    /// all-run parameters), predict the one left out; pooled over folds.
    fn held_out(&self, fitted: &FittedSet) -> Option<f64> {
        let n = self.campaign.runs.len();
        if n < 2 {
            return None;
        }
        let folds: Vec<Option<(f64, usize)>> = (0..n)
            .into_par_iter()
            .map(|k| {
                let train = sub_campaign(self.campaign, |i| i != k);
                let test = sub_campaign(self.campaign, |i| i == k);
                let p = if fitted.members.is_empty() {
                    Vec::new()
                } else {
                    self.refit(&train, fitted)?.params()
                };
                self.sse(&test, &fitted.candidates(), &p)
            })
            .collect();
        let (mut sse, mut m) = (0.0, 0usize);
        for f in folds {
            let (s, k) = f?;
            sse += s;
            m += k;
        }
        Some((sse / m.max(1) as f64).sqrt())
    }
}

impl Search<'_, '_> {
    /// Drops effects that no longer earn their keep beside the others: the
    /// best set without one of them, by BIC, judged by [`Search::accept`]
    /// against `f` (held-out RMS `held`) with [`Move::Drop`]'s policy,
    /// until none is taken.
    fn backward(&self, mut f: FittedSet, mut held: Option<f64>) -> (FittedSet, Option<f64>) {
        let eng = self.eng;
        while f.members.len() > 1 {
            let reduced: Vec<Option<FittedSet>> = (0..f.members.len())
                .into_par_iter()
                .map(|k| eng.refit(eng.campaign, &f.without(k)))
                .collect();
            let best = reduced
                .into_iter()
                .flatten()
                .min_by(|a, b| a.bic().total_cmp(&b.bic()));
            let Some(r) = best else { break };
            let verdict = self.accept((&f, held), &r, &mut None, &Move::Drop.policy());
            if !matches!(verdict, Verdict::Accepted(_)) {
                break;
            }
            let gone: Vec<String> = f
                .candidates()
                .iter()
                .filter(|c| !r.contains(c))
                .map(|c| c.words())
                .collect();
            eng.say(format!(
                "  dropped {}: no longer earns its keep",
                gone.join(", ")
            ));
            held = eng.held_out(&r);
            f = r;
        }
        (f, held)
    }
}

fn sub_campaign(c: &Campaign, keep: impl Fn(usize) -> bool) -> Campaign {
    Campaign {
        runs: c
            .runs
            .iter()
            .enumerate()
            .filter(|(i, _)| keep(*i))
            .map(|(_, r)| r.clone())
            .collect::<Vec<CampaignRun>>(),
        notes: c.notes.clone(),
    }
}

/// How many of a round's best single candidates seed pair moves.
pub const PAIR_SEEDS: usize = 4;

/// Most search steps (additions, pair additions and swaps) of one diagnosis.
const MAX_STEPS: usize = 10;

/// Most discovered torque tables of one diagnosis.
pub const MAX_TABLES: usize = 2;

/// Most swap rounds of one diagnosis.
const MAX_SWAPS: usize = 2;

/// The sets a move proposes, each a base set plus a candidate with the
/// start values of its screen ([`step::Step`]).
type Proposal = Vec<step::Step>;

/// The state of the search: the current set, its held-out RMS, the noise
/// σ̂ it was judged against, the rounds tried so far and the sets already
/// visited.
struct Search<'e, 'a> {
    eng: &'e Engine<'a>,
    candidates: Vec<Candidate>,
    max_effects: usize,
    /// The noise σ̂ of the runs \[deg\], estimated once
    /// ([`evidence::noise_sigma_deg`]).
    sigma: f64,
    current: FittedSet,
    current_held: Option<f64>,
    rounds: Vec<Round>,
    seen: Vec<Vec<Candidate>>,
    swaps: usize,
    /// The moves tried once per diagnosis that were
    /// ([`Search::first_time`]).
    tried_once: std::collections::HashSet<Move>,
    /// The table moves of the last [`Move::Table`] (the even tables
    /// are tried after them only when they add some).
    table_tried: Vec<step::Step>,
}

impl Search<'_, '_> {
    /// The noise floor \[deg\]: [`NOISE_FLOOR_FACTOR`] σ̂.
    fn floor(&self) -> f64 {
        NOISE_FLOOR_FACTOR * self.sigma
    }
}

impl Engine<'_> {
    /// The baseline: the mechanisms as given, no effect (without
    /// statistics when they cannot be simulated).
    fn baseline(&self) -> FittedSet {
        // Scored whatever the time limit: every report is read against it.
        self.sims.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let stats = self.campaign.residual_vector(&[]).map(|r| FitStats {
            sse: r.iter().map(|x| x * x).sum(),
            m: r.len(),
            evaluations: 1,
        });
        let members = Vec::new();
        FittedSet { members, stats }
    }

    /// The set reordered strongest first, with each effect's strength: the
    /// RMS \[deg\] of the set without it (the others' values kept).
    fn strongest_first(&self, current: &FittedSet) -> (FittedSet, Vec<f64>) {
        let strength: Vec<f64> = (0..current.members.len())
            .map(|k| {
                self.sse_of(self.campaign, &current.without(k))
                    .map(|(s, m)| (s / m.max(1) as f64).sqrt())
                    .unwrap_or(f64::INFINITY)
            })
            .collect();
        let mut order: Vec<usize> = (0..current.members.len()).collect();
        order.sort_by(|&a, &b| strength[b].total_cmp(&strength[a]));
        let extended = FittedSet {
            members: order.iter().map(|&i| current.members[i].clone()).collect(),
            stats: current.stats,
        };
        (extended, order.iter().map(|&i| strength[i]).collect())
    }
}

/// True when the residual of a set stays clearly above the noise floor σ̂
/// \[deg\]: above [`ABOVE_NOISE_FACTOR`] σ̂ and above σ̂ +
/// [`ABOVE_NOISE_MARGIN_DEG`].
fn above_noise(f: &FittedSet, sigma: f64) -> bool {
    let rms = f.rms();
    rms > ABOVE_NOISE_FACTOR * sigma.max(1e-6) && rms > sigma + ABOVE_NOISE_MARGIN_DEG
}

/// The `unexplained` residual when it stays clearly above the noise floor:
/// how large, at which joint and where in the stroke.
fn unexplained_above_noise(
    campaign: &Campaign,
    extended: &FittedSet,
    sigma: f64,
) -> Option<Unexplained> {
    if !above_noise(extended, sigma) {
        return None;
    }
    Some(Unexplained {
        rms_deg: extended.rms(),
        noise_sigma_deg: sigma,
        shape: UnexplainedShape::AboveNoise {
            largest_at: evidence::locate(&evidence::analyse(campaign, &extended.effects(), sigma)),
        },
    })
}

/// Diagnoses a campaign: baseline, noise floor, stepwise search
/// ([`Search`]), then the effects strongest first, the sets that explain
/// the runs alike ([`ambiguity`]) and what stays unexplained. Runs of a
/// physical latch are fitted on their free motion ([`latch_window`]) and
/// their latch events compared by their statistics ([`latch_finding`]).
/// Encoders late on their latch switches are compared with the model at
/// their stamps minus the delay ([`encoder_delay`]) throughout. An
/// `encoder_offset` within a joint's declared free-play is reported as
/// that discrepancy, not claimed ([`free_play`]). Flexible panels are
/// tried where the set found leaves the runs above the noise ([`panel_mode`]).
pub fn diagnose(campaign: &Campaign, opts: &DiagnoseOptions, progress: Progress) -> Outcome {
    let t0 = Instant::now();
    let first = diagnose_delayed(campaign, opts, progress);
    let search = |c: &Campaign, o: &DiagnoseOptions| diagnose_delayed(c, o, progress);
    let mut out = panel_mode::consider(campaign, first, (opts, t0), progress, search);
    out.wall_s = t0.elapsed().as_secs_f64();
    let out = free_play::split(campaign, out);
    for found in &out.free_play {
        progress(&free_play::words(found));
    }
    out
}

/// [`diagnose`] before the free-play split.
fn diagnose_delayed(campaign: &Campaign, opts: &DiagnoseOptions, progress: Progress) -> Outcome {
    let t0 = Instant::now();
    let Some(delay) = encoder_delay::estimate(campaign, noise_sigma_deg(campaign)) else {
        return diagnose_at(campaign, None, opts, progress, t0);
    };
    if !delay.allows_zero && !delay.taken_out() {
        // The switches late on the encoders: no angle moves.
        progress(&encoder_delay::words(&delay));
        return diagnose_at(campaign, Some(delay), opts, progress, t0);
    }
    let (first, at) = if delay.allows_zero {
        (diagnose_at(campaign, None, opts, progress, t0), 0.0)
    } else {
        progress(&encoder_delay::words(&delay));
        let c = encoder_delay::shifted(campaign, delay.delay_s);
        (
            diagnose_at(&c, Some(delay.clone()), opts, progress, t0),
            delay.delay_s,
        )
    };
    let (mut out, mut at, mut sims) = (first, at, 0);
    for _ in 0..encoder_delay::MAX_PASSES {
        if out.partial.is_some() {
            break;
        }
        let (refined, used) = refine_delay(campaign, &out, &delay, at, opts, progress, t0);
        sims += used;
        let Some(best) = refined else { break };
        if (best.delay_s - at).abs() <= encoder_delay::REFINED_ALIKE_PERIODS * delay.period_s {
            out.encoder_delay = Some(best);
            break;
        }
        progress(&format!(
            "the model found fits best with the encoders {:.2} ms late: searching again at that delay",
            best.delay_s * 1e3
        ));
        at = best.delay_s;
        sims += out.simulations;
        out = diagnose_at(
            &encoder_delay::shifted(campaign, at),
            Some(best),
            opts,
            progress,
            t0,
        );
    }
    out.simulations += sims;
    out.wall_s = t0.elapsed().as_secs_f64();
    out
}

/// The delay within what the latchings allow (`delay`) at which the set
/// `first` found (with the angles compared at their stamps minus `at`)
/// fits best, refitted at each ([`encoder_delay::refine`]); `None` when
/// the latchings allow zero and that fit does not beat the one at `at` by
/// [`MIN_DELTA_BIC`] with the delay counted as a parameter. With it, the
/// simulations it took.
fn refine_delay(
    campaign: &Campaign,
    first: &Outcome,
    delay: &encoder_delay::EncoderDelay,
    at: f64,
    opts: &DiagnoseOptions,
    progress: Progress,
    t0: Instant,
) -> (Option<encoder_delay::EncoderDelay>, usize) {
    let eng = Engine {
        campaign,
        progress,
        sims: std::sync::atomic::AtomicUsize::new(0),
        halt: Halt::new(opts, t0),
        trace: Trace::default(),
    };
    let fit_at = |d: f64| {
        let c = fitted_campaign(&encoder_delay::shifted(campaign, d));
        eng.refit(&c, &first.extended).and_then(|f| f.stats)
    };
    let best = encoder_delay::refine(delay.lo_s.max(0.0), delay.hi_s, delay.period_s, |d| {
        fit_at(d).map(|s| s.sse)
    });
    let named = !delay.allows_zero
        || match (fit_at(at), fit_at(best)) {
            (Some(here), Some(there)) if there.sse > 0.0 && here.m > 0 => {
                let m = here.m as f64;
                m * (here.sse / there.sse).ln() > MIN_DELTA_BIC + m.ln()
            }
            _ => false,
        };
    let sims = eng.sims.load(std::sync::atomic::Ordering::Relaxed);
    ((named && best > 0.0).then(|| delay.refined(best)), sims)
}

/// The samples a diagnosis fits: runs of a physical latch cut to their
/// free motion ([`latch_window`]), others whole.
fn fitted_campaign(campaign: &Campaign) -> Campaign {
    latch_window::free_campaign(campaign).map_or_else(|| campaign.clone(), |(c, _)| c)
}

/// [`diagnose`] on `campaign` as its angles are compared (a delay taken
/// out already), reporting `delay`.
fn diagnose_at(
    campaign: &Campaign,
    delay: Option<encoder_delay::EncoderDelay>,
    opts: &DiagnoseOptions,
    progress: Progress,
    t0: Instant,
) -> Outcome {
    let free = latch_window::free_campaign(campaign);
    if let Some((_, windows)) = &free {
        for (cr, w) in campaign.runs.iter().zip(windows) {
            if let Some(words) = w.words(&cr.name()) {
                progress(&words);
            }
        }
    }
    let fitted_on = free.as_ref().map_or(campaign, |(c, _)| c);
    let mut out = search_campaign(fitted_on, opts, progress, t0, false);
    if let Some((cut, windows)) = &free {
        // Up to a horizon, named effects only (`whole_fit::to_horizon`).
        let whole = |c: &Campaign, named_only: bool| {
            let discover = opts.discover && !named_only;
            let o = DiagnoseOptions {
                discover,
                ..opts.clone()
            };
            search_campaign(c, &o, progress, t0, true)
        };
        out = whole_fit::consider(campaign, cut, out, progress, whole);
        let effects = out.extended.effects();
        out.latches = latch_finding::latch_findings(campaign, &effects);
        if out.partial.is_none() {
            out.whole_run = whole_run::check(
                campaign,
                windows,
                &effects,
                out.noise_sigma_deg,
                &crate::analysis::campaign_sim::fit_sim_options(),
                |i| cut.residuals(i, &effects),
            );
        }
        if let Some(words) = out
            .whole_run
            .as_ref()
            .and_then(whole_run::WholeRun::missed_words)
        {
            progress(&words);
        }
        out.free_window = Some(windows.clone());
    }
    out.encoder_delay = delay;
    out.wall_s = t0.elapsed().as_secs_f64();
    out
}

/// The search of [`diagnose`] on the samples it fits (`whole`: runs of a
/// physical latch fitted whole, [`whole_fit`]).
fn search_campaign(
    campaign: &Campaign,
    opts: &DiagnoseOptions,
    progress: Progress,
    t0: Instant,
    whole: bool,
) -> Outcome {
    let eng = Engine {
        campaign,
        progress,
        sims: std::sync::atomic::AtomicUsize::new(0),
        halt: Halt::new(opts, t0),
        trace: Trace {
            scores: opts.trace,
            forms: opts.trace_forms,
        },
    };
    let sigma = noise_sigma_deg(campaign);
    let baseline = eng.baseline();
    eng.say(format!(
        "baseline: RMS {:.4} deg over {} runs; noise floor sigma {:.4} deg",
        baseline.rms(),
        campaign.runs.len(),
        sigma
    ));
    let truss = campaign.runs.iter().any(|r| r.mechanism.truss.is_some());
    let mut search = Search::new(
        &eng,
        candidates(campaign, opts, truss, whole),
        opts.max_effects,
        sigma,
        &baseline,
    );
    search.run();
    search.restart_without_first(&baseline);
    if opts.discover && !truss && !eng.halt.now() {
        search.discover_then_tables(&baseline);
    }
    let (mut ambiguities, mut set_aside) = search.alternatives_and_set_aside(whole);
    let settled = search.settle(&mut ambiguities, &mut set_aside);
    let partial = eng.halt.finish();
    let ambiguities = ambiguity::listed(ambiguities, &settled.set);
    let (extended, strength_rms_deg) = eng.strongest_first(&settled.set);
    let extended = ambiguity::widened(&extended, &ambiguities);
    let extended = tolerance::widen(&extended, &settled.shares);
    let tolerance = tolerance::in_order(&extended, &settled.shares);
    // The search's held-out figure is of its set unless the tolerances took
    // a member out.
    let held_out_rms_deg = match search.current_held.filter(|_| settled.within.is_empty()) {
        None if !extended.members.is_empty() => eng.held_out(&extended),
        h => h,
    };
    Outcome {
        noise_sigma_deg: sigma,
        unexplained: unexplained_above_noise(campaign, &extended, sigma)
            .or_else(|| eng.unexplained_torque(&extended, sigma)),
        baseline,
        extended,
        strength_rms_deg,
        held_out_rms_deg,
        rounds: search.rounds,
        simulations: eng.sims.load(std::sync::atomic::Ordering::Relaxed),
        wall_s: t0.elapsed().as_secs_f64(),
        encoder_delay: None,
        panel_mode: None,
        free_play: Vec::new(),
        free_window: None,
        whole_run: None,
        fitted_whole: false,
        fitted_to: None,
        latches: Vec::new(),
        tolerance,
        within_tolerance: settled.within,
        ambiguities,
        set_aside,
        partial,
    }
}

impl<'e, 'a> Search<'e, 'a> {
    /// A search of `candidates` (at most `max_effects` named) from
    /// `baseline`, against the noise σ̂ `sigma` \[deg\], nothing tried yet.
    fn new(
        eng: &'e Engine<'a>,
        candidates: Vec<Candidate>,
        max_effects: usize,
        sigma: f64,
        baseline: &FittedSet,
    ) -> Self {
        Search {
            eng,
            candidates,
            max_effects,
            sigma,
            current_held: eng.held_out(baseline),
            current: baseline.clone(),
            rounds: Vec::new(),
            seen: vec![Vec::new()],
            swaps: 0,
            tried_once: Default::default(),
            table_tried: Vec::new(),
        }
    }
}

/// The candidates of a campaign. A wing with a truss: the effects its
/// simulator models, at the hinges (`crate::simulate::truss_deployment`);
/// its friction nodes (joint n + k, e.g. 3 = the pins at F) are
/// coulomb_friction candidates too: the paper's EFT3. Runs of a physical
/// latch fitted beyond their free motion (`whole`): no `latch_detent`,
/// which moves a run by under 0.01° (physics.md §6) and there fits the
/// instant a latch is reached, which the rebounds amplify.
fn candidates(
    campaign: &Campaign,
    opts: &DiagnoseOptions,
    truss: bool,
    whole: bool,
) -> Vec<Candidate> {
    let nodes = (campaign.max_joints() + 1)..=campaign.effect_joints();
    let node_friction = nodes.map(|j| Candidate {
        kind: EffectKind::CoulombFriction,
        joint: Some(j),
        table: None,
    });
    let rigs = campaign
        .runs
        .iter()
        .filter_map(|r| r.mechanism.active_rig());
    Candidate::all(campaign.max_joints())
        .into_iter()
        .chain(node_friction)
        .chain(Candidate::rig(rigs))
        .filter(|c| opts.kinds.contains(&c.kind))
        .filter(|c| !truss || crate::simulate::truss_deployment::models(c.kind))
        .filter(|c| !whole || c.kind != EffectKind::LatchDetent)
        .collect()
}
