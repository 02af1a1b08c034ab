//! The moves of the diagnosis search and the one place they are made
//! ([`Search::attempt`]): each move proposes sets (a base set plus a
//! candidate with the start values of its screen, [`Step`]), they are
//! screened and fitted ([`super::screen`]), judged by the one acceptance
//! policy ([`super::policy`]) with the move's [`Policy`], and the choice
//! is taken. The stepwise search is one loop over [`STEPWISE`]; discovery,
//! refinement and the stand-in's table make their moves through the same
//! [`Search::attempt`]. The moves that judge one set against the current
//! one (a drop after a move, a claim dropped, the simpler law in place of
//! a friction form, the stand-in's table kept, a second start, an
//! alternative) call the same rule. The one acceptance rule is
//! [`Search::accept`], with the move's [`Policy`] ([`super::policy`]
//! states the checks and their order). The search's settings (what the
//! progress traces) are [`super::DiagnoseOptions`]'s.

use super::candidate::Candidate;
use super::outcome::{CandidateScore, FittedSet, Round};
use super::policy::{
    Attempt, Move, PastTries, Policy, Record, Rejection, Verdict, DISCREPANCY_SHARE,
    HELD_OUT_SHARE, STEPWISE,
};
use super::step::Step;
use super::{above_noise, labels, Proposal, Search, MAX_STEPS, MAX_SWAPS, PAIR_SEEDS};

impl Search<'_, '_> {
    /// The one acceptance rule: judges the move from `current` (held-out
    /// RMS `current_held`) to `to` under `policy` (see the module doc).
    /// `held` caches the move's held-out RMS: computed here when needed and
    /// not yet known.
    pub(super) fn accept(
        &self,
        (current, current_held): (&FittedSet, Option<f64>),
        to: &FittedSet,
        held: &mut Option<Option<f64>>,
        policy: &Policy,
    ) -> Verdict {
        let delta_bic = current.bic() - to.bic();
        let rms = to.rms();
        if !(delta_bic > policy.min_delta_bic) {
            return Verdict::Rejected(Rejection::BicGain {
                delta_bic,
                min: policy.min_delta_bic,
            });
        }
        if policy.intervals_clear && !new_members_clear(to, current) {
            return Verdict::Rejected(Rejection::IntervalHoldsZero);
        }
        if let Some(share) = policy.rms_share {
            let limit_deg = share * current.rms().max(self.floor());
            if !(rms <= limit_deg) {
                return Verdict::Rejected(Rejection::RmsShare {
                    rms_deg: rms,
                    limit_deg,
                });
            }
        }
        if policy.explains && above_noise(to, self.sigma) {
            return Verdict::Rejected(Rejection::AboveNoise { rms_deg: rms });
        }
        if policy.held_out {
            let h = *held.get_or_insert_with(|| self.eng.held_out(to));
            if let (Some(h), Some(c)) = (h, current_held) {
                if h >= HELD_OUT_SHARE * c {
                    return Verdict::Rejected(Rejection::HeldOut {
                        held_deg: h,
                        current_deg: c,
                    });
                }
            }
        }
        if policy.no_stand_in && self.eng.unexplained_torque(to, self.sigma).is_some() {
            return Verdict::Rejected(Rejection::StandInLeft);
        }
        if policy.within_discrepancy {
            let (explained_deg, discrepancy_deg) = self.discrepancy_of(current, to);
            if !(explained_deg * explained_deg
                < DISCREPANCY_SHARE * discrepancy_deg * discrepancy_deg)
            {
                return Verdict::Rejected(Rejection::BeyondDiscrepancy {
                    explained_deg,
                    discrepancy_deg,
                });
            }
        }
        if policy.beyond_discrepancy {
            // What `to` gains over `current` is what `current` loses
            // against it.
            let (gained_deg, discrepancy_deg) = self.discrepancy_of(to, current);
            if gained_deg * gained_deg < DISCREPANCY_SHARE * discrepancy_deg * discrepancy_deg {
                return Verdict::Rejected(Rejection::WithinDiscrepancy {
                    gained_deg,
                    discrepancy_deg,
                });
            }
        }
        Verdict::Accepted(policy.kept)
    }

