//! Mobility (degrees of freedom) of a mechanism, to check before simulating it
//! that it is neither over-constrained (DOF < 0 cannot deploy) nor a different
//! mechanism than intended.
//!
//! - Planar Gruebler equation, seed 000 Eq. 1 / Table 1:
//!   `DOF = 3 (L − 1) − 2 J1 − J2`, `L` bodies including the fixed one (the
//!   bus), `J1` one-DOF joints (revolute), `J2` two-DOF joints.
//! - Spatial count, seed 001 Eq. 3 / Table 4:
//!   `DOF = 6 · bodies − Σ constraints`, every body counted with 6 DOF and
//!   every joint removing its number of constraints (fixed 6, revolute 5,
//!   translational 5, spherical 3).

/// Constraints a fixed joint removes in space (seed 001 Table 4).
pub const FIXED_CONSTRAINTS: u32 = 6;
/// Constraints a revolute joint removes in space (seed 001 Table 4).
pub const REVOLUTE_CONSTRAINTS: u32 = 5;
/// Constraints a translational (prismatic) joint removes in space (seed 001 Table 4).
#[cfg(test)]
pub const TRANSLATIONAL_CONSTRAINTS: u32 = 5;
/// Constraints a spherical joint removes in space (seed 001 Table 4).
#[cfg(test)]
pub const SPHERICAL_CONSTRAINTS: u32 = 3;

/// Planar Gruebler mobility `3 (L − 1) − 2 J1 − J2` (seed 000 Eq. 1).
///
/// `bodies` is `L`, the fixed body included; `j1` one-DOF joints, `j2` two-DOF
/// joints. Negative means over-constrained. Returns 0 for `bodies = 0`.
pub fn planar_mobility(bodies: u32, j1: u32, j2: u32) -> i64 {
    3 * (i64::from(bodies.max(1)) - 1) - 2 * i64::from(j1) - i64::from(j2)
}

/// Spatial mobility `6 · bodies − Σ constraints` (seed 001 Eq. 3): `bodies`
/// counts every body (the ground too, held by a fixed joint), `constraints`
/// lists the constraints of each joint (e.g. [`FIXED_CONSTRAINTS`],
/// [`REVOLUTE_CONSTRAINTS`]).
pub fn spatial_mobility(bodies: u32, constraints: &[u32]) -> i64 {
    6 * i64::from(bodies) - constraints.iter().map(|&c| i64::from(c)).sum::<i64>()
}

/// Mobility of the project's planar open chain of `n` panels hinged in series
/// to a fixed bus: `n` bodies + bus, `n` revolute joints, so `n` DOF (one per
/// joint angle `φ_j`, `physics.md` 1).
#[cfg(test)]
pub fn open_chain_mobility(n: u32) -> i64 {
    planar_mobility(n + 1, n, 0)
}

/// Bodies and revolute joints of a wing with a truss, counting a node that
/// joins `k` links as `k − 1` joints (`truss-link.md`: F joins four links,
/// three joints): `(L, J1)` for [`planar_mobility`].
///
/// `L = 1 + panels + links` (the bus included); `J1 = panels` hinges, plus
/// one joint per link end on the bus or a panel, plus `k − 1` per free node
/// of `k` links.
pub fn truss_bodies_and_joints(truss: &crate::model::truss::Truss, panels: usize) -> (u32, u32) {
    use crate::model::truss::Carrier;
    let bodies = 1 + panels + truss.links.len();
    let mut joints = panels;
    for p in &truss.points {
        let k = truss
            .links
            .iter()
            .filter(|l| l.ends.iter().any(|e| e == &p.name))
            .count();
        joints += match p.on {
            Carrier::Node => k.saturating_sub(1),
            _ => k,
        };
    }
    (bodies as u32, joints as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn open_chain_has_one_dof_per_joint() {
        for n in 1..=4 {
            assert_eq!(open_chain_mobility(n), i64::from(n));
        }
    }

    #[test]
    fn over_constrained_is_negative() {
        // A triangle of three bars pinned together is a structure (0);
        // adding a fourth pin-jointed bar across it over-constrains it.
        assert_eq!(planar_mobility(3, 3, 0), 0);
        assert_eq!(planar_mobility(3, 4, 0), -2);
        assert_eq!(planar_mobility(0, 0, 0), 0);
    }

    #[test]
    fn spatial_pendulum_has_one_dof() {
        // Ground (fixed) + one link on a revolute joint.
        assert_eq!(
            spatial_mobility(2, &[FIXED_CONSTRAINTS, REVOLUTE_CONSTRAINTS]),
            1
        );
        assert_eq!(
            spatial_mobility(2, &[FIXED_CONSTRAINTS, SPHERICAL_CONSTRAINTS]),
            3
        );
        assert_eq!(
            spatial_mobility(2, &[FIXED_CONSTRAINTS, TRANSLATIONAL_CONSTRAINTS]),
            1
        );
    }
}
