//! What a chain is built of and the state it is in: panels, joints and
//! their named effects, the global effects, the continuous state and the
//! discrete mode, and why a chain cannot be built or evaluated.

use crate::physics::friction::Friction;
use crate::physics::linalg::SolveError;
use crate::physics::spring::{Branch, Spring};
use crate::physics::torque_table::{TorqueTable, TABLE_MAX_KNOTS};

/// Half-width δ of the `latch_detent` zone \[deg\] (`physics.md` section 6).
pub const DETENT_ZONE_DEG: f64 = 3.0;

/// One rigid panel (`physics.md` section 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Panel<T> {
    /// `L_i`: inboard to outboard hinge \[m\].
    pub length_m: T,
    /// `m_i` \[kg\].
    pub mass_kg: T,
    /// `c_i`: centre of mass from the inboard hinge, along the panel \[m\].
    pub com_m: T,
    /// `I_i`: inertia about the centre of mass, axis ∥ z [kg·m²].
    pub inertia_kgm2: T,
}

/// The named effects that act on one joint (`physics.md` section 6), all
/// zero by default. They add to the joint's own friction law. `K`: the
/// most points of each torque table ([`TABLE_MAX_KNOTS`] on the monitor).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct JointEffects<T, const K: usize = TABLE_MAX_KNOTS> {
    /// `coulomb_friction`: adds `−T_C tanh(φ̇/0.01)` [N·m].
    pub coulomb_nm: T,
    /// `viscous_damping`: adds `−f φ̇` [N·m·s/rad].
    pub viscous_nms: T,
    /// `stribeck_friction`'s excess `ΔT = T_brk − T_C` [N·m] (its `T_C` adds
    /// to `coulomb_nm`): adds the Stribeck term of
    /// [`crate::physics::friction::stribeck_excess`].
    pub stribeck_excess_nm: T,
    /// `stribeck_friction`'s Stribeck velocity `ω_st` [rad/s] (used while
    /// `stribeck_excess_nm ≠ 0`).
    pub stribeck_rad_s: T,
    /// `quadratic_damping`: adds `−c φ̇|φ̇|` [N·m·s²/rad²].
    pub quadratic_nms2_per_rad2: T,
    /// `spring_softening`: the spring torque is scaled by `(1 − s)` \[1\].
    pub spring_softening: T,
    /// `harness_stiffness`: adds `k_h (φ_stowed − φ)` [N·m/rad].
    pub harness_nm_per_rad: T,
    /// `latch_detent`: adds `−T_d sign(φ) sin(2π|φ|/δ)` while `|φ| < δ` [N·m].
    pub detent_nm: T,
    /// `torque_table`: adds `f(φ) + g(φ̇)` ([`crate::physics::torque_table`]).
    pub table: TorqueTable<T, K>,
}

/// The named effects that act on the whole chain (`physics.md` section 6).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct GlobalEffects<T> {
    /// `air_drag`: force per unit length `−k v_n |v_n| n_i` [kg/m²].
    pub air_drag_kg_m2: T,
    /// `rig_tilt`: in-plane gravity component `g_t` [m/s²].
    pub tilt_m_s2: T,
    /// Direction α of the tilt gravity, counter-clockwise from the bus x axis \[rad\].
    pub tilt_alpha_rad: T,
}

/// One joint: what drives and resists it (`K` as in [`JointEffects`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Joint<T, const K: usize = TABLE_MAX_KNOTS> {
    /// Stowed (initial) angle `φ_j(0)` \[rad\]; the latch angle is 0.
    pub stowed_rad: T,
    /// The hinge spring(s).
    pub spring: Spring<T>,
    /// The joint's friction law.
    pub friction: Friction<T>,
    /// Named effects acting on this joint.
    pub effects: JointEffects<T, K>,
}

/// Why a chain could not be built or evaluated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ChainError {
    /// Panel `index` (0-based) has a non-positive or non-finite mass, length or inertia.
    BadPanel {
        /// 0-based panel index.
        index: usize,
    },
    /// The mass matrix is singular or the state holds NaN.
    Singular,
}

impl core::fmt::Display for ChainError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            ChainError::BadPanel { index } => write!(
                f,
                "panel {} needs a positive finite length, mass and inertia",
                index + 1
            ),
            ChainError::Singular => {
                f.write_str("mass matrix is singular or the state is not finite")
            }
        }
    }
}

impl core::error::Error for ChainError {}

impl From<SolveError> for ChainError {
    fn from(_: SolveError) -> Self {
        ChainError::Singular
    }
}

/// The state of the chain in joint coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChainState<T, const N: usize> {
    /// Joint angles `φ` \[rad\].
    pub phi: [T; N],
    /// Joint rates `φ̇` [rad/s].
    pub phi_dot: [T; N],
}

/// Discrete state: which joints are latched and which spring branch each uses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mode<const N: usize> {
    /// `true` once joint j has latched (removed from the coordinates).
    pub latched: [bool; N],
    /// Spring branch of each joint.
    pub branch: [Branch; N],
}

impl<const N: usize> Default for Mode<N> {
    fn default() -> Self {
        Mode {
            latched: [false; N],
            branch: [Branch::Fold; N],
        }
    }
}
