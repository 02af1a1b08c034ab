//! The on-board monitor seen from the host: a mechanism turned into the
//! core's fixed-size `f32` configuration, the replay of a recorded run
//! through the monitor on the host or on the example firmware under QEMU,
//! and the run streamed to the firmware's serial link in real time
//! (hardware in the loop).
pub mod firmware;
pub mod hil;
pub mod hil_link;
pub mod monitor_config;
pub mod replay;
pub mod summary_words;
