//! Fault flags of the monitor: what was wrong with a sample or a sensor, per
//! joint. A bad sample raises a flag; it never panics the monitor and never
//! puts a NaN in its status.

use serde::{Deserialize, Serialize};

/// One fault condition. Its bit in [`FaultFlags`] is `1 << (self as u16)`:
/// the variants are numbered from 0 in the order declared here, and the
/// numbers are part of the telemetry (`faults<j>` of the status frame), so a
/// new fault goes at the end.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(u16)]
#[non_exhaustive]
pub enum Fault {
    /// The encoder reading is NaN or infinite (a missing measurement).
    EncoderMissing,
    /// The encoder reading is finite but outside ±720°.
    EncoderRange,
    /// The reading failed the innovation gate (a spike) and was not used.
    EncoderOutlier,
    /// The time stamp is NaN or infinite; the sample was not used.
    TimeInvalid,
    /// The time stamp did not increase; the sample was not used (after
    /// three consecutive such samples the monitor re-synchronises to them).
    TimeBackwards,
    /// The time stamp jumped by more than the gap limit: the observers were
    /// restarted.
    TimeGap,
    /// The latch switch is closed while the encoder is far from the latch
    /// angle: not a latch.
    SwitchEarly,
    /// The encoder has sat at the latch angle while the switch stayed open:
    /// not a latch.
    SwitchOpenAtLatch,
    /// The switch reading toggled within the debounce window.
    SwitchChatter,
    /// After a confirmed latch the switch opened or the encoder left the
    /// latch window (the latch is kept).
    LatchDisagree,
    /// An estimate went non-finite or lost track and was re-initialised.
    EstimatorReset,
    /// The encoder has repeated the exact same reading for longer than its
    /// noise allows (a frozen or stuck sensor): its readings are not used
    /// until they change.
    EncoderStuck,
    /// The sample interval differs from the running mean of the intervals
    /// by more than 20 % (time-stamp jitter); the sample is used.
    TimeJitter,
}

impl Fault {
    /// Every fault, in bit order.
    pub const ALL: [Fault; 13] = [
        Fault::EncoderMissing,
        Fault::EncoderRange,
        Fault::EncoderOutlier,
        Fault::TimeInvalid,
        Fault::TimeBackwards,
        Fault::TimeGap,
        Fault::SwitchEarly,
        Fault::SwitchOpenAtLatch,
        Fault::SwitchChatter,
        Fault::LatchDisagree,
        Fault::EstimatorReset,
        Fault::EncoderStuck,
        Fault::TimeJitter,
    ];

    /// The name used in telemetry CSV and reports.
    pub const fn as_str(self) -> &'static str {
        match self {
            Fault::EncoderMissing => "encoder_missing",
            Fault::EncoderRange => "encoder_range",
            Fault::EncoderOutlier => "encoder_outlier",
            Fault::TimeInvalid => "time_invalid",
            Fault::TimeBackwards => "time_backwards",
            Fault::TimeGap => "time_gap",
            Fault::SwitchEarly => "switch_early",
            Fault::SwitchOpenAtLatch => "switch_open_at_latch",
            Fault::SwitchChatter => "switch_chatter",
            Fault::LatchDisagree => "latch_disagree",
            Fault::EstimatorReset => "estimator_reset",
            Fault::EncoderStuck => "encoder_stuck",
            Fault::TimeJitter => "time_jitter",
        }
    }

    /// The fault of a name written by [`Fault::as_str`].
    pub fn from_name(name: &str) -> Option<Self> {
        Fault::ALL.iter().copied().find(|f| f.as_str() == name)
    }

    /// The flag bit.
    pub const fn bit(self) -> u16 {
        1 << (self as u16)
    }
}

impl core::fmt::Display for Fault {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A set of [`Fault`]s. Displays as the names joined by `|` (empty when
/// clear), the form of the status CSV's `faults<j>` column. On the wire
/// (postcard) it is the `u16` of [`FaultFlags::bits`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FaultFlags(u16);

impl FaultFlags {
    /// No fault.
    pub const EMPTY: Self = FaultFlags(0);

    /// The set as bits: [`Fault::bit`] of each fault in it.
    pub const fn bits(self) -> u16 {
        self.0
    }

    /// The set of `bits` ([`Fault::bit`] of each fault); `None` when a
    /// bit names no fault.
    pub const fn from_bits(bits: u16) -> Option<Self> {
        let all = (1u16 << Fault::ALL.len()) - 1;
        if bits & !all == 0 {
            Some(FaultFlags(bits))
        } else {
            None
        }
    }

    /// True when no flag is set.
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// True when `fault` is set.
    pub const fn contains(self, fault: Fault) -> bool {
        self.0 & fault.bit() != 0
    }

    /// Sets `fault`.
    pub fn insert(&mut self, fault: Fault) {
        self.0 |= fault.bit();
    }

    /// The union of two sets.
    #[must_use]
    pub const fn union(self, other: Self) -> Self {
        FaultFlags(self.0 | other.0)
    }

    /// The faults set, in bit order.
    pub fn iter(self) -> impl Iterator<Item = Fault> {
        Fault::ALL.into_iter().filter(move |f| self.contains(*f))
    }

    /// Parses names joined by `|` (the empty string is no fault).
    pub fn from_names(s: &str) -> Option<Self> {
        let mut flags = FaultFlags::EMPTY;
        for name in s.split('|').filter(|n| !n.is_empty()) {
            flags.insert(Fault::from_name(name)?);
        }
        Some(flags)
    }
}

impl From<Fault> for FaultFlags {
    fn from(f: Fault) -> Self {
        FaultFlags(f.bit())
    }
}

impl core::fmt::Display for FaultFlags {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        for (i, fault) in self.iter().enumerate() {
            if i > 0 {
                f.write_str("|")?;
            }
            f.write_str(fault.as_str())?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        let mut f = FaultFlags::EMPTY;
        f.insert(Fault::TimeGap);
        f.insert(Fault::EncoderMissing);
        let s = std::format!("{f}");
        assert_eq!(s, "encoder_missing|time_gap");
        assert_eq!(FaultFlags::from_names(&s), Some(f));
        assert_eq!(FaultFlags::from_names(""), Some(FaultFlags::EMPTY));
        assert_eq!(FaultFlags::from_names("nope"), None);
        assert_eq!(FaultFlags::from_bits(f.bits()), Some(f));
        assert_eq!(FaultFlags::from_bits(1 << Fault::ALL.len()), None);
        for (i, fault) in Fault::ALL.iter().enumerate() {
            assert_eq!(fault.bit(), 1 << i);
        }
        // The telemetry's numbering: the first and the last fault.
        assert_eq!(Fault::EncoderMissing.bit(), 1);
        assert_eq!(Fault::TimeJitter.bit(), 1 << 12);
    }
}
