//! The standard normal law: density `φ`, distribution `Φ` and its inverse,
//! the map between the standard normal space of subset simulation and the
//! parameters' own laws.

/// `φ(u) = exp(−u²/2)/√(2π)`.
pub fn pdf(u: f64) -> f64 {
    (-0.5 * u * u).exp() / (2.0 * std::f64::consts::PI).sqrt()
}

/// `Φ(u) = erfc(−u/√2)/2` (libm's `erfc`, accurate in both tails).
pub fn cdf(u: f64) -> f64 {
    0.5 * libm::erfc(-u / std::f64::consts::SQRT_2)
}

/// `1 − Φ(u) = Φ(−u)`, without cancellation for large `u`.
pub fn tail(u: f64) -> f64 {
    cdf(-u)
}

/// `Φ⁻¹(p)` for `0 < p < 1`: Acklam's rational approximation (relative
/// error 1.15e-9) refined by one Halley step on [`cdf`] (then to about
/// 1e-15). `±∞` at 0 and 1, NaN outside.
#[allow(clippy::excessive_precision)] // Acklam's published coefficients
pub fn inverse_cdf(p: f64) -> f64 {
    if !(0.0..=1.0).contains(&p) {
        return f64::NAN;
    }
    if p == 0.0 {
        return f64::NEG_INFINITY;
    }
    if p == 1.0 {
        return f64::INFINITY;
    }
    const A: [f64; 6] = [
        -3.969683028665376e1,
        2.209460984245205e2,
        -2.759285104469687e2,
        1.383577518672690e2,
        -3.066479806614716e1,
        2.506628277459239,
    ];
    const B: [f64; 5] = [
        -5.447609879822406e1,
        1.615858368580409e2,
        -1.556989798598866e2,
        6.680131188771972e1,
        -1.328068155288572e1,
    ];
    const C: [f64; 6] = [
        -7.784894002430293e-3,
        -3.223964580411365e-1,
        -2.400758277161838,
        -2.549732539343734,
        4.374664141464968,
        2.938163982698783,
    ];
    const D: [f64; 4] = [
        7.784695709041462e-3,
        3.224671290700398e-1,
        2.445134137142996,
        3.754408661907416,
    ];
    // Acklam's breakpoint between the central and the tail rational
    // approximations (probability).
    const P_LOW: f64 = 0.02425;
    let p_low = P_LOW;
    let tail_poly = |q: f64| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    let x = if p < p_low {
        tail_poly((-2.0 * p.ln()).sqrt())
    } else if p > 1.0 - p_low {
        -tail_poly((-2.0 * (1.0 - p).ln()).sqrt())
    } else {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    };
    // One Halley step: e = Φ(x) − p, u = e/φ(x).
    let e = cdf(x) - p;
    let u = e / pdf(x);
    x - u / (1.0 + 0.5 * x * u)
}

/// The standard normal kept to `[α, β]` at the standard normal coordinate
/// `u`: `Φ⁻¹(Φ(α) + Φ(u) (Φ(β) − Φ(α)))`, taken in the tail the window
/// lies in (a window above the mean by its mirror below, where `Φ` keeps
/// its digits: `Φ(9)` rounds to 1). Where even the tail underflows (the
/// window beyond about 37 deviations), the normal's tail there is
/// exponential: `|z|` past the near end is drawn from an exponential of
/// rate the near end's distance, kept to the window.
pub fn truncated_at(alpha: f64, beta: f64, u: f64) -> f64 {
    if alpha > 0.0 {
        return -truncated_at(-beta, -alpha, -u);
    }
    let (a, b) = (cdf(alpha), cdf(beta));
    let z = if b > a {
        inverse_cdf(a + cdf(u) * (b - a))
    } else {
        // `β` far below the mean: `y = −z` past `s = −β` is exponential
        // of rate `s`, kept to the window's length, the draw rising with
        // `u` towards `β`.
        let (s, len) = (-beta, beta - alpha);
        let keep = -(-s * len).exp_m1();
        beta + (-tail(u) * keep).ln_1p() / s
    };
    z.clamp(alpha, beta)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_window_far_in_a_tail_is_drawn_inside_it() {
        // Three windows in the upper tail and their mirrors: the median
        // draw is the window's median, not its far end.
        for (alpha, beta) in [(8.0, 9.0), (12.0, 20.0), (40.0, 41.0)] {
            let mid = truncated_at(alpha, beta, 0.0);
            // Above `α` by about ln 2 / α (the exponential tail's median).
            let want = alpha + std::f64::consts::LN_2 / alpha;
            assert!(
                (mid - want).abs() < 0.05 * (mid - alpha),
                "[{alpha}, {beta}]: {mid}"
            );
            assert_eq!(truncated_at(-beta, -alpha, 0.0), -mid);
            let (low, high) = (
                truncated_at(alpha, beta, -3.0),
                truncated_at(alpha, beta, 3.0),
            );
            assert!(alpha <= low && low < mid && mid < high && high <= beta);
        }
        // A window about the mean is the untruncated law inside it.
        assert!((truncated_at(-10.0, 10.0, 1.3) - 1.3).abs() < 1e-12);
    }

    #[test]
    fn the_inverse_inverts() {
        for p in [1e-12, 1e-6, 0.01, 0.3, 0.5, 0.9, 0.999] {
            let x = inverse_cdf(p);
            assert!(
                (cdf(x) / p - 1.0).abs() < 1e-12,
                "p = {p}: Φ(Φ⁻¹(p)) = {}",
                cdf(x)
            );
        }
        // Φ(−4.753424) = 1e-6 (tables).
        assert!((inverse_cdf(1e-6) + 4.753424).abs() < 1e-6);
        assert!((tail(2.326348) - 0.01).abs() < 1e-8);
    }
}
