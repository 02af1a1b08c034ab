//! The friction forms a tribologist names — `stribeck_friction` (a
//! break-away above the kinetic level, falling with rate) and
//! `quadratic_damping` (`−c φ̇|φ̇|`), `docs/spec/physics.md` section 6 —
//! entered where the data's evidence says so.
//!
//! They are not stepwise candidates: a Stribeck law holds Coulomb friction
//! (`ΔT = 0`), quadratic damping acts like air drag at one joint and like
//! viscous damping over a narrow range of rates, so offered in every round
//! they take the evidence a simpler named effect explains. They are tried
//! once, when the stepwise search stalls with the residual above the noise
//! floor (the simpler vocabulary does not explain the runs), and only where
//! the data point to them:
//! - a Stribeck law in place of a Coulomb friction the set holds (the
//!   search found friction there; the break-away acts at release, in the
//!   samples the residual torque leaves out, so the angles decide);
//! - either form at a joint whose residual torque from the data has its
//!   rate shape ([`evidence_starts`]): beside a set `B` (the current set,
//!   or the current set without one of its joint effects at that joint,
//!   which the form may replace), the torque `B` lacks at the joint,
//!   regressed by weighted least squares on
//!
//! ```text
//! stribeck_friction   −tanh(φ̇/0.01) T_C − √(2e) ΔT (φ̇/ω_st) e^{−(φ̇/ω_st)²}   (ω_st on a grid)
//! quadratic_damping   −φ̇|φ̇| c           (alone, or beside −φ̇ f)
//! ```
//!
//! must beat the simpler law of the same family — Coulomb alone for the
//! break-away, viscous alone for the quadratic — by ΔBIC >
//! [`MIN_DELTA_BIC`]. The regression's values start the fit through the
//! simulator (with the candidate's own scan), and the move is judged like
//! any other (ΔBIC, intervals clear of zero — a Stribeck law's excess too —
//! and the held-out RMS). A form taken is then exchanged for the simpler
//! effect (Coulomb for Stribeck; viscous or air drag for quadratic), which
//! is kept instead when its BIC is within [`MIN_DELTA_BIC`] of the form's
//! ([`Move::Simpler`], judged by `Search::accept`): the simpler named
//! effect wins when it explains the runs as well.
//!
//! Beside those moves, the forms all at once in place of the whole set
//! (`Search::forms_at_once`: each form at every joint whose residual torque
//! beside the mechanisms as given has its shape, quadratic damping also
//! where a fitted table grows about quadratically with the rate, and at
//! every joint of the wing, its idle joints then dropped), when the search stalls
//! and again when its answer holds a torque table
//! (`Search::try_forms_in_place_of_tables`).

use super::candidate::{Candidate, STRIBECK_RATE_RANGE};
use super::discover::{rate_shape, RateGrowth};
use super::outcome::FittedSet;
use super::policy::{Move, Verdict};
use super::residual_named::lsq;
use super::{labels, Search, MIN_DELTA_BIC, SCREEN_KEEP};
use crate::analysis::residual_shape::{bic, thin};
use crate::analysis::residual_torque::{residual_torque, TorqueSample};
use crate::model::effect::EffectKind;
use deploywatch_core::physics::{
    coulomb_shape, quadratic_damping, stribeck_excess, COULOMB_THRESHOLD_RAD_S,
};
use rayon::prelude::*;

/// The forms this step enters.
pub const FORMS: [EffectKind; 2] = [EffectKind::StribeckFriction, EffectKind::QuadraticDamping];

/// Stribeck velocities the residual-torque regression tries [rad/s]
/// (0.6 to 57 deg/s).
const OMEGA_GRID: [f64; 8] = [0.01, 0.02, 0.04, 0.07, 0.12, 0.2, 0.4, 1.0];

/// The Stribeck term's torque per N·m of excess at `rate` [rad/s] for
/// `ω_st` [rad/s]: `−√(2e) (ω/ω_st) e^{−(ω/ω_st)²}` (peak 1 at `ω_st/√2`;
/// the core's [`stribeck_excess`]).
fn hump(rate: f64, w: f64) -> f64 {
    -stribeck_excess(1.0, rate, w)
}

