//! The replay protocol the firmware speaks: a recorded run, sample by
//! sample, through the on-board [`Monitor`](crate::monitor::Monitor), with the
//! statuses written back.
//!
//! It lives in the core so that the host (`deploywatch replay`) and the
//! firmware share one implementation and the host never depends on a
//! firmware crate: the host writes the configuration frames with these
//! types, checks them against its own conversion of the mechanism file, and
//! can run this very loop itself.
//!
//! # Files
//! - Input: the monitor configuration ([`super::config`]: a [`ConfigHeader`](super::config::ConfigHeader) frame,
//!   then one [`JointFrame`](super::config::JointFrame) per joint), then one frame per sample, a
//!   [`Sample<N>`](crate::monitor::Sample) each, in time order, `N` the
//!   header's joint count (at most [`MAX_JOINTS`](super::config::MAX_JOINTS)).
//!
//! # Joint count and storage
//! The joint count is the caller's: a firmware builds one monitor,
//! `Monitor<N>` in a [`MonitorStore<N>`] with its configuration in a
//! [`ConfigStore<N>`] (both in its static memory), and [`configure()`]
//! refuses a header of another count with [`Error::JointCount`]. The loop
//! ([`run_paths`]) and the sample decoder are not generic: they take the
//! count at run time, up to [`MAX_JOINTS`](super::config::MAX_JOINTS).
//! - Output: one frame per input sample, the
//!   [`Status<N>`](crate::monitor::Status) that
//!   [`Monitor::update`](crate::monitor::Monitor::update) returned.
//!
//! Every frame is the core's telemetry frame
//! ([`crate::telemetry`]): postcard, CRC-32C, COBS, then `0x00`.
//! A frame that does not decode stops the replay with its index: a replay
//! input comes from a file, so a bad frame is a bad file, not line noise.
//!
//! One module per step: `frames` (the input split into frames), `configure`
//! (the header and the joint frames), `store` (where the monitor lives, its
//! meter, the monitor built in place), `run_loop` (the schedule of the two
//! paths and the whole replay); `error` (why a replay stopped).

mod configure;
mod error;
mod frames;
mod run_loop;
mod store;

pub use configure::{configure, read_header, ConfigStore};
pub use error::Error;
pub use frames::{FrameError, Source, READ_CHUNK, SAMPLE_FRAME_MAX, STATUS_FRAME_MAX};
pub use run_loop::{replay, run, run_paths, Direct, Paths};
pub use store::{status_frame, Meter, MonitorStore, Work};
