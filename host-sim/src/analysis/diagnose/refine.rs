//! Refinement of a discovered table: more knots where the fit needs them.
//!
//! A table taken by discovery has the knots it started with (five even
//! angle knots, or those the residual torque's shape placed). When the fit
//! with it still leaves a residual above the noise floor, each table of the
//! set is tried in finer forms, each replacing it (the others' values kept
//! as the start): its angle knots doubled (a midpoint between each pair at
//! least twice [`MIN_ANGLE_SPACING_DEG`] apart), a rate table with knots
//! halving towards rest (`r, r/2, r/4, …` down to [`MIN_RATE_SPACING_DEG_S`],
//! so that a rate law peaked a few deg/s from rest is representable), and
//! both. Each starts from the table as fitted (evaluated at the new knots;
//! a new rate table from 0) and is refined through the simulator and
//! judged by BIC and the held-out RMS ([`Move::Refine`]). Up to
//! [`HOST_TABLE_MAX_KNOTS`] knots per axis, the host's table size; the
//! monitor gets a compressed export ([`crate::analysis::diagnose::table_export`]).

use super::candidate::Candidate;
use super::policy::{Attempt, Move};
use super::step::Step;
use super::table_form::{PlacedKnots, TableForm};
use super::{labels, Proposal, Search};
use crate::analysis::diagnose::residual_shape::{
    Shape, MIN_ANGLE_SPACING_DEG, MIN_RATE_SPACING_DEG_S,
};
use crate::model::effect::EffectKind;
use crate::model::torque_table::{HostTorqueTable, HOST_TABLE_MAX_KNOTS};

/// Refinement rounds at most: each may double a table's angle knots once.
const REFINE_ROUNDS: usize = 2;

/// Rate knots of a refined rate table at most (0 among them): halving from
/// the largest rate, eight reach 1/64 of it.
const RATE_KNOTS: usize = 8;

impl Search<'_, '_> {
    /// While the residual stays above the noise floor, tries the finer
    /// forms of every table in the set and takes the best that earns its
    /// keep ([`Move::Refine`]: of the [`super::policy::REFINE_TRIES`] best by BIC, the
    /// first that gains more than [`super::MIN_DELTA_BIC`] and whose
    /// held-out RMS beats the current set's by [`super::policy::HELD_OUT_SHARE`]; a
    /// refinement reshapes a table already kept, so its knots' intervals
    /// are not asked to be clear of zero: more knots share the torque, and
    /// the largest may be near-collinear with a knot of the other axis).
    pub(super) fn refine_tables(&mut self) {
        for _ in 0..REFINE_ROUNDS {
            if self.current.rms() <= self.floor() {
                return;
            }
            if self.attempt(Move::Refine) != Attempt::Moved {
                return;
            }
        }
    }

    /// [`Move::Refine`]: each table of the set in its finer forms, in place
    /// of itself.
    pub(super) fn propose_refine(&mut self) -> Option<Proposal> {
        let moves = self.refine_moves();
        if moves.is_empty() {
            return None;
        }
        self.eng.say(format!(
            "refinement: the residual stays at {:.4} deg; fitting {} finer tables in {}",
            self.current.rms(),
            moves.len(),
            labels(&self.current.candidates())
        ));
        Some(moves)
    }

    /// Each table of the set in its finer forms, in place of itself, each
    /// starting from the table as fitted at its knots.
    fn refine_moves(&self) -> Vec<Step> {
        let mut moves = Vec::new();
        for (k, m) in self.current.members.iter().enumerate() {
            let Some(form) = m.candidate.table else {
                continue;
            };
            let table = form.table(&m.params);
            let base = self.current.without(k);
            for shape in finer_shapes(&form, &table) {
                let Some(placed) = PlacedKnots::form(&shape, form.from_deg, form.rate_max_deg_s)
                else {
                    continue;
                };
                let cand = Candidate {
                    kind: EffectKind::TorqueTable,
                    joint: m.candidate.joint,
                    table: Some(placed),
                };
                if self.seen.iter().any(|s| s.contains(&cand)) {
                    continue;
                }
                moves.push(Step::from(
                    base.clone(),
                    cand,
                    Some(PlacedKnots::start(&shape)),
                ));
            }
        }
        moves
    }
}