/// The rate signatures [N·m per unit of value] at a sample (the core's
/// laws: [`coulomb_shape`], [`quadratic_damping`]).
fn coulomb(s: &TorqueSample) -> f64 {
    -coulomb_shape(s.rate_deg_s.to_radians(), COULOMB_THRESHOLD_RAD_S)
}
fn viscous(s: &TorqueSample) -> f64 {
    -s.rate_deg_s.to_radians()
}
fn quadratic(s: &TorqueSample) -> f64 {
    -quadratic_damping(1.0, s.rate_deg_s.to_radians())
}

/// The BIC of a regression on `cols`, `+∞` when it fails.
fn bic_of(samples: &[TorqueSample], cols: &[&dyn Fn(&TorqueSample) -> f64]) -> f64 {
    lsq(samples, cols).map_or(f64::INFINITY, |(_, rss)| bic(samples, rss, cols.len()))
}

/// The forms whose rate shape the residual torque at one joint has, each
/// with its start values from the regression (module docs): a Stribeck
/// law `[T_C, ΔT, ω_st]` when `coulomb_free` (the base holds no Coulomb
/// friction at that joint, which the law would double), and quadratic
/// damping `[c]`.
pub fn evidence_starts(
    samples: &[TorqueSample],
    coulomb_free: bool,
) -> Vec<(EffectKind, Vec<f64>)> {
    evidence_beyond(samples, coulomb_free, MIN_DELTA_BIC)
}

/// [`evidence_starts`] with the form's regression required to beat the
/// simpler law's BIC by `margin` (`MIN_DELTA_BIC` there; 0 for
/// [`Search::forms_at_once`], whose one move is judged through the
/// simulator against the whole set).
fn evidence_beyond(
    samples: &[TorqueSample],
    coulomb_free: bool,
    margin: f64,
) -> Vec<(EffectKind, Vec<f64>)> {
    let s = thin(samples);
    if s.len() < 8 {
        return Vec::new();
    }
    let mut out = Vec::new();
    let simple = bic_of(&s, &[&coulomb]).min(bic_of(&s, &[&viscous]));
    if coulomb_free {
        let best = OMEGA_GRID
            .iter()
            .filter_map(|&w| {
                let h = move |x: &TorqueSample| hump(x.rate_deg_s.to_radians(), w);
                let (v, rss) = lsq(&s, &[&coulomb, &h])?;
                Some((bic(&s, rss, 3), v, w))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0));
        if let Some((b, v, w)) = best {
            if b + margin < bic_of(&s, &[&coulomb]) {
                let w = w.clamp(STRIBECK_RATE_RANGE[0], STRIBECK_RATE_RANGE[1]);
                out.push((EffectKind::StribeckFriction, vec![v[0], v[1], w]));
            }
        }
    }
    let q = lsq(&s, &[&quadratic]).map(|(v, rss)| (bic(&s, rss, 1), v[0]));
    let vq = lsq(&s, &[&viscous, &quadratic]).map(|(v, rss)| (bic(&s, rss, 2), v[1]));
    let best_q = [q, vq]
        .into_iter()
        .flatten()
        .min_by(|a, b| a.0.total_cmp(&b.0));
    if let Some((b, c)) = best_q {
        if b + margin < bic_of(&s, &[&viscous]) && b < simple {
            out.push((EffectKind::QuadraticDamping, vec![c]));
        }
    }
    out
}

/// The regressions behind [`evidence_starts`] and what it found (`out`), in
/// one trace line ([`super::DiagnoseOptions::trace_forms`]); `None` where it
/// has too few samples to regress.
fn evidence_trace(samples: &[TorqueSample], out: &[(EffectKind, Vec<f64>)]) -> Option<String> {
    let s = thin(samples);
    if s.len() < 8 {
        return None;
    }
    let q = lsq(&s, &[&quadratic]).map(|(v, rss)| (bic(&s, rss, 1), v[0]));
    let vq = lsq(&s, &[&viscous, &quadratic]).map(|(v, rss)| (bic(&s, rss, 2), v[1]));
    let st = OMEGA_GRID
        .iter()
        .filter_map(|&w| {
            let h = move |x: &TorqueSample| hump(x.rate_deg_s.to_radians(), w);
            let (v, rss) = lsq(&s, &[&coulomb, &h])?;
            Some(format!(
                "{w}:{:.0}({:.3},{:.3})",
                bic(&s, rss, 3),
                v[0],
                v[1]
            ))
        })
        .collect::<Vec<_>>()
        .join(" ");
    Some(format!(
        "    forms evidence: n {} coulomb {:.0} viscous {:.0} quad {:?} visc+quad {:?} stribeck [{st}] -> {:?}",
        s.len(),
        bic_of(&s, &[&coulomb]),
        bic_of(&s, &[&viscous]),
        q,
        vq,
        out
    ))
}

