//! Discovering a torque no named effect describes (`torque_table`,
//! `docs/spec/physics.md` section 6).
//!
//! When the named effects leave a residual above the noise, the missing
//! joint torque is fitted directly through the simulator: at each joint, a
//! table `f(φ)` over the stroke, a table `g(φ̇)` over the rates the runs
//! reach, or both, each with a few knots (five over the angle, two free
//! over the rate with `g(0) = 0` so that `f` carries the constant part).
//! Few, evenly spread knots are the regularisation: a piecewise-linear
//! torque with five knots cannot chase the noise of 2 × 600 samples, and
//! its knot values get 95 % intervals from the Jacobian like any effect's
//! value. The joint is localised by the training criterion (BIC) of the
//! table fitted at each joint; the table is then judged like any effect
//! (BIC gain, an interval clear of zero, the held-out RMS of the set).

use super::Candidate;
use crate::data::campaign::Campaign;
use crate::model::effect::{Effect, EffectKind};
use crate::model::torque_table::max_abs_nm;
use deploywatch_core::{Table, TorqueTable};

/// The form of a candidate table at one joint: which tables, over which
/// span. Integers so that candidates stay comparable and hashable.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TableForm {
    /// Knots of `f(φ)` (0: no angle table).
    pub angle_knots: u8,
    /// The stroke end farthest from the latch [deg]; the knots are spread
    /// from it to 0 (the latch).
    pub from_deg: i32,
    /// Free knots of `g(φ̇)` (0: no rate table).
    pub rate_knots: u8,
    /// The largest rate the runs reach at this joint, with the sign of the
    /// deployment [deg/s]; the knots are spread from 0 to it.
    pub rate_max_deg_s: i32,
}

impl TableForm {
    /// Knots of a discovered angle table `f(φ)`, spread evenly over the stroke
    /// (five: one every 45° of a 180° stroke, fine enough for a bump a quarter
    /// of the stroke wide, coarse enough not to follow the noise).
    pub const ANGLE_KNOTS: u8 = 5;
    /// Free knots of a discovered rate table `g(φ̇)` (beside `g(0) = 0`).
    pub const RATE_KNOTS: u8 = 2;
    /// Smallest rate span of a rate table [deg/s]: its first knot then sits
    /// at 30 deg/s or more, so that `g` never becomes a stiff damper.
    pub const MIN_RATE_SPAN_DEG_S: f64 = 60.0;
    /// Bound on a discovered knot's torque [N·m]: beyond any hinge spring of the
    /// seed mechanisms, so never active on a real torque.
    pub const BOUND_NM: f64 = 5.0;

    /// Number of parameters (knot torques).
    pub fn params(&self) -> usize {
        usize::from(self.angle_knots) + usize::from(self.rate_knots)
    }

    /// `"angle"`, `"rate"` or `"angle+rate"`.
    pub fn name(&self) -> &'static str {
        match (self.angle_knots > 0, self.rate_knots > 0) {
            (true, true) => "angle+rate",
            (true, false) => "angle",
            _ => "rate",
        }
    }

    /// The angle knots [deg], increasing.
    pub fn angle_xs(&self) -> Vec<f64> {
        let k = usize::from(self.angle_knots);
        let from = f64::from(self.from_deg);
        let mut xs: Vec<f64> = (0..k)
            .map(|i| from * (1.0 - i as f64 / (k - 1).max(1) as f64))
            .collect();
        xs.sort_by(f64::total_cmp);
        xs
    }

    /// The rate knots [deg/s], increasing, with `0` among them.
    pub fn rate_xs(&self) -> Vec<f64> {
        let k = usize::from(self.rate_knots);
        let r = f64::from(self.rate_max_deg_s);
        let mut xs: Vec<f64> = (0..=k).map(|i| r * i as f64 / k.max(1) as f64).collect();
        xs.sort_by(f64::total_cmp);
        xs
    }

    /// The torque table with knot torques `p` (angle knots, then the free
    /// rate knots from the rate 0 outwards).
    pub fn table(&self, p: &[f64]) -> TorqueTable<f64> {
        let na = usize::from(self.angle_knots);
        let angle = (na >= 2)
            .then(|| {
                let xs = self.angle_xs();
                let mut ys = p[..na].to_vec();
                if self.from_deg > 0 {
                    // Knots were given from the stroke end to 0: reverse to
                    // match increasing angles.
                    ys.reverse();
                }
                // `angle_xs` runs from `from_deg` to 0; for a negative
                // stroke that is already increasing and the torques match.
                Table::new(&xs, &ys).ok()
            })
            .flatten();
        let rate = (self.rate_knots > 0)
            .then(|| {
                let xs = self.rate_xs();
                let mut ys = vec![0.0];
                ys.extend_from_slice(&p[na..na + usize::from(self.rate_knots)]);
                if self.rate_max_deg_s < 0 {
                    ys.reverse();
                }
                Table::new(&xs, &ys).ok()
            })
            .flatten();
        TorqueTable { angle, rate }
    }

    /// The effect at `joint` with knot torques `p`.
    pub fn effect(&self, joint: Option<usize>, p: &[f64]) -> Effect {
        let table = self.table(p);
        Effect {
            kind: EffectKind::TorqueTable,
            joint,
            value: max_abs_nm(&table),
            table,
            ..Effect::default()
        }
    }
}

