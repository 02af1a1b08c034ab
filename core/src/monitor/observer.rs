//! The friction observer: a generalised-momentum disturbance observer and
//! recursive least squares on the Coulomb and viscous regressors, on the
//! joint rates of [`super::rate_filter`] (§1 there). `docs/monitor.md`
//! derives and justifies it.
//!
//! # 2. Disturbance observer on the generalised momentum
//! For the chain of `physics.md` §2 with `p = M(φ) φ̇`, Lagrange's equations
//! read, per joint (De Luca & Mattone, ICRA 2005; Haddadin, De Luca &
//! Albu-Schäffer, IEEE T-RO 33(6) 2017, §IV):
//!
//! ```text
//! ṗ_j = τ_s,j(φ_j) + β_j(φ, φ̇) + d_j,     β = ∂T/∂φ = Sᵀ b,
//! b_k = −θ̇_k Σ_l A_kl sin(θ_k − θ_l) θ̇_l                         [N·m]
//! ```
//! `d_j` is everything the model does not know: the friction. The observer
//! `ṙ = K (d − r)`, i.e. `r = K (p − ∫(τ_s + β + r) dt)`, needs rates but no
//! accelerations, and the latch impulse of another joint does not enter
//! joint j's equation (the constraint torque acts on the latching joint's
//! own coordinate only).
//!
//! # 3. Recursive least squares on the filtered regressors
//! With `d = −T_C tanh(ω/ω_c) − f ω` and the same first-order filter
//! `F(s) = K/(s + K)` applied to the regressors, `r = θᵀ y` holds exactly
//! for constant `θ = [T_C, f]`, `y = F[−tanh(ω/ω_c), −ω]`. θ is estimated by
//! RLS in its Kalman-filter form (Ljung & Söderström 1983, §2.6), with a
//! Gaussian prior, a random-walk drift and a measurement variance estimated
//! on line and inflated by the correlation of the filtered residual.

#[cfg(test)]
use crate::physics::chain::Chain;
use crate::physics::chain::ChainRef;
use crate::physics::friction::coulomb_shape;

/// The velocity-dependent terms of the chain's equations at one state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MomentumTerms<const N: usize> {
    /// Mass matrix `M(φ)` [kg·m²].
    pub mass: [[f32; N]; N],
    /// `β = ∂T/∂φ` [N·m]: `ṗ = τ + β`.
    pub beta: [f32; N],
    /// `−Sᵀ C` [N·m]: `M φ̈ = τ − Sᵀ C` (`chain.rs`).
    pub coriolis: [f32; N],
}

/// Mass matrix `M(φ)` [kg·m²], `β = ∂T/∂φ` and the Coriolis/centrifugal
/// torques `−Sᵀ C` [N·m] of the chain at angles `phi` \[rad\] and rates
/// `omega` [rad/s], from one evaluation of the panel angles' sines and
/// cosines.
///
/// ```text
/// θ = S φ,  D_kl = A_kl cos(θ_k − θ_l),  M = Sᵀ D S
/// b_k = −θ̇_k Σ_l A_kl sin(θ_k − θ_l) θ̇_l,  β_j = Σ_{k ≥ j} b_k
/// C_k = Σ_l A_kl sin(θ_k − θ_l) θ̇_l²
/// ```
#[cfg(test)]
pub fn momentum_terms<const N: usize>(
    chain: &Chain<f32, N>,
    phi: &[f32; N],
    omega: &[f32; N],
) -> MomentumTerms<N> {
    momentum_terms_n(&chain.counted(), phi, omega)
}

