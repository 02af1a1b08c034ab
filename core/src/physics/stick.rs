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

    /// The band of joint `j` at rest at angle `phi` [rad] (module doc).
    pub fn stick_band(&self, j: usize, phi: T) -> StickBand<T> {
        let a = self.joint_torque(j, phi, T::ZERO, Branch::Fold);
        let b = self.joint_torque(j, phi, T::ZERO, Branch::Unfold);
        let s = self.static_friction_nm(j);
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
mod tests {
    use super::*;
    use crate::physics::chain::{GlobalEffects, Joint, JointEffects, Panel};
    use crate::physics::friction::Friction;
    use crate::physics::spring::Spring;

    fn one(friction: f64, preload: f64) -> Chain<f64, 1> {
        let panel = Panel {
            length_m: 1.0,
            mass_kg: 2.0,
            com_m: 0.5,
            inertia_kgm2: 0.2,
        };
        let joint = Joint {
            stowed_rad: 1.0,
            spring: Spring::Linear {
                preload_nm: preload,
                stiffness_nm_per_rad: 0.0,
                count: 1.0,
            },
            friction: Friction::coulomb(friction),
            effects: JointEffects::default(),
        };
        Chain::new([panel], [joint], GlobalEffects::default()).unwrap()
    }

    #[test]
    fn a_spring_weaker_than_the_friction_is_held_and_a_stronger_one_is_not() {
        for (friction, preload, held) in [(1.0, 0.5, true), (1.0, 1.5, false)] {
            let c = one(friction, preload);
            let band = c.stick_band(0, 0.5);
            let (m, rhs) = c.equations(
                &crate::ChainState {
                    phi: [0.5],
                    phi_dot: [0.0],
                },
                &crate::Mode {
                    latched: [true],
                    ..Default::default()
                },
            );
            let r = holding_torques(&m, &rhs, &[true]).unwrap()[0];
            // Nothing else acts: the holding torque is zero, the band is the
            // spring's −preload ± friction.
            assert!(r.abs() < 1e-12);
            assert!((band.lo - (-preload - friction)).abs() < 1e-12);
            assert_eq!(band.holds(r), held, "{band:?}");
            if !held {
                assert_eq!(band.slip_direction(r), -1.0);
            }
        }
    }

    #[test]
    fn stribeck_effect_peaks_at_its_excess_and_raises_the_static_level() {
        let mut c = one(0.0, 0.0);
        if let Some(jt) = c.joint_mut(0) {
            jt.effects.coulomb_nm = 0.3;
            jt.effects.stribeck_excess_nm = 0.4;
            jt.effects.stribeck_rad_s = 0.05;
            jt.effects.quadratic_nms2_per_rad2 = 2.0;
        }
        let w = 0.05 / 2f64.sqrt();
        let t = c.joint_torque(0, 0.5, w, Branch::Fold);
        let expect = 0.3 * (w / 0.01).tanh() + 0.4 + 2.0 * w * w;
        assert!((t + expect).abs() < 1e-9, "{t} vs {}", -expect);
        // Far past ω_st the excess is gone: kinetic + quadratic only.
        let t = c.joint_torque(0, 0.5, 1.0, Branch::Fold);
        assert!((t + 0.3 + 2.0).abs() < 1e-6, "{t}");
        assert!((c.static_friction_nm(0) - 0.7).abs() < 1e-12);
    }
}
