//! What is simulated: a mechanism as read from its TOML file, the named
//! effects that extend it (`docs/spec/physics.md` section 6), and its
//! mobility.
pub mod curve_toml;
pub mod effect;
pub mod file_kind;
pub mod findings;
pub mod flex;
pub mod flex_chain;
pub mod flex_toml;
pub mod friction_spec;
pub mod kinematics;
pub mod latch;
pub mod latch_toml;
pub mod located;
pub mod mechanism;
pub mod mechanism_error;
pub mod mechanism_toml;
pub mod mechanism_write;
pub mod plausibility;
pub mod rig;
pub mod rig_toml;
pub mod toml_tree;
pub mod torque_table;
pub mod truss;
pub mod truss_toml;
