//! Sensor drivers for the on-board monitor, generic over the
//! [`embedded_hal`] 1.0 traits (feature `hal`).
//!
//! The drivers own their bus handle and know nothing of the MCU: the
//! firmware hands them its HAL's `SpiDevice` and `InputPin`, and the host
//! tests hand them `embedded-hal-mock` buses. They do not allocate, panic or
//! block beyond the bus calls themselves, and every failure is a value.
//!
//! - [`As5047p`]: the absolute magnetic encoder on each joint (AMS AS5047P
//!   or compatible, 14-bit angle over SPI, parity-checked both ways).
//! - [`LatchSwitch`]: the latch switch of each joint, on a digital input of
//!   either polarity.
//!
//! What the drivers read becomes a [`crate::monitor::Sample`]: the encoder angle
//! after the joint's mounting offset, and the switch state. A reading that
//! fails is a missing measurement for the monitor (NaN angle), not a reason
//! to stop.

mod as5047p;
mod switch;

pub use as5047p::{As5047p, EncoderError, ErrorFlags};
pub use switch::{ActiveLevel, LatchSwitch};
