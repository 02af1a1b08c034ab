//! Diagnosis: what the simulation gets wrong, and which named effect of
//! `docs/spec/physics.md` section 6 explains it.
//!
//! Method (details and rationale in `docs/diagnosis.md`):
//! 1. Baseline: the mechanisms as given, residuals per run and joint.
//! 2. Noise floor σ̂ estimated from the data alone (third differences).
//! 3. Candidates: every effect, per joint where it has one. Each is fitted to
//!    all runs at once: a coarse scan for a start, then Levenberg–Marquardt
//!    ([`crate::analysis::fit`]); candidates are fitted in parallel.
//! 4. Stepwise selection: the move (an addition; when none passes, a pair
//!    fitted jointly; then a swap, and a swap for a pair) with the best BIC
//!    is taken if it earns its keep — BIC better by more than
//!    [`MIN_DELTA_BIC`], every added effect's 95 % interval excludes zero,
//!    and (with two or more runs) the held-out RMS of the resulting set
//!    (fit on all runs but one, predict that one) improves; effects that no
//!    longer earn their keep are dropped again. At most three named
//!    effects; stop at the noise floor.
//! 5. Discovery ([`discover`]): when the named effects leave a residual
//!    above the noise floor, a `torque_table` fitted at each joint is judged
//!    like any candidate; a named effect that fits as well replaces it.
//! 6. A clear residual that nothing explains is reported as `unexplained`
//!    (how large, which joint, which part of the stroke), never forced onto
//!    a name. Where a global effect stands in for a joint torque, a table
//!    at that joint in its place is tried first (`stand_in`).

pub mod ambiguity;
mod candidate;
pub mod discover;
mod evidence_search;
mod halt;
pub mod latch_finding;
pub mod latch_window;
mod outcome;
mod refine;
mod screen;
mod shared_torque;
mod stand_in;
mod table_form;

pub use candidate::Candidate;
use candidate::{effects_of, ParamBound};
pub use outcome::{CandidateScore, DiagnoseOptions, FittedSet, Outcome, Round, StopFlag};
pub use table_form::{PlacedKnots, TableForm};

use crate::analysis::campaign_sim::CampaignSim;
use crate::analysis::evidence::{self, noise_sigma_deg};
use crate::analysis::fit::{self, FitOptions};
use crate::data::campaign::{Campaign, CampaignRun};
use crate::model::effect::EffectKind;
use crate::report::progress::Progress;
use halt::Halt;
use rayon::prelude::*;
use std::time::Instant;

/// ΔBIC an effect must gain to be kept ("very strong" evidence on the
/// Kass & Raftery 1995 scale).
pub const MIN_DELTA_BIC: f64 = 10.0;

/// The residual is "down to the sensor noise" below this multiple of σ̂.
pub const NOISE_FLOOR_FACTOR: f64 = 1.2;

/// A move must lower the held-out RMS below this share of the current
/// set's [1] (5 % better: a gain the noise of two runs does not give).
pub const HELD_OUT_SHARE: f64 = 0.95;

/// A residual is "clearly above the noise" beyond this multiple of σ̂ [1]
/// (and beyond [`ABOVE_NOISE_MARGIN_DEG`] over σ̂).
pub const ABOVE_NOISE_FACTOR: f64 = 1.5;

/// A residual clearly above the noise also exceeds σ̂ by this [deg] (the encoder's step, 0.022°,
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
    /// Start values of the tables shaped by the residual torque.
    starts: std::sync::Mutex<std::collections::HashMap<TableForm, Vec<f64>>>,
    /// When and on what the search stops early ([`Halt`]).
    halt: Halt,
}

