//! The one acceptance policy of the diagnosis (`docs/diagnosis.md`,
//! "Method", 5): whether a move earns its keep, as a typed [`Verdict`].
//!
//! The search is a list of moves ([`Move`]); every change of the current
//! set, the stepwise additions and the drops after them, discovery, the
//! exchanges of a friction form for a simpler law and of a global stand-in
//! for a table, a second start and an alternative alike, is judged by one
//! rule, `Search::accept` ([`super::moves`]), with the move's [`Policy`]
//! ([`Move::policy`]). The checks, in the order they run (the held-out RMS,
//! which costs a refit per run, and the residual torque of the stand-in
//! check only when the cheaper ones pass):
//! 1. the BIC gain over the current set exceeds [`Policy::min_delta_bic`]
//!    (negative for a move to a smaller or simpler set: kept unless it
//!    loses more than that);
//! 2. every effect the move adds has a 95 % interval clear of zero
//!    ([`Policy::intervals_clear`]);
//! 3. its RMS is within [`Policy::rms_share`] of the current set's (or of
//!    the noise floor);
//! 4. its residual is not clearly above the noise σ̂ ([`Policy::explains`],
//!    [`super::above_noise`]);
//! 5. its held-out RMS beats the current set's by [`HELD_OUT_SHARE`]
//!    ([`Policy::held_out`], with two or more runs);
//! 6. no global effect stands in for a joint torque
//!    ([`Policy::no_stand_in`], [`super::Engine::unexplained_torque`]);
//! 7. a move to a smaller set that sets a claim aside
//!    ([`Move::SetAside`]): what the claim accounted for is less than the
//!    discrepancy the current set leaves ([`Policy::within_discrepancy`],
//!    [`super::discrepancy`]);
//! 8. a move to another set after the drawing's tolerances took a member
//!    out ([`Move::Partner`]): what it gains is at least the discrepancy
//!    it leaves ([`Policy::beyond_discrepancy`]).
//!
//! Where the moves differ, the difference is a field of [`Policy`], set per
//! move in [`Move::policy`]; how many of a round's moves are judged, and
//! what the others are called, are fields too.
//!
//! The proposals are not judged here: which sets a move proposes (and the
//! start values of their screens) is the move's own
//! ([`super::moves`]). So is the residual-torque regression's bar for a
//! proposed pair (`residual_named::MIN_PAIR_GAIN`): it compares two
//! regressions of one joint's residual torque, without the simulator and
//! without a current set, to decide which pair is offered at all; the pair
//! offered is then judged like any move ([`Move::Proposed`]). The friction
//! forms' evidence ([`super::friction_forms`]) is a proposal rule the
//! same way.
//!
//! This module holds the rules as data (the verdicts, the [`Policy`], the
//! moves and each move's settings) and names no other module of the
//! diagnosis; [`super::moves`] applies them. The verdicts' words and what
//! a round tried are the report's (`report::diagnosis_outcome`).

/// ΔBIC an effect must gain to be kept ("very strong" evidence on the
/// Kass & Raftery 1995 scale).
pub const MIN_DELTA_BIC: f64 = 10.0;

/// A move must lower the held-out RMS below this share of the current
/// set's \[1\] (5 % better: a gain the noise of two runs does not give).
pub const HELD_OUT_SHARE: f64 = 0.95;

/// A named replacement of a table must fit within this share of the table
/// set's RMS (or of the noise floor) \[1\]: a better BIC alone would let a
/// pair of named stand-ins, with fewer parameters, replace a coarse table
/// that the refinement would have brought to the noise.
pub const NAMED_RMS_SHARE: f64 = 1.05;

/// A claim the data do not support ([`Move::DropClaim`]) is dropped only
/// when the set without it fits within this share of the set's RMS (or of
/// the noise floor) \[1\]: what the fit needs stays.
pub const CLAIM_RMS_SHARE: f64 = 1.1;

/// A claim must account for at least this share of the discrepancy its
/// set leaves above the noise to stay ([`Move::SetAside`],
/// [`super::discrepancy`]) \[1\]: dropping it must raise the SSE by at
/// least `DISCREPANCY_SHARE · (SSE − m σ̂²)`.
pub const DISCREPANCY_SHARE: f64 = 1.0;

/// Finer forms of a table judged per refinement round, best BIC first (as
/// many as a stepwise round judges).
pub const REFINE_TRIES: usize = 3;

