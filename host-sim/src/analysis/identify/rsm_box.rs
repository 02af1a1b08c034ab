//! The minimum of a response surface ([`Quadratic`]) in a box: exact by
//! enumerating the box's faces for few factors ([`minimize_in_box`]), a
//! multi-start projected-gradient descent for many
//! ([`minimize_in_box_projected`]); the third part of the response-surface
//! method of [`crate::analysis::identify::rsm`].

use nalgebra::{DMatrix, DVector};

use super::rsm::{check_dim, Coding, Quadratic, RsmError, EXACT_MAX_FACTORS};

/// The minimum of a surface in a box.
#[derive(Clone, Debug, PartialEq)]
pub struct BoxMinimum {
    /// The minimiser (the model's units).
    pub x: Vec<f64>,
    /// The surface's value there.
    pub value: f64,
    /// Per variable: `-1` at its lower bound, `+1` at its upper bound, `0` inside.
    pub active: Vec<i8>,
}

fn check_box(k: usize, lo: &[f64], hi: &[f64]) -> Result<(), RsmError> {
    check_dim("lower bounds", k, lo.len())?;
    check_dim("upper bounds", k, hi.len())?;
    if lo.iter().chain(hi).any(|v| !v.is_finite()) {
        return Err(RsmError::NotFinite);
    }
    if lo.iter().zip(hi).any(|(l, h)| l >= h) {
        return Err(RsmError::BadBox);
    }
    Ok(())
}

/// A coordinate within this fraction of its box's width of a bound is on
/// it (ratio): rounding, not an interior point.
const ACTIVE_BOUND_TOL: f64 = 1e-12;

/// A stationary point found by the linear solve may pass a bound by this
/// fraction of the box's width (ratio) and still count as inside.
const SOLUTION_BOUND_SLACK: f64 = 1e-9;

/// Most iterations of the projected gradient descent: far more than a
/// quadratic in a few coded factors needs; the cap only bounds a
/// pathological surface.
const DESCENT_MAX_ITERATIONS: usize = 20_000;

/// Most halvings of a trial step in one iteration (2⁻⁶⁰: below any step
/// that moves a coded coordinate).
const DESCENT_MAX_HALVINGS: usize = 60;

/// The first trial step of an iteration, as a multiple of the last
/// accepted one: lets the step grow again after it had to shrink.
const DESCENT_STEP_GROWTH: f64 = 4.0;

/// Armijo's sufficient-decrease fraction (Nocedal & Wright §3.1: 10⁻⁴).
const ARMIJO_FRACTION: f64 = 1e-4;

/// A step moving no coded coordinate more than this has converged (coded
/// units, a few ulps of 1).
const DESCENT_MIN_MOVE: f64 = 1e-15;

fn active_set(x: &[f64], lo: &[f64], hi: &[f64]) -> Vec<i8> {
    x.iter()
        .zip(lo.iter().zip(hi))
        .map(|(&v, (&l, &h))| {
            let tol = ACTIVE_BOUND_TOL * (h - l);
            if v <= l + tol {
                -1
            } else if v >= h - tol {
                1
            } else {
                0
            }
        })
        .collect()
}

/// The stationary point of `q` on the face where the variables with
/// `state[i] = -1/+1` sit at their lower/upper bound and the others are free,
/// if the reduced system is regular and its solution lies in the box
/// (clamped to it).
fn face_point(
    b: &DVector<f64>,
    h: &DMatrix<f64>,
    state: &[i8],
    lo: &[f64],
    hi: &[f64],
) -> Option<Vec<f64>> {
    let k = state.len();
    let mut x: Vec<f64> = (0..k)
        .map(|i| match state[i] {
            -1 => lo[i],
            1 => hi[i],
            _ => 0.5 * (lo[i] + hi[i]),
        })
        .collect();
    let free: Vec<usize> = (0..k).filter(|&i| state[i] == 0).collect();
    if free.is_empty() {
        return Some(x);
    }
    let m = free.len();
    // H_FF x_F = −(b_F + H_FB x_B)
    let hff = DMatrix::from_fn(m, m, |r, c| h[(free[r], free[c])]);
    let rhs = DVector::from_fn(m, |r, _| {
        let i = free[r];
        let mut v = -b[i];
        for j in 0..k {
            if state[j] != 0 {
                v -= h[(i, j)] * x[j];
            }
        }
        v
    });
    let sol = hff.lu().solve(&rhs)?;
    for (r, &i) in free.iter().enumerate() {
        let v = sol[r];
        let tol = SOLUTION_BOUND_SLACK * (hi[i] - lo[i]);
        if !v.is_finite() || v < lo[i] - tol || v > hi[i] + tol {
            return None;
        }
        x[i] = v.clamp(lo[i], hi[i]);
    }
    Some(x)
}