/// One move of this step: a base set, the form's candidate, its start.
type FormMove = (FittedSet, Candidate, Vec<f64>);

impl Search<'_, '_> {
    /// Whether the campaign's candidates allow the forms (the simpler
    /// laws they extend are candidates; not on a truss wing, whose
    /// simulator models neither).
    fn forms_allowed(&self) -> bool {
        let truss = self
            .eng
            .campaign
            .runs
            .iter()
            .any(|r| r.mechanism.truss.is_some());
        let has = |k| self.candidates.iter().any(|c| c.kind == k);
        !truss && has(EffectKind::CoulombFriction) && has(EffectKind::ViscousDamping)
    }

    /// When the stepwise search stalls above the noise floor: the friction
    /// forms at the joints whose residual torque has their shape, beside
    /// the current set or in place of one of its members (module docs).
    /// Tried once; true when a form was taken.
    pub(super) fn try_friction_forms(&mut self) -> bool {
        if !self.forms_allowed()
            || self.current.rms() <= self.floor()
            || !self.first_time(Move::FrictionForms)
        {
            return false;
        }
        self.eng
            .say("friction forms: the residual torque's rate shape at each joint");
        let moves = self.form_moves();
        let at_once = self.forms_at_once();
        if moves.is_empty() && at_once.is_empty() {
            return false;
        }
        self.eng.say(format!(
            "friction forms: the residual torque has a break-away or quadratic shape; fitting {} moves beside {}",
            moves.len(),
            labels(&self.current.candidates())
        ));
        let mut fits = self.fit_form_moves(&moves);
        for (set, start) in &at_once {
            self.eng.say(format!(
                "friction forms: in place of the set, from the baseline: {}",
                labels(set)
            ));
            let f = self.eng.fit(self.eng.campaign, set, start);
            let f = f.map(|f| self.without_idle_forms(f));
            fits.push((set[0], f.filter(excess_clear), false));
        }
        let mv = Move::FrictionForms;
        let round = mv.record().map(|r| (mv, r));
        let Some((f, held)) = self.judge(fits, &mv.policy(), round) else {
            return false;
        };
        let (f, held) = self.simpler_than(f, held);
        if self.seen.contains(&f.candidates()) {
            return false;
        }
        self.take(mv, f, held);
        true
    }

    /// When the set found holds a torque table: the forms at once
    /// ([`Search::forms_at_once`]) in place of the whole set, taken when
    /// they explain the runs better (judged as [`Move::FrictionForms`]:
    /// ΔBIC, intervals, held-out RMS), and the stepwise search run on from
    /// them. A named law where a table of many knots and its companions
    /// stood (a break-away at the one joint of a wing fitted as a rate
    /// table, a softening and a rig tilt). True when they were taken.
    pub(super) fn try_forms_in_place_of_tables(&mut self) -> bool {
        let holds_table = self
            .current
            .members
            .iter()
            .any(|m| m.candidate.table.is_some());
        if !holds_table || !self.forms_allowed() || self.eng.halt.now() {
            return false;
        }
        let at_once = self.forms_at_once();
        if at_once.is_empty() {
            return false;
        }
        let fits: Vec<(Candidate, Option<FittedSet>, bool)> = at_once
            .par_iter()
            .map(|(set, start)| {
                self.eng.say(format!(
                    "friction forms: in place of the tables' set, from the baseline: {}",
                    labels(set)
                ));
                let f = self.eng.fit(self.eng.campaign, set, start);
                (set[0], f.filter(excess_clear), false)
            })
            .collect();
        let mv = Move::FrictionForms;
        let Some((f, held)) = self.judge(fits, &mv.policy(), None) else {
            return false;
        };
        if self.seen.contains(&f.candidates()) {
            return false;
        }
        self.take(mv, f, held);
        self.run();
        true
    }