/// Why a move was taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kept {
    /// It added (or exchanged) effects.
    Added,
    /// It refined a table already kept ([`super::refine`]).
    Refined,
    /// It dropped an effect, or exchanged one for a simpler law.
    Dropped,
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
    /// Its RMS \[deg\] is above the share of the current set's the policy
    /// allows \[deg\].
    RmsShare {
        /// Its RMS \[deg\].
        rms_deg: f64,
        /// The largest allowed \[deg\].
        limit_deg: f64,
    },
    /// Its residual [deg RMS] stays clearly above the noise.
    AboveNoise {
        /// Its RMS \[deg\].
        rms_deg: f64,
    },
    /// Its held-out RMS does not beat the current set's by
    /// [`HELD_OUT_SHARE`].
    HeldOut {
        /// Its held-out RMS \[deg\].
        held_deg: f64,
        /// The current set's \[deg\].
        current_deg: f64,
    },
    /// A global effect of it still stands in for a joint torque.
    StandInLeft,
    /// An effect it adds is a claim the data do not support
    /// ([`Move::DropClaim`]'s rule: its joint shows no evidence of it
    /// without it, and the set without it explains the runs within
    /// [`CLAIM_RMS_SHARE`] of its RMS): the check at the end of discovery
    /// would drop it again.
    UnsupportedClaim,
    /// A claim accounts for at least [`DISCREPANCY_SHARE`] of the
    /// discrepancy its set leaves ([`Move::SetAside`]'s rule): it stays.
    BeyondDiscrepancy {
        /// What the claim accounts for: the RMS of the SSE its loss adds
        /// \[deg\].
        explained_deg: f64,
        /// The discrepancy: the RMS of the set's SSE above the noise,
        /// `√((SSE − m σ̂²)/m)` \[deg\].
        discrepancy_deg: f64,
    },
    /// What the move gains is less than [`DISCREPANCY_SHARE`] of the
    /// discrepancy it leaves ([`Move::Partner`]'s rule): the runs cannot
    /// tell the two sets apart beyond it.
    WithinDiscrepancy {
        /// What the move gains: the RMS of the SSE it takes off \[deg\].
        gained_deg: f64,
        /// The discrepancy the move's set leaves above the noise,
        /// `√((SSE_to − m σ̂²)/m)` \[deg\].
        discrepancy_deg: f64,
    },
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

/// The verdict of moves past a round's judged ones.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PastTries {
    /// [`Verdict::NotTheBest`].
    NotTheBest,
    /// [`Verdict::NotJudged`].
    NotJudged,
}

/// How a move is judged: the one rule ([`super::Search::accept`]) with the
/// differences between moves as explicit settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Policy {
    /// The BIC gain must exceed this: [`MIN_DELTA_BIC`]; 0 for a named
    /// effect in place of a table (as good a fit with fewer parameters);
    /// −[`MIN_DELTA_BIC`] for a move to a smaller or simpler set (taken
    /// unless the BIC loses [`MIN_DELTA_BIC`] or more); −∞ where the BIC is
    /// not asked.
    pub min_delta_bic: f64,
    /// Every added effect's 95 % interval must be clear of zero (not asked
    /// of a refinement, whose finer knots share the torque).
    pub intervals_clear: bool,
    /// The RMS must be within this share of the current set's (or of the
    /// noise floor, when larger) \[1\].
    pub rms_share: Option<f64>,
    /// The residual must not stay clearly above the noise (the move
    /// explains the data).
    pub explains: bool,
    /// The held-out RMS must beat the current set's by [`HELD_OUT_SHARE`].
    pub held_out: bool,
    /// No global effect may be left standing in for a joint torque.
    pub no_stand_in: bool,
    /// A move to a smaller set: what it drops must account for less than
    /// [`DISCREPANCY_SHARE`] of the discrepancy the current set leaves
    /// above the noise ([`Move::SetAside`]).
    pub within_discrepancy: bool,
    /// A move to another set: what it gains over the current set must be
    /// at least [`DISCREPANCY_SHARE`] of the discrepancy it leaves above
    /// the noise ([`Move::Partner`]): `SSE − SSE_to ≥ DISCREPANCY_SHARE ·
    /// (SSE_to − m σ̂²)`.
    pub beyond_discrepancy: bool,
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
        within_discrepancy: false,
        beyond_discrepancy: false,
        tries: 3,
        held_out_tries: usize::MAX,
        past_tries: PastTries::NotTheBest,
        revisit: false,
        kept: Kept::Added,
    };

    /// A move to a smaller or simpler set ([`Move::Drop`],
    /// [`Move::Simpler`]): taken unless its BIC is worse by
    /// [`MIN_DELTA_BIC`] or more; nothing else is asked (the set it leaves
    /// passed the other checks); the best by BIC is judged.
    pub const SMALLER: Policy = Policy {
        min_delta_bic: -MIN_DELTA_BIC,
        intervals_clear: false,
        rms_share: None,
        explains: false,
        held_out: false,
        no_stand_in: false,
        within_discrepancy: false,
        beyond_discrepancy: false,
        tries: 1,
        held_out_tries: usize::MAX,
        past_tries: PastTries::NotJudged,
        revisit: true,
        kept: Kept::Dropped,
    };
}