impl Engine<'_> {
    fn say(&self, msg: impl AsRef<str>) {
        (self.progress)(msg.as_ref());
    }

    /// Remembers the start values of a table shaped by the data.
    fn set_start(&self, form: TableForm, p: Vec<f64>) {
        let mut m = self.starts.lock().unwrap_or_else(|e| e.into_inner());
        m.insert(form, p);
    }

    /// The starting points of a candidate's coarse scan: a table shaped by
    /// the data starts from its shape (and half of it); any other from its
    /// own scan ([`Candidate::scan`]).
    fn scan_of(&self, cand: &Candidate) -> Vec<Vec<f64>> {
        let m = self.starts.lock().unwrap_or_else(|e| e.into_inner());
        match cand.table.and_then(|t| m.get(&t)) {
            Some(p) => vec![p.clone(), p.iter().map(|x| 0.5 * x).collect()],
            None => cand.scan(),
        }
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
                set: Vec::new(),
                params: Vec::new(),
                ci95: Vec::new(),
                sse,
                m,
                evaluations: 1,
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
        let r = fit::least_squares(&model, p0, &opts).ok()?;
        Some(FittedSet {
            set: set.to_vec(),
            params: r.params,
            ci95: r.ci95,
            sse: r.sse,
            m: r.residuals,
            evaluations: r.evaluations,
        })
    }

    /// Held-out RMS [deg] of a set: fit on all runs but one (from the
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
                let p = if fitted.set.is_empty() {
                    Vec::new()
                } else {
                    self.fit(&train, &fitted.set, &fitted.params)?.params
                };
                self.sse(&test, &fitted.set, &p)
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

impl Engine<'_> {
    /// Scores fitted candidates against `current` and picks the best by BIC
    /// that earns its keep: BIC gain > [`MIN_DELTA_BIC`], a 95 % interval
    /// clear of zero, and a held-out RMS at least 5 % better than the
    /// current set's (with two or more runs).
    fn judge(
        &self,
        current: &FittedSet,
        current_held: Option<f64>,
        fits: impl Iterator<Item = (Candidate, Option<FittedSet>, bool)>,
        what: String,
    ) -> (Round, Option<(FittedSet, Option<f64>)>) {
        let mut scores: Vec<CandidateScore> = fits
            .filter_map(|(cand, f, screened_out)| {
                let f = f?;
                Some(CandidateScore {
                    candidate: cand,
                    delta_bic: current.bic() - f.bic(),
                    fitted: f,
                    held_out_rms_deg: None,
                    accepted: false,
                    verdict: if screened_out {
                        "screened out by the coarse scan".into()
                    } else {
                        String::new()
                    },
                })
            })
            .collect();
        scores.sort_by(|a, b| b.delta_bic.total_cmp(&a.delta_bic));
        self.show_scores(&scores);
        let mut chosen = None;
        let mut tried = 0;
        for s in scores.iter_mut() {
            if !s.verdict.is_empty() {
                continue;
            }
            tried += 1;
            if chosen.is_some() || tried > 3 {
                if s.verdict.is_empty() {
                    s.verdict = format!("dBIC {:.1}, not the best", s.delta_bic);
                }
                continue;
            }
            if self.verdict(s, current, current_held) {
                chosen = Some(s.candidate);
            }
        }
        if std::env::var_os("DEPLOYWATCH_TRACE").is_some() {
            for s in scores.iter().filter(|s| !s.verdict.is_empty()).take(4) {
                self.say(format!("    {}: {}", labels(&s.fitted.set), s.verdict));
            }
        }
        let next = chosen.and_then(|c| {
            scores
                .iter()
                .find(|s| s.accepted && s.candidate == c)
                .map(|s| (s.fitted.clone(), s.held_out_rms_deg))
        });
        (
            Round {
                start: current.set.clone(),
                start_rms_deg: current.rms(),
                what,
                scores,
            },
            next,
        )
    }

    /// Prints the five best scores of a round (all with `DEPLOYWATCH_TRACE`).
    fn show_scores(&self, scores: &[CandidateScore]) {
        let show = if std::env::var_os("DEPLOYWATCH_TRACE").is_some() {
            usize::MAX
        } else {
            5
        };
        for s in scores.iter().take(show) {
            self.say(format!(
                "  {:<40} RMS {:.4} deg  dBIC {:>10.1}",
                labels(&s.fitted.set),
                s.fitted.rms(),
                s.delta_bic
            ));
        }
    }

    /// Whether a move earns its keep: BIC gain > [`MIN_DELTA_BIC`], every
    /// added effect's interval clear of zero, and a held-out RMS at least
    /// 5 % better than the current set's. Writes the verdict into `s`.
    fn verdict(
        &self,
        s: &mut CandidateScore,
        current: &FittedSet,
        current_held: Option<f64>,
    ) -> bool {
        s.verdict = if s.delta_bic <= MIN_DELTA_BIC {
            format!("BIC gain {:.1} ≤ {MIN_DELTA_BIC}", s.delta_bic)
        } else if !new_members_clear(&s.fitted, current) {
            "a 95 % interval contains zero".into()
        } else {
            s.held_out_rms_deg = self.held_out(&s.fitted);
            match (s.held_out_rms_deg, current_held) {
                (Some(h), Some(c)) if h >= HELD_OUT_SHARE * c => {
                    format!("held-out RMS {h:.4} deg does not beat {c:.4} deg")
                }
                _ => {
                    s.accepted = true;
                    "earns its keep: added".into()
                }
            }
        };
        s.accepted
    }

    /// Drops effects that no longer earn their keep beside the others.
    fn backward(&self, mut f: FittedSet, mut held: Option<f64>) -> (FittedSet, Option<f64>) {
        while f.set.len() > 1 {
            let reduced: Vec<Option<FittedSet>> = (0..f.set.len())
                .into_par_iter()
                .map(|k| {
                    let r = f.without(k);
                    self.fit(self.campaign, &r.set, &r.params)
                })
                .collect();
            let best = reduced
                .into_iter()
                .flatten()
                .min_by(|a, b| a.bic().total_cmp(&b.bic()));
            match best {
                Some(r) if r.bic() - f.bic() < MIN_DELTA_BIC => {
                    let gone: Vec<String> = f
                        .set
                        .iter()
                        .filter(|c| !r.set.contains(c))
                        .map(|c| c.words())
                        .collect();
                    self.say(format!(
                        "  dropped {}: no longer earns its keep",
                        gone.join(", ")
                    ));
                    held = self.held_out(&r);
                    f = r;
                }
                _ => break,
            }
        }
        (f, held)
    }
}

