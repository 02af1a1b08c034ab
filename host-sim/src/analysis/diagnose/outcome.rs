//! What a diagnosis finds: fitted sets of effects, the scores of each
//! round's candidates, the options, and the outcome.

use super::candidate::Candidate;
use super::discover;
use super::evidence::ResidualPlace;
use super::latch_finding::LatchFinding;
use super::latch_window::RunWindow;
pub use super::policy::{Move, Verdict};
use super::residual_torque::JointTorque;
use super::table_form::TableForm;
use crate::model::effect::{Effect, EffectKind};

/// The 95 % quantile of χ² with two degrees of freedom (`−2 ln 0.05`).
pub const CHI2_2DOF_95: f64 = 5.991_464_547_107_979;

/// One effect of a fitted set: the candidate, its parameters and, once
/// fitted, their 95 % intervals.
#[derive(Clone, Debug, PartialEq)]
pub struct FittedEffect {
    /// The candidate.
    pub candidate: Candidate,
    /// Its parameters ([`Candidate::params`] of them), in its unit.
    pub params: Vec<f64>,
    /// 95 % interval of each parameter as reported: the fit's
    /// autocorrelation-consistent interval, never narrower than the
    /// ordinary one ([`crate::analysis::fit::FitResult::ci95`]), widened
    /// over an ambiguity group ([`super::ambiguity::widened`]) and by the
    /// drawing's declared tolerances
    /// ([`super::tolerance`]); `None` for
    /// a point not fitted (a start, a screen's best scan point).
    pub ci95: Option<Vec<[f64; 2]>>,
    /// The fit's ordinary (white-noise) 95 % interval of each parameter
    /// ([`crate::analysis::fit::FitResult::ci95_ols`]): the search's
    /// statistic ([`FittedEffect::clear_of_zero`]); `None` when not fitted.
    pub ci95_search: Option<Vec<[f64; 2]>>,
}

impl FittedEffect {
    /// An effect at `params`, not fitted (no intervals).
    pub fn start(candidate: Candidate, params: Vec<f64>) -> FittedEffect {
        FittedEffect {
            candidate,
            params,
            ci95: None,
            ci95_search: None,
        }
    }

    /// The value interval (and a tilt's direction interval); unbounded when
    /// not fitted.
    pub fn value_ci(&self) -> ([f64; 2], Option<[f64; 2]>) {
        match &self.ci95 {
            Some(ci) => self.candidate.value_ci(&self.params, ci),
            None => ([f64::NEG_INFINITY, f64::INFINITY], None),
        }
    }

    /// The search's statistic: the value's ordinary 95 % interval
    /// ([`FittedEffect::ci95_search`]; the reported one where there is
    /// none), unbounded when not fitted.
    pub fn search_value_ci(&self) -> [f64; 2] {
        match self.ci95_search.as_ref().or(self.ci95.as_ref()) {
            Some(ci) => self.candidate.value_ci(&self.params, ci).0,
            None => [f64::NEG_INFINITY, f64::INFINITY],
        }
    }

    /// True when the value's ordinary 95 % interval excludes zero (never
    /// for an effect not fitted): the search's rule, on the fit's
    /// white-noise statistic ([`FittedEffect::ci95_search`]) rather than
    /// the wider interval it reports. A rig tilt is the in-plane gravity vector
    /// `(g_x, g_y)`: it is clear of zero when the vector is, by the joint
    /// test `(g_x/s_x)² + (g_y/s_y)² > χ²₂(0.95)` ([`CHI2_2DOF_95`]; `s` the
    /// components' standard errors, half their 95 % intervals over 1.96) —
    /// the magnitude's interval by first-order propagation is too narrow
    /// near zero, where a vector of noise still has a length.
    pub fn clear_of_zero(&self) -> bool {
        if self.candidate.kind == EffectKind::RigTilt && self.candidate.table.is_none() {
            let Some(ci) = self.ci95_search.as_ref().or(self.ci95.as_ref()) else {
                return false;
            };
            let z = |k: usize| {
                let (Some(p), Some(c)) = (self.params.get(k), ci.get(k)) else {
                    return 0.0;
                };
                let s = 0.5 * (c[1] - c[0]) / crate::analysis::fit::Z_975;
                if s > 0.0 {
                    (p / s).powi(2)
                } else {
                    f64::INFINITY
                }
            };
            return z(0) + z(1) > CHI2_2DOF_95;
        }
        let [lo, hi] = self.search_value_ci();
        lo > 0.0 || hi < 0.0
    }
}

