//! Joint friction: Coulomb with a smooth sign, Stribeck break-away, viscous.
//!
//! `docs/spec/physics.md` section 4 (seed 001 Eq. 4, seed 000 Eq. 13):
//!
//! ```text
//! τ_f = −[ √(2e) (T_brk − T_C) exp(−(ω/ω_st)²) (ω/ω_st) + T_C tanh(ω/ω_coul) + f ω ]
//! ```
//!
//! The papers' equivalent friction torque (EFT) is `T_brk = T_C`, `f = 0`.

use crate::physics::real::Real;

/// Default `ω_coul` [rad/s] of the smooth Coulomb sign.
pub const COULOMB_THRESHOLD_RAD_S: f64 = 0.01;

/// The friction law of one joint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Friction<T> {
    /// Coulomb torque `T_C` [N·m].
    pub coulomb_nm: T,
    /// Break-away torque `T_brk` [N·m]; equal to `T_C` for no Stribeck peak.
    pub breakaway_nm: T,
    /// Viscous coefficient `f` [N·m·s/rad].
    pub viscous_nms: T,
    /// Stribeck velocity `ω_st` [rad/s] (unused when `T_brk = T_C`).
    pub stribeck_rad_s: T,
    /// `ω_coul` [rad/s] of `tanh(ω/ω_coul)`.
    pub coulomb_threshold_rad_s: T,
}

impl<T: Real> Default for Friction<T> {
    fn default() -> Self {
        Self::coulomb(T::ZERO)
    }
}

impl<T: Real> Friction<T> {
    /// Pure Coulomb (EFT) friction of `T_C` [N·m], `ω_coul` = 0.01 rad/s.
    pub fn coulomb(coulomb_nm: T) -> Self {
        Friction {
            coulomb_nm,
            breakaway_nm: coulomb_nm,
            viscous_nms: T::ZERO,
            stribeck_rad_s: T::ONE,
            coulomb_threshold_rad_s: T::of(COULOMB_THRESHOLD_RAD_S),
        }
    }

    /// True when the law exerts no torque at any rate.
    pub fn is_zero(&self) -> bool {
        self.coulomb_nm == T::ZERO && self.breakaway_nm == T::ZERO && self.viscous_nms == T::ZERO
    }

    /// The friction torque [N·m] at relative rate `omega` [rad/s].
    #[inline]
    pub fn torque(&self, omega: T) -> T {
        let mut t = T::ZERO;
        if self.coulomb_nm != T::ZERO {
            t += self.coulomb_nm * coulomb_shape(omega, self.coulomb_threshold_rad_s);
        }
        let peak = self.breakaway_nm - self.coulomb_nm;
        if peak != T::ZERO && self.stribeck_rad_s > T::ZERO {
            t += stribeck_excess(peak, omega, self.stribeck_rad_s);
        }
        t += self.viscous_nms * omega;
        -t
    }

    /// The static level `T_s` [N·m] of the law at rest (`physics.md` §4a):
    /// the larger of the Coulomb and break-away torques.
    pub fn static_nm(&self) -> T {
        self.coulomb_nm.abs().max(self.breakaway_nm.abs())
    }
}

/// The Stribeck excess of the friction law (`physics.md` §4), resisting
/// magnitude [N·m]: `√(2e) ΔT exp(−(ω/ω_st)²) (ω/ω_st)` for the excess
/// `ΔT = T_brk − T_C` [N·m] at rate `omega` [rad/s] with the Stribeck
/// velocity `omega_st` [rad/s] (> 0): zero at rest, `ΔT` at
/// `ω = ω_st/√2`, falling back to zero with rate. The one place it is
/// written: the joint's law ([`Friction::torque`]) and the
/// `stribeck_friction` effect (`physics.md` §6) both call it.
#[inline]
pub fn stribeck_excess<T: Real>(excess_nm: T, omega: T, omega_st: T) -> T {
    // √(2e) = 2.331643981597124
    let r = omega / omega_st;
    T::of(2.331_643_981_597_124) * excess_nm * (-(r * r)).exp() * r
}

/// The shape of the Coulomb part of the friction law (`physics.md` §4):
/// `tanh(ω/ω_c)` \[1\] at relative rate `omega` [rad/s] for the threshold
/// `omega_c` [rad/s]. The one place the law's smoothing is written: the
/// simulator's [`Friction::torque`], the observer's regressor and the
/// rollout's linearly implicit step all call it.
#[inline]
pub fn coulomb_shape<T: Real>(omega: T, omega_c: T) -> T {
    (omega / omega_c).tanh()
}

/// The quadratic damping of the `quadratic_damping` effect (`physics.md`
/// §6), resisting magnitude [N·m]: `c ω|ω|` for the coefficient `c`
/// [N·m·s²/rad²] at rate `omega` [rad/s], signed like `omega`. The one place
/// it is written: the chain's joint torque and the diagnosis's residual
/// signature both call it.
#[inline]
pub fn quadratic_damping<T: Real>(c: T, omega: T) -> T {
    c * omega * omega.abs()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eft_is_a_smooth_sign() {
        let f = Friction::coulomb(2.0f64);
        assert!((f.torque(1.0) + 2.0).abs() < 1e-12);
        assert!((f.torque(-1.0) - 2.0).abs() < 1e-12);
        assert_eq!(f.torque(0.0), 0.0);
    }

    #[test]
    fn stribeck_peak_is_breakaway_at_omega_st() {
        // d/dr of √(2e) r exp(−r²) peaks at r = 1/√2 with value 1 · (T_brk − T_C).
        let f = Friction {
            coulomb_nm: 0.0f64,
            breakaway_nm: 1.0,
            viscous_nms: 0.0,
            stribeck_rad_s: 0.1,
            coulomb_threshold_rad_s: 0.01,
        };
        let peak = -f.torque(0.1 / 2f64.sqrt());
        assert!((peak - 1.0).abs() < 1e-9, "{peak}");
    }

    #[test]
    fn quadratic_damping_grows_as_the_square_and_keeps_the_sign() {
        assert_eq!(quadratic_damping(0.5f64, 2.0), 2.0);
        assert_eq!(quadratic_damping(0.5f64, -2.0), -2.0);
        assert_eq!(quadratic_damping(0.5f64, 0.0), 0.0);
        // Doubling the rate quadruples the torque, in f32 as in f64.
        let (a, b) = (
            quadratic_damping(0.3f32, 0.7),
            quadratic_damping(0.3f32, 1.4),
        );
        assert!((b / a - 4.0).abs() < 1e-5, "{a} {b}");
    }
}
