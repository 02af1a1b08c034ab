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

use super::candidate::Candidate;
use super::table_form::{PlacedKnots, TableForm};
use crate::data::campaign::Campaign;
use crate::model::effect::EffectKind;
use crate::model::torque_table::{HostTorqueTable, HOST_TABLE_MAX_KNOTS};

/// The farthest angle from the latch \[deg\] and the largest rate with the
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
/// table, a rate table and both, and the narrow tables of
/// [`snag_candidates`].
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
                    placed: None,
                }),
            });
        }
    }
    out.extend(snag_candidates(campaign));
    out
}

/// Centres of the narrow tables [`snag_candidates`] tries over a stroke.
pub const SNAG_CENTRES: usize = 14;

/// Narrow angle tables at each joint that moves: knots at the stroke's
/// ends and a triangle of half-width a fifteenth of the stroke at each of
/// [`SNAG_CENTRES`] centres spread evenly over it (five knots, all
/// fitted). A snag over a twentieth to a tenth of the stroke is crossed in
/// a few samples, too fast for the residual torque's smoother and too
/// narrow for the even five-knot table, whose knots are a quarter of the
/// stroke apart; the triangle's peak starts the fit there (its scan,
/// [`Candidate::scan`]) and the refinement doubles its knots.
pub fn snag_candidates(campaign: &Campaign) -> Vec<Candidate> {
    let mut out = Vec::new();
    for j in 0..campaign.max_joints() {
        let (from, rate) = spans(campaign, j);
        if from.abs() < 10.0 || rate.abs() < 1.0 {
            continue;
        }
        let (lo, hi) = (from.min(0.0), from.max(0.0));
        let w = (hi - lo) / 15.0;
        for k in 0..SNAG_CENTRES {
            let c = lo + (hi - lo) * (k as f64 + 1.0) / (SNAG_CENTRES as f64 + 1.0);
            let xs = [lo, (c - w).max(lo + 0.5), c, (c + w).min(hi - 0.5), hi];
            let mut angle_cdeg = [0; HOST_TABLE_MAX_KNOTS];
            for (d, x) in angle_cdeg.iter_mut().zip(xs) {
                *d = (x * 100.0).round() as i32;
            }
            if angle_cdeg.windows(2).take(4).any(|p| p[1] <= p[0]) {
                continue;
            }
            out.push(Candidate {
                kind: EffectKind::TorqueTable,
                joint: Some(j + 1),
                table: Some(TableForm {
                    angle_knots: 5,
                    from_deg: from.round() as i32,
                    rate_knots: 0,
                    rate_max_deg_s: rate.round() as i32,
                    placed: Some(PlacedKnots {
                        angle_cdeg,
                        rate_cdeg_s: [0; HOST_TABLE_MAX_KNOTS],
                    }),
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
pub fn shape_sentence(form: &TableForm, joint: usize, t: &HostTorqueTable) -> String {
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
        parts.push(rate_words(g.xs(), g.ys(), motion));
    } else {
        parts.push("independent of the rate".to_string());
    }
    format!("joint {joint}: {}", parts.join(", "))
}

/// Below this share of its peak, a rate law's value at the largest rate
/// makes it "peaked" (it falls back after a peak) \[1\].
const PEAK_FALL: f64 = 0.6;

/// A monotone rate law is "faster than linear (about quadratic)" when its
/// value at half the largest rate is below this share of its end value,
/// "saturating" when above `1 − QUADRATIC_MID` \[1\] (linear: ½).
const QUADRATIC_MID: f64 = 0.35;

/// How a rate law grows along the deployment's rate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RateGrowth {
    /// It falls back after a peak: at the largest rate below
    /// [`PEAK_FALL`] of its peak.
    Peaked,
    /// At half the largest rate below [`QUADRATIC_MID`] of its end value.
    Quadratic,
    /// Between the two.
    Linear,
    /// At half the largest rate above `1 − QUADRATIC_MID` of its end value.
    Saturating,
}

/// The shape of a rate law along the deployment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RateShape {
    /// How it grows.
    pub growth: RateGrowth,
    /// Its largest value: the rate \[deg/s, |φ̇|\] and the value \[N·m\].
    pub peak: (f64, f64),
    /// At the largest rate: the rate \[deg/s, |φ̇|\] and the value \[N·m\].
    pub end: (f64, f64),
}

/// The shape of the rate law of knots `xs` \[deg/s\], `ys` \[N·m\] along
/// the deployment (`motion` the sign of its rate); `None` without a knot
/// on the deployment's side.
pub fn rate_shape(xs: &[f64], ys: &[f64], motion: f64) -> Option<RateShape> {
    // Along the deployment: |rate| increasing.
    let mut pts: Vec<(f64, f64)> = xs
        .iter()
        .zip(ys)
        .filter(|(x, _)| **x * motion >= 0.0)
        .map(|(x, y)| (x.abs(), *y))
        .collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    let &end = pts.last()?;
    let &peak = pts
        .iter()
        .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
        .unwrap_or(&end);
    let shape = |growth| Some(RateShape { growth, peak, end });
    if end.1.abs() < PEAK_FALL * peak.1.abs() && peak.0 < end.0 {
        return shape(RateGrowth::Peaked);
    }
    let mid = crate::analysis::diagnose::residual_shape::interp(
        &pts.iter().map(|p| p.0).collect::<Vec<_>>(),
        &pts.iter().map(|p| p.1).collect::<Vec<_>>(),
        0.5 * end.0,
    );
    let ratio = mid / end.1;
    shape(if ratio < QUADRATIC_MID {
        RateGrowth::Quadratic
    } else if ratio > 1.0 - QUADRATIC_MID {
        RateGrowth::Saturating
    } else {
        RateGrowth::Linear
    })
}

/// How a rate table depends on the rate, in words: peaked near a rate,
/// growing faster than linearly, about linearly or saturating; resisting or
/// driving; its size. `motion` is the sign of the deployment's rate.
pub fn rate_words(xs: &[f64], ys: &[f64], motion: f64) -> String {
    let Some(RateShape { growth, peak, end }) = rate_shape(xs, ys, motion) else {
        return "independent of the rate".into();
    };
    let sign = if peak.1 * motion < 0.0 {
        "resisting"
    } else {
        "driving"
    };
    let (r_end, y_end) = end;
    let growth = match growth {
        RateGrowth::Peaked => {
            return format!(
                "a {sign} part peaked near zero rate ({:.3} N·m at {:.0} deg/s, {:.3} N·m at {r_end:.0} deg/s)",
                peak.1.abs(),
                peak.0,
                y_end.abs()
            )
        }
        RateGrowth::Quadratic => "growing faster than linearly (about quadratic)",
        RateGrowth::Saturating => "rising fast and saturating",
        RateGrowth::Linear => "growing about linearly",
    };
    format!(
        "a {sign} part {growth} with the rate to {:.3} N·m at {r_end:.0} deg/s",
        y_end.abs()
    )
}

/// A discovered table with its 95 % band, knot by knot: `[fitted, lower,
/// upper]` (the rate table's fixed `g(0) = 0` has no width).
pub fn band(form: &TableForm, p: &[f64], ci: &[[f64; 2]]) -> [HostTorqueTable; 3] {
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
            placed: None,
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
