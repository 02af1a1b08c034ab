//! Driver of the AS5047P 14-bit absolute magnetic rotary encoder (AMS), over
//! an [`embedded_hal::spi::SpiDevice`].
//!
//! # Protocol (AS5047P datasheet v1-06, "SPI Interface")
//! SPI mode 1, 16-bit frames sent MSB first (two bytes here), chip select
//! released between frames. A command frame is
//!
//! ```text
//! bit 15: PARC   even parity over bits 14:0
//! bit 14: R/W    1 = read
//! 13:0:   ADDR   register address
//! ```
//!
//! and the answer to a read comes back in the *next* frame:
//!
//! ```text
//! bit 15: PARD   even parity over bits 14:0
//! bit 14: EF     error flag: a previous command had a framing, command or
//!                parity error (details in ERRFL, which reading clears)
//! 13:0:   DATA
//! ```
//!
//! So one register read is two SPI transactions: `READ addr`, then `NOP`
//! whose answer carries the register. The driver checks the answer's parity
//! first (a corrupt frame's other bits mean nothing), then its error flag.
//!
//! The angle is ANGLECOM (0x3FFF): the dynamic-angle-error-compensated
//! angle, 16384 counts per turn (0.022° per count).

use embedded_hal::spi::SpiDevice;

pub use crate::monitor::encoder::COUNTS_PER_TURN;
use crate::monitor::encoder::{FrameError, DATA_MASK};

/// Register addresses (14 bits): the chip's whole map, of which the
/// driver reads some.
#[allow(dead_code)]
pub(crate) mod reg {
    /// No operation; reading it fetches the previous command's answer.
    pub const NOP: u16 = 0x0000;
    /// Error register: framing, invalid command, parity. Reading clears it.
    pub const ERRFL: u16 = 0x0001;
    /// Diagnostics and automatic gain control.
    pub const DIAAGC: u16 = 0x3FFC;
    /// CORDIC magnitude.
    pub const MAG: u16 = 0x3FFD;
    /// Measured angle without dynamic angle error compensation.
    pub const ANGLEUNC: u16 = 0x3FFE;
    /// Measured angle with dynamic angle error compensation.
    pub const ANGLECOM: u16 = 0x3FFF;
}

const READ_BIT: u16 = 1 << 14;

/// Why an encoder reading failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum EncoderError<E> {
    /// The SPI bus (or its chip select) failed.
    Bus(E),
    /// The answer frame fails its even parity check: corrupted on the wire.
    Parity,
    /// The encoder set its error flag (EF): a previous command reached it
    /// corrupted. [`As5047p::clear_error_flags`] reads and clears the cause.
    ErrorFlag,
}

impl<E: core::fmt::Debug> core::fmt::Display for EncoderError<E> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            EncoderError::Bus(e) => write!(f, "encoder SPI bus error: {e:?}"),
            EncoderError::Parity => f.write_str("encoder answer fails its parity check"),
            EncoderError::ErrorFlag => {
                f.write_str("encoder error flag set (a command reached it corrupted)")
            }
        }
    }
}

impl<E: core::fmt::Debug> core::error::Error for EncoderError<E> {}

/// The ERRFL register: why the encoder raised its error flag.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct ErrorFlags(u16);

impl ErrorFlags {
    /// FRERR: a frame did not have 16 clock cycles.
    pub const FRAMING: u16 = 1 << 0;
    /// INVCOMM: a command addressed a register that does not exist.
    pub const INVALID_COMMAND: u16 = 1 << 1;
    /// PARERR: a command frame failed its parity check.
    pub const PARITY: u16 = 1 << 2;

    /// The register's bits (the constants above; others as the chip
    /// gave them).
    pub const fn bits(self) -> u16 {
        self.0
    }

    /// True when `bit` (one of the constants) is set.
    pub const fn contains(self, bit: u16) -> bool {
        self.0 & bit != 0
    }

    /// True when no error is recorded.
    pub const fn is_empty(self) -> bool {
        self.0 & (Self::FRAMING | Self::INVALID_COMMAND | Self::PARITY) == 0
    }
}

use crate::monitor::encoder::with_even_parity;

/// The command frame that reads register `addr` (parity included).
pub const fn read_command(addr: u16) -> u16 {
    with_even_parity(READ_BIT | (addr & DATA_MASK))
}