/// `a, b, c` of a set in words ([`Candidate::words`]); `nothing` for the
/// empty set.
fn labels(set: &[Candidate]) -> String {
    if set.is_empty() {
        return "nothing".to_string();
    }
    set.iter().map(|c| c.words()).collect::<Vec<_>>().join(", ")
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
    }
}

/// True when the 95 % interval of the value of every member of `f` that is
/// not in `current` excludes zero (a pair move adds two).
fn new_members_clear(f: &FittedSet, current: &FittedSet) -> bool {
    let mut off = 0;
    for c in &f.set {
        let n = c.params();
        if !current.set.contains(c) {
            let (Some(p), Some(ci)) = (f.params.get(off..off + n), f.ci95.get(off..off + n)) else {
                return false;
            };
            let (v, _) = c.value_ci(p, ci);
            if !(v[0] > 0.0 || v[1] < 0.0) {
                return false;
            }
        }
        off += n;
    }
    true
}

/// How many of a round's best single candidates seed pair moves.
pub const PAIR_SEEDS: usize = 4;

/// Most search steps (additions, pair additions and swaps) of one diagnosis.
const MAX_STEPS: usize = 10;

/// Most discovered torque tables of one diagnosis.
pub const MAX_TABLES: usize = 2;

/// Most swap rounds of one diagnosis.
const MAX_SWAPS: usize = 2;

/// The state of the stepwise search: the current set, its held-out RMS, the
/// rounds tried so far and the sets already visited.
struct Search<'e, 'a> {
    eng: &'e Engine<'a>,
    candidates: Vec<Candidate>,
    max_effects: usize,
    floor_deg: f64,
    current: FittedSet,
    current_held: Option<f64>,
    rounds: Vec<Round>,
    seen: Vec<Vec<Candidate>>,
    swaps: usize,
    /// Whether the pairs the residual torque proposes were tried.
    proposed: bool,
    /// Whether the named pairs at the set's joints were tried
    /// ([`Search::try_joint_pairs`]).
    paired: bool,
}

