//! The shape of a residual torque at the resolution the data supports.
//!
//! A joint's residual torque samples ([`crate::analysis::diagnose::residual_torque`])
//! are fitted by least squares — no simulation — as `f(φ)`, `g(φ̇)` or
//! `f(φ) + g(φ̇)`, each piecewise linear through its knots and held
//! constant beyond its end knots (the `torque_table` of `physics.md`
//! section 6), with `g(0) = 0` so that `f` carries any constant part.
//! The knots are placed where the torque bends: greedy insertion from a
//! grid of candidate places (quantiles of the samples), each step adding
//! the knot that lowers the residual sum of squares most, then removal of
//! knots that no longer pay. The number of knots is chosen by BIC,
//! `n_eff ln(RSS/n) + k ln n_eff`, with `n_eff` counting one independent
//! value per smoothing window (neighbouring samples' errors correlate).

use crate::analysis::diagnose::residual_torque::TorqueSample;

/// Most knots of one fitted table (angle or rate): the host's table size.
pub const MAX_KNOTS: usize = crate::model::torque_table::HOST_TABLE_MAX_KNOTS;

/// Candidate knot places per axis (quantiles of the samples).
const GRID: usize = 48;

/// Knot insertion stops after this many steps without a better BIC.
const STALE_STEPS: usize = 3;

/// Smallest spacing of two angle knots \[deg\]: a feature a tenth of a 90°
/// stroke wide spans 9°, resolved by knots 2° apart.
pub const MIN_ANGLE_SPACING_DEG: f64 = 2.0;

/// Smallest spacing of two rate knots, and smallest first rate knot
/// [deg/s]: below this a table is a stiff damper near rest.
pub const MIN_RATE_SPACING_DEG_S: f64 = 3.0;

/// Which axis a knot is on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    /// The joint angle \[deg\].
    Angle,
    /// The joint rate [deg/s]; its knot at 0 is held at 0 N·m.
    Rate,
}

/// A fitted shape: knots and values of `f` and `g`, and the fit's scores.
#[derive(Clone, Debug, PartialEq)]
pub struct Shape {
    /// Angle knots \[deg\], increasing (empty: no `f`).
    pub angle_deg: Vec<f64>,
    /// `f` at those knots [N·m].
    pub angle_nm: Vec<f64>,
    /// Rate knots [deg/s], increasing, with 0 among them (empty: no `g`).
    pub rate_deg_s: Vec<f64>,
    /// `g` at those knots [N·m] (0 at the rate 0).
    pub rate_nm: Vec<f64>,
    /// Residual sum of squares [N·m²].
    pub rss: f64,
    /// The fit's BIC (on the effective sample count).
    pub bic: f64,
    /// BIC of no torque at all (the same samples).
    pub bic_zero: f64,
}

impl Shape {
    /// Number of free values.
    pub fn params(&self) -> usize {
        self.angle_nm.len() + self.rate_nm.len().saturating_sub(1)
    }

    /// The fitted torque at angle `phi` \[deg\] and rate `rate` [deg/s] [N·m].
    pub fn eval(&self, phi: f64, rate: f64) -> f64 {
        interp(&self.angle_deg, &self.angle_nm, phi) + interp(&self.rate_deg_s, &self.rate_nm, rate)
    }
}

/// Piecewise-linear interpolation, held beyond the ends (as the core's
/// `Table::eval`); 0 for an empty table.
pub fn interp(xs: &[f64], ys: &[f64], x: f64) -> f64 {
    let (Some(&x0), Some(&y0)) = (xs.first(), ys.first()) else {
        return 0.0;
    };
    if !(x > x0) {
        return y0;
    }
    for k in 1..xs.len() {
        if x < xs[k] {
            let s = (x - xs[k - 1]) / (xs[k] - xs[k - 1]);
            return ys[k - 1] + s * (ys[k] - ys[k - 1]);
        }
    }
    ys.last().copied().unwrap_or(0.0)
}

/// The hat-function weights of `x` on knots `xs`: the value of the
/// piecewise-linear basis function of each knot at `x`.
fn hats(xs: &[f64], x: f64, out: &mut [f64]) {
    out.iter_mut().for_each(|v| *v = 0.0);
    if xs.is_empty() {
        return;
    }
    if !(x > xs[0]) {
        out[0] = 1.0;
        return;
    }
    for k in 1..xs.len() {
        if x < xs[k] {
            let s = (x - xs[k - 1]) / (xs[k] - xs[k - 1]);
            out[k - 1] = 1.0 - s;
            out[k] = s;
            return;
        }
    }
    out[xs.len() - 1] = 1.0;
}

/// Knots of both axes being fitted.
#[derive(Clone, Debug, PartialEq)]
struct Knots {
    angle: Vec<f64>,
    rate: Vec<f64>,
}

