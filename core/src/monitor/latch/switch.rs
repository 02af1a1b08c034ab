//! The switch against the encoder, the latch tracker's checks of each
//! sample (`docs/monitor.md` §4): chatter, a switch that closes far from
//! the latch (`switch_early`, then distrusted), the encoder alone at the
//! latch (a latch confirmed without the switch), and a switch that stays
//! open at the latch (`switch_open_at_latch`).

use super::{LatchConfig, LatchInput, LatchOutput, LatchTracker};
use crate::monitor::faults::{Fault, FaultFlags};

impl LatchTracker {
    /// Records the switch reading and flags chatter: a closed-open-closed
    /// or open-closed-open pattern, or any reversal within the debounce
    /// time of the previous change of state (a clean ideal switch closes
    /// once, at the latch, and stays closed). With a physical latch a
    /// reversal is judged when the switch closes again, and is a rebound,
    /// not chatter, when the encoder has seen the joint leave its stop
    /// ([`Bounce::seen`](crate::monitor::bounce::Bounce::seen)). Returns the closed samples among the last three.
    pub(super) fn record_switch(
        &mut self,
        x: &LatchInput,
        cfg: &LatchConfig,
        physical: bool,
        faults: &mut FaultFlags,
    ) -> u8 {
        self.history = (self.history << 1) | u8::from(x.switch);
        self.samples = self.samples.saturating_add(1);
        let last3 = self.history & 0b111;
        let votes = last3.count_ones() as u8;
        let judged = !physical || (x.switch && !self.bounce.seen());
        if judged && self.samples >= 3 && (last3 == 0b101 || last3 == 0b010) {
            faults.insert(Fault::SwitchChatter);
        }
        if self.samples >= 2 && (last3 & 0b01 != 0) != (last3 & 0b10 != 0) {
            if judged && self.flip.within(x.t_s, cfg.debounce_s) {
                faults.insert(Fault::SwitchChatter);
            }
            self.flip.restart(x.t_s);
        }
        votes
    }

    /// The switch's verdict: a latch when it is closed (debounced) and a
    /// valid encoder reading agrees, or, with no valid reading or a stuck
    /// encoder, once it has stayed closed for the whole debounce time — the filtered angle
    /// alone is not evidence (two corrupted samples, a spurious closure and
    /// a missing reading, must not make a latch). A physical latch also
    /// needs `held`: the switch closed without a break for its bounce
    /// window, the reading on the stop. A distrusted switch declares
    /// nothing; one closed far from the latch is flagged, and distrusted
    /// once that has lasted the debounce time.
    pub(super) fn check_switch(
        &mut self,
        x: &LatchInput,
        cfg: &LatchConfig,
        votes: u8,
        held: bool,
        faults: &mut FaultFlags,
    ) -> Option<LatchOutput> {
        let closed_long = self.closed.at_least(x.t_s, cfg.debounce_s);
        if x.encoder_stuck {
            // The disagreement was the encoder's.
            self.switch_suspect = false;
            self.early.stop();
        }
        let closed = x.switch && votes >= cfg.closed_votes;
        // A stuck encoder's reading is no evidence either way: the switch
        // alone, debounced, as with no reading (docs/robustness.md §1).
        let agrees = match x.measured_deg {
            Some(m) if !x.encoder_stuck => libm::fabsf(m) <= cfg.window_deg,
            _ => closed_long,
        };
        if closed && agrees && held && !self.switch_suspect {
            return Some(self.declare(x.switch, *faults, cfg));
        }
        // Early only by a reading that counts: without one (missing, or
        // the encoder stuck) the switch is waited for, not flagged.
        self.switch_early = closed && !agrees && x.measured_deg.is_some() && !x.encoder_stuck;
        if self.switch_early {
            faults.insert(Fault::SwitchEarly);
            if x.measured_deg.is_some() {
                self.early.start(x.t_s);
                if self.early.at_least(x.t_s, cfg.debounce_s) {
                    self.switch_suspect = true;
                }
            }
        } else {
            self.early.stop();
        }
        if self.switch_suspect {
            faults.insert(Fault::SwitchEarly);
        }
        None
    }

    /// Encoder alone: at the latch angle (`at_latch`) for the confirmation
    /// time while the switch stays open or is distrusted: the latch is
    /// declared (flagged `switch_open_at_latch` when the switch is open).
    pub(super) fn confirm_by_encoder(
        &mut self,
        x: &LatchInput,
        cfg: &LatchConfig,
        at_latch: bool,
        faults: &mut FaultFlags,
    ) -> Option<LatchOutput> {
        let alone = (!x.switch || self.switch_suspect) && at_latch;
        self.confirm.update(alone, x.t_s);
        if self.confirm.at_least(x.t_s, cfg.encoder_confirm_s) {
            if !x.switch {
                faults.insert(Fault::SwitchOpenAtLatch);
            }
            return Some(self.declare(x.switch, *faults, cfg));
        }
        None
    }

    /// Encoder at the latch (`at_latch`) while the switch stays open for
    /// the switch timeout: flagged `switch_open_at_latch`, and the joint
    /// held at the latch by the dynamics model.
    pub(super) fn check_open_at_latch(
        &mut self,
        x: &LatchInput,
        cfg: &LatchConfig,
        at_latch: bool,
        faults: &mut FaultFlags,
    ) {
        self.at_latch.update(!x.switch && at_latch, x.t_s);
        self.open_at_latch = self.at_latch.at_least(x.t_s, cfg.switch_timeout_s);
        if self.open_at_latch {
            faults.insert(Fault::SwitchOpenAtLatch);
        }
    }
}
