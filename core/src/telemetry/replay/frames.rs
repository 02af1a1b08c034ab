//! The input read as frames: the frame bounds of any joint count and a
//! byte stream split at its `0x00`s without allocating.

use crate::telemetry::config::MAX_JOINTS;
use crate::telemetry::{sample_frame_max, status_frame_max};

/// Largest input sample frame of any joint count up to [`MAX_JOINTS`],
/// `0x00` included \[bytes\].
pub const SAMPLE_FRAME_MAX: usize = sample_frame_max(MAX_JOINTS);

/// Largest output frame of any joint count up to [`MAX_JOINTS`], `0x00`
/// included \[bytes\].
pub const STATUS_FRAME_MAX: usize = status_frame_max(MAX_JOINTS);

/// Bytes read from the input at a time.
pub const READ_CHUNK: usize = 256;

/// Why [`Source::next_frame`] gave no frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameError {
    /// Reading failed.
    Read,
    /// The frame was longer than the buffer (it was skipped up to its `0x00`).
    TooLong,
    /// The input ended inside a frame.
    Truncated,
}

/// A byte stream read in chunks and split into `0x00`-terminated frames,
/// without allocating.
pub struct Source<R> {
    read: R,
    chunk: [u8; READ_CHUNK],
    pos: usize,
    len: usize,
}

impl<R: FnMut(&mut [u8]) -> Result<usize, ()>> Source<R> {
    /// A source over `read` (like `std::io::Read::read`: `Ok(0)` at the end).
    pub const fn new(read: R) -> Self {
        Source {
            read,
            chunk: [0; READ_CHUNK],
            pos: 0,
            len: 0,
        }
    }

    fn byte(&mut self) -> Result<Option<u8>, FrameError> {
        if self.pos == self.len {
            let n = (self.read)(&mut self.chunk).map_err(|_| FrameError::Read)?;
            self.pos = 0;
            self.len = n.min(READ_CHUNK);
            if self.len == 0 {
                return Ok(None);
            }
        }
        let b = self.chunk.get(self.pos).copied();
        self.pos += 1;
        Ok(b)
    }

    /// Bytes read from the input and not yet taken by a frame (the start of
    /// the next one, when the input brought more than a frame at once).
    pub(crate) fn buffered(&self) -> usize {
        self.len.saturating_sub(self.pos)
    }

    /// The next frame (its `0x00` included) in `buf`, `Ok(None)` at the end
    /// of the input.
    pub(crate) fn next_frame<'b>(
        &mut self,
        buf: &'b mut [u8],
    ) -> Result<Option<&'b mut [u8]>, FrameError> {
        let mut len = 0usize;
        let mut too_long = false;
        loop {
            let Some(b) = self.byte()? else {
                return if len == 0 && !too_long {
                    Ok(None)
                } else {
                    Err(FrameError::Truncated)
                };
            };
            match buf.get_mut(len) {
                Some(slot) if !too_long => {
                    *slot = b;
                    len += 1;
                }
                _ => too_long = true,
            }
            if b == 0 {
                if too_long {
                    return Err(FrameError::TooLong);
                }
                return Ok(buf.get_mut(..len));
            }
        }
    }
}
