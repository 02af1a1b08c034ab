//! Centred local-polynomial fit of the encoder readings: the angle and rate
//! of every joint half a window in the past, from the readings on both
//! sides of it.
//!
//! The friction observer needs rates that neither lag nor carry the noise of
//! a filter opened up for a manoeuvre. A causal rate filter has to choose
//! one of the two; a fit centred on a sample a few steps back has neither
//! problem, at the price of that delay (friction is a slowly varying
//! parameter, so the observer can afford it). Over the last [`WINDOW`]
//! readings, with their own time stamps,
//!
//! ```text
//! φ(t) ≈ a + b τ + c τ²,   τ = t − t_m   (t_m: the middle sample)
//! [a b c] = argmin Σ (φ_i − a − b τ_i − c τ_i²)²
//! ```
//!
//! gives `φ(t_m) = a`, `φ̇(t_m) = b` with `var b = σ² [(XᵀX)⁻¹]₁₁`. For
//! equally spaced samples this is the Savitzky–Golay derivative filter
//! (A. Savitzky & M. J. E. Golay, "Smoothing and differentiation of data by
//! simplified least squares procedures", Anal. Chem. 36(8), 1964): exact
//! for a quadratic, with a bias of `φ⃛ Στ⁴/(6 Στ²)` (≈ 3·10⁻⁴ s² × jerk
//! for 11 samples at 100 Hz) and a noise of `σ/(dt √110)` ≈ 0.19°/s at
//! σ = 0.02°. A window whose residual is far above the noise (an impact,
//! a snap, a spike the rate filter let through) gives no fit.

/// Number of readings in the window (odd): the fit is for the middle one,
/// `(WINDOW − 1)/2` samples back.
pub const WINDOW: usize = 11;
// `CentredFit` counts its slots in bytes.
const _: () = assert!(WINDOW <= u8::MAX as usize);

/// Residual (sum of squares over the noise variance) above which a window
/// is not a smooth motion: `WINDOW − 3` degrees of freedom, mean 8; this is
/// far in the tail of the χ² distribution (p < 10⁻⁵).
const RESIDUAL_LIMIT: f32 = 40.0;

/// The angle and rate of every joint at the middle of the window.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Centre<const N: usize> {
    /// Time of the middle sample \[s\].
    pub t_s: f32,
    /// Time since the previous middle sample \[s\].
    pub dt_s: f32,
    /// Joint angles \[rad\] (0 for a locked joint).
    pub phi: [f32; N],
    /// Joint rates [rad/s] (0 for a locked joint).
    pub rate: [f32; N],
    /// Variance of each rate [rad²/s²].
    pub rate_var: [f32; N],
    /// Joints locked at the middle sample.
    pub locked: [bool; N],
}

/// One sample in the window.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Slot<const N: usize> {
    t_s: f32,
    /// Readings \[rad\]; NaN where missing or rejected.
    phi: [f32; N],
    /// Whether the monitor found the sample fit to learn from.
    clean: bool,
    locked: [bool; N],
}

impl<const N: usize> Default for Slot<N> {
    fn default() -> Self {
        Slot {
            t_s: 0.0,
            phi: [f32::NAN; N],
            clean: false,
            locked: [false; N],
        }
    }
}

/// The last [`WINDOW`] samples and the fit at their middle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CentredFit<const N: usize> {
    slots: [Slot<N>; WINDOW],
    /// Index of the oldest slot (below [`WINDOW`]; read at every slot
    /// access, so a word: a `u32`, the width of `usize` on the MCU, and
    /// half of it on a 64-bit host).
    head: u32,
    /// Number of slots filled (up to [`WINDOW`]; a byte, as the monitor
    /// has to fit its RAM budget, `tests/monitor/footprint.rs`).
    len: u8,
}

impl<const N: usize> Default for CentredFit<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> CentredFit<N> {
    /// An empty window.
    pub fn new() -> Self {
        CentredFit {
            slots: [Slot::default(); WINDOW],
            head: 0,
            len: 0,
        }
    }