/// The samples' values on one axis.
fn axis_value(s: &TorqueSample, a: Axis) -> f64 {
    match a {
        Axis::Angle => s.phi_deg,
        Axis::Rate => s.rate_deg_s,
    }
}

/// Weighted least squares of the samples on the knots' basis (the rate knot
/// at 0 excluded: `g(0) = 0`). Returns the values per knot and the RSS.
fn solve(samples: &[TorqueSample], k: &Knots) -> Option<(Vec<f64>, Vec<f64>, f64)> {
    let na = k.angle.len();
    let nr = k.rate.len();
    let zero = k.rate.iter().position(|&x| x == 0.0);
    let p = na + nr - usize::from(zero.is_some());
    if p == 0 {
        return None;
    }
    let mut ata = vec![vec![0.0; p]; p];
    let mut atb = vec![0.0; p];
    let (mut ha, mut hr) = (vec![0.0; na], vec![0.0; nr]);
    let mut row = vec![0.0; p];
    for s in samples {
        hats(&k.angle, s.phi_deg, &mut ha);
        hats(&k.rate, s.rate_deg_s, &mut hr);
        row[..na].copy_from_slice(&ha);
        let mut c = na;
        for (q, v) in hr.iter().enumerate() {
            if Some(q) != zero {
                row[c] = *v;
                c += 1;
            }
        }
        let w = 1.0 / s.se_nm.max(1e-9).powi(2);
        for a in 0..p {
            if row[a] == 0.0 {
                continue;
            }
            atb[a] += w * row[a] * s.torque_nm;
            for b in 0..p {
                ata[a][b] += w * row[a] * row[b];
            }
        }
    }
    let x = solve_spd(ata, atb)?;
    let angle = x[..na].to_vec();
    let mut rate = Vec::with_capacity(nr);
    let mut c = na;
    for q in 0..nr {
        if Some(q) == zero {
            rate.push(0.0);
        } else {
            rate.push(x[c]);
            c += 1;
        }
    }
    let rss = samples
        .iter()
        .map(|s| {
            let e = s.torque_nm
                - interp(&k.angle, &angle, s.phi_deg)
                - interp(&k.rate, &rate, s.rate_deg_s);
            (e / s.se_nm.max(1e-9)).powi(2)
        })
        .sum();
    Some((angle, rate, rss))
}

/// Solves `A x = b` for a symmetric positive semi-definite `A` by Cholesky
/// with a small ridge (a knot no sample reaches gets 0).
fn solve_spd(mut a: Vec<Vec<f64>>, b: Vec<f64>) -> Option<Vec<f64>> {
    let n = b.len();
    let scale = (0..n).map(|i| a[i][i]).fold(0.0, f64::max).max(1e-30);
    for (i, row) in a.iter_mut().enumerate() {
        row[i] += 1e-9 * scale;
    }
    let mut l = vec![vec![0.0; n]; n];
    for i in 0..n {
        for j in 0..=i {
            let s: f64 = a[i][j] - (0..j).map(|k| l[i][k] * l[j][k]).sum::<f64>();
            if i == j {
                if !(s > 0.0) {
                    return None;
                }
                l[i][i] = s.sqrt();
            } else {
                l[i][j] = s / l[j][j];
            }
        }
    }
    let mut y = vec![0.0; n];
    for i in 0..n {
        y[i] = (b[i] - (0..i).map(|k| l[i][k] * y[k]).sum::<f64>()) / l[i][i];
    }
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        x[i] = (y[i] - (i + 1..n).map(|k| l[k][i] * x[k]).sum::<f64>()) / l[i][i];
    }
    Some(x)
}

/// Effective number of independent samples among samples [`thin`]ned to
/// half a window apart (their errors correlate little).
fn n_eff(samples: &[TorqueSample]) -> f64 {
    (samples.len() as f64).max(1.0)
}

/// BIC of a fit with weighted RSS `rss` and `k` free values.
pub fn bic(samples: &[TorqueSample], rss: f64, k: usize) -> f64 {
    let n = samples.len().max(1) as f64;
    let ne = n_eff(samples);
    ne * (rss.max(1e-300) / n).ln() + k as f64 * ne.ln()
}

/// The range of `axis` every run covers: a knot outside it would be
/// fitted by some runs only, and a table fitted on one run would not
/// predict another (the held-out rule).
fn common_range(samples: &[TorqueSample], axis: Axis) -> (f64, f64) {
    let runs = samples.iter().map(|s| s.run).max().map_or(0, |r| r + 1);
    let mut lo = f64::NEG_INFINITY;
    let mut hi = f64::INFINITY;
    for r in 0..runs {
        let v = samples
            .iter()
            .filter(|s| s.run == r)
            .map(|s| axis_value(s, axis));
        let (a, b) = v.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
        if a <= b {
            lo = lo.max(a);
            hi = hi.min(b);
        }
    }
    (lo, hi)
}