    /// Scores the fitted moves against the current set, best BIC first,
    /// and judges them under `policy` ([`Search::accept`]): the first
    /// accepted is the choice. With `round`, the round is recorded (the
    /// move it tried, whether moves screened out are listed, and how many
    /// scores to print first). Returns the chosen set and its held-out RMS.
    pub(super) fn judge(
        &mut self,
        fits: Vec<(Candidate, Option<FittedSet>, bool)>,
        policy: &Policy,
        round: Option<(Move, Record)>,
    ) -> Option<(FittedSet, Option<f64>)> {
        let keep_screened = round.as_ref().is_some_and(|(_, r)| r.screened);
        let current = self.current.clone();
        let mut scores: Vec<CandidateScore> = fits
            .into_iter()
            .filter(|(_, _, screened_out)| keep_screened || !screened_out)
            .filter_map(|(candidate, f, screened_out)| {
                let f = f?;
                Some(CandidateScore {
                    candidate,
                    delta_bic: current.bic() - f.bic(),
                    fitted: f,
                    held_out_rms_deg: None,
                    verdict: if screened_out {
                        Verdict::Screened
                    } else {
                        Verdict::NotJudged
                    },
                })
            })
            .collect();
        scores.sort_by(|a, b| b.delta_bic.total_cmp(&a.delta_bic));
        if let Some((_, r)) = &round {
            self.show_scores(&scores, r.show);
        }
        let chosen = self.choose(&mut scores, &current, policy);
        if round.as_ref().is_some_and(|(_, r)| r.screened) && self.eng.trace.scores {
            for s in scores
                .iter()
                .filter(|s| s.verdict != Verdict::NotJudged)
                .take(4)
            {
                self.eng.say(format!(
                    "    {}: {}",
                    labels(&s.fitted.candidates()),
                    s.verdict
                ));
            }
        }
        let next = chosen.map(|i| (scores[i].fitted.clone(), scores[i].held_out_rms_deg));
        if let Some((what, _)) = round {
            self.rounds.push(Round {
                start: current.candidates(),
                start_rms_deg: current.rms(),
                what,
                scores,
            });
        }
        next
    }

    /// Judges `scores` (best first) under `policy`, writing each verdict;
    /// the index of the first accepted.
    fn choose(
        &self,
        scores: &mut [CandidateScore],
        current: &FittedSet,
        policy: &Policy,
    ) -> Option<usize> {
        let (mut chosen, mut tried, mut held_checks) = (None, 0usize, 0usize);
        for (i, s) in scores.iter_mut().enumerate() {
            if s.verdict == Verdict::Screened {
                continue;
            }
            tried += 1;
            if tried > policy.tries {
                s.verdict = match policy.past_tries {
                    PastTries::NotTheBest => Verdict::NotTheBest {
                        delta_bic: s.delta_bic,
                    },
                    PastTries::NotJudged => Verdict::NotJudged,
                };
                continue;
            }
            if chosen.is_some() || held_checks >= policy.held_out_tries {
                s.verdict = Verdict::NotTheBest {
                    delta_bic: s.delta_bic,
                };
                continue;
            }
            let mut held = None;
            s.verdict = self.accept((current, self.current_held), &s.fitted, &mut held, policy);
            if held.is_some() {
                held_checks += 1;
            }
            s.held_out_rms_deg = held.flatten();
            if s.accepted() {
                chosen = Some(i);
            }
        }
        chosen
    }

    /// Prints the best scores of a round (`show` of them; all when the
    /// settings trace the scores, [`super::DiagnoseOptions::trace`]).
    fn show_scores(&self, scores: &[CandidateScore], show: usize) {
        let show = if self.eng.trace.scores {
            usize::MAX
        } else {
            show
        };
        for s in scores.iter().take(show) {
            self.eng.say(format!(
                "  {:<40} RMS {:.4} deg  dBIC {:>10.1}",
                labels(&s.fitted.candidates()),
                s.fitted.rms(),
                s.delta_bic
            ));
        }
    }
}

/// True when the 95 % interval of the value of every member of `f` that is
/// not in `current` excludes zero (a pair move adds two).
pub(super) fn new_members_clear(f: &FittedSet, current: &FittedSet) -> bool {
    f.members
        .iter()
        .filter(|m| !current.contains(&m.candidate))
        .all(|m| m.clear_of_zero())
}

