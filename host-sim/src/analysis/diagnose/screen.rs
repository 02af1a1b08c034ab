//! The coarse screen of a round's moves: each move (a base set plus a
//! candidate and its start, [`Step`]) is scanned from a few start points, and only the
//! most promising are fitted fully through the simulator.

use super::candidate::Candidate;
use super::outcome::{FitStats, FittedSet};
use super::step::Step;
use super::table_form::TableForm;
use super::{Engine, SCREEN_KEEP};
use crate::data::campaign::Campaign;
use rayon::prelude::*;

/// One start per table form and round: a form proposed more than once in a
/// round (the same knots shaped beside two bases) starts everywhere from
/// the start given to it last.
fn one_start_per_form(steps: &[Step]) -> Vec<Step> {
    let mut last: Vec<(TableForm, &Vec<f64>)> = Vec::new();
    for s in steps {
        if let (Some(form), Some(p)) = (s.candidate.table, &s.start) {
            match last.iter_mut().find(|(f, _)| *f == form) {
                Some(l) => l.1 = p,
                None => last.push((form, p)),
            }
        }
    }
    steps
        .iter()
        .map(|s| {
            let start = s
                .candidate
                .table
                .and_then(|form| last.iter().find(|(f, _)| *f == form))
                .map_or_else(|| s.start.clone(), |(_, p)| Some((*p).clone()));
            Step::from(s.base.clone(), s.candidate, start)
        })
        .collect()
}

/// Where the screen of a move starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Starts {
    /// The candidate's scan with the base's values held (every stepwise
    /// round, discovery and refinement).
    Held,
    /// Also where the candidate shares its torque with a named effect of
    /// the base at its joint ([`Engine::screen_shared`]): named pairs at
    /// one joint in place of a table ([`super::policy::Move::NamedForTable`]) or
    /// of the named effects there ([`super::policy::Move::JointPairs`]).
    /// Measured in the stepwise rounds too, where it let named pairs stand
    /// in for unnamed torques (`docs/diagnosis.md`, "Two causes at one
    /// joint").
    AlsoShared,
}

/// How many narrow tables ([`Candidate::is_snag`]) of a round, best by
/// their scan, are fitted fully beside the [`SCREEN_KEEP`] best others.
const SNAG_KEEP: usize = 2;