/// Checks an answer frame and returns its 14 data bits.
/// ([`crate::monitor::encoder::check_answer`]).
pub fn answer_data<E>(frame: u16) -> Result<u16, EncoderError<E>> {
    crate::monitor::encoder::check_answer(frame).map_err(|e| match e {
        FrameError::Parity => EncoderError::Parity,
        FrameError::ErrorFlag => EncoderError::ErrorFlag,
    })
}

/// Counts of the 14-bit angle to degrees, in [0, 360).
pub fn counts_to_deg(counts: u16) -> f32 {
    f32::from(counts & DATA_MASK) * (360.0 / COUNTS_PER_TURN as f32)
}

/// Counts of the 14-bit angle to radians, in [0, 2π).
pub fn counts_to_rad(counts: u16) -> f32 {
    f32::from(counts & DATA_MASK) * (core::f32::consts::TAU / COUNTS_PER_TURN as f32)
}

/// An AS5047P on its own SPI device (bus + chip select).
#[derive(Debug)]
pub struct As5047p<SPI> {
    spi: SPI,
}

impl<SPI: SpiDevice> As5047p<SPI> {
    /// A driver for the encoder behind `spi` (SPI mode 1, up to 10 MHz,
    /// 8-bit words).
    pub const fn new(spi: SPI) -> Self {
        As5047p { spi }
    }

    /// Gives the SPI device back.
    pub fn release(self) -> SPI {
        self.spi
    }

    /// Sends one 16-bit frame and returns the frame clocked in meanwhile.
    fn frame(&mut self, out: u16) -> Result<u16, EncoderError<SPI::Error>> {
        let mut buf = out.to_be_bytes();
        self.spi
            .transfer_in_place(&mut buf)
            .map_err(EncoderError::Bus)?;
        Ok(u16::from_be_bytes(buf))
    }

    /// Reads register `addr` (14 bits): `READ addr`, then `NOP` to fetch the
    /// answer, which is parity- and error-flag-checked.
    pub fn read_register(&mut self, addr: u16) -> Result<u16, EncoderError<SPI::Error>> {
        // The answer to this frame belongs to the previous command.
        self.frame(read_command(addr))?;
        let answer = self.frame(read_command(reg::NOP))?;
        answer_data(answer)
    }

    /// The compensated angle (ANGLECOM) in counts, 0..16384.
    pub fn angle_counts(&mut self) -> Result<u16, EncoderError<SPI::Error>> {
        self.read_register(reg::ANGLECOM)
    }

    /// The compensated angle in degrees, in [0, 360).
    pub fn angle_deg(&mut self) -> Result<f32, EncoderError<SPI::Error>> {
        self.angle_counts().map(counts_to_deg)
    }

    /// The compensated angle in radians, in [0, 2π).
    pub fn angle_rad(&mut self) -> Result<f32, EncoderError<SPI::Error>> {
        self.angle_counts().map(counts_to_rad)
    }

