//! A planar multibody simulator for closed loops (the truss-link wing of
//! `docs/spec/truss-link.md`, four-bar linkages, Andrews' squeezing
//! mechanism).
//!
//! Formulation: relative coordinates on a spanning tree of the pin graph
//! ([`system`]), loop-closure constraints at the cut pins and lock
//! constraints as extra rows ([`kin`]), the index-1 equations solved in the
//! mass-matrix metric by a rank-revealing least-squares solve ([`solve`]),
//! Dormand–Prince 5(4) with coordinate projection after every step and lock
//! events with plastic impacts ([`integrate`]). Straight knees and redundant
//! latches leave the solves regular: a dependent row only adds a zero
//! singular value, which the pseudo-inverse ignores.
//!
//! The open chain without a truss stays in [`crate::simulate::deployment`]
//! (the core's chain equations): one physics for the chain, which this
//! simulator reproduces when given the chain as bodies and hinges
//! ([`build::open_chain_system`]; `tests/truss.rs` checks it
//! against the chain's golden deployments). Validation: `tests/truss.rs`
//! (truss goldens, four-bar, Andrews' squeezer, lock-up mode),
//! `host-sim/tests/truss_cli.rs` (bad input).
pub mod build;
pub mod integrate;
pub mod kin;
pub mod solve;
pub mod system;
pub mod wing;

pub use integrate::{run, MbTrajectory};
pub use kin::Model;
pub use system::{Body, Pin, PointSpring, System, SystemError};
pub use wing::{simulate_wing, wing_model, wing_options, WingRun, GOLDEN_COLUMNS, GOLDEN_LOCKS};

impl Model {
    /// Builds the spanning tree of a system.
    pub fn new(sys: System) -> Result<Model, SystemError> {
        let tree = sys.tree()?;
        Ok(Model { sys, tree })
    }
}