/// A move of the search.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Move {
    /// Add the best single candidate.
    Add,
    /// Complete the [`super::PAIR_SEEDS`] best sets of the last round with every
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
    /// Two tables at two joints together (the first tables, when no
    /// single table was kept): torques missing at two joints, where a
    /// table fitted at one of them alone takes a shape that does not
    /// predict the runs left out.
    TablePair,
    /// A named effect (or a pair at its joint) in place of a table.
    NamedForTable,
    /// A table in a finer form ([`super::refine`]).
    Refine,
    /// A table at the joint a global stand-in hides, in place of that
    /// global effect ([`super::stand_in`]).
    StandInTable,
    /// The set after [`Move::StandInTable`] and its refinement, in place of
    /// the set with the stand-in ([`super::stand_in`]): it must also
    /// explain the data and leave no global stand-in.
    StandIn,
    /// A Stribeck law or quadratic damping where the residual torque has
    /// its rate shape, once the stepwise moves stall above the noise
    /// ([`super::friction_forms`]; its own screen from the regression's
    /// start values).
    FrictionForms,
    /// The simpler law of a friction form just taken in its place (Coulomb
    /// friction for a Stribeck law; viscous damping or air drag for
    /// quadratic damping): kept when it explains the runs as well
    /// ([`Policy::SMALLER`]).
    Simpler,
    /// An effect that no longer earns its keep beside the others, dropped
    /// after a move (the best drop by BIC, [`Policy::SMALLER`]).
    Drop,
    /// A claim the data do not support dropped at the end of discovery
    /// (its joint shows no evidence of it without it, or its interval
    /// holds zero) when the fit hardly notices: the set without it within
    /// [`CLAIM_RMS_SHARE`] of the set's RMS, whatever its BIC.
    DropClaim,
    /// A claim set aside at the end, when the set found leaves a residual
    /// clearly above the noise: the set without it (the others refitted)
    /// loses less than [`DISCREPANCY_SHARE`] of that discrepancy
    /// ([`super::discrepancy`]), whatever its BIC.
    SetAside,
    /// The set a second start of the search reached, in place of the
    /// current one ([`super::restart`]).
    Restart,
    /// A set the ambiguity stage fitted in place of what the set holds at
    /// a joint, in place of the current one ([`super::ambiguity`]).
    Alternative,
    /// A set the ambiguity stage fitted in place of the partner that an
    /// effect the drawing's tolerances took out left at its joint
    /// ([`super::tolerance`], `Search::partners_after_tolerances`): judged
    /// as [`Move::Alternative`], and what it gains must be at least
    /// [`DISCREPANCY_SHARE`] of the discrepancy it leaves above the noise
    /// ([`Policy::beyond_discrepancy`]): a wing built within its
    /// tolerances leaves that discrepancy, and a gain within it is one the
    /// wing as built can make.
    Partner,
}

/// The stepwise moves in the order tried: the first that moves ends the
/// step ([`super::Search::run`]).
pub const STEPWISE: [Move; 6] = [
    Move::Add,
    Move::Pair,
    Move::Swap,
    Move::PairAfterSwap,
    Move::Proposed,
    Move::JointPairs,
];

/// How a move's round is recorded in [`super::Outcome::rounds`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Record {
    /// Moves screened out are listed (as [`Verdict::Screened`]).
    pub screened: bool,
    /// How many scores are printed first.
    pub show: usize,
}

/// What became of an attempted move.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Attempt {
    /// Its conditions did not hold: nothing was fitted.
    NotTried,
    /// Fitted and judged; nothing taken.
    Judged,
    /// Taken.
    Moved,
}