impl Engine<'_> {
    /// Screens `base ∪ {cand}` of a step: scans the candidate's value
    /// ([`Step::scan`]) with the base's parameters held; the best point by
    /// SSE.
    fn screen(&self, c: &Campaign, step: &Step) -> Option<FittedSet> {
        let base = &step.base;
        let held = step.scan().into_iter().map(|start| {
            let mut p = base.params();
            p.extend(start);
            p
        });
        self.best_point(c, base, step.candidate, held)
    }

    /// The point of `base ∪ {cand}` (all parameters) with the smallest SSE,
    /// unfitted (intervals unbounded).
    pub(super) fn best_point(
        &self,
        c: &Campaign,
        base: &FittedSet,
        cand: Candidate,
        points: impl Iterator<Item = Vec<f64>>,
    ) -> Option<FittedSet> {
        let mut set = base.candidates();
        set.push(cand);
        let mut best: Option<(f64, usize, Vec<f64>)> = None;
        for p in points {
            if let Some((sse, m)) = self.sse(c, &set, &p) {
                if best.as_ref().is_none_or(|(b, _, _)| sse < *b) {
                    best = Some((sse, m, p));
                }
            }
        }
        let (sse, m, params) = best?;
        let stats = FitStats {
            sse,
            m,
            evaluations: 0,
        };
        Some(FittedSet::from_flat(&set, &params, None, Some(stats)))
    }

    /// Screens every move (a base set plus a candidate) by its coarse scan
    /// and fits the [`SCREEN_KEEP`] most promising ones fully; the others
    /// keep their scan result and are marked as screened out. With
    /// [`Starts::AlsoShared`], a move whose candidate shares its torque
    /// with an effect of the base ([`Engine::screen_shared`]) is also
    /// fitted from where both share it when that point beats its own scan
    /// and the last kept move's scan: the better of its fits counts.
    pub(super) fn fit_moves(
        &self,
        c: &Campaign,
        moves: &[Step],
    ) -> Vec<(Candidate, Option<FittedSet>, bool)> {
        self.fit_moves_from(c, moves, Starts::Held)
    }

    /// [`Engine::fit_moves`] with [`Starts::AlsoShared`]: named pairs at
    /// one joint, where the two share a torque.
    pub(super) fn fit_moves_sharing(
        &self,
        c: &Campaign,
        moves: &[Step],
    ) -> Vec<(Candidate, Option<FittedSet>, bool)> {
        self.fit_moves_from(c, moves, Starts::AlsoShared)
    }

    /// Screens and fits the moves, the screen starting `starts_from`
    /// ([`Engine::fit_moves`]; one start per table form,
    /// [`one_start_per_form`]).
    fn fit_moves_from(
        &self,
        c: &Campaign,
        moves: &[Step],
        starts_from: Starts,
    ) -> Vec<(Candidate, Option<FittedSet>, bool)> {
        let moves = one_start_per_form(moves);
        let screened: Vec<(Option<FittedSet>, Option<FittedSet>)> = moves
            .par_iter()
            .map(|step| {
                let shared = match starts_from {
                    Starts::Held => None,
                    Starts::AlsoShared => self.screen_shared(c, &step.base, step.candidate),
                };
                (self.screen(c, step), shared)
            })
            .collect();
        let sse_of = |f: &Option<FittedSet>| f.as_ref().map_or(f64::INFINITY, FittedSet::sse);
        let mut order: Vec<usize> = (0..moves.len())
            .filter(|&i| screened[i].0.is_some())
            .collect();
        order.sort_by(|&a, &b| sse_of(&screened[a].0).total_cmp(&sse_of(&screened[b].0)));
        let bar = match order.get(SCREEN_KEEP) {
            Some(_) => order
                .get(SCREEN_KEEP - 1)
                .map_or(f64::INFINITY, |&i| sse_of(&screened[i].0)),
            None => f64::INFINITY,
        };
        // Narrow tables (snags) have their own few places: their raised
        // start fits the scan better than the even tables' constant one,
        // and would otherwise crowd out the forms the fit needs.
        let (snags, others): (Vec<usize>, Vec<usize>) =
            order.iter().partition(|&&i| moves[i].candidate.is_snag());
        let keep: Vec<usize> = others
            .iter()
            .copied()
            .take(SCREEN_KEEP)
            .chain(snags.iter().copied().take(SNAG_KEEP))
            .collect();
        let mut starts: Vec<(usize, &FittedSet)> = keep
            .iter()
            .filter_map(|&i| Some((i, screened[i].0.as_ref()?)))
            .collect();
        for (i, (held, shared)) in screened.iter().enumerate() {
            let s = sse_of(shared);
            if let Some(f) = shared.as_ref().filter(|_| s < sse_of(held) && s < bar) {
                starts.push((i, f));
            }
        }
        let fitted: Vec<(usize, Option<FittedSet>)> = starts
            .par_iter()
            .map(|&(i, s)| (i, self.refit(c, s)))
            .collect();
        let mut out: Vec<(Candidate, Option<FittedSet>, bool)> = moves
            .iter()
            .zip(screened)
            .map(|(step, (held, _))| (step.candidate, held, true))
            .collect();
        for (i, f) in fitted {
            let better = match (&out[i], &f) {
                ((_, _, true), _) => true,
                ((_, Some(a), false), Some(b)) => b.sse() < a.sse(),
                ((_, None, false), _) => true,
                _ => false,
            };
            if better {
                out[i] = (moves[i].candidate, f, false);
            }
        }
        out
    }
}
