//! Telemetry framing of the monitor's [`Sample`](crate::monitor::Sample) and
//! [`Status`](crate::monitor::Status): postcard, then a CRC-32, then COBS.
//!
//! # Frame
//! ```text
//! frame = COBS( postcard(value) ‖ CRC-32C(postcard(value)) as 4 bytes LE ) ‖ 0x00
//! ```
//! postcard writes `f32` as 4 bytes little-endian, `bool` as 1 byte, enums
//! and `u16` flags as varints (1 byte for the discriminants used here, up to
//! 3 for the flags), `Option` as a 1-byte tag then the value. The CRC is
//! CRC-32C (Castagnoli, `crc::CRC_32_ISCSI`), computed by postcard's CRC
//! flavor over the postcard bytes. COBS (Cheshire & Baker 1999) removes
//! every zero byte so that `0x00` ends a frame: a receiver that loses sync
//! resynchronises at the next zero.
//!
//! Everything here is `no_std` and heap-free: frames are written into a
//! caller's buffer, at most [`sample_frame_max`] / [`status_frame_max`]
//! bytes long.

pub mod config;
pub mod counted;
pub mod link;
pub mod replay;

use postcard::ser_flavors::crc::CrcModifier;
use postcard::ser_flavors::{Cobs, Slice};
use serde::{Deserialize, Serialize};

/// The CRC of a frame: CRC-32C (Castagnoli), as postcard's `use-crc` flavor
/// computes it.
pub const CRC: crc::Crc<u32> = crc::Crc::<u32>::new(&crc::CRC_32_ISCSI);

/// Why a frame could not be written or read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum TelemetryError {
    /// The output buffer is too small for the frame.
    BufferTooSmall,
    /// The frame is not valid COBS (or is empty).
    BadFraming,
    /// The CRC does not match the payload.
    BadCrc,
    /// The payload does not decode as the expected type.
    BadPayload,
}

impl core::fmt::Display for TelemetryError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            TelemetryError::BufferTooSmall => "telemetry buffer too small for the frame",
            TelemetryError::BadFraming => "telemetry frame is not valid COBS",
            TelemetryError::BadCrc => "telemetry frame CRC mismatch",
            TelemetryError::BadPayload => "telemetry payload does not decode",
        })
    }
}

impl core::error::Error for TelemetryError {}

/// Result of a telemetry operation.
pub type Result<T> = core::result::Result<T, TelemetryError>;

/// Writes `value` as one frame (postcard ‖ CRC-32C, COBS-encoded, `0x00`
/// terminated) into `buf` and returns the frame.
pub fn encode<'a, T: Serialize + ?Sized>(value: &T, buf: &'a mut [u8]) -> Result<&'a mut [u8]> {
    let cobs = Cobs::try_new(Slice::new(buf)).map_err(|_| TelemetryError::BufferTooSmall)?;
    let flavor = CrcModifier::new(cobs, CRC.digest());
    postcard::serialize_with_flavor(value, flavor).map_err(|e| match e {
        postcard::Error::SerializeBufferFull => TelemetryError::BufferTooSmall,
        _ => TelemetryError::BadPayload,
    })
}

/// Reads one frame written by [`encode`]. `frame` is decoded in place (its
/// contents are overwritten); a trailing `0x00` and anything after it are
/// ignored.
pub fn decode<'a, T: Deserialize<'a>>(frame: &'a mut [u8]) -> Result<T> {
    let payload = cobs_payload(frame)?;
    postcard::from_bytes_crc32(payload, CRC.digest()).map_err(payload_error)
}

/// The payload of `frame` (postcard bytes and CRC), COBS-decoded in place.
fn cobs_payload(frame: &mut [u8]) -> Result<&[u8]> {
    let n = cobs::decode_in_place(frame).map_err(|_| TelemetryError::BadFraming)?;
    frame.get(..n).ok_or(TelemetryError::BadFraming)
}

/// The error of a payload postcard did not read.
fn payload_error(e: postcard::Error) -> TelemetryError {
    match e {
        postcard::Error::DeserializeBadCrc => TelemetryError::BadCrc,
        _ => TelemetryError::BadPayload,
    }
}

/// Framing overhead: COBS adds one byte per 254 (rounded up, at least one),
/// plus the terminating zero.
const fn framed(payload: usize) -> usize {
    let with_crc = payload + 4;
    with_crc + with_crc.div_ceil(254) + 1
}

/// Largest postcard payload of a `Sample<n>`: time (4), `n` angles (4 each),
/// `n` switches (1 each).
pub(crate) const fn sample_payload_max(n: usize) -> usize {
    4 + 5 * n
}

/// Largest frame of a `Sample<n>` \[bytes\].
pub const fn sample_frame_max(n: usize) -> usize {
    framed(sample_payload_max(n))
}

/// Largest postcard payload of one `JointStatus`: seven `f32` (28), the
/// viscous observability, latch state and prediction (1 each), the
/// confidence (4), two `Option<f32>` (5 each), the fault flags (varint
/// `u16`, ≤ 3) and the resolution (1).
pub(crate) const JOINT_STATUS_PAYLOAD_MAX: usize = 7 * 4 + 1 + 1 + 1 + 4 + 2 * 5 + 3 + 1;

/// Largest postcard payload of a `Status<n>`: time (4), sample count
/// (varint `u32`, ≤ 5), then `n` joints.
pub(crate) const fn status_payload_max(n: usize) -> usize {
    4 + 5 + n * JOINT_STATUS_PAYLOAD_MAX
}

/// Largest frame of a `Status<n>` \[bytes\].
pub const fn status_frame_max(n: usize) -> usize {
    framed(status_payload_max(n))
}