/// The minimum of the quadratic `q` over the box `lo ≤ x ≤ hi` (the model's
/// units; to minimise a coded-unit model over a natural-unit box, convert it
/// first with [`Quadratic::to_natural`]).
///
/// For `k ≤` [`EXACT_MAX_FACTORS`] the result is exact: the minimiser lies in
/// the relative interior of some face of the box (all `3^k` of them: each
/// variable at its lower bound, its upper bound, or free), where the gradient
/// with respect to the free variables vanishes, `H_FF x_F = −(b_F + H_FB x_B)`.
/// Every face with a regular `H_FF` whose solution is in the box is a
/// candidate and the lowest candidate wins. A face whose `H_FF` is singular
/// can be skipped: if the minimiser lay only there, `f` would be constant
/// along a null direction of `H_FF` (gradient zero, curvature zero), and
/// following it to the face's boundary gives an equally low point on a
/// smaller face. Vertices have no free variable and are always candidates.
///
/// For more factors, [`minimize_in_box_projected`] from the centre, the
/// centres of the faces and the vertex the gradient points away from.
pub fn minimize_in_box(q: &Quadratic, lo: &[f64], hi: &[f64]) -> Result<BoxMinimum, RsmError> {
    let k = q.factors();
    check_box(k, lo, hi)?;
    if k > EXACT_MAX_FACTORS {
        let centre: Vec<f64> = lo.iter().zip(hi).map(|(l, h)| 0.5 * (l + h)).collect();
        let mut starts = vec![centre.clone()];
        for i in 0..k {
            for bound in [lo[i], hi[i]] {
                let mut s = centre.clone();
                s[i] = bound;
                starts.push(s);
            }
        }
        let g = q.gradient(&centre);
        starts.push(
            (0..k)
                .map(|i| if g[i] > 0.0 { lo[i] } else { hi[i] })
                .collect(),
        );
        return minimize_in_box_projected(q, lo, hi, &starts);
    }
    let (_, b, h) = q.parts();
    let mut state = vec![-1i8; k];
    let mut best: Option<(f64, Vec<f64>)> = None;
    loop {
        if let Some(x) = face_point(&b, &h, &state, lo, hi) {
            let v = q.eval(&x);
            if best.as_ref().is_none_or(|(bv, _)| v < *bv) {
                best = Some((v, x));
            }
        }
        // Next state in {−1, 0, +1}^k.
        let mut i = 0;
        while i < k {
            if state[i] < 1 {
                state[i] += 1;
                break;
            }
            state[i] = -1;
            i += 1;
        }
        if i == k {
            break;
        }
    }
    // Vertices are always feasible, so there is a candidate.
    let (value, x) = best.ok_or(RsmError::BadBox)?;
    Ok(BoxMinimum {
        active: active_set(&x, lo, hi),
        x,
        value,
    })
}