/// The finer forms of `table` (of form `form`) as shapes whose values are
/// the start: angle knots doubled, a halving rate table, and both.
fn finer_shapes(form: &TableForm, table: &HostTorqueTable) -> Vec<Shape> {
    let angle = table.angle.as_ref().map(|f| f.xs().to_vec());
    let finer_angle = angle
        .as_deref()
        .map(doubled)
        .filter(|x| Some(x) != angle.as_ref());
    let rate_now = table.rate.as_ref().map(|g| g.xs().to_vec());
    let halving = halving_rates(f64::from(form.rate_max_deg_s));
    let finer_rate = (halving.len() > rate_now.as_ref().map_or(0, Vec::len)).then_some(halving);
    let mut out = Vec::new();
    let mut push = |a: Option<Vec<f64>>, r: Option<Vec<f64>>| {
        let angle_deg = a.unwrap_or_default();
        let rate_deg_s = r.unwrap_or_default();
        let angle_nm = angle_deg
            .iter()
            .map(|&x| table.angle.as_ref().map_or(0.0, |f| f.eval(x)))
            .collect();
        let rate_nm = rate_deg_s
            .iter()
            .map(|&x| table.rate.as_ref().map_or(0.0, |g| g.eval(x)))
            .collect();
        out.push(Shape {
            angle_deg,
            angle_nm,
            rate_deg_s,
            rate_nm,
            rss: f64::NAN,
            bic: f64::NAN,
            bic_zero: f64::NAN,
        });
    };
    if finer_angle.is_some() {
        push(finer_angle.clone(), rate_now.clone());
    }
    if finer_rate.is_some() {
        push(angle.clone(), finer_rate.clone());
    }
    if finer_angle.is_some() && finer_rate.is_some() {
        push(finer_angle, finer_rate);
    }
    out
}

/// `xs` with a midpoint between each pair of knots at least twice
/// [`MIN_ANGLE_SPACING_DEG`] apart, up to [`HOST_TABLE_MAX_KNOTS`] knots
/// (rounded to the hundredths the forms store).
fn doubled(xs: &[f64]) -> Vec<f64> {
    let mut out = Vec::with_capacity(2 * xs.len());
    for w in xs.windows(2) {
        out.push(w[0]);
        if w[1] - w[0] >= 2.0 * MIN_ANGLE_SPACING_DEG && out.len() + 2 < HOST_TABLE_MAX_KNOTS {
            out.push((0.5 * (w[0] + w[1]) * 100.0).round() / 100.0);
        }
    }
    out.extend(xs.last());
    out
}

/// Rate knots `0, …, r/4, r/2, r` (increasing, `r` with its sign), halving
/// from `r` while the gap to the next stays at least
/// [`MIN_RATE_SPACING_DEG_S`]; at most [`RATE_KNOTS`].
fn halving_rates(r: f64) -> Vec<f64> {
    let mut v = vec![r];
    let mut x = r;
    while v.len() + 1 < RATE_KNOTS && (0.5 * x).abs() >= MIN_RATE_SPACING_DEG_S {
        x *= 0.5;
        v.push((x * 100.0).round() / 100.0);
    }
    v.push(0.0);
    v.sort_by(f64::total_cmp);
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn doubling_puts_midpoints_between_wide_knots_only() {
        assert_eq!(
            doubled(&[0.0, 45.0, 90.0, 93.0]),
            vec![0.0, 22.5, 45.0, 67.5, 90.0, 93.0]
        );
    }

    #[test]
    fn halving_rates_reach_a_few_deg_s_from_rest() {
        let v = halving_rates(-300.0);
        assert_eq!(v.len(), RATE_KNOTS);
        assert_eq!(v.first(), Some(&-300.0));
        assert_eq!(v.last(), Some(&0.0));
        assert!(v[v.len() - 2].abs() >= MIN_RATE_SPACING_DEG_S && v[v.len() - 2].abs() < 10.0);
    }
}