    /// Adds a sample: time \[s\], readings \[rad\] (NaN where missing or
    /// rejected), whether it is fit to learn from, and the locked joints.
    pub fn push(&mut self, t_s: f32, phi: &[f32; N], clean: bool, locked: &[bool; N]) {
        let slot = Slot {
            t_s,
            phi: *phi,
            clean,
            locked: *locked,
        };
        let (head, len) = (self.head as usize, usize::from(self.len));
        if len < WINDOW {
            if let Some(s) = self.slots.get_mut((head + len) % WINDOW) {
                *s = slot;
            }
            self.len += 1;
        } else {
            if let Some(s) = self.slots.get_mut(head % WINDOW) {
                *s = slot;
            }
            self.head = ((head + 1) % WINDOW) as u32;
        }
    }

    fn slot(&self, k: usize) -> &Slot<N> {
        &self.slots[(self.head as usize + k) % WINDOW]
    }

    /// The fit at the middle of the window, with `meas_var` the variance of
    /// one reading \[rad²\]; `None` unless the window is full, every sample in
    /// it is clean, no joint latched or unlatched inside it, every free
    /// joint has every reading, and each fit's residual is that of noise.
    #[cfg(test)]
    pub fn centre(&self, meas_var: f32) -> Option<Centre<N>> {
        self.centre_with(meas_var, |c| *c)
    }

    /// What `read` makes of the `CentredFit::centre`, handed to it where
    /// it is built (a fit moved into an `Option` is copied byte by byte on
    /// the MCU).
    #[inline(always)]
    pub fn centre_with<T>(&self, meas_var: f32, read: impl FnOnce(&Centre<N>) -> T) -> Option<T> {
        if usize::from(self.len) < WINDOW || !(meas_var > 0.0) {
            return None;
        }
        let mid = WINDOW / 2;
        let m = *self.slot(mid);
        let prev_t = self.slot(mid - 1).t_s;
        let mut out = Centre {
            t_s: m.t_s,
            dt_s: m.t_s - prev_t,
            phi: [0.0; N],
            rate: [0.0; N],
            rate_var: [0.0; N],
            locked: m.locked,
        };
        if !(out.dt_s > 0.0) {
            return None;
        }
        let mut tau = [0.0f32; WINDOW];
        let mut sums = [0.0f32; 5];
        for (k, tk) in tau.iter_mut().enumerate() {
            let sl = self.slot(k);
            if !sl.clean || sl.locked != m.locked {
                return None;
            }
            *tk = sl.t_s - m.t_s;
            let mut p = 1.0f32;
            for sk in sums.iter_mut() {
                *sk += p;
                p *= *tk;
            }
        }
        // XᵀX of [1 τ τ²] depends on the times alone; var b = σ² (XᵀX)⁻¹₁₁.
        let s = sums;
        let xtx = [[s[0], s[1], s[2]], [s[1], s[2], s[3]], [s[2], s[3], s[4]]];
        // Inverted once for every joint (the fits share the times).
        let inv = inverse_sym3(&xtx)?;
        let unit_var_b = inv[1][1];
        for j in 0..N {
            if m.locked[j] {
                continue;
            }
            // Relative to the middle reading, for the f32 sums.
            // Written in place: an array built by `from_fn` is copied.
            let mut y = [0.0f32; WINDOW];
            for (k, yk) in y.iter_mut().enumerate() {
                *yk = self.slot(k).phi[j] - m.phi[j];
            }
            let (a, b) = fit_quadratic(&tau, &y, &inv, meas_var)?;
            out.phi[j] = m.phi[j] + a;
            out.rate[j] = b;
            out.rate_var[j] = meas_var * unit_var_b;
        }
        let finite = out
            .phi
            .iter()
            .chain(out.rate.iter())
            .chain(out.rate_var.iter())
            .all(|v| v.is_finite());
        if finite {
            Some(read(&out))
        } else {
            None
        }
    }
}