/// `momentum_terms` of the chain's first `n` joints ([`ChainRef`]) over
/// arrays of capacity `M` (zero past `n`): the same arithmetic in the same
/// order, one copy of the code for every joint count up to `M`.
#[inline(always)]
pub fn momentum_terms_n<const M: usize>(
    chain: &ChainRef<'_, f32, M>,
    phi: &[f32; M],
    omega: &[f32; M],
) -> MomentumTerms<M> {
    let n = chain.joint_count().min(M);
    let a = chain.inertia_coefficients();
    let mut c = [0.0f32; M];
    let mut s = [0.0f32; M];
    let mut thd = [0.0f32; M];
    let (mut th_acc, mut thd_acc) = (0.0f32, 0.0f32);
    for k in 0..n {
        th_acc += phi[k];
        thd_acc += omega[k];
        (s[k], c[k]) = crate::physics::trig::sin_cos(th_acc);
        thd[k] = thd_acc;
    }
    // M = Sᵀ D S built where it is returned: D, then its suffix sums along
    // columns, then along rows, each entry read once before it is
    // overwritten (arrays moved into the result, or kept apart, are
    // cleared and copied on the MCU).
    let mut out = MomentumTerms {
        mass: [[0.0f32; M]; M],
        beta: [0.0f32; M],
        coriolis: [0.0f32; M],
    };
    let mut b = [0.0f32; M];
    let mut cor = [0.0f32; M];
    for k in 0..n {
        let mut acc = 0.0f32;
        let mut acc2 = 0.0f32;
        for l in 0..n {
            let cos_kl = c[k] * c[l] + s[k] * s[l];
            let sin_kl = s[k] * c[l] - c[k] * s[l];
            out.mass[k][l] = a[k][l] * cos_kl;
            acc += a[k][l] * sin_kl * thd[l];
            acc2 += a[k][l] * sin_kl * thd[l] * thd[l];
        }
        b[k] = -thd[k] * acc;
        cor[k] = acc2;
    }
    for row in out.mass.iter_mut().take(n) {
        let mut acc = 0.0f32;
        for k in (0..n).rev() {
            acc += row[k];
            row[k] = acc;
        }
    }
    for k in 0..n {
        let mut acc = 0.0f32;
        for j in (0..n).rev() {
            acc += out.mass[j][k];
            out.mass[j][k] = acc;
        }
    }
    let (mut acc, mut acc2) = (0.0f32, 0.0f32);
    for k in (0..n).rev() {
        acc += b[k];
        acc2 -= cor[k];
        out.beta[k] = acc;
        out.coriolis[k] = acc2;
    }
    out
}

/// Tuning of one joint's friction observer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObserverTuning {
    /// Disturbance-observer bandwidth `K` [1/s].
    pub bandwidth_per_s: f32,
    /// `ω_c` of the Coulomb regressor `tanh(ω/ω_c)` [rad/s].
    pub coulomb_threshold_rad_s: f32,
    /// Random-walk intensity of `T_C` [N·m/√s].
    pub coulomb_walk: f32,
    /// Random-walk intensity of `f` [N·m·s/rad/√s].
    pub viscous_walk: f32,
    /// Floor of the measurement variance [N²·m²].
    pub residual_var_floor: f32,
}

/// Prior of one joint's friction parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionPrior {
    /// Mean Coulomb torque [N·m].
    pub coulomb_nm: f32,
    /// Its standard deviation [N·m].
    pub coulomb_sd_nm: f32,
    /// Mean viscous coefficient [N·m·s/rad].
    pub viscous_nms: f32,
    /// Its standard deviation [N·m·s/rad].
    pub viscous_sd_nms: f32,
}

/// The friction estimate of one joint.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct FrictionEstimate {
    /// Coulomb torque `T_C` [N·m] (≥ 0).
    pub coulomb_nm: f32,
    /// Viscous coefficient `f` [N·m·s/rad] (≥ 0).
    pub viscous_nms: f32,
    /// Variance of `T_C` [N²·m²].
    pub coulomb_var: f32,
    /// Variance of `f` [(N·m·s/rad)²].
    pub viscous_var: f32,
    /// Covariance of `T_C` and `f`.
    pub cov: f32,
    /// Relative error of the spring curve `κ` (the spring torque is
    /// `(1 + κ) τ_s`) \[1\].
    pub spring_scale_err: f32,
    /// Variance of `κ`.
    pub spring_scale_var: f32,
}