impl Search<'_, '_> {
    /// Makes move `mv`: proposes its sets ([`Search::propose`]), screens
    /// and fits them, judges them by the move's policy and takes the
    /// choice when it leads to a set not visited (unless the policy allows
    /// it).
    pub(super) fn attempt(&mut self, mv: Move) -> Attempt {
        let Some(moves) = self.propose(mv) else {
            return Attempt::NotTried;
        };
        let c = self.eng.campaign;
        let fits = if mv.shares_torque() {
            self.eng.fit_moves_sharing(c, &moves)
        } else {
            self.eng.fit_moves(c, &moves)
        };
        let policy = mv.policy();
        let next = self.judge(fits, &policy, mv.record().map(|r| (mv, r)));
        match next {
            Some((f, held)) if policy.revisit || !self.seen.contains(&f.candidates()) => {
                self.take(mv, f, held);
                Attempt::Moved
            }
            _ => {
                if mv == Move::Swap {
                    self.eng.say("  no swap earns its keep: stop");
                }
                Attempt::Judged
            }
        }
    }

    /// The sets move `mv` proposes now; `None` when its conditions do not
    /// hold.
    fn propose(&mut self, mv: Move) -> Option<Proposal> {
        match mv {
            Move::Add => self.propose_add(),
            Move::Pair | Move::PairAfterSwap => self.propose_pair(),
            Move::Swap => self.propose_swap(),
            Move::Proposed => self.propose_proposed(),
            Move::JointPairs => self.propose_joint_pairs(),
            Move::Table => self.propose_tables(),
            Move::EvenTable => self.propose_even_tables(),
            Move::TablePair => self.propose_table_pairs(),
            Move::NamedForTable => Some(self.named_for_tables()),
            Move::Refine => self.propose_refine(),
            Move::StandInTable => self.propose_stand_in(),
            // Made by `Search::try_friction_forms` (its own screen from the
            // residual torque's starts, then the simpler-law exchange).
            Move::FrictionForms | Move::Simpler => None,
            // Judged after `Move::StandInTable` and its refinement
            // (`Search::replace_stand_in`).
            Move::StandIn => None,
            // Made after every move that drops (`Search::backward`) and at
            // the end of discovery (`Search::check_claims`).
            Move::Drop | Move::DropClaim => None,
            // Made at the end, above the noise (`super::discrepancy`).
            Move::SetAside => None,
            // Made by a second start of the search (`super::restart`).
            Move::Restart => None,
            // Fitted by the ambiguity stage (`super::ambiguity`).
            Move::Alternative | Move::Partner => None,
        }
    }

    /// Takes `f` (held-out RMS `held`) as the current set after move `mv`,
    /// then (unless the move keeps its set as found) drops what no longer
    /// earns its keep. A move whose policy asks no held-out RMS gets it
    /// computed here.
    pub(super) fn take(&mut self, mv: Move, f: FittedSet, held: Option<f64>) {
        self.eng.say(format!(
            "  {} {} (RMS {:.4} deg)",
            mv.done(),
            labels(&f.candidates()),
            f.rms()
        ));
        let held = if mv.policy().held_out {
            held
        } else {
            self.eng.held_out(&f)
        };
        let (f, held) = if mv.drops_after() {
            self.backward(f, held)
        } else {
            (f, held)
        };
        self.seen.push(f.candidates());
        self.current = f;
        self.current_held = held;
    }

    /// Runs the stepwise search to its end: at each step the moves of
    /// [`STEPWISE`] in order until one is taken ([`Move::PairAfterSwap`]
    /// only when the swap was tried); stop at the noise floor, when no
    /// move is taken, or after [`MAX_STEPS`].
    pub(super) fn run(&mut self) {
        for _ in 0..MAX_STEPS {
            if self.eng.halt.now() {
                self.eng
                    .say("search stopped early: the best set so far is kept");
                return;
            }
            if self.current.rms() <= self.floor() {
                self.eng.say(format!(
                    "residual {:.4} deg is down to the noise floor: stop",
                    self.current.rms()
                ));
                return;
            }
            let mut last = Attempt::NotTried;
            let mut moved = false;
            for mv in STEPWISE {
                if mv == Move::PairAfterSwap && last == Attempt::NotTried {
                    continue;
                }
                last = self.attempt(mv);
                if last == Attempt::Moved {
                    moved = true;
                    break;
                }
            }
            if !moved && !self.try_friction_forms() {
                return;
            }
        }
    }

