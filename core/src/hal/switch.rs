//! A joint's latch switch on a digital input
//! ([`embedded_hal::digital::InputPin`]).
//!
//! The switch closes when the joint latches. Whether closed reads high or low
//! depends on the wiring (a switch to ground with a pull-up reads low when
//! closed), so the active level is part of the configuration. The driver
//! reads the pin as it is: debouncing and the fusion with the encoder angle
//! are the monitor's (`crate::monitor::latch`).

use embedded_hal::digital::InputPin;

/// The pin level that means "latched".
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ActiveLevel {
    /// Latched reads high (switch to the supply, pull-down).
    High,
    /// Latched reads low (switch to ground, pull-up).
    Low,
}

/// The latch switch of one joint.
#[derive(Debug)]
pub struct LatchSwitch<P> {
    pin: P,
    active: ActiveLevel,
}

impl<P: InputPin> LatchSwitch<P> {
    /// A switch on `pin` that reads `active` when the joint is latched.
    pub const fn new(pin: P, active: ActiveLevel) -> Self {
        LatchSwitch { pin, active }
    }

    /// The configured active level.
    pub const fn active_level(&self) -> ActiveLevel {
        self.active
    }

    /// True when the switch reports the joint latched.
    pub fn is_latched(&mut self) -> Result<bool, P::Error> {
        match self.active {
            ActiveLevel::High => self.pin.is_high(),
            ActiveLevel::Low => self.pin.is_low(),
        }
    }

    /// Gives the pin back.
    pub fn release(self) -> P {
        self.pin
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use embedded_hal_mock::eh1::digital::{Mock, State, Transaction};
    use embedded_hal_mock::eh1::MockError;

    #[test]
    fn active_high_switch_reads_latched_when_high() {
        let mut pin = Mock::new(&[Transaction::get(State::Low), Transaction::get(State::High)]);
        let mut sw = LatchSwitch::new(pin.clone(), ActiveLevel::High);
        assert_eq!(sw.is_latched(), Ok(false));
        assert_eq!(sw.is_latched(), Ok(true));
        pin.done();
    }

    #[test]
    fn active_low_switch_reads_latched_when_low() {
        let mut pin = Mock::new(&[Transaction::get(State::High), Transaction::get(State::Low)]);
        let mut sw = LatchSwitch::new(pin.clone(), ActiveLevel::Low);
        assert_eq!(sw.active_level(), ActiveLevel::Low);
        assert_eq!(sw.is_latched(), Ok(false));
        assert_eq!(sw.is_latched(), Ok(true));
        pin.done();
    }

    #[test]
    fn pin_error_is_returned() {
        let err = MockError::Io(std::io::ErrorKind::NotConnected);
        let mut pin = Mock::new(&[Transaction::get(State::High).with_error(err.clone())]);
        let mut sw = LatchSwitch::new(pin.clone(), ActiveLevel::High);
        assert_eq!(sw.is_latched(), Err(err));
        let _pin = sw.release();
        pin.done();
    }
}