/// What a set's residuals over all runs came to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitStats {
    /// Sum of squared residuals over all runs \[deg²\].
    pub sse: f64,
    /// Number of residuals.
    pub m: usize,
    /// Simulations used to fit it (per run); 0 for a point not fitted.
    pub evaluations: usize,
}

/// A set of effects with their parameters and, once simulated, its fit
/// statistics.
#[derive(Clone, Debug, PartialEq)]
pub struct FittedSet {
    /// The effects, in selection order.
    pub members: Vec<FittedEffect>,
    /// Its residuals' statistics; `None` when not simulated at these
    /// parameters (a set with a member taken out, say).
    pub stats: Option<FitStats>,
}

impl FittedSet {
    /// The set of `set` at the concatenated parameters `params` (and
    /// intervals `ci95`, when fitted), with `stats`.
    pub fn from_flat(
        set: &[Candidate],
        params: &[f64],
        ci95: Option<&[[f64; 2]]>,
        stats: Option<FitStats>,
    ) -> FittedSet {
        let mut members = Vec::with_capacity(set.len());
        let mut off = 0;
        for c in set {
            let n = c.params();
            members.push(FittedEffect {
                candidate: *c,
                params: params.get(off..off + n).unwrap_or_default().to_vec(),
                ci95: ci95.and_then(|ci| ci.get(off..off + n)).map(<[_]>::to_vec),
                ci95_search: None,
            });
            off += n;
        }
        FittedSet { members, stats }
    }

    /// The set with the fit's ordinary intervals `ci95_ols` (concatenated
    /// in the set's order) as each member's search statistic
    /// ([`FittedEffect::ci95_search`]).
    pub fn with_search_intervals(mut self, ci95_ols: &[[f64; 2]]) -> FittedSet {
        let mut off = 0;
        for m in self.members.iter_mut() {
            let n = m.candidate.params();
            m.ci95_search = ci95_ols.get(off..off + n).map(<[_]>::to_vec);
            off += n;
        }
        self
    }

    /// The candidates, in selection order.
    pub fn candidates(&self) -> Vec<Candidate> {
        self.members.iter().map(|m| m.candidate).collect()
    }

    /// Whether `c` is a member.
    pub fn contains(&self, c: &Candidate) -> bool {
        self.members.iter().any(|m| m.candidate == *c)
    }

    /// All parameters, concatenated in member order (a fit's vector).
    pub fn params(&self) -> Vec<f64> {
        self.members
            .iter()
            .flat_map(|m| m.params.iter().copied())
            .collect()
    }

    /// Sum of squared residuals \[deg²\]; infinite when not simulated.
    pub fn sse(&self) -> f64 {
        self.stats.map_or(f64::INFINITY, |s| s.sse)
    }

    /// The effects.
    pub fn effects(&self) -> Vec<Effect> {
        self.members
            .iter()
            .map(|m| m.candidate.effect(&m.params))
            .collect()
    }

    /// RMS of the residuals \[deg\]; infinite when not simulated.
    pub fn rms(&self) -> f64 {
        match self.stats {
            Some(s) => (s.sse / s.m.max(1) as f64).sqrt(),
            None => f64::INFINITY,
        }
    }

    /// The set without its `k`-th effect, the others' parameters and
    /// intervals kept (not refitted, so without statistics).
    pub fn without(&self, k: usize) -> FittedSet {
        let mut members = self.members.clone();
        if k < members.len() {
            members.remove(k);
        }
        FittedSet {
            members,
            stats: None,
        }
    }