    /// The moves: at each joint, each form the residual torque beside the
    /// base supports, beside the current set (when it has room), and at a
    /// joint in place of a joint effect there (sensor offsets aside; a
    /// global effect is never replaced: the stand-in rule of step 8 and
    /// the ambiguity groups judge those).
    fn form_moves(&self) -> Vec<FormMove> {
        let cur = &self.current;
        let mut bases = Vec::new();
        if self.named_len() < self.max_effects {
            bases.push(cur.clone());
        }
        // `None`: beside the whole set, at any joint; `Some(j)`: in place of
        // a joint effect at `j`, at `j` only (a form replaces what it
        // extends at its joint, never a global effect nor a sensor offset).
        let mut bases: Vec<(FittedSet, Option<usize>)> =
            bases.into_iter().map(|b| (b, None)).collect();
        for (k, m) in cur.members.iter().enumerate() {
            let m = m.candidate;
            if m.kind != EffectKind::EncoderOffset && m.joint.is_some() {
                bases.push((cur.without(k), m.joint));
            }
        }
        let mut moves = Vec::new();
        for (base, only) in bases {
            let res = residual_torque(self.eng.campaign, &base.effects());
            for jt in res.iter().filter(|jt| only.is_none_or(|j| j == jt.joint)) {
                if self.eng.trace.forms {
                    eprintln!(
                        "  beside {} at joint {}:",
                        labels(&base.candidates()),
                        jt.joint
                    );
                }
                let at = |k| Candidate {
                    kind: k,
                    joint: Some(jt.joint),
                    table: None,
                };
                let free = !base.contains(&at(EffectKind::CoulombFriction));
                let mut starts = evidence_starts(&jt.samples, free);
                if self.eng.trace.forms {
                    if let Some(line) = evidence_trace(&jt.samples, &starts) {
                        eprintln!("{line}");
                    }
                }
                // In place of the Coulomb friction the set holds here.
                if let Some(tc) = swapped_coulomb(cur, &base, jt.joint) {
                    if !starts.iter().any(|s| s.0 == EffectKind::StribeckFriction) {
                        starts.push((EffectKind::StribeckFriction, vec![tc, 0.5 * tc, 0.05]));
                    }
                }
                for (kind, start) in starts {
                    if !base.contains(&at(kind)) {
                        moves.push((base.clone(), at(kind), start));
                    }
                }
            }
        }
        moves
    }

    /// The moves that replace the whole set: one form at every joint whose
    /// residual torque beside the mechanisms as given has its shape better
    /// than the simpler law's (by any BIC: the move is judged through the
    /// simulator), all at once (one set for the Stribeck law, one for
    /// quadratic damping with [`Search::quadratic_tables`]' joints added,
    /// and one with quadratic damping at every joint,
    /// [`quadratic_everywhere`]; the regressions' values start the fit). A loss of one form at
    /// several joints is taken up, one joint at a time, by the stepwise
    /// search's global effects (quadratic damping at each joint of seed 001
    /// T01 by a rig tilt beside a table at each of two joints), and a
    /// break-away at the one joint of a wing by a softening and a table:
    /// beside what the search found, no joint's residual torque shows the
    /// form any more.
    fn forms_at_once(&self) -> Vec<(Vec<Candidate>, Vec<f64>)> {
        let res = residual_torque(self.eng.campaign, &[]);
        let mut sets: [(Vec<Candidate>, Vec<f64>); 2] = Default::default();
        for jt in &res {
            let mut starts = evidence_beyond(&jt.samples, true, 0.0);
            // The break-away acts at release, in the samples the residual
            // torque leaves out: where a kinetic level is what it shows,
            // the law starts from it and the angles decide.
            if let Some(tc) = kinetic_level(&jt.samples) {
                if !starts.iter().any(|s| s.0 == EffectKind::StribeckFriction) {
                    starts.push((EffectKind::StribeckFriction, vec![tc, 0.5 * tc, 0.05]));
                }
            }
            if self.eng.trace.forms {
                eprintln!("  beside the mechanisms as given at joint {}:", jt.joint);
                if let Some(line) = evidence_trace(&jt.samples, &starts) {
                    eprintln!("{line}");
                }
            }
            for (kind, start) in starts {
                let cand = named(kind, Some(jt.joint));
                let slot = usize::from(kind == EffectKind::QuadraticDamping);
                sets[slot].0.push(cand);
                sets[slot].1.extend(start);
            }
        }
        self.quadratic_tables(&mut sets[1]);
        let every = quadratic_everywhere(&sets[1], res.iter().map(|jt| jt.joint));
        let current = self.current.candidates();
        sets.into_iter()
            .chain(every)
            .filter(|(set, _)| !set.is_empty() && *set != current)
            .collect()
    }