impl Search<'_, '_> {
    /// Runs the search to its end: at each step an addition, else a pair
    /// addition, else a swap; stop at the noise floor or when nothing
    /// earns its keep.
    fn run(&mut self) {
        for _ in 0..MAX_STEPS {
            if self.eng.halt.now() {
                self.eng
                    .say("search stopped early: the best set so far is kept");
                return;
            }
            if self.current.rms() <= self.floor_deg {
                self.eng.say(format!(
                    "residual {:.4} deg is down to the noise floor: stop",
                    self.current.rms()
                ));
                return;
            }
            if self.try_add() || self.try_pair() {
                continue;
            }
            // A swap, else a pair swap seeded by the swap round (one effect
            // replaced by two that only work together).
            let before = self.rounds.len();
            if self.try_swap() {
                continue;
            }
            if (self.rounds.len() == before || !self.try_pair())
                && !self.try_proposed()
                && !self.try_joint_pairs()
            {
                return;
            }
        }
    }

    /// Named effects in the current set (discovered tables do not count
    /// against `max_effects`).
    fn named_len(&self) -> usize {
        self.current
            .set
            .iter()
            .filter(|c| c.table.is_none())
            .count()
    }

    /// A named effect that explains the data wins over a table: each table
    /// of the set is replaced by every named candidate in turn (and by the
    /// pairs of named effects at its joint, [`Search::named_pairs_for`],
    /// screened also where the two share their torque,
    /// [`Engine::fit_moves_sharing`]), and the best replacement by BIC is
    /// taken when its BIC is better than the table's set, its RMS within
    /// [`NAMED_RMS_SHARE`] of the table set's (or of the noise floor: as
    /// good a fit, with fewer parameters), its residual not above the noise
    /// σ̂ (it explains the data: a coarse table is left to the refinement
    /// instead) and its intervals clear of zero. True when a table was
    /// replaced.
    fn prefer_named(&mut self, sigma: f64) -> bool {
        let named: Vec<Candidate> = self.outside();
        let mut moves = Vec::new();
        for (k, c) in self.current.set.iter().enumerate() {
            if c.table.is_some() {
                let reduced = self.current.without(k);
                moves.extend(named.iter().map(|&n| (reduced.clone(), n)));
                moves.extend(self.named_pairs_for(&reduced, *c));
            }
        }
        let fits = self.eng.fit_moves_sharing(self.eng.campaign, &moves);
        let best = fits
            .into_iter()
            .filter(|(_, _, screened_out)| !screened_out)
            .filter_map(|(_, f, _)| f)
            .filter(|f| f.bic() < self.current.bic() && new_members_clear(f, &self.current))
            .filter(|f| f.rms() <= NAMED_RMS_SHARE * self.current.rms().max(self.floor_deg))
            .filter(|f| !above_noise(f, sigma))
            .min_by(|a, b| a.bic().total_cmp(&b.bic()));
        let Some(f) = best else {
            return false;
        };
        self.eng.say(format!(
            "  a named effect explains it as well: {} (RMS {:.4} deg)",
            labels(&f.set),
            f.rms()
        ));
        self.current_held = self.eng.held_out(&f);
        self.seen.push(f.set.clone());
        self.current = f;
        true
    }

    /// Takes `f` (held-out RMS `held`) as the current set, saying `done`,
    /// then drops what no longer earns its keep.
    fn take(&mut self, done: &str, f: FittedSet, held: Option<f64>) {
        self.eng.say(format!(
            "  {done} {} (RMS {:.4} deg)",
            labels(&f.set),
            f.rms()
        ));
        let (f, held) = self.eng.backward(f, held);
        self.seen.push(f.set.clone());
        self.current = f;
        self.current_held = held;
    }

