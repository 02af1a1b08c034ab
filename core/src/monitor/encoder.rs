//! The AS5047P's 14-bit angle and its SPI frame check: pure functions, with
//! no bus and no feature gate, shared by the driver (`crate::hal`, feature
//! `hal`), the monitor's sensor model ([`crate::monitor::SensorConfig`]) and
//! the host's sensor simulation and fault injection.
//!
//! An answer frame (AS5047P datasheet v1-06, "SPI Interface"):
//!
//! ```text
//! bit 15: PARD   even parity over bits 14:0
//! bit 14: EF     error flag
//! 13:0:   DATA   the angle, COUNTS_PER_TURN counts per turn
//! ```

/// Counts per mechanical turn of the 14-bit angle.
pub const COUNTS_PER_TURN: u16 = 1 << 14;

/// One count of the 14-bit angle \[deg\]: 360/16384 = 0.02197265625 (exact
/// in binary), the quantisation step of the reference encoder
/// (`physics.md` section 7).
pub const STEP_DEG: f64 = 360.0 / COUNTS_PER_TURN as f64;

/// Bit 15 of a frame: even parity over bits 14:0.
pub const PARITY_BIT: u16 = 1 << 15;

/// Bit 14 of an answer: the error flag (EF).
pub const ERROR_FLAG_BIT: u16 = 1 << 14;

/// Bits 13:0: the data (an angle count or a register address).
pub const DATA_MASK: u16 = 0x3FFF;

/// Why an answer frame is refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum FrameError {
    /// The frame fails its even parity check: corrupted on the wire.
    Parity,
    /// The encoder set its error flag.
    ErrorFlag,
}

impl core::fmt::Display for FrameError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            FrameError::Parity => "encoder answer fails its parity check",
            FrameError::ErrorFlag => "encoder error flag set (a command reached it corrupted)",
        })
    }
}

impl core::error::Error for FrameError {}

/// Sets bit 15 so that the 16-bit frame has even parity.
pub const fn with_even_parity(frame: u16) -> u16 {
    let low = frame & !PARITY_BIT;
    if low.count_ones() & 1 == 1 {
        low | PARITY_BIT
    } else {
        low
    }
}

/// Checks an answer frame (parity first: a corrupt frame's other bits mean
/// nothing, then the error flag) and returns its 14 data bits.
pub const fn check_answer(frame: u16) -> Result<u16, FrameError> {
    if frame.count_ones() & 1 != 0 {
        return Err(FrameError::Parity);
    }
    if frame & ERROR_FLAG_BIT != 0 {
        return Err(FrameError::ErrorFlag);
    }
    Ok(frame & DATA_MASK)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_flipped_bit_fails_the_parity_two_pass_it() {
        let word = with_even_parity(0x1234);
        assert_eq!(check_answer(word), Ok(0x1234));
        assert_eq!(check_answer(word ^ 0x0001), Err(FrameError::Parity));
        assert_eq!(check_answer(word ^ 0x0003), Ok(0x1237));
        assert_eq!(
            check_answer(word ^ 0x4001 ^ 0x0001 ^ 0x8000),
            Err(FrameError::ErrorFlag)
        );
    }
}
