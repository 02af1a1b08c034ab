//! The one acceptance policy of the diagnosis (`docs/diagnosis.md`,
//! "Method", 5): whether a move earns its keep, as a typed [`Verdict`].
//!
//! Every move of the search ([`super::moves::Move`]) is judged here, by
//! [`Search::accept`] with the move's [`Policy`]. The checks, in the order
//! they run (the held-out RMS, which costs a refit per run, and the
//! residual torque of the stand-in check only when the cheaper ones pass):
//! 1. the BIC gain over the current set exceeds [`Policy::min_delta_bic`];
//! 2. every effect the move adds has a 95 % interval clear of zero
//!    ([`Policy::intervals_clear`]);
//! 3. its RMS is within [`Policy::rms_share`] of the current set's (or of
//!    the noise floor);
//! 4. its residual is not clearly above the noise σ̂ ([`Policy::explains`],
//!    [`super::above_noise`]);
//! 5. its held-out RMS beats the current set's by [`HELD_OUT_SHARE`]
//!    ([`Policy::held_out`], with two or more runs);
//! 6. no global effect stands in for a joint torque
//!    ([`Policy::no_stand_in`], [`super::Engine::unexplained_torque`]).
//!
//! Where the moves differ, the difference is a field of [`Policy`], set per
//! move in [`super::moves::Move::policy`].

use super::candidate::Candidate;
use super::outcome::{CandidateScore, FittedSet, Round};
use super::{above_noise, labels, Search, HELD_OUT_SHARE, MIN_DELTA_BIC};
use std::fmt;

/// Why a move was taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kept {
    /// It added (or exchanged) effects.
    Added,
    /// It refined a table already kept ([`super::refine`]).
    Refined,
}

/// Why a move that was judged was not taken.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Rejection {
    /// Its BIC gain is not above the policy's minimum.
    BicGain {
        /// The gain.
        delta_bic: f64,
        /// The minimum it had to exceed.
        min: f64,
    },
    /// An added effect's 95 % interval contains zero.
    IntervalHoldsZero,
    /// Its RMS [deg] is above the share of the current set's the policy
    /// allows [deg].
    RmsShare {
        /// Its RMS [deg].
        rms_deg: f64,
        /// The largest allowed [deg].
        limit_deg: f64,
    },
    /// Its residual [deg RMS] stays clearly above the noise.
    AboveNoise {
        /// Its RMS [deg].
        rms_deg: f64,
    },
    /// Its held-out RMS does not beat the current set's by
    /// [`HELD_OUT_SHARE`].
    HeldOut {
        /// Its held-out RMS [deg].
        held_deg: f64,
        /// The current set's [deg].
        current_deg: f64,
    },
    /// A global effect of it still stands in for a joint torque.
    StandInLeft,
}

/// What the search made of one candidate move.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Verdict {
    /// Not fitted: its coarse scan ranked it below the moves fitted fully.
    Screened,
    /// Fitted but not judged (beyond the moves a round judges).
    NotJudged,
    /// Not judged because a better move (by BIC) was taken, or beyond the
    /// moves a round judges.
    NotTheBest {
        /// Its BIC gain.
        delta_bic: f64,
    },
    /// Judged and not taken.
    Rejected(Rejection),
    /// Judged and taken.
    Accepted(Kept),
}

impl fmt::Display for Verdict {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Verdict::Screened => f.write_str("screened out by the coarse scan"),
            Verdict::NotJudged => Ok(()),
            Verdict::NotTheBest { delta_bic } => write!(f, "dBIC {delta_bic:.1}, not the best"),
            Verdict::Rejected(r) => r.fmt(f),
            Verdict::Accepted(Kept::Added) => f.write_str("earns its keep: added"),
            Verdict::Accepted(Kept::Refined) => f.write_str("earns its keep: refined"),
        }
    }
}