/// The minimum of `q` over the box by projected gradient descent (Armijo
/// backtracking, in box-normalised variables so that the factors' scales do
/// not matter) from each of `starts` (projected into the box), each result
/// polished by solving the face system of its active set; the lowest wins.
///
/// A local method: for a convex surface any start gives the global minimum;
/// otherwise the result is the best local minimum found from the starts
/// (e.g. the design runs and the box's vertices). With no starts, the centre
/// of the box is used.
pub fn minimize_in_box_projected(
    q: &Quadratic,
    lo: &[f64],
    hi: &[f64],
    starts: &[Vec<f64>],
) -> Result<BoxMinimum, RsmError> {
    let k = q.factors();
    check_box(k, lo, hi)?;
    for s in starts {
        check_dim("a start point", k, s.len())?;
    }
    // u ∈ [0,1]^k, x = lo + w u, w = hi − lo: the scaled model.
    let w: Vec<f64> = lo.iter().zip(hi).map(|(l, h)| h - l).collect();
    let scaled = q.to_coded(&Coding::new(lo.to_vec(), w.clone())?)?;
    let (_, b, h) = scaled.parts();
    let zeros = vec![0.0; k];
    let ones = vec![1.0; k];
    let lipschitz = h.norm().max(f64::MIN_POSITIVE);
    let mut centre_only = Vec::new();
    let starts: &[Vec<f64>] = if starts.is_empty() {
        centre_only.push(lo.iter().zip(hi).map(|(l, h)| 0.5 * (l + h)).collect());
        &centre_only
    } else {
        starts
    };
    let mut best: Option<(f64, Vec<f64>)> = None;
    for s in starts {
        let u: Vec<f64> = s
            .iter()
            .zip(lo.iter().zip(&w))
            .map(|(x, (l, w))| ((x - l) / w).clamp(0.0, 1.0))
            .collect();
        if u.iter().any(|v| !v.is_finite()) {
            return Err(RsmError::NotFinite);
        }
        let (mut u, mut fu) = descend(&scaled, u, lipschitz);
        // Polish: solve the face system of the final active set.
        let state = active_set(&u, &zeros, &ones);
        if let Some(up) = face_point(&b, &h, &state, &zeros, &ones) {
            let fp = scaled.eval(&up);
            // The face solution is exact; allow for rounding in the comparison.
            if fp <= fu + 1e-12 * (1.0 + fu.abs()) {
                u = up;
                fu = fp;
            }
        }
        if best.as_ref().is_none_or(|(bv, _)| fu < *bv) {
            best = Some((fu, u));
        }
    }
    let (_, u) = best.ok_or(RsmError::BadBox)?;
    let x: Vec<f64> = u
        .iter()
        .zip(lo.iter().zip(&w))
        .map(|(u, (l, w))| (l + w * u).clamp(*l, l + w))
        .collect();
    Ok(BoxMinimum {
        value: q.eval(&x),
        active: active_set(&x, lo, hi),
        x,
    })
}

/// Projected gradient descent of `scaled` on the unit box from `u` (Armijo
/// backtracking from four times the last accepted step, the first step
/// `1/L`), until no step moves: the point and its value.
fn descend(scaled: &Quadratic, mut u: Vec<f64>, lipschitz: f64) -> (Vec<f64>, f64) {
    let mut fu = scaled.eval(&u);
    let mut step = 1.0 / lipschitz;
    for _ in 0..DESCENT_MAX_ITERATIONS {
        let g = scaled.gradient(&u);
        let mut moved = false;
        let mut t = step * DESCENT_STEP_GROWTH;
        for _ in 0..DESCENT_MAX_HALVINGS {
            let mut un: Vec<f64> = u.iter().zip(&g).map(|(x, g)| x - t * g).collect();
            un.iter_mut().for_each(|v| *v = v.clamp(0.0, 1.0));
            let d: f64 = un
                .iter()
                .zip(&u)
                .zip(&g)
                .map(|((a, b), g)| g * (a - b))
                .sum();
            let fn_ = scaled.eval(&un);
            if fn_ <= fu + ARMIJO_FRACTION * d {
                let dx: f64 = un
                    .iter()
                    .zip(&u)
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                moved = dx > DESCENT_MIN_MOVE;
                u = un;
                fu = fn_;
                step = t;
                break;
            }
            t *= 0.5;
        }
        if !moved {
            break;
        }
    }
    (u, fu)
}

/// The minimum of `Σ w_i f_i` over the box: [`Quadratic::weighted_sum`] then
/// [`minimize_in_box`].
pub fn minimize_weighted_in_box(
    surfaces: &[(f64, &Quadratic)],
    lo: &[f64],
    hi: &[f64],
) -> Result<BoxMinimum, RsmError> {
    minimize_in_box(&Quadratic::weighted_sum(surfaces)?, lo, hi)
}
