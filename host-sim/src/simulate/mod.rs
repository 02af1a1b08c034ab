//! From a mechanism to a run: the full deployment simulator (the core's
//! chain equations in `f64`, Dormand–Prince 5(4) with event location), the
//! reference sensor model, and the sensor faults a test bench can inject.
//!
//! [`deployment`] is the one entry point: it integrates an open chain
//! itself and hands a truss wing to [`truss_deployment`] (the multibody
//! simulator of [`multibody`]); both fill a [`trajectory::Trajectory`].
pub mod chain_ledger;
pub(crate) mod chain_sampler;
pub mod creep;
pub mod deployment;
pub mod fault_injection;
pub mod fault_syntax;
pub mod latch_deployment;
pub mod latch_run;
pub mod multibody;
pub mod ode;
pub mod rig;
pub mod rig_ode;
pub mod sensor;
pub mod spring_knots;
pub mod stowed;
pub mod trajectory;
pub mod truss_deployment;