/// The observer's lag variance at a restart mid-motion, in prior variances
/// of `T_C` (until `r` has converged it may be off by several prior
/// deviations); a fresh observer starts at rest with this many times less.
const LAG_VAR_START: f32 = 4.0;

/// Weight of one step in the running mean square of the observer lag.
const LAG_WEIGHT: f32 = 0.1;

/// Smallest `K dt` the residual's correlation inflation divides by (a
/// guard: `K dt` is 0.1 at 100 Hz).
const MIN_KDT: f32 = 1e-3;

/// Number of estimated parameters: `θ = [T_C, f, κ]`.
const P: usize = 3;

/// Bounds of the parameter projection: `0 ≤ T_C, f ≤ 1000`, `|κ| ≤ 0.5`.
const THETA_MIN: [f32; P] = [0.0, 0.0, -0.5];
const THETA_MAX: [f32; P] = [1000.0, 1000.0, 0.5];

/// Momentum disturbance observer and RLS estimator of one joint's friction.
///
/// ```text
/// d = κ τ_s − T_C tanh(ω/ω_c) − f ω,   h = [−tanh(ω/ω_c), −ω, τ_s]
/// ```
/// with `κ` the relative error of the spring curve (the spring torque is
/// `(1 + κ) τ_s`) and a prior `N(0, σ_κ²)` on it:
/// over the part of the stroke seen by half stroke it is partly collinear
/// with the Coulomb one, and the prior keeps the split stable.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionObserver {
    /// Disturbance estimate `r` [N·m] (first-order filtered `d`).
    r: f32,
    /// Filtered regressors `y = F[h]`.
    y: [f32; P],
    /// Previous momentum [N·m·s], known torque [N·m], regressors.
    p_prev: f32,
    u_prev: f32,
    h_prev: [f32; P],
    primed: bool,
    /// θ = [T_C, f].
    theta: [f32; P],
    /// Covariance of θ.
    sigma: [[f32; P]; P],
    /// Mean square of the observer's lag `d − r = ṙ/K` [N²·m²].
    lag_var: f32,
    /// `K dt` of the last step.
    kdt: f32,
    prior: FrictionPrior,
    /// Prior standard deviation of `κ` \[1\].
    spring_sd_rel: f32,
}

/// What one observer step needs about the joint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObserverInput {
    /// Generalised momentum `p_j` [N·m·s].
    pub momentum: f32,
    /// Spring torque `τ_s,j` [N·m] (nominal curve).
    pub spring_torque_nm: f32,
    /// `β_j = ∂T/∂φ_j` [N·m].
    pub beta_nm: f32,
    /// Joint rate estimate [rad/s].
    pub rate_rad_s: f32,
    /// Variance of the rate estimate [rad²/s²].
    pub rate_var: f32,
    /// Time step \[s\] (> 0).
    pub dt_s: f32,
    /// Whether the parameters may be updated with this step.
    pub learn: bool,
}

impl FrictionObserver {
    /// A fresh observer at the prior.
    pub fn new(prior: FrictionPrior, spring_sd_rel: f32) -> Self {
        let mut sigma = [[0.0f32; P]; P];
        sigma[0][0] = prior.coulomb_sd_nm * prior.coulomb_sd_nm;
        sigma[1][1] = prior.viscous_sd_nms * prior.viscous_sd_nms;
        sigma[2][2] = spring_sd_rel * spring_sd_rel;
        FrictionObserver {
            r: 0.0,
            y: [0.0; P],
            p_prev: 0.0,
            u_prev: 0.0,
            h_prev: [0.0; P],
            primed: false,
            theta: [prior.coulomb_nm, prior.viscous_nms, 0.0],
            sigma,
            // At the start the joints rest (r = d = 0): no lag yet.
            lag_var: prior.coulomb_sd_nm * prior.coulomb_sd_nm / LAG_VAR_START,
            kdt: 0.0,
            prior,
            spring_sd_rel,
        }
    }

