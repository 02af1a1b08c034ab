//! The on-board monitor seen from the host: a mechanism turned into the
//! core's fixed-size `f32` configuration, and the replay of a recorded run
//! through the monitor on the host or on the example firmware under QEMU.
pub mod monitor_config;
pub mod replay;
pub mod summary_words;
