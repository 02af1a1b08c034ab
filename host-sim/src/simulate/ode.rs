//! Dormand–Prince 5(4) with its 4th-order continuous extension, for the
//! chain's second-order state `(φ, φ̇)`.
//!
//! Coefficients: Dormand & Prince (1980); dense output and step-size control
//! as in Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.4–II.6 (DOPRI5).
//! Why a stepper of our own rather than a crate: see `docs/simulator.md`.

use deploywatch_core::ChainState;

/// `ChainState` arithmetic the stepper needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct State<const N: usize> {
    /// `φ` \[rad\].
    pub q: [f64; N],
    /// `φ̇` [rad/s].
    pub v: [f64; N],
}

impl<const N: usize> State<N> {
    /// The zero state.
    pub const ZERO: Self = State {
        q: [0.0; N],
        v: [0.0; N],
    };

    /// As the core's state type.
    pub fn chain(&self) -> ChainState<f64, N> {
        ChainState {
            phi: self.q,
            phi_dot: self.v,
        }
    }

    /// `self + Σ c_i k_i`.
    #[inline]
    fn axpy(&self, h: f64, terms: &[(f64, &State<N>)]) -> State<N> {
        let mut out = *self;
        for &(c, k) in terms {
            if c == 0.0 {
                continue;
            }
            let hc = h * c;
            for i in 0..N {
                out.q[i] += hc * k.q[i];
                out.v[i] += hc * k.v[i];
            }
        }
        out
    }
}

/// The step a stepper took, with what it needs to interpolate inside it.
#[derive(Clone, Copy, Debug)]
pub struct Dense<const N: usize> {
    /// Start of the step \[s\].
    pub t0: f64,
    /// Step size \[s\].
    pub h: f64,
    r: [State<N>; 5],
}

impl<const N: usize> Dense<N> {
    /// The state at `t` ∈ [t0, t0 + h] (4th-order accurate).
    #[inline]
    pub fn at(&self, t: f64) -> State<N> {
        let s = ((t - self.t0) / self.h).clamp(0.0, 1.0);
        let s1 = 1.0 - s;
        let mut out = State::ZERO;
        for i in 0..N {
            let [r1, r2, r3, r4, r5] = &self.r;
            out.q[i] = r1.q[i] + s * (r2.q[i] + s1 * (r3.q[i] + s * (r4.q[i] + s1 * r5.q[i])));
            out.v[i] = r1.v[i] + s * (r2.v[i] + s1 * (r3.v[i] + s * (r4.v[i] + s1 * r5.v[i])));
        }
        out
    }
}

// Butcher tableau of Dormand–Prince 5(4).
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;
// Error coefficients b5 − b4.
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
// Dense output (Hairer's DOPRI5 contd5).
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

/// Outcome of one attempted step.
pub struct Attempt<const N: usize> {
    /// The state at `t + h` (5th order).
    pub y1: State<N>,
    /// The derivative at `t + h` (first stage of the next step, FSAL).
    pub k7: State<N>,
    /// Scaled error norm; the step is accepted when ≤ 1.
    pub err: f64,
    /// Interpolant over the step.
    pub dense: Dense<N>,
}

/// One Dormand–Prince step from `(t, y)` with derivative `k1 = f(t, y)`.
///
/// `f` returns `None` when the derivative cannot be evaluated (singular mass
/// matrix, NaN): the step then fails with `None`.
#[inline]
pub fn step<const N: usize, F>(
    f: &mut F,
    t: f64,
    y: &State<N>,
    k1: &State<N>,
    h: f64,
    rtol: f64,
    atol: f64,
) -> Option<Attempt<N>>
where
    F: FnMut(f64, &State<N>) -> Option<State<N>>,
{
    let k2 = f(t + C2 * h, &y.axpy(h, &[(A21, k1)]))?;
    let k3 = f(t + C3 * h, &y.axpy(h, &[(A31, k1), (A32, &k2)]))?;
    let k4 = f(t + C4 * h, &y.axpy(h, &[(A41, k1), (A42, &k2), (A43, &k3)]))?;
    let k5 = f(
        t + C5 * h,
        &y.axpy(h, &[(A51, k1), (A52, &k2), (A53, &k3), (A54, &k4)]),
    )?;
    let k6 = f(
        t + h,
        &y.axpy(
            h,
            &[(A61, k1), (A62, &k2), (A63, &k3), (A64, &k4), (A65, &k5)],
        ),
    )?;
    let y1 = y.axpy(
        h,
        &[(A71, k1), (A73, &k3), (A74, &k4), (A75, &k5), (A76, &k6)],
    );
    let k7 = f(t + h, &y1)?;
    let e = State::ZERO.axpy(
        h,
        &[
            (E1, k1),
            (E3, &k3),
            (E4, &k4),
            (E5, &k5),
            (E6, &k6),
            (E7, &k7),
        ],
    );
    let err = error_norm(y, &y1, &e, rtol, atol);
    let r = dense_coefficients(y, &y1, [k1, &k3, &k4, &k5, &k6, &k7], h);
    Some(Attempt {
        y1,
        k7,
        err: if err.is_finite() { err } else { f64::INFINITY },
        dense: Dense { t0: t, h, r },
    })
}