    /// Adds to the quadratic set `q` quadratic damping at each joint where
    /// the current set holds a torque table whose rate part resists the
    /// deployment and grows about quadratically ([`RateGrowth::Quadratic`],
    /// the report's "faster than linearly"), started where `c ω²` meets the
    /// table's value at its largest rate `ω`: a joint whose residual beside
    /// the mechanisms as given hid the form (a slow joint dragged by the
    /// others, seed 001 T02's joint 1) shows it in the table fitted there.
    fn quadratic_tables(&self, q: &mut (Vec<Candidate>, Vec<f64>)) {
        for m in &self.current.members {
            let (Some(form), Some(joint)) = (m.candidate.table, m.candidate.joint) else {
                continue;
            };
            let motion = -f64::from(form.from_deg).signum();
            let table = form.table(&m.params);
            let Some(shape) = table
                .rate
                .as_ref()
                .and_then(|g| rate_shape(g.xs(), g.ys(), motion))
            else {
                continue;
            };
            let (rate, torque) = (shape.end.0.to_radians(), shape.end.1);
            let resists = torque * motion < 0.0;
            let known = q.0.iter().any(|c| c.joint == Some(joint));
            if shape.growth == RateGrowth::Quadratic && resists && !known && rate > 0.0 {
                q.0.push(named(EffectKind::QuadraticDamping, Some(joint)));
                q.1.push(torque.abs() / (rate * rate));
            }
        }
    }

    /// A set of forms at once that explains the runs down to the noise
    /// ([`Search::floor`]) without its quadratic dampings whose interval
    /// holds zero, refitted: the every-joint set ([`quadratic_everywhere`])
    /// names the joints that need the form by the others' idling (the
    /// six-panel wing on its rig with the form at two joints: the six fit
    /// to the noise, and four idle intervals had the set refused). `f`
    /// itself when it fits worse, none idles, all do, or the refit fails.
    fn without_idle_forms(&self, f: FittedSet) -> FittedSet {
        if f.rms() > self.floor() {
            return f;
        }
        let idle = |k: &usize| {
            let m = &f.members[*k];
            m.candidate.kind == EffectKind::QuadraticDamping
                && m.candidate.table.is_none()
                && !m.clear_of_zero()
        };
        let n = f.members.len();
        let dropped = (0..n).filter(idle).count();
        if dropped == 0 || dropped == n {
            return f;
        }
        let mut r = f.clone();
        for k in (0..n).rev().filter(idle) {
            r = r.without(k);
        }
        self.eng.say(format!(
            "friction forms: {} idle in the set at once, refitting {}",
            dropped,
            labels(&r.candidates())
        ));
        self.eng.refit(self.eng.campaign, &r).unwrap_or(f)
    }

    /// Screens the moves (the evidence's start and the candidate's scan,
    /// the base's values held) and fits the [`SCREEN_KEEP`] best through
    /// the simulator; a Stribeck law whose excess's interval holds zero is
    /// Coulomb friction and is screened out.
    fn fit_form_moves(&self, moves: &[FormMove]) -> Vec<(Candidate, Option<FittedSet>, bool)> {
        let c = self.eng.campaign;
        let screened: Vec<Option<FittedSet>> = moves
            .par_iter()
            .map(|(base, cand, start)| {
                let pts = std::iter::once(start.clone())
                    .chain(cand.scan())
                    .map(|s| base.params().into_iter().chain(s).collect());
                self.eng.best_point(c, base, *cand, pts)
            })
            .collect();
        let sse = |f: &Option<FittedSet>| f.as_ref().map_or(f64::INFINITY, FittedSet::sse);
        let mut order: Vec<usize> = (0..moves.len()).collect();
        order.sort_by(|&a, &b| sse(&screened[a]).total_cmp(&sse(&screened[b])));
        let keep: Vec<usize> = order.into_iter().take(SCREEN_KEEP).collect();
        let fitted: Vec<(usize, Option<FittedSet>)> = keep
            .par_iter()
            .filter_map(|&i| screened[i].as_ref().map(|s| (i, s)))
            .map(|(i, s)| (i, self.eng.fit(c, &s.candidates(), &s.params())))
            .collect();
        let mut out: Vec<(Candidate, Option<FittedSet>, bool)> = moves
            .iter()
            .zip(screened)
            .map(|((_, cand, _), s)| (*cand, s, true))
            .collect();
        for (i, f) in fitted {
            if let Some(f) = f.filter(excess_clear) {
                out[i] = (moves[i].1, Some(f), false);
            }
        }
        out
    }

