//! The joint rates from encoder angles: a kinematic Kalman filter per
//! joint, the friction observer's §1 ([`super::observer`]).
//!
//! State `x = [φ, ω, α]` (rad, rad/s, rad/s²), white-jerk ("Wiener-process
//! acceleration") model, Bar-Shalom, Li & Kirubarajan (2001) §6.3.3:
//!
//! ```text
//! F = [1 T T²/2; 0 1 T; 0 0 1],  Q = q [T⁵/20 T⁴/8 T³/6; T⁴/8 T³/3 T²/2; T³/6 T²/2 T]
//! z = φ + v,  v ~ N(0, σ² + Δ²/12)      (σ encoder noise, Δ = 360°/2¹⁴ its step)
//! ```
//! It needs no model of the chain, so an error in the model (or in the
//! friction estimate) can never bias the rates the friction is fitted on.

/// Number of unique entries of a symmetric 3×3 matrix.
const SYM3: usize = 6;

/// Outcome of a Kalman measurement update.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fusion {
    /// The measurement was used.
    Accepted,
    /// The measurement failed the innovation gate and was not used.
    Rejected,
}

/// Factor of the jerk spectral density per sample while the rate filter
/// lags ([`JerkAdaptation::high`]).
const Q_GROWTH: f32 = 4.0;
/// Factor per sample while it follows with room to spare
/// ([`JerkAdaptation::low`]).
const Q_SHRINK: f32 = 0.9;

/// Kinematic Kalman filter of one joint angle: `[φ, ω, α]` in rad, rad/s,
/// rad/s², white-jerk process noise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RateFilter {
    x: [f32; 3],
    /// Upper triangle of the covariance: P00 P01 P02 P11 P12 P22.
    p: [f32; SYM3],
    /// Jerk spectral density now [rad²/s⁵] (adapted, see [`JerkAdaptation`]).
    q: f32,
    /// Running mean of the normalised innovation squared.
    nis: f32,
}

/// Adaptation of the rate filter's jerk spectral density to its own
/// innovations (an "adjustable process noise" filter, Bar-Shalom, Li &
/// Kirubarajan 2001 §11.2): `q` doubles while the running mean of the
/// normalised innovation squared exceeds `high` (×4 per sample), and shrinks by 10 % per
/// sample while it is below `low`, within `[q_min, q_max]`. A creeping joint
/// thus gets a long averaging window, a manoeuvring one a short one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JerkAdaptation {
    /// Smallest jerk spectral density [rad²/s⁵].
    pub q_min: f32,
    /// Largest [rad²/s⁵].
    pub q_max: f32,
    /// NIS mean above which `q` grows.
    pub high: f32,
    /// NIS mean below which `q` shrinks.
    pub low: f32,
    /// Weight of one sample in the NIS running mean.
    pub weight: f32,
}

impl RateFilter {
    /// Starts at angle `phi_rad` \[rad\] at rest, with standard deviations
    /// `sd_phi_rad` \[rad\], `sd_rate` [rad/s] and `sd_acc` [rad/s²].
    pub fn new(phi_rad: f32, sd_phi_rad: f32, sd_rate: f32, sd_acc: f32) -> Self {
        RateFilter {
            q: 1.0,
            nis: 1.0,
            x: [phi_rad, 0.0, 0.0],
            p: [
                sd_phi_rad * sd_phi_rad,
                0.0,
                0.0,
                sd_rate * sd_rate,
                0.0,
                sd_acc * sd_acc,
            ],
        }
    }

    /// The angle estimate \[rad\].
    pub fn angle(&self) -> f32 {
        self.x[0]
    }

    /// The rate estimate [rad/s].
    pub fn rate(&self) -> f32 {
        self.x[1]
    }

    /// The acceleration estimate [rad/s²].
    pub fn acceleration(&self) -> f32 {
        self.x[2]
    }

    /// Variance of the angle estimate \[rad²\].
    pub fn angle_var(&self) -> f32 {
        self.p[0]
    }

    /// Variance of the rate estimate [rad²/s²].
    pub fn rate_var(&self) -> f32 {
        self.p[3]
    }

    /// The jerk spectral density in use [rad²/s⁵].
    #[cfg(test)]
    pub fn jerk_psd(&self) -> f32 {
        self.q
    }

    /// Sets the jerk spectral density [rad²/s⁵].
    pub fn set_jerk_psd(&mut self, q: f32) {
        self.q = q;
    }