impl fmt::Display for Rejection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Rejection::BicGain { delta_bic, min } => write!(f, "BIC gain {delta_bic:.1} ≤ {min}"),
            Rejection::IntervalHoldsZero => f.write_str("a 95 % interval contains zero"),
            Rejection::RmsShare { rms_deg, limit_deg } => {
                write!(f, "RMS {rms_deg:.4} deg above {limit_deg:.4} deg")
            }
            Rejection::AboveNoise { rms_deg } => {
                write!(f, "residual {rms_deg:.4} deg stays above the noise")
            }
            Rejection::HeldOut {
                held_deg,
                current_deg,
            } => write!(
                f,
                "held-out RMS {held_deg:.4} deg does not beat {current_deg:.4} deg"
            ),
            Rejection::StandInLeft => {
                f.write_str("a global effect still stands in for a joint torque")
            }
        }
    }
}

/// The verdict of moves past a round's judged ones.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PastTries {
    /// [`Verdict::NotTheBest`].
    NotTheBest,
    /// [`Verdict::NotJudged`].
    NotJudged,
}

/// How a move is judged: the one rule ([`Search::accept`]) with the
/// differences between moves as explicit settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Policy {
    /// The BIC gain must exceed this: [`MIN_DELTA_BIC`], or 0 for a named
    /// effect in place of a table (as good a fit with fewer parameters).
    pub min_delta_bic: f64,
    /// Every added effect's 95 % interval must be clear of zero (not asked
    /// of a refinement, whose finer knots share the torque).
    pub intervals_clear: bool,
    /// The RMS must be within this share of the current set's (or of the
    /// noise floor, when larger) [1].
    pub rms_share: Option<f64>,
    /// The residual must not stay clearly above the noise (the move
    /// explains the data).
    pub explains: bool,
    /// The held-out RMS must beat the current set's by [`HELD_OUT_SHARE`].
    pub held_out: bool,
    /// No global effect may be left standing in for a joint torque.
    pub no_stand_in: bool,
    /// The best this many moves by BIC are judged.
    pub tries: usize,
    /// Judging stops after this many held-out checks (the costly one).
    pub held_out_tries: usize,
    /// What the moves past [`Policy::tries`] are called.
    pub past_tries: PastTries,
    /// A move may lead back to a set already visited.
    pub revisit: bool,
    /// What an accepted move is called.
    pub kept: Kept,
}

impl Policy {
    /// A stepwise move (an addition, a pair, a swap, a table): ΔBIC >
    /// [`MIN_DELTA_BIC`], intervals clear of zero, the held-out RMS 5 %
    /// better; the best 3 by BIC are judged.
    pub const STEPWISE: Policy = Policy {
        min_delta_bic: MIN_DELTA_BIC,
        intervals_clear: true,
        rms_share: None,
        explains: false,
        held_out: true,
        no_stand_in: false,
        tries: 3,
        held_out_tries: usize::MAX,
        past_tries: PastTries::NotTheBest,
        revisit: false,
        kept: Kept::Added,
    };
}

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
        Verdict::Accepted(policy.kept)
    }

    /// Scores the fitted moves against the current set, best BIC first,
    /// and judges them under `policy` ([`Search::accept`]): the first
    /// accepted is the choice. With `round`, the round is recorded (its
    /// description, whether moves screened out are listed, and how many
    /// scores to print first). Returns the chosen set and its held-out RMS.
    pub(super) fn judge(
        &mut self,
        fits: Vec<(Candidate, Option<FittedSet>, bool)>,
        policy: &Policy,
        round: Option<(String, super::moves::Record)>,
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
        if round.as_ref().is_some_and(|(_, r)| r.screened) && trace() {
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

    /// Prints the best scores of a round (`show` of them; all with
    /// `DEPLOYWATCH_TRACE`).
    fn show_scores(&self, scores: &[CandidateScore], show: usize) {
        let show = if trace() { usize::MAX } else { show };
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

/// Whether `DEPLOYWATCH_TRACE` asks for every score and verdict.
fn trace() -> bool {
    std::env::var_os("DEPLOYWATCH_TRACE").is_some()
}

/// True when the 95 % interval of the value of every member of `f` that is
/// not in `current` excludes zero (a pair move adds two).
pub(super) fn new_members_clear(f: &FittedSet, current: &FittedSet) -> bool {
    f.members
        .iter()
        .filter(|m| !current.contains(&m.candidate))
        .all(|m| m.clear_of_zero())
}
