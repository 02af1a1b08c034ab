//! The events of a physical latch in a run, as statistics that do not
//! depend on their phase: how many impacts, how many escapes back over the
//! plunger's crest, how high the rebounds that stayed in, when the joint
//! first touched and when it held for good (`docs/diagnosis.md`, "Runs of a
//! physical latch").
//!
//! The sequence of rebounds and escapes at a Hertzian stop is chaotic: the
//! same latch, run twice with a difference in the last digit, escapes at
//! other instants. What a drawing predicts, and what a rig can show, is its
//! statistics. The classifier reads the angle and the latch switch the way
//! the on-board monitor's bounce classifier (`core/src/monitor/bounce.rs`)
//! reads them: a closing of the switch is an impact, a travel beyond the
//! crest after the first impact is an escape, a switch closed from some
//! instant to the end of the run is a hold.

use crate::model::latch::LatchSpec;

/// A joint's latch events in one run (measured or simulated).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LatchEvents {
    /// First closing of the switch [s], `None` if it never closed.
    pub first_contact_s: Option<f64>,
    /// Closings of the switch: impacts on the stop (a rebound within the
    /// switch's travel is not seen) [1].
    pub impacts: usize,
    /// Excursions after the first impact that went back over the crest [1].
    pub escapes: usize,
    /// Peak travel of each excursion after the first impact that stayed
    /// inside the crest [deg from the stop], in time order.
    pub rebounds_deg: Vec<f64>,
    /// The last closing of the switch [s] when it stays closed to the end
    /// of the run, `None` when the joint does not hold at the end.
    pub hold_s: Option<f64>,
    /// Travel from the stop at the end of the run [deg].
    pub end_travel_deg: f64,
}

impl LatchEvents {
    /// The largest rebound that stayed in [deg], 0 without one.
    pub fn largest_rebound_deg(&self) -> f64 {
        self.rebounds_deg.iter().copied().fold(0.0, f64::max)
    }
}

/// The travel from the stop [deg] of an angle `phi_deg` of a joint stowed at
/// `stowed_deg`: the stop is at 0, the stowed side positive
/// (`deploywatch_core::physics::latch_contact`).
pub fn travel_deg(stowed_deg: f64, phi_deg: f64) -> f64 {
    if stowed_deg >= 0.0 {
        phi_deg
    } else {
        -phi_deg
    }
}

/// How far from the stop the latch acts [deg of travel]: the crest plus the
/// plunger's entry ramp, or the magnet's reach, whichever is larger. Outside
/// it the joint moves free of its latch.
pub fn zone_deg(latch: &LatchSpec) -> f64 {
    let p = &latch.plunger;
    let entry = (p.stroke_mm / (p.radius_mm * p.entry_ramp_deg.to_radians().tan())).to_degrees();
    let magnet = latch
        .magnet
        .as_ref()
        .map_or(0.0, |m| (m.reach_mm / m.radius_mm).to_degrees());
    (p.crest_deg + entry).max(magnet)
}

/// The events in a series: times `t_s`, travel from the stop `travel` [deg]
/// and the switch `switch`, with the crest `crest_deg` [deg of travel]
/// (an excursion is an escape when its peak passes the crest by more than
/// `slack_deg`, the sensor's resolution).
pub fn events(
    t_s: &[f64],
    travel: &[f64],
    switch: &[bool],
    crest_deg: f64,
    slack_deg: f64,
) -> LatchEvents {
    let n = t_s.len().min(travel.len()).min(switch.len());
    let mut ev = LatchEvents {
        end_travel_deg: travel.get(n.wrapping_sub(1)).copied().unwrap_or(f64::NAN),
        ..LatchEvents::default()
    };
    let mut last_close = None;
    let mut peak: Option<f64> = None;
    for i in 0..n {
        let closed = switch[i];
        let was = i > 0 && switch[i - 1];
        if closed && !was {
            ev.impacts += 1;
            ev.first_contact_s.get_or_insert(t_s[i]);
            last_close = Some(t_s[i]);
            if let Some(h) = peak.take() {
                ev.close_excursion(h, crest_deg + slack_deg);
            }
        }
        if !closed && ev.first_contact_s.is_some() {
            peak = Some(peak.map_or(travel[i], |h: f64| h.max(travel[i])));
        }
    }
    if let Some(h) = peak {
        ev.close_excursion(h, crest_deg + slack_deg);
    }
    if n > 0 && switch[n - 1] {
        ev.hold_s = last_close;
    }
    ev
}

impl LatchEvents {
    fn close_excursion(&mut self, peak: f64, crest: f64) {
        if peak > crest {
            self.escapes += 1;
        } else {
            self.rebounds_deg.push(peak.max(0.0));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn impacts_escapes_rebounds_and_hold_are_counted() {
        // Approach, impact, rebound 0.3, impact, escape to 2.0, impact, hold.
        let travel = [5.0, 1.0, 0.0, 0.3, 0.0, 1.0, 2.0, 0.5, 0.0, 0.0, 0.0, 0.0];
        let switch: Vec<bool> = travel.iter().map(|&u| u <= 0.05).collect();
        let t: Vec<f64> = (0..travel.len()).map(|i| i as f64 * 0.1).collect();
        let ev = events(&t, &travel, &switch, 0.6, 0.02);
        assert_eq!(ev.impacts, 3);
        assert_eq!(ev.escapes, 1);
        assert_eq!(ev.rebounds_deg, vec![0.3]);
        assert_eq!(ev.first_contact_s, Some(0.2));
        assert!((ev.hold_s.unwrap_or(0.0) - 0.8).abs() < 1e-12);
        assert!((ev.largest_rebound_deg() - 0.3).abs() < 1e-12);
    }

    #[test]
    fn a_joint_that_escapes_for_good_does_not_hold() {
        let travel = [3.0, 0.0, 0.4, 1.5, 9.0, 14.0];
        let switch: Vec<bool> = travel.iter().map(|&u| u <= 0.05).collect();
        let t: Vec<f64> = (0..travel.len()).map(|i| i as f64).collect();
        let ev = events(&t, &travel, &switch, 0.6, 0.02);
        assert_eq!((ev.impacts, ev.escapes, ev.hold_s), (1, 1, None));
        assert!(ev.rebounds_deg.is_empty());
    }
}