    /// The set with `e` added (not refitted, so without statistics).
    pub fn with(&self, e: FittedEffect) -> FittedSet {
        let mut members = self.members.clone();
        members.push(e);
        FittedSet {
            members,
            stats: None,
        }
    }

    /// The value interval (and a tilt's direction interval) of the `k`-th
    /// effect; unbounded when not fitted.
    pub fn effect_ci(&self, k: usize) -> ([f64; 2], Option<[f64; 2]>) {
        match self.members.get(k) {
            Some(m) => m.value_ci(),
            None => ([f64::NEG_INFINITY, f64::INFINITY], None),
        }
    }

    /// The parameters and their 95 % intervals of the `k`-th effect, when
    /// fitted.
    pub fn effect_params(&self, k: usize) -> Option<(&[f64], &[[f64; 2]])> {
        let m = self.members.get(k)?;
        Some((&m.params, m.ci95.as_deref()?))
    }

    /// A discovered table at the `k`-th place: its form, the one-sentence
    /// shape and the table with its 95 % band (`[fitted, lower, upper]`).
    pub fn table_of(
        &self,
        k: usize,
    ) -> Option<(
        TableForm,
        String,
        [crate::model::torque_table::HostTorqueTable; 3],
    )> {
        let c = self.members.get(k)?.candidate;
        let form = c.table?;
        let (p, ci) = self.effect_params(k)?;
        let tables = discover::band(&form, p, ci);
        let shape = discover::shape_sentence(&form, c.joint.unwrap_or(0), &tables[0]);
        Some((form, shape, tables))
    }

    /// Bayesian information criterion of the Gaussian likelihood,
    /// `m ln(SSE/m) + k ln m`; infinite when not simulated.
    pub fn bic(&self) -> f64 {
        let Some(s) = self.stats else {
            return f64::INFINITY;
        };
        let m = s.m.max(1) as f64;
        let k: usize = self.members.iter().map(|e| e.params.len()).sum();
        m * (s.sse.max(1e-300) / m).ln() + k as f64 * m.ln()
    }
}

/// A claim set aside because the runs cannot tell it from the
/// discrepancy its set leaves above the noise ([`super::discrepancy`]).
#[derive(Clone, Debug, PartialEq)]
pub struct SetAside {
    /// The effect as it was fitted in the set.
    pub effect: FittedEffect,
    /// The named effects put in its place (a table's shape beyond a named
    /// law set aside); empty when it was dropped.
    pub replaced_by: Vec<Candidate>,
    /// What it accounted for: the RMS of the SSE its loss added \[deg\].
    pub explained_deg: f64,
    /// The discrepancy of the set it was in: the RMS of its SSE above the
    /// noise, `√((SSE − m σ̂²)/m)` \[deg\].
    pub discrepancy_deg: f64,
}

/// How one candidate fared in one round.
#[derive(Clone, Debug, PartialEq)]
pub struct CandidateScore {
    /// The candidate.
    pub candidate: Candidate,
    /// The set it was fitted in (the current set plus it).
    pub fitted: FittedSet,
    /// BIC gain over the current set (positive is better).
    pub delta_bic: f64,
    /// Held-out RMS with it \[deg\], when computed.
    pub held_out_rms_deg: Option<f64>,
    /// Why it was or was not taken ([`Verdict`]; its `Display`, in
    /// `report::diagnosis_outcome`, is the sentence the report and the
    /// JSON give).
    pub verdict: Verdict,
}

impl CandidateScore {
    /// Whether the move was accepted.
    pub fn accepted(&self) -> bool {
        matches!(self.verdict, Verdict::Accepted(_))
    }
}

/// One round of the search: the sets one move proposed, scored and
/// judged.
#[derive(Clone, Debug, PartialEq)]
pub struct Round {
    /// The move the round tried (add a candidate to [`Round::start`], swap
    /// one of it, …); its words are the report's
    /// (`report::diagnosis_outcome`).
    pub what: Move,
    /// The set the round started from.
    pub start: Vec<Candidate>,
    /// RMS of that set \[deg\].
    pub start_rms_deg: f64,
    /// Every candidate, best BIC first.
    pub scores: Vec<CandidateScore>,
}