/// `∫ P dt` over the first `s·h` of a step of `h` \[s\] (`s` ∈ [0, 1]), of a
/// rate `P` evaluated with each of the step's derivatives: `p[0]` with
/// `k1`, `p[i]` with stage `i + 1`, `p[6]` with `k7` at the step's end. At
/// `s = 1` it is the step's own 5th-order quadrature `h Σ b_i P_i`;
/// inside, the step's continuous extension of it, as [`Dense::at`] is of
/// the state (a quantity integrated beside the state, without entering its
/// error norm).
pub fn stage_integral(h: f64, p: &[f64; 7], s: f64) -> f64 {
    let k = p.map(|pi| State::<1> { q: [pi], v: [0.0] });
    let w1 = State::ZERO.axpy(
        h,
        &[
            (A71, &k[0]),
            (A73, &k[2]),
            (A74, &k[3]),
            (A75, &k[4]),
            (A76, &k[5]),
        ],
    );
    let r = dense_coefficients(
        &State::ZERO,
        &w1,
        [&k[0], &k[2], &k[3], &k[4], &k[5], &k[6]],
        h,
    );
    Dense { t0: 0.0, h, r }.at(s * h).q[0]
}

/// The error norm of a step: the RMS over the `2N` components of the
/// embedded error `e`, each scaled by `atol + rtol · max(|y|, |y1|)`.
#[inline]
fn error_norm<const N: usize>(
    y: &State<N>,
    y1: &State<N>,
    e: &State<N>,
    rtol: f64,
    atol: f64,
) -> f64 {
    let mut acc = 0.0;
    for i in 0..N {
        let sq = atol + rtol * y.q[i].abs().max(y1.q[i].abs());
        let sv = atol + rtol * y.v[i].abs().max(y1.v[i].abs());
        acc += (e.q[i] / sq).powi(2) + (e.v[i] / sv).powi(2);
    }
    (acc / (2 * N) as f64).sqrt()
}

/// The coefficients of the step's dense output (Hairer, Nørsett & Wanner's
/// `CONTD5`): `k` holds `k1, k3, k4, k5, k6, k7`.
#[inline]
fn dense_coefficients<const N: usize>(
    y: &State<N>,
    y1: &State<N>,
    k: [&State<N>; 6],
    h: f64,
) -> [State<N>; 5] {
    let [k1, k3, k4, k5, k6, k7] = k;
    let mut r = [State::ZERO; 5];
    r[0] = *y;
    for i in 0..N {
        let dq = y1.q[i] - y.q[i];
        let dv = y1.v[i] - y.v[i];
        let bq = h * k1.q[i] - dq;
        let bv = h * k1.v[i] - dv;
        r[1].q[i] = dq;
        r[1].v[i] = dv;
        r[2].q[i] = bq;
        r[2].v[i] = bv;
        r[3].q[i] = dq - h * k7.q[i] - bq;
        r[3].v[i] = dv - h * k7.v[i] - bv;
        r[4].q[i] = h
            * (D1 * k1.q[i]
                + D3 * k3.q[i]
                + D4 * k4.q[i]
                + D5 * k5.q[i]
                + D6 * k6.q[i]
                + D7 * k7.q[i]);
        r[4].v[i] = h
            * (D1 * k1.v[i]
                + D3 * k3.v[i]
                + D4 * k4.v[i]
                + D5 * k5.v[i]
                + D6 * k6.v[i]
                + D7 * k7.v[i]);
    }
    r
}

/// The first step of an integration \[s\] (at most the options'
/// `max_step_s`): small against the fastest time scale of a deployment (a
/// latch impact or a knee snap, milliseconds); the controller grows it.
pub const INITIAL_STEP_S: f64 = 1e-4;

/// The step after a discontinuity (a latch, a branch switch, a lock) is at
/// most this \[s\]: the controller's memory of the old smooth regime says
/// nothing of the new one, so it starts over with a modest step.
pub const RESTART_STEP_S: f64 = 1e-3;

/// Smallest step before the integration gives up \[s\]: 10⁻¹³ s is a few
/// hundred ulps of a time of seconds, below which `t + h` stops moving.
pub const MIN_STEP_S: f64 = 1e-13;

