//! The moves of the diagnosis search and the one place they are made
//! ([`Search::attempt`]): each move proposes sets (a base set plus a
//! candidate), they are screened and fitted ([`super::screen`]), judged by
//! the one acceptance policy ([`super::policy`]) with the move's
//! [`Policy`], and the choice is taken. The stepwise search is one loop
//! over [`STEPWISE`]; discovery, refinement and the stand-in check make
//! their moves through the same [`Search::attempt`].

use super::candidate::Candidate;
use super::outcome::FittedSet;
use super::policy::{Kept, PastTries, Policy, Verdict};
use super::{labels, Search, MAX_STEPS, MAX_SWAPS, PAIR_SEEDS};

/// A move of the search.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) enum Move {
    /// Add the best single candidate.
    Add,
    /// Complete the [`PAIR_SEEDS`] best sets of the last round with every
    /// other candidate (two causes that only earn their keep together).
    Pair,
    /// Replace one effect by another candidate.
    Swap,
    /// [`Move::Pair`] seeded by the swap round (one effect replaced by two).
    PairAfterSwap,
    /// The pairs of named effects at one joint the baseline's residual
    /// torque proposes, in place of the set (once).
    Proposed,
    /// Named pairs at a joint in place of its named effects (once).
    JointPairs,
    /// A torque table at the joints whose residual torque is significant.
    Table,
    /// The even tables at every joint (the first table, when the evidence's
    /// were not kept).
    EvenTable,
    /// A named effect (or a pair at its joint) in place of a table.
    NamedForTable,
    /// A table in a finer form ([`super::refine`]).
    Refine,
    /// A table in place of a global stand-in ([`super::stand_in`]).
    StandIn,
}

/// The stepwise moves in the order tried: the first that moves ends the
/// step ([`Search::run`]).
pub(super) const STEPWISE: [Move; 6] = [
    Move::Add,
    Move::Pair,
    Move::Swap,
    Move::PairAfterSwap,
    Move::Proposed,
    Move::JointPairs,
];

/// How a move's round is recorded in [`super::Outcome::rounds`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Record {
    /// Moves screened out are listed (as [`Verdict::Screened`]).
    pub screened: bool,
    /// How many scores are printed first.
    pub show: usize,
}

/// What became of an attempted move.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Attempt {
    /// Its conditions did not hold: nothing was fitted.
    NotTried,
    /// Fitted and judged; nothing taken.
    Judged,
    /// Taken.
    Moved,
}

impl Move {
    /// The acceptance policy of the move ([`Search::accept`]).
    pub(super) fn policy(self) -> Policy {
        let s = Policy::STEPWISE;
        match self {
            // As good a fit with fewer parameters, that explains the data:
            // a better BIC (not by 10), its RMS within `NAMED_RMS_SHARE` of
            // the table set's, its residual not above the noise; no
            // held-out check; the set found may be one visited before.
            Move::NamedForTable => Policy {
                min_delta_bic: 0.0,
                rms_share: Some(super::NAMED_RMS_SHARE),
                explains: true,
                held_out: false,
                tries: usize::MAX,
                revisit: true,
                ..s
            },
            // The best by BIC that passes the others, whose held-out RMS
            // is checked alone; it must explain the data.
            Move::JointPairs => Policy {
                explains: true,
                tries: usize::MAX,
                held_out_tries: 1,
                ..s
            },
            // A refinement reshapes a table already kept: its knots'
            // intervals are not asked to be clear of zero.
            Move::Refine => Policy {
                intervals_clear: false,
                tries: super::refine::REFINE_TRIES,
                past_tries: PastTries::NotJudged,
                kept: Kept::Refined,
                ..s
            },
            _ => s,
        }
    }

    /// Whether the screen also starts the move where two named effects at
    /// a joint share their torque ([`super::Engine::fit_moves_sharing`]).
    fn shares_torque(self) -> bool {
        matches!(self, Move::NamedForTable | Move::JointPairs)
    }

    /// How its round is recorded; `None`: not recorded.
    fn record(self) -> Option<Record> {
        match self {
            Move::NamedForTable | Move::JointPairs => None,
            Move::Refine => Some(Record {
                screened: false,
                show: usize::MAX,
            }),
            _ => Some(Record {
                screened: true,
                show: 5,
            }),
        }
    }

    /// Whether effects that no longer earn their keep are dropped after it
    /// ([`super::Engine::backward`]).
    fn drops_after(self) -> bool {
        self != Move::NamedForTable
    }

    /// What the progress line says when it is taken.
    fn done(self) -> &'static str {
        match self {
            Move::Add => "added:",
            Move::Pair | Move::PairAfterSwap => "added the pair:",
            Move::Swap => "swapped to",
            Move::Proposed => "proposed by the residual torque:",
            Move::JointPairs => "named pair at a joint:",
            Move::Table | Move::EvenTable => "discovered:",
            Move::NamedForTable => "a named effect explains it as well:",
            Move::Refine => "refined:",
            Move::StandIn => "a table in place of a global stand-in:",
        }
    }
}

/// The sets a move proposes (each a base set plus a candidate) and what its
/// round tried, in words.
pub(super) type Proposal = (Vec<(FittedSet, Candidate)>, String);

impl Search<'_, '_> {
    /// Makes move `mv`: proposes its sets ([`Search::propose`]), screens
    /// and fits them, judges them by the move's policy and takes the
    /// choice when it leads to a set not visited (unless the policy allows
    /// it).
    pub(super) fn attempt(&mut self, mv: Move) -> Attempt {
        let Some((moves, what)) = self.propose(mv) else {
            return Attempt::NotTried;
        };
        let c = self.eng.campaign;
        let fits = if mv.shares_torque() {
            self.eng.fit_moves_sharing(c, &moves)
        } else {
            self.eng.fit_moves(c, &moves)
        };
        let policy = mv.policy();
        let next = self.judge(fits, &policy, mv.record().map(|r| (what, r)));
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
            Move::NamedForTable => Some((self.named_for_tables(), String::new())),
            Move::Refine => self.propose_refine(),
            Move::StandIn => self.propose_stand_in(),
        }
    }

    /// Takes `f` (held-out RMS `held`) as the current set after move `mv`,
    /// then (unless the move keeps its set as found) drops what no longer
    /// earns its keep. A move whose policy asks no held-out RMS gets it
    /// computed here.
    fn take(&mut self, mv: Move, f: FittedSet, held: Option<f64>) {
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
            self.eng.backward(f, held)
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
            if !moved {
                return;
            }
        }
    }

    /// Named effects in the current set (discovered tables do not count
    /// against `max_effects`).
    fn named_len(&self) -> usize {
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
        let moves = todo.iter().map(|&c| (self.current.clone(), c)).collect();
        let what = format!("add to {}", labels(&self.current.candidates()));
        Some((moves, what))
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
                    moves.push((seed.clone(), c));
                }
            }
        }
        let now = labels(&self.current.candidates());
        self.eng.say(format!(
            "pairs: fitting {} sets of two, seeded by the last round, beside {now}",
            moves.len(),
        ));
        Some((moves, format!("add a pair to {now}")))
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
                moves.push((reduced.clone(), *c));
            }
        }
        let now = labels(&self.current.candidates());
        self.eng.say(format!(
            "swap {}: trying {} replacements in {now}",
            self.swaps,
            moves.len(),
        ));
        Some((moves, format!("swap one of {now}")))
    }

    /// A move tried once per diagnosis: true the first time.
    pub(super) fn first_time(&mut self, mv: Move) -> bool {
        self.tried_once.insert(mv)
    }
}