    /// The simpler named effect in place of each form of `f` (Coulomb for
    /// Stribeck; viscous damping or air drag for quadratic damping): the
    /// best by BIC, judged by [`Search::accept`] against `f` with
    /// [`Move::Simpler`]'s policy (kept when its BIC is within
    /// [`MIN_DELTA_BIC`] of `f`'s).
    fn simpler_than(&self, mut f: FittedSet, mut held: Option<f64>) -> (FittedSet, Option<f64>) {
        let c = self.eng.campaign;
        for k in (0..f.members.len()).rev() {
            let form = f.members[k].candidate;
            let Some(j) = form.joint.filter(|_| FORMS.contains(&form.kind)) else {
                continue;
            };
            let simple: Vec<Candidate> = match form.kind {
                EffectKind::StribeckFriction => vec![named(EffectKind::CoulombFriction, Some(j))],
                _ => vec![
                    named(EffectKind::ViscousDamping, Some(j)),
                    named(EffectKind::AirDrag, None),
                ],
            };
            let base = f.without(k);
            let options: Vec<FittedSet> = simple
                .par_iter()
                .filter(|s| !base.contains(s) && self.candidates.contains(s))
                .filter_map(|s| {
                    let pts = s
                        .scan()
                        .into_iter()
                        .map(|p| base.params().into_iter().chain(p).collect());
                    let p = self.eng.best_point(c, &base, *s, pts)?;
                    self.eng.fit(c, &p.candidates(), &p.params())
                })
                .collect();
            let best = options
                .into_iter()
                .min_by(|a, b| a.bic().total_cmp(&b.bic()))
                .filter(|s| {
                    let v = self.accept((&f, held), s, &mut None, &Move::Simpler.policy());
                    matches!(v, Verdict::Accepted(_))
                });
            if let Some(s) = best {
                self.eng.say(format!(
                    "  {} explains the runs as well as {} (BIC within {MIN_DELTA_BIC}): the simpler is kept",
                    labels(&s.candidates()),
                    form.words()
                ));
                held = self.eng.held_out(&s);
                f = s;
            }
        }
        (f, held)
    }
}

/// The value of the Coulomb friction at `joint` that `cur` holds and
/// `base` (`cur` without one member) does not: the member a Stribeck law
/// may replace.
fn swapped_coulomb(cur: &FittedSet, base: &FittedSet, joint: usize) -> Option<f64> {
    let c = named(EffectKind::CoulombFriction, Some(joint));
    if base.contains(&c) {
        return None;
    }
    cur.members
        .iter()
        .find(|m| m.candidate == c)
        .and_then(|m| m.params.first().copied())
}

/// The Coulomb level \[N·m\] of a residual torque whose rate shape is
/// Coulomb's rather than viscous's, with its regression better than none
/// by [`MIN_DELTA_BIC`]; `None` otherwise.
fn kinetic_level(samples: &[TorqueSample]) -> Option<f64> {
    let s = thin(samples);
    if s.len() < 8 {
        return None;
    }
    let rss0: f64 = s
        .iter()
        .map(|x| (x.torque_nm / x.se_nm.max(1e-9)).powi(2))
        .sum();
    let none = bic(&s, rss0, 0);
    let (v, rss) = lsq(&s, &[&coulomb])?;
    let b = bic(&s, rss, 1);
    (v[0] > 0.0 && b < bic_of(&s, &[&viscous]) && b + MIN_DELTA_BIC < none).then_some(v[0])
}

/// A named candidate.
fn named(kind: EffectKind, joint: Option<usize>) -> Candidate {
    Candidate {
        kind,
        joint,
        table: None,
    }
}