/// The inverse of a symmetric positive definite 3×3 matrix by its
/// adjugate, `A⁻¹ = adj(A)/det(A)`; `None` unless `det(A) > 0` and the
/// result is finite. (Cramer's rule is as accurate as a factorisation for
/// the well-conditioned normal matrix of [`WINDOW`] time offsets, and takes
/// neither square roots nor a solve per joint.)
fn inverse_sym3(a: &[[f32; 3]; 3]) -> Option<[[f32; 3]; 3]> {
    let c00 = a[1][1] * a[2][2] - a[1][2] * a[2][1];
    let c01 = a[1][2] * a[2][0] - a[1][0] * a[2][2];
    let c02 = a[1][0] * a[2][1] - a[1][1] * a[2][0];
    let det = a[0][0] * c00 + a[0][1] * c01 + a[0][2] * c02;
    if !(det > 0.0) {
        return None;
    }
    let c11 = a[0][0] * a[2][2] - a[0][2] * a[2][0];
    let c12 = a[0][2] * a[1][0] - a[0][0] * a[1][2];
    let c22 = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    let k = 1.0 / det;
    let inv = [
        [c00 * k, c01 * k, c02 * k],
        [c01 * k, c11 * k, c12 * k],
        [c02 * k, c12 * k, c22 * k],
    ];
    inv.iter().flatten().all(|v| v.is_finite()).then_some(inv)
}

/// Least-squares `y ≈ a + b τ + c τ²` with `inv` the inverse of the normal
/// matrix of the times: `(a, b)`, `None` when a reading is missing or the
/// residual is not that of noise of variance `meas_var`. One copy for every
/// joint count.
#[inline(never)]
fn fit_quadratic(
    tau: &[f32; WINDOW],
    y: &[f32; WINDOW],
    inv: &[[f32; 3]; 3],
    meas_var: f32,
) -> Option<(f32, f32)> {
    let mut xty = [0.0f32; 3];
    for (&t, &v) in tau.iter().zip(y.iter()) {
        if !v.is_finite() {
            return None;
        }
        xty[0] += v;
        xty[1] += v * t;
        xty[2] += v * t * t;
    }
    let coef: [f32; 3] =
        core::array::from_fn(|i| inv[i].iter().zip(xty.iter()).map(|(a, b)| a * b).sum());
    let mut ssr = 0.0f32;
    for (&t, &v) in tau.iter().zip(y.iter()) {
        let e = v - coef[0] - coef[1] * t - coef[2] * t * t;
        ssr += e * e;
    }
    (ssr <= RESIDUAL_LIMIT * meas_var).then_some((coef[0], coef[1]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_is_exact_for_a_quadratic_and_centred() {
        let mut f = CentredFit::<2>::new();
        let phi = |t: f32| 0.3 + 1.5 * t - 2.0 * t * t;
        for k in 0..20 {
            let t = 1.0 + 0.01 * k as f32;
            f.push(t, &[phi(t), f32::NAN], true, &[false, true]);
            let c = f.centre(1e-8);
            if k + 1 < WINDOW {
                assert!(c.is_none());
                continue;
            }
            let c = c.expect("full clean window");
            let tm = 1.0 + 0.01 * (k - WINDOW / 2) as f32;
            assert!((c.t_s - tm).abs() < 1e-5);
            assert!((c.phi[0] - phi(tm)).abs() < 1e-5, "{c:?}");
            assert!((c.rate[0] - (1.5 - 4.0 * tm)).abs() < 2e-3, "{c:?}");
            assert_eq!(c.rate[1], 0.0);
        }
    }

    #[test]
    fn a_jump_a_gap_or_an_unclean_sample_gives_no_fit() {
        let fill = |jump_at: Option<usize>, missing_at: Option<usize>, dirty_at: Option<usize>| {
            let mut f = CentredFit::<1>::new();
            for k in 0..WINDOW {
                let t = 0.01 * k as f32;
                let mut z = 0.5 * t;
                if jump_at.is_some_and(|i| k >= i) {
                    z += 0.01;
                }
                let z = if missing_at == Some(k) { f32::NAN } else { z };
                f.push(t, &[z], dirty_at != Some(k), &[false]);
            }
            f.centre(1e-8)
        };
        assert!(fill(None, None, None).is_some());
        assert!(fill(Some(7), None, None).is_none());
        assert!(fill(None, Some(3), None).is_none());
        assert!(fill(None, None, Some(10)).is_none());
    }
}
