//! What the runs say about the model: how a model is scored against a run
//! (`metrics`), least squares over simulations (`fit`), the equivalent
//! friction torques (`identify`), the cause of what the model gets wrong
//! (`diagnose`), and the design torque margins of the flight standards
//! (`design_margin`).
pub mod campaign_sim;
pub mod design_margin;
pub mod diagnose;
pub mod effect_margin;
pub mod evidence;
pub mod fit;
pub mod identify;
pub mod latch_events;
pub mod metrics;
pub mod reliability;
pub mod residual_named;
pub mod residual_shape;
pub mod residual_torque;
pub mod rig_margin;
pub mod smoothing;
pub mod table_export;
