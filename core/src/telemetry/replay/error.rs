//! Why a replay stopped.

/// Why a replay stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Error {
    /// The configuration frames are missing, do not decode, are of another
    /// [`CONFIG_VERSION`](crate::telemetry::config::CONFIG_VERSION) or give a joint count outside `1..=`[`MAX_JOINTS`](crate::telemetry::config::MAX_JOINTS).
    ConfigFrame,
    /// The configuration is of `found` joints where the monitor's store
    /// ([`MonitorStore<N>`](super::MonitorStore)) has `expected`: the firmware was built for
    /// another joint count.
    JointCount {
        /// The monitor's joint count `N`.
        expected: u8,
        /// The header's.
        found: u8,
    },
    /// The monitor (or the core's spring constructor) rejects the
    /// configuration.
    Config,
    /// Reading the input failed.
    Read,
    /// Writing the output failed.
    Write,
    /// Sample frame `index` (0-based, after the configuration frames) does
    /// not decode as a sample of the configured joint count, or is too long.
    Frame {
        /// 0-based index of the sample frame.
        index: u32,
    },
    /// The input ends inside a frame (no `0x00` after its last bytes).
    Truncated,
    /// A status did not fit its frame (a bug: [`STATUS_FRAME_MAX`](super::STATUS_FRAME_MAX) is the bound).
    Encode,
}

impl Error {
    /// A short description, for logs that cannot format (defmt).
    pub fn as_str(&self) -> &'static str {
        match self {
            Error::ConfigFrame => "the configuration frames are missing or do not decode",
            Error::JointCount { .. } => "the configuration is of another joint count",
            Error::Config => "the monitor rejects the configuration",
            Error::Read => "cannot read the input",
            Error::Write => "cannot write the output",
            Error::Frame { .. } => "a sample frame does not decode",
            Error::Truncated => "the input ends inside a frame",
            Error::Encode => "a status does not fit its frame",
        }
    }
}

impl core::fmt::Display for Error {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Error::Frame { index } => {
                write!(f, "sample frame {index} does not decode")
            }
            Error::JointCount { expected, found } => write!(
                f,
                "the configuration is of {found} joints, the monitor of {expected}"
            ),
            other => f.write_str(other.as_str()),
        }
    }
}

impl core::error::Error for Error {}