impl Move {
    /// The acceptance policy of the move ([`super::Search::accept`]).
    pub fn policy(self) -> Policy {
        let s = Policy::STEPWISE;
        match self {
            // As good a fit with fewer parameters, that explains the data:
            // a better BIC (not by 10), its RMS within `NAMED_RMS_SHARE` of
            // the table set's, its residual not above the noise; no
            // held-out check; the set found may be one visited before.
            Move::NamedForTable => Policy {
                min_delta_bic: 0.0,
                rms_share: Some(NAMED_RMS_SHARE),
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
            // Judged whole: a better BIC and held-out RMS (a second start's
            // members were judged by the moves that made it, an
            // alternative's are clear of zero).
            Move::Restart | Move::Alternative => Policy {
                intervals_clear: false,
                ..s
            },
            Move::Partner => Policy {
                beyond_discrepancy: true,
                ..Move::Alternative.policy()
            },
            // A refinement reshapes a table already kept: its knots'
            // intervals are not asked to be clear of zero.
            Move::Refine => Policy {
                intervals_clear: false,
                tries: REFINE_TRIES,
                past_tries: PastTries::NotJudged,
                kept: Kept::Refined,
                ..s
            },
            // The table and its refinement against the set with the
            // stand-in: a better BIC and held-out RMS, a residual not above
            // the noise and no global stand-in left; its tables' intervals
            // were judged when they were taken.
            Move::StandIn => Policy {
                intervals_clear: false,
                explains: true,
                no_stand_in: true,
                ..s
            },
            Move::Drop | Move::Simpler => Policy::SMALLER,
            // The fit hardly notices: only the RMS is asked.
            Move::DropClaim => Policy {
                min_delta_bic: f64::NEG_INFINITY,
                rms_share: Some(CLAIM_RMS_SHARE),
                ..Policy::SMALLER
            },
            // The runs cannot tell the claim from the discrepancy: only
            // that is asked.
            Move::SetAside => Policy {
                min_delta_bic: f64::NEG_INFINITY,
                within_discrepancy: true,
                ..Policy::SMALLER
            },
            Move::Add
            | Move::Pair
            | Move::Swap
            | Move::PairAfterSwap
            | Move::Proposed
            | Move::Table
            | Move::EvenTable
            | Move::TablePair
            | Move::StandInTable
            | Move::FrictionForms => s,
        }
    }

    /// Whether the screen also starts the move where two named effects at
    /// a joint share their torque ([`super::Engine::fit_moves_sharing`]).
    pub fn shares_torque(self) -> bool {
        matches!(self, Move::NamedForTable | Move::JointPairs)
    }

    /// How its round is recorded; `None`: not recorded.
    pub fn record(self) -> Option<Record> {
        match self {
            Move::NamedForTable
            | Move::JointPairs
            | Move::StandIn
            | Move::Simpler
            | Move::Drop
            | Move::DropClaim
            | Move::SetAside => None,
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
    /// ([`Move::Drop`], `Search::backward`).
    pub fn drops_after(self) -> bool {
        !matches!(
            self,
            Move::NamedForTable
                | Move::Drop
                | Move::DropClaim
                | Move::SetAside
                | Move::Simpler
                | Move::StandIn
        )
    }

    /// What the progress line says when it is taken.
    pub fn done(self) -> &'static str {
        match self {
            Move::Add => "added:",
            Move::Pair | Move::PairAfterSwap => "added the pair:",
            Move::Swap => "swapped to",
            Move::Proposed => "proposed by the residual torque:",
            Move::JointPairs => "named pair at a joint:",
            Move::Table | Move::EvenTable => "discovered:",
            Move::TablePair => "discovered the pair:",
            Move::NamedForTable => "a named effect explains it as well:",
            Move::Refine => "refined:",
            Move::StandInTable => "a table in place of a global stand-in:",
            Move::StandIn => "the table explains the data the stand-in held:",
            Move::Simpler => "the simpler law explains the runs as well:",
            Move::Drop => "dropped, no longer earns its keep:",
            Move::DropClaim => "dropped, a claim the data do not support:",
            Move::SetAside => "set aside, the runs cannot tell it from the discrepancy:",
            Move::FrictionForms => "a friction form:",
            Move::Restart => "a second start reached",
            Move::Alternative => "an alternative of the ambiguity stage beats the set found:",
            Move::Partner => {
                "after the drawing's tolerances, an alternative of the ambiguity stage beats the set found:"
            }
        }
    }
}