/// The farthest angle from the latch [deg] and the largest rate with the
/// sign of the motion [deg/s] that the runs reach at 0-based joint `j`
/// (rates from 5-sample differences, which average the sensor noise down).
fn spans(campaign: &Campaign, j: usize) -> (f64, f64) {
    let (mut from, mut rate) = (0.0f64, 0.0f64);
    for r in &campaign.runs {
        let (Some(phi), t) = (r.run.phi_deg.get(j), &r.run.t_s) else {
            continue;
        };
        for (i, &p) in phi.iter().enumerate() {
            if p.abs() > from.abs() {
                from = p;
            }
            if i >= 5 {
                let v = (p - phi[i - 5]) / (t[i] - t[i - 5]);
                if v.is_finite() && v.abs() > rate.abs() {
                    rate = v;
                }
            }
        }
    }
    (from, rate)
}

/// Every table candidate of a campaign: at each joint that moves, an angle
/// table, a rate table and both.
pub fn table_candidates(campaign: &Campaign) -> Vec<Candidate> {
    let mut out = Vec::new();
    for j in 0..campaign.max_joints() {
        let (from, rate) = spans(campaign, j);
        if from.abs() < 1.0 || rate.abs() < 1.0 {
            continue;
        }
        let from_deg = from.round() as i32;
        // Knots closer than this in rate would make a stiff damper of the
        // table (a steep g near φ̇ = 0 stalls the integrator).
        let rate_max_deg_s =
            (rate.abs().max(TableForm::MIN_RATE_SPAN_DEG_S) * rate.signum()).round() as i32;
        for (a, r) in [
            (TableForm::ANGLE_KNOTS, 0),
            (0, TableForm::RATE_KNOTS),
            (TableForm::ANGLE_KNOTS, TableForm::RATE_KNOTS),
        ] {
            out.push(Candidate {
                kind: EffectKind::TorqueTable,
                joint: Some(j + 1),
                table: Some(TableForm {
                    angle_knots: a,
                    from_deg,
                    rate_knots: r,
                    rate_max_deg_s,
                }),
            });
        }
    }
    out
}

/// Where in the stroke a torque over `[lo, hi]` deg acts, in words, for a
/// joint whose stroke runs from `from_deg` to 0.
fn stroke_region(from_deg: f64, lo: f64, hi: f64) -> String {
    let frac = |x: f64| 1.0 - x / from_deg; // 0 at the stowed end, 1 at the latch
    let (a, b) = {
        let (p, q) = (frac(lo).clamp(0.0, 1.0), frac(hi).clamp(0.0, 1.0));
        (p.min(q), p.max(q))
    };
    let part = |x: f64| {
        if x < 1.0 / 3.0 {
            "first third"
        } else if x < 2.0 / 3.0 {
            "middle third"
        } else {
            "last third"
        }
    };
    if b - a > 0.8 {
        "over the whole stroke".to_string()
    } else if part(a) == part(b) {
        format!("in the {} of the stroke", part(a))
    } else {
        format!("from the {} to the {} of the stroke", part(a), part(b))
    }
}

