//! What the runs say about the model: how a model is scored against a run
//! (`metrics`), least squares over simulations (`fit`), the equivalent
//! friction torques (`identify`), the cause of what the model gets wrong
//! (`diagnose`), and the design torque margins of the flight standards
//! (`design_margin`).
pub mod campaign_sim;
pub mod design_margin;
pub mod diagnose;
pub mod diagnosis_details;
pub mod dynamic_margin;
pub mod effect_margin;
pub mod fit;
pub mod identify;
pub mod identify_edge;
pub mod joint_margins;
pub mod latch_events;
pub mod metrics;
pub mod nominal_deployment;
pub mod reliability;
pub mod resistances;
pub mod rig_margin;
pub mod stroke_margin;
/// The evidence modules of the diagnosis (in `analysis/diagnose/`) that
/// identify and the reports use, reachable as `analysis::evidence`,
/// `analysis::residual_torque`, ….
pub use diagnose::{evidence, residual_shape, residual_torque, table_export};
