//! The panel chain's physics (`docs/spec/physics.md`), written once and
//! generic over the float type ([`real::Real`]: `f32` on board, `f64` in the
//! host simulator): the chain's mass matrix and equations of motion
//! ([`chain`]), the hinge springs ([`spring`]), the friction law
//! ([`friction`]), the physical latch ([`latch_contact`]) and its pawl
//! ([`pawl`]), tabulated joint torques ([`torque_table`]), and the
//! arithmetic they need ([`linalg`], [`trig`]). Nothing here knows about
//! sensors or the monitor.

pub mod chain;
pub mod friction;
pub mod latch_contact;
pub mod linalg;
pub mod pawl;
pub mod real;
pub mod spring;
pub mod stick;
pub mod torque_table;
pub mod trig;
