//! Smoothing a sampled angle and its derivatives, with the bandwidth chosen
//! from the data.
//!
//! A local cubic (Savitzky & Golay 1964) over `±h` samples estimates the
//! value, the rate and the acceleration at each sample as linear
//! combinations of the samples, so each has a standard error
//! `σ √(Σ w_k²)`. The half-width `h` is chosen per segment by generalised
//! cross-validation (Craven & Wahba 1979):
//! `GCV(h) = (RSS/n) / (1 − w₀)²`, `w₀` the smoother's weight on the sample
//! itself (the diagonal of its hat matrix). Samples closer than `h` to a
//! segment's ends get no estimate: the window would have to reach over a
//! release, a latch or an impact, where the motion is not smooth.

/// Largest half-width of the local cubic \[samples\]: 0.15 s at 100 Hz. GCV
/// chooses the window for the angle; its second derivative, the torque,
/// needs a narrower one to resolve a feature over a tenth of the stroke.
pub const MAX_HALF_WINDOW: usize = 15;

/// The half-widths \[samples\] GCV chooses from (about 25 % apart: finer
/// steps change the estimates by less than their standard error).
const HALF_WINDOWS: [usize; 8] = [3, 4, 5, 6, 8, 10, 12, MAX_HALF_WINDOW];

/// The weights of a centred local cubic over `±h` samples: value, first
/// derivative [per sample] and second derivative [per sample²], and the
/// hat-matrix diagonal `w₀`.
#[derive(Clone, Debug, PartialEq)]
pub struct CubicWeights {
    /// Half-width \[samples\].
    pub h: usize,
    /// Weights of the value, `k = −h..=h`.
    pub value: Vec<f64>,
    /// Weights of the first derivative.
    pub rate: Vec<f64>,
    /// Weights of the second derivative.
    pub accel: Vec<f64>,
}

impl CubicWeights {
    /// The weights for half-width `h` (the even and odd powers decouple on
    /// a symmetric window: value and curvature from `1, k²`, slope from
    /// `k, k³`).
    pub fn new(h: usize) -> Self {
        let ks: Vec<f64> = (-(h as i64)..=h as i64).map(|k| k as f64).collect();
        let s = |p: i32| ks.iter().map(|k| k.powi(p)).sum::<f64>();
        let (s0, s2, s4, s6) = (s(0), s(2), s(4), s(6));
        let det_e = s0 * s4 - s2 * s2;
        let det_o = s2 * s6 - s4 * s4;
        CubicWeights {
            h,
            value: ks.iter().map(|k| (s4 - s2 * k * k) / det_e).collect(),
            rate: ks
                .iter()
                .map(|k| (s6 * k - s4 * k.powi(3)) / det_o)
                .collect(),
            accel: ks.iter().map(|k| 2.0 * (s0 * k * k - s2) / det_e).collect(),
        }
    }

    /// The weight on the sample itself (the hat-matrix diagonal).
    pub fn w0(&self) -> f64 {
        self.value.get(self.h).copied().unwrap_or(1.0)
    }

    /// `Σ w_k y_{i+k}`, `None` when the window leaves `y`.
    fn apply(w: &[f64], y: &[f64], i: usize, h: usize) -> Option<f64> {
        let lo = i.checked_sub(h)?;
        let win = y.get(lo..lo + w.len())?;
        Some(w.iter().zip(win).map(|(a, b)| a * b).sum())
    }

    /// Root sum of squares of a weight vector.
    fn norm(w: &[f64]) -> f64 {
        w.iter().map(|x| x * x).sum::<f64>().sqrt()
    }
}

/// One smoothed segment of one series: the estimates at every sample of the
/// segment (`None` within `h` of its ends) and their standard errors.
#[derive(Clone, Debug, PartialEq)]
pub struct Smoothed {
    /// The half-width GCV chose \[samples\].
    pub h: usize,
    /// Smoothed value, rate [per s] and acceleration [per s²], one entry per
    /// sample of the segment.
    pub value: Vec<Option<[f64; 3]>>,
    /// Standard errors of value, rate and acceleration (the same at every
    /// sample: white noise of the estimated σ).
    pub se: [f64; 3],
    /// The noise σ of the samples, from the chosen fit's residuals.
    pub sigma: f64,
}