/// How close to the end time a step below [`MIN_STEP_S`] counts as having
/// arrived rather than as an underflow \[s\].
pub const END_SLACK_S: f64 = 1e-12;

/// The factor a step shrinks by when its trial state leaves the domain of
/// the equations (singular mass matrix, NaN): no error norm says by how
/// much, so a fixed quarter.
pub const FAILED_STEP_SHRINK: f64 = 0.25;

/// Constants of a [`StepController`] (Hairer, Nørsett & Wanner I §II.4;
/// Hairer & Wanner II §IV.2): after a step with error norm `err`, the next
/// step is `h · safety · err^−(1/5 − 0.75 β) · err_prev^β`, the factor
/// clamped to `[min_factor, max_factor]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepControl {
    /// Safety factor on the step the error estimate asks for.
    pub safety: f64,
    /// Integral gain β of the proportional-integral controller (0: the
    /// elementary controller `h · safety · err^−1/5`).
    pub beta: f64,
    /// Smallest step ratio after one attempt.
    pub min_factor: f64,
    /// Largest step ratio after one accepted step.
    pub max_factor: f64,
    /// The step after a rejection may not grow.
    pub hold_after_reject: bool,
}

/// Exponent of the error norm in the elementary controller: 1/5, one over
/// the order + 1 of the embedded 4th-order estimate of DOPRI5.
const ERROR_EXPONENT: f64 = 0.2;

/// The error norm a step is credited with at least: a step that makes no
/// measurable error grows by `max_factor`, not by infinity.
const MIN_ERROR_NORM: f64 = 1e-10;

/// The error norm remembered by the integral term at least, and before the
/// first step: keeps one exact step from licensing a jump later.
const MIN_ERROR_MEMORY: f64 = 1e-4;

/// The physical-latch runs' controller (`latch_deployment`): the
/// elementary one, safety 0.9, growth within [0.2, 5]. Every physical-latch
/// verdict on record (`docs/measured.md`) was computed with it, and the
/// verdicts decided by the phase of a rattle move with any change of the
/// step sequence (`docs/performance.md`).
pub const ELEMENTARY_CONTROL: StepControl = StepControl {
    safety: 0.9,
    beta: 0.0,
    min_factor: 0.2,
    max_factor: 5.0,
    hold_after_reject: false,
};

/// The proportional-integral controller of Hairer's DOPRI5 code, `β =
/// 0.04`, growth within [0.2, 10], and no growth in the step after a
/// rejection: the ideal-latch chain's (`deployment.rs`) and the truss
/// wing's (`multibody/integrate.rs`). Where the equations stiffen — a
/// truss pin's friction `tanh(ω/ω_c)` while its rate crosses zero, a tape
/// spring's peak in the last degree before a latch — the elementary
/// controller alternates growing and rejected steps, which the memory of
/// the integral term and the no-growth rule damp (seed 001 T01's
/// reliability draws: `docs/performance.md`, "An ideal-latch deployment's
/// steps").
pub const PI_CONTROL: StepControl = StepControl {
    safety: 0.9,
    beta: 0.04,
    min_factor: 0.2,
    max_factor: 10.0,
    hold_after_reject: true,
};

/// Step-size control of DOPRI5: the next step after each attempt, from its
/// error norm and, for `β > 0`, the last accepted one's.
#[derive(Clone, Copy, Debug)]
pub struct StepController {
    control: StepControl,
    /// Error norm of the last accepted step.
    err_prev: f64,
    /// The last attempt was rejected.
    rejected: bool,
}

impl StepController {
    /// A controller with no memory yet.
    pub fn new(control: StepControl) -> Self {
        StepController {
            control,
            err_prev: MIN_ERROR_MEMORY,
            rejected: false,
        }
    }

    /// Forgets the past steps (after a discontinuity).
    pub fn restart(&mut self) {
        *self = StepController::new(self.control);
    }

    /// The next step after an accepted step `h` with error norm `err ≤ 1`.
    #[inline]
    pub fn accept(&mut self, h: f64, err: f64) -> f64 {
        let c = self.control;
        let err = err.max(MIN_ERROR_NORM);
        let fac =
            c.safety * err.powf(-(ERROR_EXPONENT - 0.75 * c.beta)) * self.err_prev.powf(c.beta);
        let mut fac = fac.clamp(c.min_factor, c.max_factor);
        if self.rejected && c.hold_after_reject {
            fac = fac.min(1.0);
        }
        self.err_prev = err.max(MIN_ERROR_MEMORY);
        self.rejected = false;
        h * fac
    }

