//! From a mechanism to a run: the full deployment simulator (the core's
//! chain equations in `f64`, Dormand–Prince 5(4) with event location), the
//! reference sensor model, and the sensor faults a test bench can inject.
pub mod deployment;
pub mod fault_injection;
pub mod multibody;
pub mod ode;
pub mod sensor;
pub mod truss_deployment;