    /// Named effects in the current set (discovered tables do not count
    /// against `max_effects`).
    pub(super) fn named_len(&self) -> usize {
        self.current
            .members
            .iter()
            .filter(|m| m.candidate.table.is_none())
            .count()
    }

    /// Candidates not in the current set.
    pub(super) fn outside(&self) -> Vec<Candidate> {
        self.candidates
            .iter()
            .copied()
            .filter(|c| !self.current.contains(c))
            .collect()
    }

    /// [`Move::Add`]: every candidate beside the current set.
    fn propose_add(&mut self) -> Option<Proposal> {
        if self.named_len() >= self.max_effects {
            return None;
        }
        let todo = self.outside();
        self.eng.say(format!(
            "round {}: fitting {} candidates beside {} (RMS {:.4} deg)",
            self.rounds.len() + 1,
            todo.len(),
            labels(&self.current.candidates()),
            self.current.rms()
        ));
        let moves = todo
            .iter()
            .map(|&c| Step::new(self.current.clone(), c))
            .collect();
        Some(moves)
    }

    /// [`Move::Pair`]: two causes that act together may each fail the
    /// held-out test alone (one effect cannot predict a run the other
    /// shapes). The [`PAIR_SEEDS`] best moves of the last round (an
    /// addition or a swap) by BIC, the training criterion, are each
    /// completed with every other candidate, the sets fitted jointly, and
    /// the held-out check applied to the set as a whole.
    fn propose_pair(&mut self) -> Option<Proposal> {
        let last = self.rounds.last()?;
        let room = |f: &FittedSet| {
            f.members
                .iter()
                .filter(|m| m.candidate.table.is_none())
                .count()
                < self.max_effects
        };
        let seeds: Vec<FittedSet> = last
            .scores
            .iter()
            .filter(|s| s.verdict != Verdict::Screened && room(&s.fitted))
            .take(PAIR_SEEDS)
            .map(|s| s.fitted.clone())
            .collect();
        if seeds.is_empty() {
            return None;
        }
        let last_of = |s: &FittedSet| s.members.last().map(|m| m.candidate);
        let mut moves = Vec::new();
        for (a, seed) in seeds.iter().enumerate() {
            let first = last_of(seed);
            for c in self.outside() {
                let earlier = seeds[..a].iter().any(|s| last_of(s) == Some(c));
                if Some(c) != first && !earlier {
                    moves.push(Step::new(seed.clone(), c));
                }
            }
        }
        let now = labels(&self.current.candidates());
        self.eng.say(format!(
            "pairs: fitting {} sets of two, seeded by the last round, beside {now}",
            moves.len(),
        ));
        Some(moves)
    }

    /// [`Move::Swap`]: replace one effect by another candidate (greedy
    /// steps can take a wrong turn when two effects act together). Every
    /// candidate may swap in: the moves are prescreened by their coarse
    /// scan. At most [`MAX_SWAPS`] per stepwise search.
    fn propose_swap(&mut self) -> Option<Proposal> {
        if self.current.members.is_empty() || self.swaps >= MAX_SWAPS {
            return None;
        }
        self.swaps += 1;
        let outside = self.outside();
        let mut moves = Vec::new();
        for k in 0..self.current.members.len() {
            let reduced = self.current.without(k);
            for c in &outside {
                moves.push(Step::new(reduced.clone(), *c));
            }
        }
        let now = labels(&self.current.candidates());
        self.eng.say(format!(
            "swap {}: trying {} replacements in {now}",
            self.swaps,
            moves.len(),
        ));
        Some(moves)
    }

    /// A move tried once per diagnosis: true the first time.
    pub(super) fn first_time(&mut self, mv: Move) -> bool {
        self.tried_once.insert(mv)
    }
}