    /// Restarts the disturbance observer and its regressor filters from zero
    /// at the next step (both sides of `r = θᵀy` restart together, so the
    /// identity still holds); the parameter estimate is kept.
    pub fn restart(&mut self) {
        if !self.primed {
            // Not running: nothing to restart (a fresh observer starts at
            // rest, where r = d = 0 holds without a transient).
            return;
        }
        self.r = 0.0;
        self.y = [0.0; P];
        self.primed = false;
        self.kdt = 0.0;
        self.lag_var = self
            .lag_var
            .max(LAG_VAR_START * self.prior.coulomb_sd_nm * self.prior.coulomb_sd_nm);
    }

    /// A lower bound of the Coulomb torque [N·m] from the friction torque
    /// acting now: `|d| = |T_C tanh(ω/ω_c) + f ω| ≤ T_C + f|ω|`, so
    /// `T_C ≥ |r| − f|ω| − 2σ_r` for the viscous coefficient `viscous_nms`
    /// the bound is taken with (the one the caller's `T_C` goes with, see
    /// [`FrictionObserver::estimate_given_viscous`]), with
    /// `σ_r² = E[(d̄ − r)²] K dt/(2 − K dt)` the noise of `r`. 0 until the
    /// observer has run.
    pub fn coulomb_lower_bound(&self, rate_rad_s: f32, viscous_nms: f32) -> f32 {
        if !self.primed || !(self.kdt > 0.0) {
            return 0.0;
        }
        let sd = crate::physics::real::sqrtf(self.lag_var.max(0.0) * self.kdt / (2.0 - self.kdt));
        let bound = libm::fabsf(self.r) - viscous_nms.max(0.0) * libm::fabsf(rate_rad_s) - 2.0 * sd;
        if bound.is_finite() {
            bound.max(0.0)
        } else {
            0.0
        }
    }

    /// Resets the parameters to the prior (after a numerical failure).
    pub fn reset_parameters(&mut self) {
        *self = FrictionObserver::new(self.prior, self.spring_sd_rel);
    }

    /// The prior of the friction parameters.
    pub fn prior(&self) -> &FrictionPrior {
        &self.prior
    }

    /// The disturbance estimate `r` [N·m]: the friction torque, filtered.
    pub fn disturbance_nm(&self) -> f32 {
        self.r
    }

    /// The current parameter estimate.
    pub fn estimate(&self) -> FrictionEstimate {
        FrictionEstimate {
            coulomb_nm: self.theta[0],
            viscous_nms: self.theta[1],
            coulomb_var: self.sigma[0][0],
            viscous_var: self.sigma[1][1],
            cov: self.sigma[0][1],
            spring_scale_err: self.theta[2],
            spring_scale_var: self.sigma[2][2],
        }
    }