/// Candidate knot places on `axis`: quantiles of the samples within the
/// range every run covers (rates only on the side the joint deploys, away
/// from 0 by the minimum spacing).
fn grid(samples: &[TorqueSample], axis: Axis, motion: f64) -> Vec<f64> {
    let (lo, hi) = common_range(samples, axis);
    let mut v: Vec<f64> = samples
        .iter()
        .map(|s| axis_value(s, axis))
        .filter(|x| x.is_finite() && *x >= lo && *x <= hi)
        .filter(|x| axis == Axis::Angle || x * motion >= MIN_RATE_SPACING_DEG_S)
        .collect();
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        return v;
    }
    let mut g: Vec<f64> = (0..GRID)
        .map(|i| v[(i * (v.len() - 1)) / (GRID - 1)])
        .map(|x| (x * 100.0).round() / 100.0)
        .collect();
    g.dedup();
    g
}

/// The starting knots of an axis: the ends of the samples' range (for the
/// rate: 0 and the largest rate in the direction of deployment).
fn ends(samples: &[TorqueSample], axis: Axis, motion: f64) -> Vec<f64> {
    let g = grid(samples, axis, motion);
    match (axis, g.first(), g.last()) {
        (Axis::Angle, Some(&a), Some(&b)) if b - a >= MIN_ANGLE_SPACING_DEG => vec![a, b],
        (Axis::Rate, Some(&a), Some(&b)) => {
            let far = if motion > 0.0 { b } else { a };
            let mut v = vec![0.0, far];
            v.sort_by(f64::total_cmp);
            v
        }
        _ => Vec::new(),
    }
}

/// Whether `x` may join `knots` on `axis` (room to the others).
fn room(knots: &[f64], x: f64, axis: Axis) -> bool {
    let gap = match axis {
        Axis::Angle => MIN_ANGLE_SPACING_DEG,
        Axis::Rate => MIN_RATE_SPACING_DEG_S,
    };
    knots.iter().all(|k| (k - x).abs() >= gap)
}

/// How knots are counted: what a knot must gain to be kept.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KnotScore {
    /// BIC on the samples: a knot must pay for itself (a fit to measured,
    /// noisy torques).
    Bic,
    /// The residual sum of squares alone: every knot up to the limit is
    /// kept (a compression of a known torque, where more knots are always
    /// closer).
    Rss,
}

/// Fits the samples of a joint deploying in direction `motion` (the sign of
/// `φ̇`) with the axes `axes` (angle, rate or both): greedy knot insertion
/// up to [`MAX_KNOTS`] per axis, the count by BIC, then removal of knots
/// that lower the BIC.
pub fn fit_shape(samples: &[TorqueSample], motion: f64, axes: &[Axis]) -> Option<Shape> {
    fit_shape_with(samples, motion, axes, MAX_KNOTS, KnotScore::Bic)
}

/// [`fit_shape`] with at most `max_knots` knots per axis, counted by
/// `criterion`.
pub fn fit_shape_with(
    samples: &[TorqueSample],
    motion: f64,
    axes: &[Axis],
    max_knots: usize,
    criterion: KnotScore,
) -> Option<Shape> {
    let mut k = Knots {
        angle: Vec::new(),
        rate: Vec::new(),
    };
    for &a in axes {
        match a {
            Axis::Angle => k.angle = ends(samples, a, motion),
            Axis::Rate => k.rate = ends(samples, a, motion),
        }
    }
    let grids: Vec<(Axis, Vec<f64>)> = axes
        .iter()
        .map(|&a| (a, grid(samples, a, motion)))
        .collect();
    let score = |k: &Knots| -> Option<f64> {
        let (_, _, rss) = solve(samples, k)?;
        let p = k.angle.len() + k.rate.len().saturating_sub(1);
        Some(match criterion {
            KnotScore::Bic => bic(samples, rss, p),
            KnotScore::Rss => rss,
        })
    };
    let mut best = (score(&k)?, k.clone());
    let mut cur = k;
    let mut stale = 0;
    while stale < STALE_STEPS {
        let mut step: Option<(f64, Knots)> = None;
        for (axis, g) in &grids {
            let list = match axis {
                Axis::Angle => &cur.angle,
                Axis::Rate => &cur.rate,
            };
            if list.len() >= max_knots {
                continue;
            }
            for &x in g.iter().filter(|&&x| room(list, x, *axis)) {
                let mut next = cur.clone();
                let l = match axis {
                    Axis::Angle => &mut next.angle,
                    Axis::Rate => &mut next.rate,
                };
                l.push(x);
                l.sort_by(f64::total_cmp);
                if let Some(s) = score(&next) {
                    if step.as_ref().is_none_or(|b| s < b.0) {
                        step = Some((s, next));
                    }
                }
            }
        }
        let Some((s, next)) = step else { break };
        if s < best.0 {
            best = (s, next.clone());
            stale = 0;
        } else {
            stale += 1;
        }
        cur = next;
    }
    let knots = prune(best.1, &score);
    finish(samples, knots)
}