    /// Sets the rate [rad/s] (after a latch impulse) and adds `var`
    /// [rad²/s²] to its variance.
    pub fn set_rate(&mut self, rate: f32, var: f32) {
        self.x[1] = rate;
        self.p[3] += var;
    }

    /// Sets the acceleration estimate [rad/s²] (its variance unchanged).
    pub fn set_acceleration(&mut self, acc: f32) {
        self.x[2] = acc;
    }

    /// Pins the joint: angle `phi_rad`, rate and acceleration zero (a
    /// latched joint).
    pub fn pin(&mut self, phi_rad: f32) {
        self.x = [phi_rad, 0.0, 0.0];
    }

    /// Adds `var_rate` [rad²/s²] and `var_acc` [rad²/s⁴] to the rate and
    /// acceleration variances (a manoeuvre or a gap the model cannot see).
    pub fn inflate(&mut self, var_rate: f32, var_acc: f32) {
        self.p[3] += var_rate;
        self.p[5] += var_acc;
    }

    /// True when every state and covariance entry is finite and the
    /// variances are positive.
    pub fn is_healthy(&self) -> bool {
        // A NaN or an infinity anywhere makes the sum NaN or infinite (as
        // in `FrictionObserver::is_healthy`: one pass, no branch per entry;
        // written out, left to right: the sample path runs it for every
        // joint, and an iterator chain over the fields takes twice the
        // instructions on the Cortex-M4F).
        let [x0, x1, x2] = self.x;
        let [p0, p1, p2, p3, p4, p5] = self.p;
        let sum = x0 + x1 + x2 + p0 + p1 + p2 + p3 + p4 + p5 + self.q + self.nis;
        sum.is_finite() && self.p[0] > 0.0 && self.p[3] > 0.0 && self.p[5] > 0.0
    }

    /// Time update over `dt` \[s\] with the adapted jerk spectral density, or
    /// `q_floor` [rad²/s⁵] if that is larger.
    pub fn predict(&mut self, dt: f32, q_floor: f32) {
        let q = self.q.max(q_floor);
        let t = dt;
        let h = 0.5 * t * t;
        let [x0, x1, x2] = self.x;
        self.x = [x0 + t * x1 + h * x2, x1 + t * x2, x2];
        let [a, b, c, d, e, f] = self.p;
        // F P, row by row (P symmetric).
        let r0 = [a + t * b + h * c, b + t * d + h * e, c + t * e + h * f];
        let r1 = [b + t * c, d + t * e, e + t * f];
        // (F P) Fᵀ plus the white-jerk Q.
        let t2 = t * t;
        let t3 = t2 * t;
        let t4 = t3 * t;
        let t5 = t4 * t;
        self.p = [
            r0[0] + t * r0[1] + h * r0[2] + q * t5 / 20.0,
            r0[1] + t * r0[2] + q * t4 / 8.0,
            r0[2] + q * t3 / 6.0,
            r1[1] + t * r1[2] + q * t3 / 3.0,
            r1[2] + q * t2 / 2.0,
            f + q * t,
        ];
    }

    /// Measurement update with angle `z` \[rad\] of variance `r` \[rad²\].
    /// Rejected when the normalised innovation squared exceeds `gate2`.
    pub fn update(&mut self, z: f32, r: f32, gate2: f32, adapt: &JerkAdaptation) -> Fusion {
        let nu = z - self.x[0];
        let s = self.p[0] + r;
        if !(s > 0.0) || !(nu * nu <= gate2 * s) {
            return Fusion::Rejected;
        }
        self.nis += adapt.weight * (nu * nu / s - self.nis);
        if self.nis > adapt.high {
            self.q = (Q_GROWTH * self.q).min(adapt.q_max);
        } else if self.nis < adapt.low {
            self.q = (Q_SHRINK * self.q).max(adapt.q_min);
        }
        let k = [self.p[0] / s, self.p[1] / s, self.p[2] / s];
        self.x[0] += k[0] * nu;
        self.x[1] += k[1] * nu;
        self.x[2] += k[2] * nu;
        let [a, b, c, d, e, f] = self.p;
        // P − K H P with H = [1 0 0]: P_ij − P_i0 P_0j / s.
        self.p = [
            a - k[0] * a,
            b - k[0] * b,
            c - k[0] * c,
            d - k[1] * b,
            e - k[1] * c,
            f - k[2] * c,
        ];
        Fusion::Accepted
    }
}