/// Settings of a diagnosis.
#[derive(Clone, Debug, PartialEq)]
pub struct DiagnoseOptions {
    /// Most effects to add.
    pub max_effects: usize,
    /// The candidates considered (all by default).
    pub kinds: Vec<EffectKind>,
    /// Whether to look for a torque no named effect describes
    /// ([`discover`]) when the named effects leave a residual.
    pub discover: bool,
    /// Stop the search after this wall time \[s\] and report the best set
    /// found so far, marked as such (`None`, or more than the clock can
    /// hold such as `inf`: no limit).
    pub max_seconds: Option<f64>,
    /// Stop the search when this flag is raised (Ctrl-C), likewise.
    pub stop: Option<StopFlag>,
    /// The progress also lists every score of a round, and the verdicts
    /// of the first judged (the command line's `DEPLOYWATCH_TRACE`).
    pub trace: bool,
    /// The friction forms' residual-torque regressions are written to
    /// stderr (the command line's `DEPLOYWATCH_TRACE_FORMS`).
    pub trace_forms: bool,
}

/// A flag another thread raises to stop a diagnosis early (the command
/// line's Ctrl-C handler); two flags are equal when they are the same flag.
#[derive(Clone, Debug, Default)]
pub struct StopFlag(pub std::sync::Arc<std::sync::atomic::AtomicBool>);