    /// The estimate conditioned on the viscous coefficient being
    /// `viscous_nms` [N·m·s/rad]: what the observer would report had it
    /// known `f`, for use where the data do not resolve `f`
    /// (`docs/monitor.md` §3.2). For the Gaussian posterior
    /// `θ ~ N(θ̂, Σ)`, `θ = [T_C, f, κ]`, the conditional of a joint
    /// Gaussian:
    ///
    /// ```text
    /// θ_i | f = f₀  ~  N(θ̂_i + Σ_if/Σ_ff (f₀ − f̂),  Σ_ii − Σ_if²/Σ_ff),   i ∈ {T_C, κ}
    /// ```
    ///
    /// Over a stroke at rates near `ω̄` the data fix `T_C + f ω̄`, so the
    /// conditioned Coulomb torque is `≈ T_C + (f − f₀) ω̄`: it holds the
    /// friction seen at the rates observed. The viscous variance and the
    /// covariance are 0 in the result.
    #[inline(never)]
    pub fn estimate_given_viscous(&self, viscous_nms: f32) -> FrictionEstimate {
        let (s, th) = (&self.sigma, &self.theta);
        // Σ_ff > 0 while the observer is healthy (a reset follows
        // otherwise), and well above 0 where `f` is unresolved, the use the
        // monitor makes of this.
        let (g0, g2) = (s[0][1] / s[1][1], s[2][1] / s[1][1]);
        let df = viscous_nms - th[1];
        FrictionEstimate {
            coulomb_nm: (th[0] + g0 * df).max(THETA_MIN[0]),
            viscous_nms,
            coulomb_var: s[0][0] - g0 * s[0][1],
            viscous_var: 0.0,
            cov: 0.0,
            spring_scale_err: th[2] + g2 * df,
            spring_scale_var: s[2][2] - g2 * s[2][1],
        }
    }

    /// True when every state is finite and the variances are positive.
    pub fn is_healthy(&self) -> bool {
        // A NaN or an infinity anywhere makes the sum NaN or infinite (and
        // a finite sum of finite values cannot overflow to a false alarm
        // that matters: it resets an observer that is beyond 10³⁸ anyway).
        // Written out, left to right, as `RateFilter::is_healthy` (the
        // learning slice runs it for every joint; an iterator chain over
        // the fields takes several times the instructions).
        let [y0, y1, y2] = self.y;
        let [h0, h1, h2] = self.h_prev;
        let [t0, t1, t2] = self.theta;
        let [[s00, s01, s02], [s10, s11, s12], [s20, s21, s22]] = self.sigma;
        let sum = self.r
            + self.p_prev
            + self.u_prev
            + self.lag_var
            + self.kdt
            + y0
            + y1
            + y2
            + h0
            + h1
            + h2
            + t0
            + t1
            + t2
            + s00
            + s01
            + s02
            + s10
            + s11
            + s12
            + s20
            + s21
            + s22;
        let finite = sum.is_finite();
        // κ may be fixed (a zero prior spread); T_C and f are always free.
        finite && self.sigma[0][0] > 0.0 && self.sigma[1][1] > 0.0 && self.sigma[2][2] >= 0.0
    }

    /// One step: advances the observer and, if `input.learn`, the RLS.
    pub fn step(&mut self, input: &ObserverInput, tuning: &ObserverTuning) {
        let wc = tuning.coulomb_threshold_rad_s;
        let h = [
            -coulomb_shape(input.rate_rad_s, wc),
            -input.rate_rad_s,
            input.spring_torque_nm,
        ];
        let u = input.spring_torque_nm + input.beta_nm;
        if !self.primed {
            self.p_prev = input.momentum;
            self.u_prev = u;
            self.h_prev = h;
            self.primed = true;
            return;
        }
        let dt = input.dt_s;
        // Forward-Euler first-order filter, K·dt kept ≤ 1 (stable, monotone).
        let kdt = (tuning.bandwidth_per_s * dt).clamp(0.0, 1.0);
        if !(kdt > 0.0) {
            return;
        }
        let u_bar = 0.5 * (self.u_prev + u);
        // r⁺ = (1 − K dt) r + K dt · d̄,  d̄ dt = Δp − ū dt.
        let r_new = (1.0 - kdt) * self.r + (kdt / dt) * (input.momentum - self.p_prev - u_bar * dt);
        let lag = (r_new - self.r) / kdt;
        self.kdt = kdt;
        self.lag_var += LAG_WEIGHT * (lag * lag - self.lag_var);
        self.r = r_new;
        for ((yi, hi), hp) in self.y.iter_mut().zip(h.iter()).zip(self.h_prev.iter()) {
            *yi = (1.0 - kdt) * *yi + kdt * 0.5 * (*hi + *hp);
        }
        self.p_prev = input.momentum;
        self.u_prev = u;
        self.h_prev = h;

        // Random walk of the parameters.
        self.sigma[0][0] += tuning.coulomb_walk * tuning.coulomb_walk * dt;
        self.sigma[1][1] += tuning.viscous_walk * tuning.viscous_walk * dt;
        if input.learn {
            // Errors in variables ("effective variance"): a rate error δω
            // moves the Coulomb regressor by sech²(ω/ω_c) δω/ω_c, i.e. the
            // torque by T_C sech²(ω/ω_c) δω/ω_c; |r| bounds T_C from below.
            // sech² = 1 − tanh², and −h₀ is the tanh.
            let sech2 = (1.0 - h[0] * h[0]).max(0.0);
            let tc = self.theta[0].max(libm::fabsf(self.r));
            let g = tc * sech2 / wc;
            let eiv = g * g * input.rate_var.max(0.0);
            self.learn(kdt, eiv, tuning);
        }
    }