/// Quadratic damping at every joint of `joints`, from the set `q` found
/// at some of them (its starts kept, the others started at a tenth of its
/// smallest): a joint whose own residual looks viscous beside the
/// mechanisms as given (a light outboard joint of seed 001 T02) may still
/// lose to the form, which the fit decides (an unneeded one has an
/// interval holding zero and is dropped, [`Search::without_idle_forms`]).
/// `None` when `q` is empty or already everywhere.
fn quadratic_everywhere(
    q: &(Vec<Candidate>, Vec<f64>),
    joints: impl Iterator<Item = usize>,
) -> Option<(Vec<Candidate>, Vec<f64>)> {
    let low = 0.1 * q.1.iter().copied().fold(f64::INFINITY, f64::min);
    let mut every: (Vec<Candidate>, Vec<f64>) = Default::default();
    for joint in joints {
        let at = q.0.iter().position(|c| c.joint == Some(joint));
        every
            .0
            .push(named(EffectKind::QuadraticDamping, Some(joint)));
        every.1.push(at.map_or(low, |i| q.1[i]));
    }
    (low.is_finite() && every.0.len() > q.0.len()).then_some(every)
}

/// False when a Stribeck law of `f` has an excess whose ordinary 95 %
/// interval (the search's statistic, [`super::outcome::FittedEffect::ci95_search`])
/// holds zero (then it is Coulomb friction with two idle parameters).
fn excess_clear(f: &FittedSet) -> bool {
    f.members
        .iter()
        .filter(|m| m.candidate.kind == EffectKind::StribeckFriction)
        .all(|m| {
            m.ci95_search
                .as_ref()
                .or(m.ci95.as_ref())
                .and_then(|ci| ci.get(1))
                .is_some_and(|ci| ci[0] > 0.0)
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(rate_deg_s: f64, torque_nm: f64) -> TorqueSample {
        TorqueSample {
            run: 0,
            index: 0,
            t_s: 0.0,
            phi_deg: 0.0,
            rate_deg_s,
            torque_nm,
            se_nm: 0.01,
            spring_nm: 0.0,
            from_stowed_rad: 0.0,
            window: 1,
        }
    }

    fn samples(law: impl Fn(f64) -> f64) -> Vec<TorqueSample> {
        // Rates from 0.2 to 200 deg/s, as a deployment sweeps them.
        (0..300)
            .map(|i| {
                let r = 0.2 * 1.0235f64.powi(i);
                let noise = 0.004 * ((i * 7919 % 13) as f64 / 6.0 - 1.0);
                sample(r, law(r.to_radians()) + noise)
            })
            .collect()
    }

    fn kinds(v: &[(EffectKind, Vec<f64>)]) -> Vec<EffectKind> {
        v.iter().map(|x| x.0).collect()
    }

    #[test]
    fn a_torque_falling_from_a_static_peak_is_a_stribeck_law() {
        // Kinetic 0.2 N·m, a break-away 0.3 N·m above it decaying
        // exponentially (not the simulator's law) over 0.05 rad/s.
        let s = samples(|w| {
            let coulomb = 0.2 * coulomb_shape(w, COULOMB_THRESHOLD_RAD_S);
            -(coulomb + 0.3 * (1.0 - (-w / 0.02).exp()) * (-w / 0.05).exp())
        });
        let e = evidence_starts(&s, true);
        assert_eq!(kinds(&e), vec![EffectKind::StribeckFriction], "{e:?}");
        let p = &e[0].1;
        assert!(p[0] > 0.1 && p[0] < 0.3 && p[1] > 0.1, "{p:?}");
        // Beside a Coulomb friction already at the joint it is not offered.
        assert!(evidence_starts(&s, false).is_empty());
    }

    #[test]
    fn a_torque_growing_as_the_square_of_the_rate_is_quadratic() {
        let s = samples(|w| -0.1 * w * w.abs());
        assert_eq!(
            kinds(&evidence_starts(&s, true)),
            vec![EffectKind::QuadraticDamping]
        );
    }

    #[test]
    fn coulomb_and_viscous_torques_offer_no_form() {
        let coulomb = |w: f64| -0.3 * coulomb_shape(w, COULOMB_THRESHOLD_RAD_S);
        assert!(evidence_starts(&samples(coulomb), true).is_empty());
        assert!(evidence_starts(&samples(|w| -0.2 * w), true).is_empty());
    }
}