    /// Candidates not in the current set.
    fn outside(&self) -> Vec<Candidate> {
        self.candidates
            .iter()
            .copied()
            .filter(|c| !self.current.set.contains(c))
            .collect()
    }

    /// Judges `moves` against the current set, records the round and, when
    /// a move earns its keep and leads to a set not yet visited, takes it
    /// (then drops what no longer earns its keep). True when it moved.
    fn step(&mut self, moves: &[(FittedSet, Candidate)], what: String, done: &str) -> bool {
        let fits = self.eng.fit_moves(self.eng.campaign, moves);
        let (round, next) =
            self.eng
                .judge(&self.current, self.current_held, fits.into_iter(), what);
        self.rounds.push(round);
        match next {
            Some((f, held)) if !self.seen.contains(&f.set) => {
                self.take(done, f, held);
                true
            }
            _ => false,
        }
    }

    /// Forward step: the best single candidate that earns its keep.
    fn try_add(&mut self) -> bool {
        if self.named_len() >= self.max_effects {
            return false;
        }
        let todo = self.outside();
        self.eng.say(format!(
            "round {}: fitting {} candidates beside {} (RMS {:.4} deg)",
            self.rounds.len() + 1,
            todo.len(),
            labels(&self.current.set),
            self.current.rms()
        ));
        let moves: Vec<(FittedSet, Candidate)> =
            todo.iter().map(|&c| (self.current.clone(), c)).collect();
        let what = format!("add to {}", labels(&self.current.set));
        self.step(&moves, what, "added:")
    }

    /// Pair step, when no single move earned its keep: two causes that act
    /// together may each fail the held-out test alone (one effect cannot
    /// predict a run the other shapes). The [`PAIR_SEEDS`] best moves of the
    /// last round (an addition or a swap) by BIC, the training criterion,
    /// are each completed with every other candidate, the sets fitted
    /// jointly, and the held-out check applied to the set as a whole.
    fn try_pair(&mut self) -> bool {
        let Some(last) = self.rounds.last() else {
            return false;
        };
        let room =
            |f: &FittedSet| f.set.iter().filter(|c| c.table.is_none()).count() < self.max_effects;
        let seeds: Vec<FittedSet> = last
            .scores
            .iter()
            .filter(|s| !s.verdict.starts_with("screened") && room(&s.fitted))
            .take(PAIR_SEEDS)
            .map(|s| s.fitted.clone())
            .collect();
        if seeds.is_empty() {
            return false;
        }
        let mut moves = Vec::new();
        for (a, seed) in seeds.iter().enumerate() {
            let first = seed.set[seed.set.len() - 1];
            for c in self.outside() {
                let earlier = seeds[..a].iter().any(|s| s.set.last() == Some(&c));
                if c != first && !earlier {
                    moves.push((seed.clone(), c));
                }
            }
        }
        self.eng.say(format!(
            "pairs: fitting {} sets of two, seeded by the last round, beside {}",
            moves.len(),
            labels(&self.current.set)
        ));
        let what = format!("add a pair to {}", labels(&self.current.set));
        self.step(&moves, what, "added the pair:")
    }

    /// Swap step: replace one effect by another candidate when the residual
    /// is still above the noise floor (greedy steps can take a wrong turn
    /// when two effects act together). Every candidate may swap in: the
    /// moves are prescreened by their coarse scan.
    fn try_swap(&mut self) -> bool {
        if self.current.set.is_empty() || self.swaps >= MAX_SWAPS {
            return false;
        }
        self.swaps += 1;
        let outside = self.outside();
        let mut moves = Vec::new();
        for k in 0..self.current.set.len() {
            let reduced = self.current.without(k);
            for c in &outside {
                moves.push((reduced.clone(), *c));
            }
        }
        self.eng.say(format!(
            "swap {}: trying {} replacements in {}",
            self.swaps,
            moves.len(),
            labels(&self.current.set)
        ));
        let what = format!("swap one of {}", labels(&self.current.set));
        let moved = self.step(&moves, what, "swapped to");
        if !moved {
            self.eng.say("  no swap earns its keep: stop");
        }
        moved
    }
}

