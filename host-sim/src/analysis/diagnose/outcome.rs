//! What a diagnosis finds: fitted sets of effects, the scores of each
//! round's candidates, the options, and the outcome.

use super::candidate::{effects_of, Candidate};
use super::discover;
use super::latch_finding::LatchFinding;
use super::latch_window::RunWindow;
use super::table_form::TableForm;
use crate::model::effect::{Effect, EffectKind};

/// A fitted set of effects.
#[derive(Clone, Debug, PartialEq)]
pub struct FittedSet {
    /// The candidates, in selection order.
    pub set: Vec<Candidate>,
    /// Their parameters, concatenated.
    pub params: Vec<f64>,
    /// 95 % intervals of the parameters.
    pub ci95: Vec<[f64; 2]>,
    /// Sum of squared residuals over all runs [deg²].
    pub sse: f64,
    /// Number of residuals.
    pub m: usize,
    /// Simulations used to fit it (per run).
    pub evaluations: usize,
}

impl FittedSet {
    /// The effects.
    pub fn effects(&self) -> Vec<Effect> {
        effects_of(&self.set, &self.params)
    }

    /// RMS of the residuals [deg].
    pub fn rms(&self) -> f64 {
        (self.sse / self.m.max(1) as f64).sqrt()
    }

    /// The set without its `k`-th effect, the others' parameters kept (not
    /// refitted).
    pub fn without(&self, k: usize) -> FittedSet {
        let mut set = Vec::new();
        let mut params = Vec::new();
        let mut ci95 = Vec::new();
        let mut off = 0;
        for (i, c) in self.set.iter().enumerate() {
            if i != k {
                set.push(*c);
                params.extend_from_slice(&self.params[off..off + c.params()]);
                ci95.extend_from_slice(&self.ci95[off..(off + c.params()).min(self.ci95.len())]);
            }
            off += c.params();
        }
        FittedSet {
            set,
            params,
            ci95,
            sse: f64::NAN,
            m: self.m,
            evaluations: 0,
        }
    }

    /// The value interval (and a tilt's direction interval) of the `k`-th
    /// effect.
    pub fn effect_ci(&self, k: usize) -> ([f64; 2], Option<[f64; 2]>) {
        let off: usize = self.set[..k].iter().map(|c| c.params()).sum();
        let n = self.set[k].params();
        match (self.params.get(off..off + n), self.ci95.get(off..off + n)) {
            (Some(p), Some(ci)) => self.set[k].value_ci(p, ci),
            _ => ([f64::NEG_INFINITY, f64::INFINITY], None),
        }
    }

    /// The parameters and their 95 % intervals of the `k`-th effect.
    pub fn effect_params(&self, k: usize) -> Option<(&[f64], &[[f64; 2]])> {
        let off: usize = self.set.get(..k)?.iter().map(|c| c.params()).sum();
        let n = self.set.get(k)?.params();
        Some((self.params.get(off..off + n)?, self.ci95.get(off..off + n)?))
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
        let c = self.set.get(k)?;
        let form = c.table?;
        let (p, ci) = self.effect_params(k)?;
        let tables = discover::band(&form, p, ci);
        let shape = discover::shape_sentence(&form, c.joint.unwrap_or(0), &tables[0]);
        Some((form, shape, tables))
    }

    /// Bayesian information criterion of the Gaussian likelihood,
    /// `m ln(SSE/m) + k ln m`.
    pub fn bic(&self) -> f64 {
        let m = self.m.max(1) as f64;
        m * (self.sse.max(1e-300) / m).ln() + self.params.len() as f64 * m.ln()
    }
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
    /// Held-out RMS with it [deg], when computed.
    pub held_out_rms_deg: Option<f64>,
    /// Whether it was added.
    pub accepted: bool,
    /// Why it was or was not added.
    pub verdict: String,
}

/// One round of the stepwise search.
#[derive(Clone, Debug, PartialEq)]
pub struct Round {
    /// What the round tried (add a candidate, or swap one).
    pub what: String,
    /// The set the round started from.
    pub start: Vec<Candidate>,
    /// RMS of that set [deg].
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
    /// Stop the search after this wall time [s] and report the best set
    /// found so far, marked as such (`None`: no limit).
    pub max_seconds: Option<f64>,
    /// Stop the search when this flag is raised (Ctrl-C), likewise.
    pub stop: Option<StopFlag>,
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
        }
    }
}

/// What a diagnosis concluded.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// The noise floor σ̂ estimated from the runs [deg].
    pub noise_sigma_deg: f64,
    /// The baseline (no effect).
    pub baseline: FittedSet,
    /// The selected effects, fitted together.
    pub extended: FittedSet,
    /// Each selected effect's strength: the RMS [deg] of the extended model
    /// without it (values of the others kept).
    pub strength_rms_deg: Vec<f64>,
    /// Held-out RMS of the extended model [deg] (two or more runs).
    pub held_out_rms_deg: Option<f64>,
    /// Held-out RMS of the baseline [deg] (the baseline fits nothing, so this
    /// is its plain RMS).
    pub rounds: Vec<Round>,
    /// A description of a clear residual no candidate explains.
    pub unexplained: Option<String>,
    /// Simulations used in all (each over all runs).
    pub simulations: usize,
    /// Wall time [s].
    pub wall_s: f64,
    /// Runs of a physical latch: where each run's free motion ends, the
    /// window the effects were fitted on (`None`: the whole runs).
    pub free_window: Option<Vec<RunWindow>>,
    /// Each physical latch's events against the drawing's.
    pub latches: Vec<LatchFinding>,
    /// Sets of causes that explain the runs alike ([`super::ambiguity`]).
    pub ambiguities: Vec<Ambiguity>,
    /// Why the search stopped before its end, when it did (a time limit,
    /// Ctrl-C): the effects are then the best found so far.
    pub partial: Option<String>,
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
    /// The test that would separate them, in words.
    pub separating_test: String,
}
