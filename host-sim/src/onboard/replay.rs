//! Replay of a recorded run through the on-board monitor, on the host or on
//! the example firmware under QEMU (`deploywatch replay`), and the check that
//! both give bit-identical statuses.
//!
//! ```text
//! Mechanism ──config_frames──┐
//! Run ───────sample frames───┴─> input ──host: Monitor<N>::update (f32)──> status frames
//!                                      └─QEMU: firmware (Cortex-M4F)─────> status frames ── compare
//! ```
//!
//! The input is the firmware's protocol (`deploywatch_core::telemetry::replay`): the
//! monitor configuration as frames ([`config_frames`]), then one
//! [`Sample<N>`](deploywatch_core::monitor::Sample) frame per sample; the output one [`Status<N>`](deploywatch_core::monitor::Status) frame per
//! sample. Frames are the core's telemetry frames
//! ([`deploywatch_core::telemetry`]). The host's statuses come from the
//! simulator's own path ([`monitor_config`](crate::onboard::monitor_config::monitor_config)
//! and [`Monitor::replay_step`](deploywatch_core::monitor::Monitor::replay_step)); the configuration frames are checked to build
//! the very same [`MonitorConfig`](deploywatch_core::monitor::MonitorConfig) before any replay, so a difference of the
//! two sides is one of the target, never of the configuration.
//!
//! Everything after the frames works on [`StatusRow`]s, which hold any joint
//! count: the status CSV ([`write_status_csv`]), the per-joint
//! [`summary()`], the [`plot()`] and the field-by-field [`compare()`].
//!
//! One module per responsibility: `encode` (configuration frames), `prepare`
//! (a run made ready: input frames and the host's statuses), `decode`
//! (status frames read back), `compare`, `status_csv`, `summary`, `figure`,
//! `qemu` (the firmware's ELF and its run under QEMU); `error` and `status`
//! hold the types they share.

mod compare;
mod decode;
mod encode;
mod error;
mod figure;
mod prepare;
mod qemu;
mod status;
mod status_csv;
mod summary;

pub use compare::compare;
pub use decode::{decode_statuses, frames};
pub use encode::config_frames;
pub use error::ReplayError;
pub use figure::plot;
pub(crate) use prepare::{config_and_samples, run_of};
pub use prepare::{load_run, prepare, rig_note, Prepared};
pub(crate) use qemu::{find_firmware, SETUP_HINT};
pub use qemu::{run_qemu, QEMU};
pub use status::StatusRow;
pub use status_csv::write_status_csv;
pub use summary::{summary, JointSummary};