impl Engine<'_> {
    /// The baseline: the mechanisms as given, no effect.
    fn baseline(&self) -> FittedSet {
        self.fit(self.campaign, &[], &[]).unwrap_or(FittedSet {
            set: Vec::new(),
            params: Vec::new(),
            ci95: Vec::new(),
            sse: f64::INFINITY,
            m: self.campaign.samples(),
            evaluations: 0,
        })
    }

    /// The set reordered strongest first, with each effect's strength: the
    /// RMS [deg] of the set without it (the others' values kept).
    fn strongest_first(&self, current: &FittedSet) -> (FittedSet, Vec<f64>) {
        let strength: Vec<f64> = (0..current.set.len())
            .map(|k| {
                let r = current.without(k);
                self.sse(self.campaign, &r.set, &r.params)
                    .map(|(s, m)| (s / m.max(1) as f64).sqrt())
                    .unwrap_or(f64::INFINITY)
            })
            .collect();
        let mut order: Vec<usize> = (0..current.set.len()).collect();
        order.sort_by(|&a, &b| strength[b].total_cmp(&strength[a]));
        let mut offs = Vec::new();
        let mut off = 0;
        for c in &current.set {
            offs.push(off);
            off += c.params();
        }
        let pick = |v: &[f64], i: usize| v[offs[i]..offs[i] + current.set[i].params()].to_vec();
        let pick_ci =
            |v: &[[f64; 2]], i: usize| v[offs[i]..offs[i] + current.set[i].params()].to_vec();
        let extended = FittedSet {
            set: order.iter().map(|&i| current.set[i]).collect(),
            params: order
                .iter()
                .flat_map(|&i| pick(&current.params, i))
                .collect(),
            ci95: order
                .iter()
                .flat_map(|&i| pick_ci(&current.ci95, i))
                .collect(),
            ..current.clone()
        };
        (extended, order.iter().map(|&i| strength[i]).collect())
    }
}

/// A named replacement of a table must fit within this share of the table
/// set's RMS (or of the noise floor) [1]: a better BIC alone would let a
/// pair of named stand-ins, with fewer parameters, replace a coarse table
/// that the refinement would have brought to the noise.
const NAMED_RMS_SHARE: f64 = 1.05;

/// True when the residual of a set stays clearly above the noise floor σ̂
/// [deg]: above [`ABOVE_NOISE_FACTOR`] σ̂ and above σ̂ +
/// [`ABOVE_NOISE_MARGIN_DEG`].
fn above_noise(f: &FittedSet, sigma: f64) -> bool {
    let rms = f.rms();
    rms > ABOVE_NOISE_FACTOR * sigma.max(1e-6) && rms > sigma + ABOVE_NOISE_MARGIN_DEG
}

/// The `unexplained` description when the residual stays clearly above the
/// noise floor: how large, at which joint and where in the stroke.
fn unexplained_text(campaign: &Campaign, extended: &FittedSet, sigma: f64) -> Option<String> {
    if !above_noise(extended, sigma) {
        return None;
    }
    let rms = extended.rms();
    let at = evidence::locate(&evidence::analyse(campaign, &extended.effects(), sigma))
        .map(|w| format!(", largest at {w}"))
        .unwrap_or_default();
    Some(format!(
        "the residual stays at {rms:.4} deg RMS, {:.1} times the noise floor ({sigma:.4} deg){at}, and no further candidate earns its keep",
        rms / sigma.max(1e-9),
    ))
}