impl StopFlag {
    /// True once raised.
    pub fn raised(&self) -> bool {
        self.0.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// Raises it.
    pub fn raise(&self) {
        self.0.store(true, std::sync::atomic::Ordering::Relaxed);
    }
}

impl PartialEq for StopFlag {
    fn eq(&self, other: &Self) -> bool {
        std::sync::Arc::ptr_eq(&self.0, &other.0)
    }
}

impl Default for DiagnoseOptions {
    fn default() -> Self {
        DiagnoseOptions {
            max_effects: 3,
            // The rig's causes are candidates only on a campaign with a rig.
            kinds: EffectKind::ALL.into_iter().chain(EffectKind::RIG).collect(),
            discover: true,
            max_seconds: None,
            stop: None,
            trace: false,
            trace_forms: false,
        }
    }
}

/// An encoder reading off its panel within the hinge's declared free-play.
#[derive(Clone, Debug, PartialEq)]
pub struct FreePlayOffset {
    /// 1-based joint.
    pub joint: usize,
    /// The fitted reading's offset from the panel's angle \[deg\] (the
    /// `encoder_offset` the search kept: reading = angle + offset).
    pub offset_deg: f64,
    /// Its 95 % interval \[deg\].
    pub ci95_deg: [f64; 2],
    /// The free-play every mechanism of the campaign declares at the
    /// joint (the least of them), a half band \[deg\].
    pub play_deg: f64,
}

/// What the drawing's declared tolerances of mass, inertia and spring
/// torque add to one effect's reported interval ([`super::tolerance`]).
#[derive(Clone, Debug, PartialEq)]
pub struct ToleranceShare {
    /// The effect.
    pub candidate: Candidate,
    /// The effect in words ([`Candidate::words`]).
    pub effect: String,
    /// The standard uncertainty of each of its parameters from the
    /// tolerances, in the parameter's unit.
    pub sd: Vec<f64>,
    /// The tolerance that moves it most (`panel 2's inertia (±1 %) of
    /// seed001-T01`).
    pub largest: String,
}

/// A named effect the drawing's declared tolerances of mass, inertia and
/// spring torque alone could make, taken out of the set found
/// ([`super::tolerance`]).
#[derive(Clone, Debug, PartialEq)]
pub struct WithinTolerance {
    /// The effect as it was fitted in the set.
    pub effect: FittedEffect,
    /// What took its place in the set, when something did (a Stribeck
    /// friction gives way to Coulomb friction at its kinetic level,
    /// [`super::tolerance`]).
    pub in_its_place: Option<Candidate>,
    /// Its share of the tolerances there.
    pub share: ToleranceShare,
}

/// What a diagnosis concluded.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// The noise floor σ̂ estimated from the runs \[deg\].
    pub noise_sigma_deg: f64,
    /// The baseline (no effect).
    pub baseline: FittedSet,
    /// The selected effects, fitted together.
    pub extended: FittedSet,
    /// Each selected effect's strength: the RMS \[deg\] of the extended model
    /// without it (values of the others kept).
    pub strength_rms_deg: Vec<f64>,
    /// Held-out RMS of the extended model \[deg\] (two or more runs).
    pub held_out_rms_deg: Option<f64>,
    /// Held-out RMS of the baseline \[deg\] (the baseline fits nothing, so this
    /// is its plain RMS).
    pub rounds: Vec<Round>,
    /// A clear residual no candidate explains: its size and what it shows.
    pub unexplained: Option<Unexplained>,
    /// Simulations used in all (each over all runs).
    pub simulations: usize,
    /// Wall time \[s\].
    pub wall_s: f64,
    /// The encoders' delay behind their latch switches, when the ideal
    /// latches' closings agree on one clear of zero ([`super::encoder_delay`]):
    /// the fit compared the angles with the model at their stamps minus it.
    pub encoder_delay: Option<super::encoder_delay::EncoderDelay>,
    /// Flexible panels, when the rigid wing's set left the runs clearly
    /// above the noise and the wing with its first mode fitted took most of
    /// that out ([`super::panel_mode`]): the search ran on the flexible
    /// wing, and every figure of this outcome is of it.
    pub panel_mode: Option<PanelMode>,
    /// Encoder offsets within their joints' declared free-play, taken out
    /// of the effects (`diagnose/free_play.rs`): the angles are compared
    /// with them taken out.
    pub free_play: Vec<FreePlayOffset>,
    /// Runs of a physical latch: where each run's free motion ends, the
    /// window the effects were fitted on (`None`: the whole runs).
    pub free_window: Option<Vec<RunWindow>>,
    /// The model found over the whole of runs of a physical latch: the
    /// motion after the free window, shot from the measured state
    /// ([`super::whole_run`]); `None` when no run goes on after its free
    /// window (or the search stopped early).
    pub whole_run: Option<super::whole_run::WholeRun>,
    /// Runs of a physical latch fitted whole: the model found closes every
    /// latch switch as often as each run does, so the search ran again on
    /// the whole runs and its set is the one given
    /// ([`super::whole_fit`]); false when the effects are fitted on the
    /// free windows only.
    pub fitted_whole: bool,
    /// Runs of a physical latch fitted up to where the model follows them
    /// ([`super::whole_fit`]): each run's window, longer than its free
    /// motion (`free_window`), the effects and every fit figure are of;
    /// `None` when they are of the free windows or the whole runs.
    pub fitted_to: Option<Vec<RunWindow>>,
    /// Each physical latch's events against the drawing's.
    pub latches: Vec<LatchFinding>,
    /// What the drawing's declared tolerances of mass, inertia and spring
    /// torque add to each effect's reported interval (empty: none declared;
    /// [`super::tolerance`]).
    pub tolerance: Vec<ToleranceShare>,
    /// Named effects the tolerances alone could make, taken out of the
    /// set found, in the order they were ([`super::tolerance`]).
    pub within_tolerance: Vec<WithinTolerance>,
    /// Sets of causes that explain the runs alike ([`super::ambiguity`]).
    pub ambiguities: Vec<Ambiguity>,
    /// Claims the search had kept that the runs cannot tell from the
    /// discrepancy the set leaves, set aside ([`super::discrepancy`]), in
    /// the order they were.
    pub set_aside: Vec<SetAside>,
    /// Why the search stopped before its end, when it did (a time limit,
    /// a raised [`StopFlag`]): the effects are then the best found so far.
    pub partial: Option<HaltReason>,
}