/// Removes interior knots one at a time while that lowers the BIC.
fn prune(mut k: Knots, score: &dyn Fn(&Knots) -> Option<f64>) -> Knots {
    loop {
        let Some(now) = score(&k) else { return k };
        let mut best: Option<(f64, Knots)> = None;
        for axis in [Axis::Angle, Axis::Rate] {
            let list = match axis {
                Axis::Angle => &k.angle,
                Axis::Rate => &k.rate,
            };
            for q in 1..list.len().saturating_sub(1) {
                let mut next = k.clone();
                match axis {
                    Axis::Angle => next.angle.remove(q),
                    Axis::Rate => next.rate.remove(q),
                };
                if let Some(s) = score(&next) {
                    if s < now && best.as_ref().is_none_or(|b| s < b.0) {
                        best = Some((s, next));
                    }
                }
            }
        }
        match best {
            Some((_, next)) => k = next,
            None => return k,
        }
    }
}

/// The shape of the final knots, with its scores.
fn finish(samples: &[TorqueSample], k: Knots) -> Option<Shape> {
    let (angle_nm, rate_nm, rss) = solve(samples, &k)?;
    let p = k.angle.len() + k.rate.len().saturating_sub(1);
    let rss0: f64 = samples
        .iter()
        .map(|s| (s.torque_nm / s.se_nm.max(1e-9)).powi(2))
        .sum();
    Some(Shape {
        angle_deg: k.angle,
        angle_nm,
        rate_deg_s: k.rate,
        rate_nm,
        rss,
        bic: bic(samples, rss, p),
        bic_zero: bic(samples, rss0, 0),
    })
}

/// Every few samples, half a smoothing window apart: neighbouring samples
/// carry nearly the same information (their errors correlate over a
/// window), and fits are faster on fewer.
pub fn thin(samples: &[TorqueSample]) -> Vec<TorqueSample> {
    let mut w: Vec<usize> = samples.iter().map(|s| s.window).collect();
    w.sort_unstable();
    let stride = (w.get(w.len() / 2).copied().unwrap_or(1) / 2).max(1);
    samples.iter().step_by(stride).copied().collect()
}

/// The best of the three forms (angle, rate, both) by BIC.
pub fn best_shape(samples: &[TorqueSample], motion: f64) -> Option<Shape> {
    let thinned = thin(samples);
    let samples = &thinned[..];
    [
        vec![Axis::Angle],
        vec![Axis::Rate],
        vec![Axis::Angle, Axis::Rate],
    ]
    .iter()
    .filter_map(|axes| fit_shape(samples, motion, axes))
    .min_by(|a, b| a.bic.total_cmp(&b.bic))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 2000 samples of a stroke, the rate peaking at 4e+02 deg/s.
    fn samples(f: impl Fn(f64, f64) -> f64) -> Vec<TorqueSample> {
        crate::analysis::diagnose::residual_torque::synthetic_stroke(2000, 400.0, 0.01, 5, f)
    }

    #[test]
    fn given_a_narrow_bump_then_knots_gather_on_it() {
        let s = samples(|phi, _| 0.3 * (-((phi - 120.0) / 5.0).powi(2)).exp());
        let shape = fit_shape(&s, -1.0, &[Axis::Angle]).unwrap();
        let near = shape
            .angle_deg
            .iter()
            .filter(|x| (*x - 120.0).abs() < 12.0)
            .count();
        assert!(near >= 3, "{:?}", shape.angle_deg);
        assert!((shape.eval(120.0, 0.0) - 0.3).abs() < 0.06, "{shape:?}");
    }

    #[test]
    fn given_a_hump_at_low_rate_then_the_rate_table_peaks_there() {
        let hump = |v: f64| 0.2 * (v / 15.0) * (1.0 - v / 15.0).exp();
        let s = samples(|_, rate| hump(-rate));
        let shape = best_shape(&s, -1.0).unwrap();
        assert!(!shape.rate_deg_s.is_empty(), "{shape:?}");
        assert!((shape.eval(90.0, -15.0) - 0.2).abs() < 0.05, "{shape:?}");
        assert!(shape.eval(90.0, -200.0).abs() < 0.05, "{shape:?}");
    }
}
