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
    /// First closing of the switch \[s\], `None` if it never closed.
    pub first_contact_s: Option<f64>,
    /// Closings of the switch: impacts on the stop (a rebound within the
    /// switch's travel is not seen) \[1\].
    pub impacts: usize,
    /// Excursions after the first impact that went back over the crest \[1\].
    pub escapes: usize,
    /// Peak travel of each excursion after the first impact that stayed
    /// inside the crest [deg from the stop], in time order.
    pub rebounds_deg: Vec<f64>,
    /// The last closing of the switch \[s\] when it stays closed to the end
    /// of the run, `None` when the joint does not hold at the end.
    pub hold_s: Option<f64>,
    /// Travel from the stop at the end of the run \[deg\].
    pub end_travel_deg: f64,
    /// The rebounds that stayed in, each a free flight off the stop with
    /// [`MIN_FLIGHT_SAMPLES`] samples or more: the parabola fitted to it.
    pub flights: Vec<Flight>,
}

/// Fewest samples of a rebound (switch open) for a parabola: one more than
/// its three coefficients, so that the noise shows in the scatter of the
/// rebounds' decelerations (at 100 Hz, 40 ms: a rebound of about 0.03° at
/// the bundled latches' 120 deg/s²).
pub const MIN_FLIGHT_SAMPLES: usize = 4;

/// Shortest span of a rebound's samples for a parabola \[s\]: over a shorter
/// span the sensor's noise (0.02°) swamps the curvature (at 100 Hz, the
/// span of [`MIN_FLIGHT_SAMPLES`]; at 500 Hz, 16 samples).
pub const MIN_FLIGHT_SPAN_S: f64 = 0.0295;

/// One rebound off the stop that stayed inside the crest, as a parabola:
/// between two closings of the switch the joint flies against the torque
/// that holds it (plunger on its hold ramp, magnet, spring, friction), which
/// over the rebound's fraction of a degree is nearly constant, so the
/// travel is `u(t) = u0 + v (t − t̄) − a (t − t̄)² / 2` (least squares over
/// the samples with the switch open; the sensor's noise averages out).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Flight {
    /// Time of the switch opening \[s\].
    pub start_s: f64,
    /// Peak of the fitted parabola [deg from the stop].
    pub peak_deg: f64,
    /// The hold's deceleration `a` [deg/s²]: what the latch, spring and
    /// friction pull back with, per unit of the joint's inertia.
    pub accel_deg_s2: f64,
    /// Samples with the switch open.
    pub samples: usize,
}

/// The parabola through `(t, u)` by least squares: `(u(t̄), u̇(t̄), a)`
/// with `ü = −a`, `t̄` the mean time; `None` when degenerate.
pub fn parabola(t: &[f64], u: &[f64]) -> Option<(f64, f64, f64)> {
    let n = t.len().min(u.len());
    if n < 3 {
        return None;
    }
    let tm = t[..n].iter().sum::<f64>() / n as f64;
    let mut a = nalgebra::Matrix3::<f64>::zeros();
    let mut b = nalgebra::Vector3::<f64>::zeros();
    for (&ti, &ui) in t[..n].iter().zip(&u[..n]) {
        let x = ti - tm;
        let row = nalgebra::Vector3::new(1.0, x, x * x);
        a += row * row.transpose();
        b += row * ui;
    }
    let c = a.lu().solve(&b)?;
    Some((c[0], c[1], -2.0 * c[2]))
}

/// The flight over the open samples `idx` (indices into `t_s`, `travel`).
fn flight(t_s: &[f64], travel: &[f64], idx: std::ops::Range<usize>) -> Option<Flight> {
    if idx.len() < MIN_FLIGHT_SAMPLES || t_s[idx.end - 1] - t_s[idx.start] < MIN_FLIGHT_SPAN_S {
        return None;
    }
    let (t, u) = (&t_s[idx.clone()], &travel[idx.clone()]);
    let (u0, v, a) = parabola(t, u)?;
    let peak = if a > 0.0 { u0 + v * v / (2.0 * a) } else { u0 };
    Some(Flight {
        start_s: t_s[idx.start],
        peak_deg: peak,
        accel_deg_s2: a,
        samples: idx.len(),
    })
}

impl LatchEvents {
    /// The largest rebound that stayed in \[deg\], 0 without one.
    pub fn largest_rebound_deg(&self) -> f64 {
        self.rebounds_deg.iter().copied().fold(0.0, f64::max)
    }
}

/// The travel from the stop \[deg\] of an angle `phi_deg` of a joint stowed at
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

/// The events in a series: times `t_s`, travel from the stop `travel` \[deg\]
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
    let mut open_from = 0;
    for i in 0..n {
        let closed = switch[i];
        let was = i > 0 && switch[i - 1];
        if !closed && was {
            open_from = i;
        }
        if closed && !was {
            ev.impacts += 1;
            ev.first_contact_s.get_or_insert(t_s[i]);
            last_close = Some(t_s[i]);
            if let Some(h) = peak.take() {
                if ev.close_excursion(h, crest_deg + slack_deg) {
                    ev.flights.extend(flight(t_s, travel, open_from..i));
                }
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
    /// Counts an excursion; `true` when it stayed in.
    fn close_excursion(&mut self, peak: f64, crest: f64) -> bool {
        if peak > crest {
            self.escapes += 1;
            false
        } else {
            self.rebounds_deg.push(peak.max(0.0));
            true
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
    fn a_rebound_is_fitted_by_its_parabola() {
        // A rebound off the stop at 3 deg/s against 50 deg/s²: peak 0.09°.
        let (v, a, dt) = (3.0, 50.0, 0.01);
        let mut t = vec![0.0, 0.01];
        let mut travel = vec![1.0, 0.0];
        for k in 1..12 {
            let s = k as f64 * dt;
            t.push(0.01 + s);
            travel.push((v * s - a * s * s / 2.0).max(0.0));
        }
        t.push(0.14);
        travel.push(0.0);
        let switch: Vec<bool> = travel.iter().map(|&u| u <= 0.001).collect();
        let ev = events(&t, &travel, &switch, 0.6, 0.02);
        assert_eq!(ev.flights.len(), 1);
        let f = ev.flights[0];
        assert!((f.accel_deg_s2 - a).abs() < 1e-6, "{f:?}");
        assert!((f.peak_deg - 0.09).abs() < 1e-6, "{f:?}");
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