/// Why a search stopped before its end; the words are the report's
/// (`report::diagnosis_outcome`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HaltReason {
    /// The [`DiagnoseOptions::stop`] flag was raised (Ctrl-C on the
    /// command line).
    Interrupted,
    /// The wall-time limit [`DiagnoseOptions::max_seconds`] was reached.
    TimeLimit {
        /// The limit \[s\].
        limit_s: f64,
    },
}

/// A residual the effects found leave and no further candidate explains
/// (`docs/diagnosis.md`, step 6); the words are the report's
/// (`report::diagnosis_outcome`).
#[derive(Clone, Debug, PartialEq)]
pub struct Unexplained {
    /// RMS of the extended model's residuals over all runs \[deg\].
    pub rms_deg: f64,
    /// The noise floor σ̂ it is judged against \[deg\].
    pub noise_sigma_deg: f64,
    /// What the residual shows.
    pub shape: UnexplainedShape,
}

impl Unexplained {
    /// The joint (1-based) it names: where the residual is largest, or
    /// where the torque a global effect stands in for is missing; `None`
    /// when the runs give no joint evidence.
    pub fn joint(&self) -> Option<usize> {
        match &self.shape {
            UnexplainedShape::AboveNoise { largest_at } => largest_at.map(|p| p.joint),
            UnexplainedShape::StandIn { torque } => Some(torque.joint),
        }
    }
}

/// What an [`Unexplained`] residual shows.
#[derive(Clone, Debug, PartialEq)]
pub enum UnexplainedShape {
    /// The residual stays clearly above the noise: where it is largest
    /// (`None` when the runs give no joint evidence).
    AboveNoise {
        /// The joint and third of the stroke of the largest residual.
        largest_at: Option<ResidualPlace>,
    },
    /// The residual is near the noise but not down to it, and a global
    /// effect of the set (rig tilt, air drag) stands in for a joint
    /// torque: without it, the residual torque is significant at a joint
    /// that holds no effect found.
    StandIn {
        /// That joint's residual torque without the global effect (the one
        /// of the largest `χ²`).
        torque: JointTorque,
    },
}

/// The runs that would separate the sets of an ambiguity group.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SeparatingTest {
    /// The runs are of one configuration: runs with another spring at the
    /// joint (softening scales with the spring's torque, friction and a
    /// harness do not), or at another temperature.
    AnotherSpring,
    /// Runs that move the joint over another range of angle and rate
    /// (another spring or stowed angle there), or at another temperature.
    AnotherRange,
    /// A set exchanges a ground-rig effect (air drag, a tilt) for a loss of
    /// the wing's own at the joint: runs without that part of the rig (in
    /// vacuum, the rig levelled) would separate them. Until then the flight
    /// margins keep the wing's loss (`docs/margin.md`, "On orbit").
    WithoutTheRig,
}

/// Sets of causes that explain the runs alike at one joint
/// ([`super::ambiguity`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Ambiguity {
    /// The joint (1-based) whose named effects the sets exchange.
    pub joint: usize,
    /// The set found, then each alternative, fitted (BIC within
    /// `MIN_DELTA_BIC` of the set found).
    pub sets: Vec<FittedSet>,
    /// The test that would separate them (in words by
    /// `report::diagnosis_latch`).
    pub separating_test: SeparatingTest,
}

/// Flexible panels named: the mode and what they take out.
#[derive(Clone, Debug, PartialEq)]
pub struct PanelMode {
    /// The first mode and its damping ratio, as fitted.
    pub flex: crate::model::flex::PanelFlex,
    /// RMS \[deg\] of the rigid wing's set found.
    pub rigid_rms_deg: f64,
    /// RMS \[deg\] of the same set refitted on the flexible wing, before the
    /// search runs again.
    pub flexible_rms_deg: f64,
}

impl PanelMode {
    /// The mode in words, for the progress and the report.
    pub fn words(&self) -> String {
        format!(
            "the panels are flexible: the deployed wing's first mode at {:.2} Hz, damping ratio {:.1} %, takes the set found from {:.4} to {:.4} deg RMS",
            self.flex.first_mode_hz,
            100.0 * self.flex.damping_ratio,
            self.rigid_rms_deg,
            self.flexible_rms_deg
        )
    }
}