/// One sentence on the shape of a discovered torque: which joint, where in
/// the stroke, how it depends on the rate, and its sign (resisting or
/// driving the deployment).
pub fn shape_sentence(form: &TableForm, joint: usize, t: &TorqueTable<f64>) -> String {
    let motion = -f64::from(form.from_deg).signum(); // sign of φ̇ while deploying
    let mut parts = Vec::new();
    if let Some(f) = &t.angle {
        let peak = f
            .ys()
            .iter()
            .copied()
            .fold(0.0f64, |m, y| if y.abs() > m.abs() { y } else { m });
        let strong: Vec<f64> = f
            .xs()
            .iter()
            .zip(f.ys())
            .filter(|(_, y)| *y * peak > 0.0 && y.abs() >= 0.5 * peak.abs())
            .map(|(x, _)| *x)
            .collect();
        let lo = strong.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = strong.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let span = if hi - lo < 1.0 {
            format!("around {lo:.0}°")
        } else {
            format!("{lo:.0}° to {hi:.0}°")
        };
        parts.push(format!(
            "a {} torque of up to {:.3} N·m {} ({span})",
            if peak * motion < 0.0 {
                "resisting"
            } else {
                "driving"
            },
            peak.abs(),
            stroke_region(f64::from(form.from_deg), lo, hi)
        ));
    }
    if let Some(g) = &t.rate {
        let end = if motion > 0.0 {
            g.ys()[g.ys().len() - 1]
        } else {
            g.ys()[0]
        };
        parts.push(format!(
            "a {} part that grows with the rate to {:.3} N·m at {} deg/s",
            if end * motion < 0.0 {
                "resisting"
            } else {
                "driving"
            },
            end.abs(),
            form.rate_max_deg_s
        ));
    } else {
        parts.push("independent of the rate".to_string());
    }
    format!("joint {joint}: {}", parts.join(", "))
}

/// A discovered table with its 95 % band, knot by knot: `[fitted, lower,
/// upper]` (the rate table's fixed `g(0) = 0` has no width).
pub fn band(form: &TableForm, p: &[f64], ci: &[[f64; 2]]) -> [TorqueTable<f64>; 3] {
    let lo: Vec<f64> = ci.iter().map(|c| c[0]).collect();
    let hi: Vec<f64> = ci.iter().map(|c| c[1]).collect();
    [form.table(p), form.table(&lo), form.table(&hi)]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn form(from_deg: i32, rate_max_deg_s: i32) -> TableForm {
        TableForm {
            angle_knots: TableForm::ANGLE_KNOTS,
            from_deg,
            rate_knots: TableForm::RATE_KNOTS,
            rate_max_deg_s,
        }
    }

    #[test]
    fn given_a_stroke_from_180_when_tabled_then_knot_values_follow_the_angles() {
        // Knot torques are given from the stowed end towards the latch.
        let t = form(180, -200).table(&[1.0, 2.0, 3.0, 4.0, 5.0, 0.5, 0.7]);
        let f = t.angle.unwrap();
        assert_eq!(f.xs(), &[0.0, 45.0, 90.0, 135.0, 180.0]);
        assert_eq!(f.ys(), &[5.0, 4.0, 3.0, 2.0, 1.0]);
        let g = t.rate.unwrap();
        assert_eq!(g.xs(), &[-200.0, -100.0, 0.0]);
        assert_eq!(g.ys(), &[0.7, 0.5, 0.0]);
    }

    #[test]
    fn given_a_stroke_from_minus_90_then_the_knots_are_already_increasing() {
        let t = form(-90, 150).table(&[1.0, 2.0, 3.0, 4.0, 5.0, -0.1, -0.2]);
        assert_eq!(t.angle.unwrap().xs(), &[-90.0, -67.5, -45.0, -22.5, 0.0]);
        assert_eq!(t.angle.unwrap().ys(), &[1.0, 2.0, 3.0, 4.0, 5.0]);
        assert_eq!(t.rate.unwrap().ys(), &[0.0, -0.1, -0.2]);
    }

    #[test]
    fn given_a_resisting_bump_then_the_shape_names_joint_region_and_sign() {
        // Joint 2 deploys from 180° towards 0 (φ̇ < 0): a positive torque resists.
        let f = TableForm {
            rate_knots: 0,
            ..form(180, -200)
        };
        let t = f.table(&[0.0, 0.05, 0.3, 0.05, 0.0]);
        let s = shape_sentence(&f, 2, &t);
        assert!(
            s.starts_with("joint 2: a resisting torque of up to 0.300 N·m"),
            "{s}"
        );
        assert!(
            s.contains("middle third") && s.contains("around 90°"),
            "{s}"
        );
        assert!(s.contains("independent of the rate"), "{s}");
    }
}