    /// Reads ERRFL, which clears it and the error flag: call it after
    /// [`EncoderError::ErrorFlag`] to learn the cause. Reading ERRFL itself
    /// may report the flag that it clears, so its answer is taken whatever
    /// its EF bit (the parity is still checked).
    pub fn clear_error_flags(&mut self) -> Result<ErrorFlags, EncoderError<SPI::Error>> {
        self.frame(read_command(reg::ERRFL))?;
        let answer = self.frame(read_command(reg::NOP))?;
        match answer_data(answer) {
            Ok(bits) => Ok(ErrorFlags(bits)),
            Err(EncoderError::ErrorFlag) => Ok(ErrorFlags(answer & DATA_MASK)),
            Err(e) => Err(e),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::monitor::encoder::ERROR_FLAG_BIT;
    use embedded_hal::spi::{ErrorKind, ErrorType, Operation};
    use embedded_hal_mock::eh1::spi::{Mock, Transaction};

    /// An answer frame with data `d` and error flag `ef`, with correct parity.
    fn answer(d: u16, ef: bool) -> u16 {
        with_even_parity(d | if ef { ERROR_FLAG_BIT } else { 0 })
    }

    /// The two transactions of a register read whose answer is `frame`.
    fn read_expectations(addr: u16, frame: u16) -> [Transaction<u8>; 6] {
        let cmd = read_command(addr).to_be_bytes().to_vec();
        let nop = read_command(reg::NOP).to_be_bytes().to_vec();
        [
            Transaction::transaction_start(),
            Transaction::transfer_in_place(cmd, vec![0x00, 0x00]),
            Transaction::transaction_end(),
            Transaction::transaction_start(),
            Transaction::transfer_in_place(nop, frame.to_be_bytes().to_vec()),
            Transaction::transaction_end(),
        ]
    }

    #[test]
    fn command_frames_have_even_parity() {
        // Datasheet values: READ ANGLECOM = 0xFFFF, READ NOP = 0xC000,
        // READ ERRFL = 0x4001.
        assert_eq!(read_command(reg::ANGLECOM), 0xFFFF);
        assert_eq!(read_command(reg::NOP), 0xC000);
        assert_eq!(read_command(reg::ERRFL), 0x4001);
        assert_eq!(read_command(reg::DIAAGC).count_ones() & 1, 0);
    }

    #[test]
    fn good_read_gives_the_angle() {
        // GIVEN an encoder at 4096 counts (a quarter turn)
        let mut spi = Mock::new(&read_expectations(reg::ANGLECOM, answer(4096, false)));
        let mut enc = As5047p::new(spi.clone());
        // WHEN the angle is read THEN it is 90° (π/2)
        assert_eq!(enc.angle_counts(), Ok(4096));
        spi.done();

        let mut spi = Mock::new(&read_expectations(reg::ANGLECOM, answer(4096, false)));
        let mut enc = As5047p::new(spi.clone());
        assert_eq!(enc.angle_deg(), Ok(90.0));
        spi.done();

        let mut spi = Mock::new(&read_expectations(reg::ANGLECOM, answer(0x3FFF, false)));
        let mut enc = As5047p::new(spi.clone());
        let rad = enc.angle_rad().unwrap();
        assert_eq!(rad, 16383.0 * (core::f32::consts::TAU / 16384.0));
        assert!(rad < core::f32::consts::TAU);
        spi.done();
    }

    #[test]
    fn corrupted_answer_is_a_parity_error() {
        // GIVEN an answer with one bit flipped on the wire
        let corrupted = answer(4096, false) ^ 0x0001;
        let mut spi = Mock::new(&read_expectations(reg::ANGLECOM, corrupted));
        let mut enc = As5047p::new(spi.clone());
        // THEN the read is a parity error, not a wrong angle
        assert_eq!(enc.angle_deg(), Err(EncoderError::Parity));
        spi.done();
    }

    #[test]
    fn error_flag_is_reported_then_cleared() {
        // GIVEN an encoder whose error flag is set (a command parity error)
        let mut exp = read_expectations(reg::ANGLECOM, answer(4096, true)).to_vec();
        exp.extend(read_expectations(
            reg::ERRFL,
            answer(ErrorFlags::PARITY, true),
        ));
        let mut spi = Mock::new(&exp);
        let mut enc = As5047p::new(spi.clone());
        // WHEN the angle is read THEN the error flag is the result
        assert_eq!(enc.angle_counts(), Err(EncoderError::ErrorFlag));
        // AND ERRFL says why
        let flags = enc.clear_error_flags().unwrap();
        assert!(flags.contains(ErrorFlags::PARITY) && !flags.contains(ErrorFlags::FRAMING));
        assert!(!flags.is_empty());
        spi.done();
    }

    /// An SPI device whose bus always fails.
    struct BrokenBus;

    impl ErrorType for BrokenBus {
        type Error = ErrorKind;
    }

    impl SpiDevice for BrokenBus {
        fn transaction(&mut self, _: &mut [Operation<'_, u8>]) -> Result<(), ErrorKind> {
            Err(ErrorKind::ChipSelectFault)
        }
    }

    #[test]
    fn bus_failure_is_a_bus_error() {
        let mut enc = As5047p::new(BrokenBus);
        let e = enc.angle_deg().unwrap_err();
        assert_eq!(e, EncoderError::Bus(ErrorKind::ChipSelectFault));
        assert_eq!(
            std::format!("{e}"),
            "encoder SPI bus error: ChipSelectFault"
        );
        assert_eq!(
            enc.clear_error_flags(),
            Err(EncoderError::Bus(ErrorKind::ChipSelectFault))
        );
    }

    #[test]
    fn conversions_cover_one_turn() {
        assert_eq!(counts_to_deg(0), 0.0);
        assert_eq!(counts_to_deg(8192), 180.0);
        assert!(counts_to_deg(16383) < 360.0);
        assert_eq!(counts_to_rad(8192), core::f32::consts::PI);
        // The status bits never leak into the angle.
        assert_eq!(counts_to_deg(0xC000 | 8192), 180.0);
    }
}