/// Smooths one segment `y` sampled every `dt` s: the half-width by GCV, then
/// value, rate and acceleration with their standard errors. The noise σ is
/// the larger of `sigma_floor` (from the whole series: a short segment's own
/// residuals say little) and the chosen fit's residuals. `None` when the
/// segment is too short for the smallest window with room to spare.
pub fn smooth_segment(y: &[f64], dt: f64, sigma_floor: f64) -> Option<Smoothed> {
    let n = y.len();
    let hmax = HALF_WINDOWS.iter().copied().filter(|&h| n > 4 * h).max()?;
    // Every h is scored on the same samples: those the widest window reaches.
    let mut best: Option<(f64, CubicWeights, f64)> = None;
    for &h in HALF_WINDOWS.iter().filter(|&&h| h <= hmax) {
        let w = CubicWeights::new(h);
        let (mut rss, mut m) = (0.0, 0usize);
        for i in hmax..n - hmax {
            if let (Some(v), Some(yi)) = (CubicWeights::apply(&w.value, y, i, h), y.get(i)) {
                rss += (yi - v) * (yi - v);
                m += 1;
            }
        }
        let denom = (1.0 - w.w0()).powi(2);
        let gcv = rss / m.max(1) as f64 / denom;
        // σ² from the residuals: E RSS = σ² (n − 2 tr H + tr HᵀH) ≈ σ² n (1 − w₀).
        let sigma = (rss / m.max(1) as f64 / (1.0 - w.w0()).max(1e-9)).sqrt();
        if best.as_ref().is_none_or(|b| gcv < b.0) {
            best = Some((gcv, w, sigma));
        }
    }
    let (_, w, sigma) = best?;
    let sigma = sigma.max(sigma_floor);
    let h = w.h;
    let value = (0..n)
        .map(|i| {
            if i < h || i + h >= n {
                return None;
            }
            Some([
                CubicWeights::apply(&w.value, y, i, h)?,
                CubicWeights::apply(&w.rate, y, i, h)? / dt,
                CubicWeights::apply(&w.accel, y, i, h)? / (dt * dt),
            ])
        })
        .collect();
    let se = [
        sigma * CubicWeights::norm(&w.value),
        sigma * CubicWeights::norm(&w.rate) / dt,
        sigma * CubicWeights::norm(&w.accel) / (dt * dt),
    ];
    Some(Smoothed {
        h,
        value,
        se,
        sigma,
    })
}

/// The white-noise σ of a series from its third differences: the median
/// absolute `Δ³y`, scaled for white noise (`Var Δ³e = 20 σ²`, MAD → σ by
/// 1.4826). Smooth motion adds only `y⃛ Δt³`; a latch instant is an
/// outlier the median ignores. 0 for a series of fewer than four samples.
pub fn noise_sigma(y: &[f64]) -> f64 {
    third_difference_sigma(y, 1).unwrap_or(0.0)
}

/// [`noise_sigma`] of a series with at least `min_differences` finite
/// third differences; `None` for a shorter one. The one estimate of the
/// sensor noise: the diagnosis's σ̂ ([`crate::analysis::diagnose::evidence::noise_sigma_deg`])
/// and the smoother's floor ([`crate::analysis::diagnose::residual_torque`]) both use it.
/// The median is [`interpolated_median`]: an encoder's readings are whole
/// quanta, so are their differences, and a plain median would move σ̂ in
/// steps of a third of itself where the noise is about a quantum.
pub fn third_difference_sigma(y: &[f64], min_differences: usize) -> Option<f64> {
    let mut d3: Vec<f64> = y
        .windows(4)
        .map(|w| (w[3] - 3.0 * w[2] + 3.0 * w[1] - w[0]).abs())
        .filter(|x| x.is_finite())
        .collect();
    if d3.len() < min_differences.max(1) {
        return None;
    }
    d3.sort_by(f64::total_cmp);
    Some(1.4826 * interpolated_median(&d3) / 20f64.sqrt())
}

/// Values within this fraction of the median's magnitude are tied with it
/// (differences of whole quanta, rounded in floating point).
const TIE_RELATIVE: f64 = 1e-9;

/// Values within this of the median are tied with it \[deg\]: a run file
/// writes its angles to 6 decimals (`docs/spec/formats.md`), so a third
/// difference of whole quanta read back is off by up to 8 × 0.5e-6.
const TIE_ABSOLUTE: f64 = 1e-5;

