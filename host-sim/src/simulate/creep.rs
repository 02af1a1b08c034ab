//! A joint creeping to rest (`docs/spec/physics.md` §4a, "creep"): the
//! Coulomb law of §4 is regularised, `T_C tanh(φ̇/ω_coul)`, so a joint
//! that decelerates where its driving torque is below `T_C` never reaches
//! rest: its rate settles at the creep speed `ω_coul atanh(τ/T_C)` and it
//! creeps on (seed 001 T01's joint 2 at 1.9 N·m: 3.4° short of its latch
//! at 4 s, 0.84°/s after that), so whether the wing latched depended on
//! the run's `duration_s`. The rule: a free joint slower than
//! [`rest_rate`] whose holding torque lies inside its kinetic band (the
//! net torque on it, under the unregularised law, stops it) sticks,
//! unless under that law it would reach its latch first ([`stops_short`]).
//! Both simulators apply it at the end of each accepted step
//! (`simulate/deployment/stick.rs`, `simulate/latch_deployment/stick.rs`).

use crate::model::torque_table::HostChain;
use deploywatch_core::physics::COULOMB_THRESHOLD_RAD_S;

/// The rate at which the creep rule starts, in units of the joint's
/// `ω_coul` (ratio): `tanh(5) = 0.99991`, so every creep speed of a joint
/// whose driving torque is below 99.99 % of its Coulomb level is under it.
pub const CREEP_RATE_FACTOR: f64 = 5.0;

/// The rate [rad/s] below which joint `j` (0-based) is tested for the
/// creep rule: [`CREEP_RATE_FACTOR`] times the larger of its law's
/// `ω_coul` and the `coulomb_friction` effect's ([`COULOMB_THRESHOLD_RAD_S`]).
pub fn rest_rate<const N: usize>(chain: &HostChain<N>, j: usize) -> f64 {
    let own = chain
        .joints()
        .get(j)
        .map_or(0.0, |jt| jt.friction.coulomb_threshold_rad_s.abs());
    CREEP_RATE_FACTOR * own.max(COULOMB_THRESHOLD_RAD_S)
}

/// Whether joint `j` moving at `rate` [rad/s] is slower than its
/// [`rest_rate`] (and moves).
pub fn is_slow<const N: usize>(chain: &HostChain<N>, j: usize, rate: f64) -> bool {
    rate != 0.0 && rate.abs() <= rest_rate(chain, j)
}

/// Whether a joint for which `free` holds moves slower than its
/// [`rest_rate`] at the rates `v` [rad/s] (the cheap test before the
/// holding torques).
pub fn any_slow<const N: usize>(
    chain: &HostChain<N>,
    free: impl Fn(usize) -> bool,
    v: &[f64; N],
) -> bool {
    (0..N).any(|j| free(j) && is_slow(chain, j, v[j]))
}

/// Whether a joint at `phi` \[rad\] (its latch at 0) moving at `rate`
/// [rad/s], with `stopping` [N·m] the net torque that decelerates it (its
/// holding torque's margin inside the kinetic band, > 0) and `inertia`
/// [kg·m²] its diagonal of the mass matrix, stops short of its latch
/// under the unregularised law: it moves away from its latch (or has
/// none: `latching` false), or its stopping distance `I φ̇² / (2 m)` is
/// shorter than the way left `|φ|`. The diagonal is at least the
/// effective inertia `1/(M⁻¹)_jj`, so the distance is not short of the
/// true one: a joint near its latch is left to creep into it.
pub fn stops_short(phi: f64, rate: f64, stopping: f64, inertia: f64, latching: bool) -> bool {
    let towards = phi * rate < 0.0;
    if !latching || !towards {
        return true;
    }
    0.5 * inertia * rate * rate / stopping < phi.abs()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_joint_stops_short_unless_its_stopping_distance_reaches_the_latch() {
        // I = 0.5 kg·m², 0.04 rad/s, 0.01 N·m: 0.04 rad to stop.
        assert!(stops_short(0.05, -0.04, 0.01, 0.5, true));
        assert!(!stops_short(0.03, -0.04, 0.01, 0.5, true));
        // Moving away from the latch, or no latch: it stops.
        assert!(stops_short(0.03, 0.04, 0.01, 0.5, true));
        assert!(stops_short(0.03, -0.04, 0.01, 0.5, false));
    }
}