    /// The RLS (Kalman) update of θ with `z = r`, `H = y`; `eiv` [N²·m²] is
    /// the variance the rate error adds to the measurement.
    fn learn(&mut self, kdt: f32, eiv: f32, tuning: &ObserverTuning) {
        let y = self.y;
        // Σ H and Hᵀ Σ H.
        let mut sh = [0.0f32; P];
        for (shi, row) in sh.iter_mut().zip(self.sigma.iter()) {
            *shi = row.iter().zip(y.iter()).map(|(a, b)| a * b).sum();
        }
        let hsh: f32 = y.iter().zip(sh.iter()).map(|(a, b)| a * b).sum();
        // The filtered residual is an AR(1) sequence with ρ = 1 − K dt: n
        // samples of it carry the information of n (1 − ρ)/(1 + ρ)
        // independent ones. The white part of its noise has the variance
        // E[(d̄ − r)²]·(1 − ρ)/(1 + ρ), so after the inflation it counts as
        // E[(d̄ − r)²] = `lag_var` (which also grows while r lags d); the
        // rate error (`eiv`) varies slowly and is inflated as it stands.
        let rho = 1.0 - kdt;
        let inflation = ((1.0 + rho) / (1.0 - rho).max(MIN_KDT)).max(1.0);
        let noise = self.lag_var.max(tuning.residual_var_floor) + eiv * inflation;
        let s = hsh + noise;
        if !(s > 0.0) || !s.is_finite() {
            return;
        }
        let pred: f32 = self.theta.iter().zip(y.iter()).map(|(a, b)| a * b).sum();
        let e = self.r - pred;
        for i in 0..P {
            self.theta[i] += sh[i] / s * e;
        }
        for i in 0..P {
            for j in 0..P {
                self.sigma[i][j] -= sh[i] * sh[j] / s;
            }
        }
        // Parameter projection onto the physical set. The bound the data
        // press against is `f ≥ 0` (a damping of 0 under a wide prior): it
        // is met in the metric Σ⁻¹ (D. Simon & T. L. Chia, "Kalman
        // filtering with state equality constraints", IEEE T-AES 38(1),
        // 2002), which moves T_C and κ as the data would have, had f = 0
        // been known ([`FrictionObserver::estimate_given_viscous`]). A clamp of f alone leaves them
        // where the violating f pulled them, and the Coulomb estimate then
        // drifts away step after step.
        if self.theta[1] < THETA_MIN[1] {
            let e = self.estimate_given_viscous(THETA_MIN[1]);
            self.theta = [e.coulomb_nm, THETA_MIN[1], e.spring_scale_err];
        }
        // The other bounds (and rounding) by a clamp.
        for ((t, lo), hi) in self
            .theta
            .iter_mut()
            .zip(THETA_MIN.iter())
            .zip(THETA_MAX.iter())
        {
            *t = t.max(*lo).min(*hi);
        }
    }
}

#[cfg(test)]
pub(crate) mod tests;
