//! The panel chain's physics (`docs/spec/physics.md`), written once and
//! generic over the float type ([`real::Real`]: `f32` on board, `f64` in the
//! host simulator): the chain's mass matrix and equations of motion
//! ([`chain`]), the hinge springs ([`spring`]), the friction law
//! ([`friction`]), the physical latch ([`latch_contact`]) and its pawl
//! ([`pawl`]), tabulated joint torques ([`torque_table`]), and the
//! arithmetic they need ([`linalg`], [`trig`]). Nothing here knows about
//! sensors or the monitor.

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