/// Diagnoses a campaign: baseline, noise floor, stepwise search
/// ([`Search`]), then the effects strongest first, the sets that explain
/// the runs alike ([`ambiguity`]) and what stays unexplained. Runs of a
/// physical latch are fitted on their free motion ([`latch_window`]) and
/// their latch events compared by their statistics ([`latch_finding`]).
pub fn diagnose(campaign: &Campaign, opts: &DiagnoseOptions, progress: Progress) -> Outcome {
    let t0 = Instant::now();
    let free = latch_window::free_campaign(campaign);
    if let Some((_, windows)) = &free {
        for (cr, w) in campaign.runs.iter().zip(windows) {
            if let (Some(t), Some(j)) = (w.end_s, w.joint) {
                progress(&format!(
                    "{}: free motion to {t:.2} s ({} of {} samples), where joint {j} enters its latch's reach",
                    cr.name(),
                    w.kept,
                    w.of
                ));
            }
        }
    }
    let fitted_on = free.as_ref().map_or(campaign, |(c, _)| c);
    let mut out = search_campaign(fitted_on, opts, progress, t0);
    if let Some((_, windows)) = free {
        out.free_window = Some(windows);
        out.latches = latch_finding::latch_findings(campaign, &out.extended.effects());
    }
    out.wall_s = t0.elapsed().as_secs_f64();
    out
}

/// The search of [`diagnose`] on the samples it fits.
fn search_campaign(
    campaign: &Campaign,
    opts: &DiagnoseOptions,
    progress: Progress,
    t0: Instant,
) -> Outcome {
    let eng = Engine {
        campaign,
        progress,
        sims: std::sync::atomic::AtomicUsize::new(0),
        starts: Default::default(),
        halt: Halt::new(opts, t0),
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
    let mut search = Search {
        eng: &eng,
        candidates: candidates(campaign, opts, truss),
        max_effects: opts.max_effects,
        floor_deg: NOISE_FLOOR_FACTOR * sigma,
        current_held: eng.held_out(&baseline),
        current: baseline.clone(),
        rounds: Vec::new(),
        seen: vec![Vec::new()],
        swaps: 0,
        proposed: false,
        paired: false,
    };
    search.run();
    if opts.discover && !truss && !eng.halt.now() {
        search.discover(sigma);
        search.replace_stand_in(sigma);
    }
    let ambiguities = if eng.halt.now() {
        Vec::new()
    } else {
        search.ambiguities()
    };
    let partial = eng.halt.finish();
    let (extended, strength_rms_deg) = eng.strongest_first(&search.current);
    let extended = ambiguity::widened(&extended, &ambiguities);
    let held_out_rms_deg = match search.current_held {
        None if !extended.set.is_empty() => eng.held_out(&extended),
        h => h,
    };
    Outcome {
        noise_sigma_deg: sigma,
        unexplained: unexplained_text(campaign, &extended, sigma)
            .or_else(|| eng.unexplained_torque(&extended, sigma)),
        baseline,
        extended,
        strength_rms_deg,
        held_out_rms_deg,
        rounds: search.rounds,
        simulations: eng.sims.load(std::sync::atomic::Ordering::Relaxed),
        wall_s: t0.elapsed().as_secs_f64(),
        free_window: None,
        latches: Vec::new(),
        ambiguities,
        partial,
    }
}

/// The candidates of a campaign. A wing with a truss: the effects its
/// simulator models, at the hinges (`crate::simulate::truss_deployment`);
/// its friction nodes (joint n + k, e.g. 3 = the pins at F) are
/// coulomb_friction candidates too: the paper's EFT3.
fn candidates(campaign: &Campaign, opts: &DiagnoseOptions, truss: bool) -> Vec<Candidate> {
    let nodes = (campaign.max_joints() + 1)..=campaign.effect_joints();
    let node_friction = nodes.map(|j| Candidate {
        kind: EffectKind::CoulombFriction,
        joint: Some(j),
        table: None,
    });
    let rig = campaign
        .runs
        .iter()
        .any(|r| r.mechanism.active_rig().is_some());
    Candidate::all(campaign.max_joints())
        .into_iter()
        .chain(node_friction)
        .chain(Candidate::rig(rig))
        .filter(|c| opts.kinds.contains(&c.kind))
        .filter(|c| !truss || crate::simulate::truss_deployment::models(c.kind))
        .collect()
}
