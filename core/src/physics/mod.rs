//! The panel chain's physics (`docs/spec/physics.md`), written once and
//! generic over the float type ([`Real`](crate::Real): `f32` on board,
//! `f64` in the host simulator). Nothing here knows about sensors or the
//! monitor.
//!
//! The chain model itself is at the crate root ([`Chain`](crate::Chain),
//! [`Spring`](crate::Spring), [`Friction`](crate::Friction), …); this
//! module holds the rest: the physical latch ([`latch_contact`]) and its
//! pawl ([`pawl`]), the set-valued rest of a joint ([`stick`]), the
//! friction law's shape functions, the masked `L D Lᵀ` solve, and the
//! constants the host shares. Inside, crate-private, one module per
//! concern: `chain` (mass matrix, equations of motion), `spring`,
//! `friction`, `torque_table`, `linalg`, `real`, `trig`.

pub(crate) mod chain;
pub(crate) mod friction;
pub mod latch_contact;
pub(crate) mod linalg;
pub mod pawl;
pub(crate) mod real;
pub(crate) mod spring;
pub mod stick;
pub(crate) mod torque_table;
pub(crate) mod trig;

pub use chain::DETENT_ZONE_DEG;
pub use friction::{coulomb_shape, quadratic_damping, stribeck_excess, COULOMB_THRESHOLD_RAD_S};
pub use linalg::{solve_spd_masked, SolveError};
pub use spring::MAX_KNOTS;
pub use torque_table::TABLE_MAX_KNOTS;
