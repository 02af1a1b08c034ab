//! The example firmware's replay (`src/main.rs`, which says what it does)
//! built for a monitor of 6 joints.
#![no_std]
#![no_main]

/// Joints of this build's monitor.
const JOINTS: usize = 6;

#[path = "../../replay_app.rs"]
mod replay_app;
