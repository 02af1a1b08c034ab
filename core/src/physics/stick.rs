//! A joint at rest inside the band of its set-valued laws sticks
//! (`docs/spec/physics.md` section 4a, this project's rule).
//!
//! Two joint laws are set-valued at rest: the tape spring's fold/unfold
//! hysteresis (seed 001 Eq. 1: at `φ̇ = 0` the spring may exert any torque
//! between its two branches) and Coulomb friction (any torque in
//! `[−T_s, T_s]`, `T_s` the static level: the Coulomb torque, or the
//! break-away torque of a Stribeck curve). Their sum at angle `φ` is the
//! **band** `[lo, hi]`:
//!
//! ```text
//! lo = min_b τ_j(φ, 0, b) − T_s,   hi = max_b τ_j(φ, 0, b) + T_s
//! ```
//!
//! with `τ_j(φ, 0, b)` the joint's torque at rest on branch `b` (spring,
//! harness, detent, table; the rate terms vanish). The **holding torque**
//! `R_j` is the joint torque that keeps `φ̈_j = 0` with the joints already
//! held:
//!
//! ```text
//! R_j = (M a)_j − r_j,   a = M⁻¹ r on the free joints, 0 on the held ones
//! ```
//!
//! where `r` is the right-hand side of Lagrange's equations without the
//! held joints' own torques. A joint whose rate crosses zero with
//! `lo < R_j < hi` sticks: its rate is set to zero (a plastic impulse on
//! that joint alone, the others' momenta kept; at a located zero crossing
//! it takes no measurable energy) and it stays held until `R_j` leaves the
//! band; it then slips towards the side `R_j` left by. In motion the
//! smooth laws of §4 apply unchanged.
//!
//! The **kinetic band** ([`Chain::kinetic_band`]) is the same with the
//! kinetic level `T_k` in place of `T_s`: a joint moving slowly with its
//! holding torque inside it is decelerated by the unregularised law, the
//! band's margin the net torque that stops it (§4a, "Creep": the host
//! simulator's verdicts hold such a joint instead of letting the law's
//! `tanh` creep it on).

use crate::physics::chain::Chain;
use crate::physics::linalg::{solve_spd_masked, SolveError};
use crate::physics::real::Real;
use crate::physics::spring::Branch;

/// The torques [N·m] the set-valued laws of a joint at rest can supply.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StickBand<T> {
    /// Lower end `lo` [N·m].
    pub lo: T,
    /// Upper end `hi` [N·m].
    pub hi: T,
}

impl<T: Real> StickBand<T> {
    /// How far `r` [N·m] lies inside the band (negative: outside).
    #[inline]
    pub fn margin(&self, r: T) -> T {
        (r - self.lo).min(self.hi - r)
    }

    /// True when the band holds the torque `r` [N·m].
    #[inline]
    pub fn holds(&self, r: T) -> bool {
        self.margin(r) >= T::ZERO
    }

    /// The direction [±1] a joint held by the torque `r` moves in once
    /// `r` left the band: towards negative `φ` when it left by the top.
    #[inline]
    pub fn slip_direction(&self, r: T) -> T {
        if r > self.hi {
            -T::ONE
        } else {
            T::ONE
        }
    }
}

impl<T: Real, const N: usize, const K: usize> Chain<T, N, K> {
    /// The static friction level `T_s` [N·m] of joint `j`: the joint's own
    /// law's ([`crate::Friction::static_nm`]) plus the `coulomb_friction`
    /// and `stribeck_friction` effects on it.
    pub fn static_friction_nm(&self, j: usize) -> T {
        self.joints().get(j).map_or(T::ZERO, |jt| {
            let e = &jt.effects;
            jt.friction.static_nm() + e.coulomb_nm.abs() + e.stribeck_excess_nm.abs()
        })
    }

    /// True when joint `j` has a set-valued law at all (static friction, or
    /// a spring whose branches differ): only such a joint can stick.
    pub fn can_stick(&self, j: usize) -> bool {
        self.static_friction_nm(j) > T::ZERO
            || self
                .joints()
                .get(j)
                .is_some_and(|jt| jt.spring.has_hysteresis())
    }

    /// The kinetic friction level `T_k` [N·m] of joint `j`: the Coulomb
    /// torque of its law plus the `coulomb_friction` effect on it (a
    /// Stribeck excess is zero at rest and at speed, `physics.md` §4).
    pub fn kinetic_friction_nm(&self, j: usize) -> T {
        self.joints().get(j).map_or(T::ZERO, |jt| {
            jt.friction.coulomb_nm.abs() + jt.effects.coulomb_nm.abs()
        })
    }

    /// The band of joint `j` at rest at angle `phi` \[rad\] (module doc).
    pub fn stick_band(&self, j: usize, phi: T) -> StickBand<T> {
        self.band_with(j, phi, self.static_friction_nm(j))
    }

    /// The band of joint `j` moving slowly at angle `phi` \[rad\]: the
    /// spring branches at rest ± the kinetic level `T_k`
    /// ([`Chain::kinetic_friction_nm`]). A joint whose holding torque is
    /// inside it decelerates under the unregularised law (`physics.md`
    /// §4a, "creep"); its margin is the net torque that stops it.
    pub fn kinetic_band(&self, j: usize, phi: T) -> StickBand<T> {
        self.band_with(j, phi, self.kinetic_friction_nm(j))
    }

    /// The spring branches at rest at `phi` widened by the friction `s`.
    fn band_with(&self, j: usize, phi: T, s: T) -> StickBand<T> {
        let a = self.joint_torque(j, phi, T::ZERO, Branch::Fold);
        let b = self.joint_torque(j, phi, T::ZERO, Branch::Unfold);
        StickBand {
            lo: a.min(b) - s,
            hi: a.max(b) + s,
        }
    }
}

/// The holding torques `R` [N·m] of the `held` joints (module doc), from
/// the mass matrix `m` and the right-hand side `rhs` computed without the
/// held joints' own torques; 0 for the joints not held.
pub fn holding_torques<T: Real, const N: usize>(
    m: &[[T; N]; N],
    rhs: &[T; N],
    held: &[bool; N],
) -> Result<[T; N], SolveError> {
    let a = solve_spd_masked(m, rhs, held)?;
    let mut out = [T::ZERO; N];
    for j in 0..N {
        if held[j] {
            let mut ma = T::ZERO;
            for k in 0..N {
                ma += m[j][k] * a[k];
            }
            out[j] = ma - rhs[j];
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests;