/// The median of sorted values ≥ 0; where several values are tied with
/// it (values on a lattice, as readings in whole quanta are), the median of
/// grouped data: the tied values spread evenly over their class, the
/// half-gap to the nearest other value on each side (from 0 for a class
/// at 0), and the median read where half the values lie below. Without
/// ties, the plain median.
fn interpolated_median(sorted: &[f64]) -> f64 {
    let n = sorted.len();
    let Some(&m) = sorted.get(n / 2) else {
        return 0.0;
    };
    let tol = (TIE_RELATIVE * m.abs()).max(TIE_ABSOLUTE);
    let lo = sorted.partition_point(|&x| x < m - tol);
    let hi = sorted.partition_point(|&x| x <= m + tol);
    let tied = hi - lo;
    if tied < 2 {
        return m;
    }
    let below = lo.checked_sub(1).map(|i| m - sorted[i]);
    let above = sorted.get(hi).map(|&x| x - m);
    let gap = match (below, above) {
        (Some(a), Some(b)) => a.min(b),
        (Some(g), None) | (None, Some(g)) => g,
        (None, None) => return m,
    };
    let (start, width) = if m - 0.5 * gap < 0.0 {
        (0.0, m + 0.5 * gap)
    } else {
        (m - 0.5 * gap, gap)
    };
    start + width * (0.5 * n as f64 - lo as f64) / tied as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    /// White noise read in whole quanta, σ from half a quantum to two: the
    /// estimate stays within 12 % of σ (the plain median's steps are a
    /// third of σ at σ ≈ q); unquantised noise gives the plain median.
    #[test]
    fn quantised_noise_is_estimated_without_the_quantum_steps() {
        use rand::SeedableRng;
        use rand_distr::{Distribution, Normal};
        let q = 360.0 / 16384.0;
        for (k, ratio) in [0.5, 0.8, 0.96, 1.0, 1.3, 2.0].into_iter().enumerate() {
            let sigma = ratio * q;
            for seed in 0..8u64 {
                let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(100 * k as u64 + seed);
                let normal = Normal::new(0.0, sigma).expect("σ > 0");
                let x: Vec<f64> = (0..1200).map(|i| 30.0 + 0.01 * i as f64).collect();
                let read: Vec<f64> = x
                    .iter()
                    .map(|v| ((v + normal.sample(&mut rng)) / q).round() * q)
                    // As a run file writes them: 6 decimals.
                    .map(|v| (v * 1e6).round() / 1e6)
                    .collect();
                // Rounding adds its own q²/12 of variance.
                let truth = (sigma * sigma + q * q / 12.0).sqrt();
                let est = noise_sigma(&read);
                assert!(
                    (est / truth - 1.0).abs() < 0.12,
                    "σ = {ratio} q, seed {seed}: {est} against {truth}"
                );
            }
        }
        let continuous = [0.3, -1.2, 0.7, 2.2, -0.4, 0.9, -1.7, 0.1];
        let mut d3: Vec<f64> = continuous
            .windows(4)
            .map(|w: &[f64]| (w[3] - 3.0 * w[2] + 3.0 * w[1] - w[0]).abs())
            .collect();
        d3.sort_by(f64::total_cmp);
        assert_eq!(interpolated_median(&d3), d3[d3.len() / 2]);
    }

    #[test]
    fn given_a_cubic_then_value_rate_and_acceleration_are_exact() {
        let dt = 0.01;
        let f = |t: f64| 1.0 + 2.0 * t - 3.0 * t * t + 0.5 * t.powi(3);
        let y: Vec<f64> = (0..200).map(|i| f(i as f64 * dt)).collect();
        let s = smooth_segment(&y, dt, 0.0).unwrap();
        let t = 100.0 * dt;
        let [v, r, a] = s.value[100].unwrap();
        assert!((v - f(t)).abs() < 1e-9);
        assert!((r - (2.0 - 6.0 * t + 1.5 * t * t)).abs() < 1e-7);
        assert!((a - (-6.0 + 3.0 * t)).abs() < 1e-5);
        assert!(s.value[0].is_none() && s.value[199].is_none());
    }

    #[test]
    fn given_noise_on_a_small_smooth_curve_then_gcv_widens_the_window_and_the_band_holds() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let dt = 0.01;
        let sigma = 3e-4;
        // A small smooth signal, like a measured angle's difference from a
        // model close to it: the smoother's bias stays below its band.
        let f = |t: f64| 2e-3 * (2.0 * t).sin();
        let y: Vec<f64> = (0..600)
            .map(|i| f(i as f64 * dt) + sigma * (rng.gen::<f64>() - 0.5) * 12f64.sqrt())
            .collect();
        let s = smooth_segment(&y, dt, 0.0).unwrap();
        assert!(s.h >= 8, "h = {}", s.h);
        assert!((s.sigma / sigma - 1.0).abs() < 0.2, "σ̂ = {}", s.sigma);
        // The acceleration error stays within about its band.
        let (mut z2, mut n) = (0.0, 0);
        for (i, v) in s.value.iter().enumerate() {
            if let Some([_, _, a]) = v {
                let t = i as f64 * dt;
                z2 += ((a + 8e-3 * (2.0 * t).sin()) / s.se[2]).powi(2);
                n += 1;
            }
        }
        let rms_z = (z2 / n as f64).sqrt();
        assert!(rms_z < 1.5, "acceleration errors {rms_z:.2} bands RMS");
    }
}