    /// The next step after a rejected step `h` with error norm `err > 1`:
    /// the elementary controller's (the integral term only steers growth).
    #[inline]
    pub fn reject(&mut self, h: f64, err: f64) -> f64 {
        let c = self.control;
        self.rejected = true;
        h * (c.safety * err.powf(-ERROR_EXPONENT)).clamp(c.min_factor, c.max_factor)
    }
}

/// Most Illinois iterations of [`locate`]: it converges superlinearly, a
/// few tens reach [`LOCATE_REL_TOL`]; the cap only bounds a pathological `g`.
const LOCATE_MAX_ITERATIONS: usize = 200;

/// Width of the bracket [`locate`] stops at, relative to `1 + |t|` [s/s]:
/// a few hundred ulps of a time of seconds.
const LOCATE_REL_TOL: f64 = 1e-13;

/// Locates the root of `g` on the interpolant in `[t0, t1]` where
/// `g(t0) > 0 ≥ g(t1)` (Illinois method), returning a time just past it
/// (where `g ≤ 0`).
pub fn locate<const N: usize>(
    g: impl Fn(&State<N>) -> f64,
    dense: &Dense<N>,
    t0: f64,
    t1: f64,
) -> f64 {
    let (mut a, mut b) = (t0, t1);
    let (mut fa, mut fb) = (g(&dense.at(a)), g(&dense.at(b)));
    if fa <= 0.0 {
        return a;
    }
    let mut side = 0;
    for _ in 0..LOCATE_MAX_ITERATIONS {
        if b - a <= LOCATE_REL_TOL * (1.0 + b.abs()) {
            break;
        }
        let mut c = (a * fb - b * fa) / (fb - fa);
        if !(c > a && c < b) {
            c = 0.5 * (a + b);
        }
        let fc = g(&dense.at(c));
        if fc > 0.0 {
            a = c;
            fa = fc;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            b = c;
            fb = fc;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn harmonic_oscillator_is_accurate_and_dense_output_interpolates() {
        // q'' = −q, q(0) = 1: q = cos t.
        let mut f = |_t: f64, y: &State<1>| {
            Some(State {
                q: y.v,
                v: [-y.q[0]],
            })
        };
        let mut y = State { q: [1.0], v: [0.0] };
        let mut k1 = f(0.0, &y).unwrap();
        let (mut t, mut h) = (0.0f64, 1e-3f64);
        let mut worst: f64 = 0.0;
        let mut ctl = StepController::new(ELEMENTARY_CONTROL);
        while t < 10.0 {
            h = h.min(10.0 - t);
            let a = step(&mut f, t, &y, &k1, h, 1e-10, 1e-12).unwrap();
            if a.err <= 1.0 {
                let tm = t + 0.37 * h;
                worst = worst.max((a.dense.at(tm).q[0] - tm.cos()).abs());
                t += h;
                y = a.y1;
                k1 = a.k7;
            }
            h = if a.err <= 1.0 {
                ctl.accept(h, a.err)
            } else {
                ctl.reject(h, a.err)
            };
        }
        assert!((y.q[0] - 10f64.cos()).abs() < 1e-8);
        assert!(worst < 1e-8, "{worst}");
    }

    #[test]
    fn stage_integral_is_the_steps_own_quadrature() {
        // The stages sit at t0 + c·h, c = 0, 1/5, 3/10, 4/5, 8/9, 1, 1
        // (FSAL). Over the whole step the weights are exact for a rate of
        // degree 4 in t (5th order), and the continuous extension to any
        // point inside for degree 3 (4th order); degree 5 is not exact.
        let c = [0.0, C2, C3, C4, C5, 1.0, 1.0];
        let (t0, h) = (0.7, 0.3);
        let stages = |deg: i32| c.map(|ci| (t0 + ci * h).powi(deg));
        let exact =
            |deg: i32, s: f64| ((t0 + s * h).powi(deg + 1) - t0.powi(deg + 1)) / f64::from(deg + 1);
        let rel = |got: f64, want: f64| (got - want).abs() / want.abs();
        for deg in 0..=4 {
            let got = stage_integral(h, &stages(deg), 1.0);
            assert!(rel(got, exact(deg, 1.0)) < 1e-14, "degree {deg}: {got}");
        }
        for deg in 0..=3 {
            for s in [0.1, 0.37, 0.5, 0.9] {
                let got = stage_integral(h, &stages(deg), s);
                assert!(
                    rel(got, exact(deg, s)) < 1e-13,
                    "degree {deg} at {s}: {got}"
                );
            }
        }
        assert!(rel(stage_integral(h, &stages(5), 1.0), exact(5, 1.0)) > 1e-9);
    }
}
