//! What a physical-latch run gives (`crate::simulate::latch_deployment`):
//! its events, its energy ledger, and what each latch did.

use crate::simulate::trajectory::{Trajectory, MAX_LEDGER_DRIFT};
use deploywatch_core::physics::latch_contact::{LatchMark, PhysicalLatch, PlungerSegment};

/// What happened at an event.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LatchEventKind {
    /// The joint crossed a mark of its travel (towards the stop when
    /// `rate_rad_s` of the event is negative).
    Mark(LatchMark),
    /// The stop's force reached zero while the joint is in it.
    Release,
    /// The stop's force rose from zero again inside it.
    Press,
    /// An ideal latch locked the joint (section 5).
    IdealLatch,
    /// A tape spring changed branch.
    Branch,
    /// The joint came to rest inside the band of its set-valued laws and
    /// sticks (`physics.md` §4a).
    Stick,
    /// The joint's rate reached rest outside its band: it moves on.
    Turn,
    /// A stuck joint's holding torque left its band: it slips.
    Slip,
    /// A pawl riding its cam reached the notch's edge and dropped into its
    /// notch (`physics.md` §10.5): the latch is locked.
    PawlDrop,
    /// An engaged pawl's contact with its notch's wall began, let go or
    /// ended.
    Notch,
    /// The torque a pawl carried reached its breaking torque: it broke, the
    /// joint is free of it (a failed latch).
    PawlBreak,
}

/// One event of a physical-latch run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LatchEvent {
    /// Instant \[s\].
    pub t_s: f64,
    /// 1-based joint.
    pub joint: usize,
    /// What happened.
    pub kind: LatchEventKind,
    /// The travel from the stop `u = s φ` there \[rad\].
    pub travel_rad: f64,
    /// The travel's rate `u̇` there [rad/s] (negative: towards the stop).
    pub rate_rad_s: f64,
    /// Evaluations of the equations of motion the run had made by then
    /// (rejected and retaken steps included): where a run's work goes
    /// (`examples/physical_profile.rs`).
    pub evaluations: usize,
}

/// The energy ledger of a run \[J\]: `kinetic + spring + latch + friction +
/// contact + impact` is the energy stored at the start, to the drift.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energy {
    /// Potential energy stored at the start (springs, harness, latches).
    pub stored_j: f64,
    /// Kinetic energy at the end.
    pub kinetic_j: f64,
    /// Potential of the chain at the end: springs on their unfolding
    /// branch, harness, rig tilt.
    pub spring_j: f64,
    /// Potential of the latches at the end: plunger, magnet, the stops'
    /// elastic energy.
    pub latch_j: f64,
    /// Dissipated by the joint torques that are not conservative (friction,
    /// the tape springs' hysteresis, joint effects) and by air drag.
    pub friction_j: f64,
    /// Dissipated by the stops' damping.
    pub contact_j: f64,
    /// Lost in the plastic impacts of ideal latches and by pawls (their
    /// clicks and breaks, `pawl_j`).
    pub impact_j: f64,
    /// Of `impact_j`, what the pawls took: the cam's energy at each drop
    /// into the notch (the click), the notch contact's elastic energy at a
    /// break.
    pub pawl_j: f64,
    /// Of `friction_j`, the kinetic energy the stick rule's impulses took
    /// when joints stuck (`physics.md` §4a: a located zero crossing leaves
    /// next to none).
    pub stick_j: f64,
    /// Joints that stuck over the run.
    pub sticks: usize,
    /// Largest `|total − stored|` over the step ends of the run.
    pub worst_drift_j: f64,
}

/// The floor of [`step_budget`], relative to the stored energy.
pub const STEP_DRIFT: f64 = 1e-10;

/// The share of [`MAX_LEDGER_DRIFT`] that [`step_budget`] spreads over a
/// run's duration.
pub const DRIFT_RATE_SHARE: f64 = 0.25;

/// Largest move of the energy ledger's drift over one step of `h` \[s\] in a
/// run of `duration_s` \[s\] storing `stored_j` \[J\] before the step is taken
/// again shorter: `STEP_DRIFT` plus `DRIFT_RATE_SHARE` of the run's
/// tolerance `max_drift` ([`crate::simulate::trajectory::SimOptions::max_drift`])
/// in proportion to `h / duration_s`, both scaled by `max_drift /`
/// [`MAX_LEDGER_DRIFT`] (of `stored_j`).
/// The ledger is an error estimate of its own beside DOPRI5's: on a stiff
/// stop contact the default tolerances alone let a run drift past
/// [`MAX_LEDGER_DRIFT`] in a few steps (the four-panel wing of `data/mechanisms/four_panel_mixed.toml`: 1.07e-6
/// at its pawl's stop at 1.469 s), and over a long run of many joints the
/// smooth steps' errors add up to it (an eight-panel wing: 1.0e-6 at 8 s).
pub fn step_budget(stored_j: f64, h: f64, duration_s: f64, max_drift: f64) -> f64 {
    let share = DRIFT_RATE_SHARE * max_drift * h / duration_s.max(h);
    stored_j.abs() * (STEP_DRIFT * max_drift / MAX_LEDGER_DRIFT + share)
}

/// Steps at most this long \[s\] are not taken again for the ledger (an
/// event located a rounding error after the step's start).
pub const LEDGER_MIN_STEP_S: f64 = 1e-9;

/// Safety factor of [`ledger_step_factor`].
const LEDGER_SAFETY: f64 = 0.8;

/// The exponent of the ledger's drift over a step against its length: the
/// drift of a step on a stiff contact grows as `h⁵` (DOPRI5's local error)
/// while the budget there is its floor ([`STEP_DRIFT`]).
const LEDGER_EXPONENT: f64 = 0.2;

/// Least and largest factor [`ledger_step_factor`] gives.
const LEDGER_FACTOR_RANGE: (f64, f64) = (0.1, 5.0);

/// The factor on a step's length \[1\] that brings the ledger's drift over
/// it to [`LEDGER_SAFETY`] of its budget, from `ratio` = the drift's move
/// over the step / its budget (`latch_deployment`'s `Runner::book`): `0.8 ratio^(−1/5)`,
/// within [0.1, 5]. Below 1 (shrink) when the step was over budget.
pub fn ledger_step_factor(ratio: f64) -> f64 {
    let (lo, hi) = LEDGER_FACTOR_RANGE;
    if ratio <= 0.0 || !ratio.is_finite() {
        return if ratio > 0.0 { lo } else { hi };
    }
    (LEDGER_SAFETY * ratio.powf(-LEDGER_EXPONENT)).clamp(lo, hi)
}

/// A physical-latch run: the trajectory, the events and the ledger.
#[derive(Clone, Debug, PartialEq)]
pub struct LatchRun {
    /// The sampled trajectory (`latched` is the switch).
    pub traj: Trajectory,
    /// Every event, in time order.
    pub events: Vec<LatchEvent>,
    /// The energy ledger at the end.
    pub energy: Energy,
    /// Each joint's angle where the run ended, at `traj.end_s` \[deg\],
    /// whether a sample falls there or not (0 for a joint an ideal latch
    /// holds).
    pub end_phi_deg: Vec<f64>,
    /// Where the run ended, before its last sample, because every latch
    /// was held for good \[s\] ([`Keep::Settled`](crate::simulate::latch_deployment::Keep::Settled); `None`: it ran to its end).
    pub settled_s: Option<f64>,
}

/// Where a joint with a physical latch ended: the verdict names the latch
/// that holds it (a ball plunger's detent or a pawl, `physics.md` §10.3
/// and §10.5), in the words of that latch (its `Display`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LatchEnd {
    /// A joint held by a ball plunger (and magnet).
    Plunger(PlungerEnd),
    /// A joint locked by a pawl.
    Pawl(PawlEnd),
}

/// Where a joint with a ball plunger ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlungerEnd {
    /// Short of the plunger: the protrusion never touched the ball, or left it.
    ShortOfPlunger,
    /// On the entry ramp, short of the crest: the switch is open unless its
    /// travel reaches that far.
    OnRamp,
    /// Past the crest, held by the plunger (and magnet) towards the stop.
    Held,
}

/// Where a joint with a pawl ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PawlEnd {
    /// Short of the pawl's cam: the pawl never rode it, or the joint went
    /// back off it, and never dropped into its notch.
    ShortOfCam,
    /// Riding the cam, short of the notch: the pawl did not drop in.
    OnCam,
    /// The pawl in its notch: the joint is locked between stop and pawl.
    InNotch,
    /// The pawl broke (its breaking torque reached): the joint is free of it.
    Broken,
}

impl LatchEnd {
    /// Whether the latch holds the joint at the end: a plunger past its
    /// crest, a pawl in its notch.
    pub fn holds(self) -> bool {
        matches!(
            self,
            LatchEnd::Plunger(PlungerEnd::Held) | LatchEnd::Pawl(PawlEnd::InNotch)
        )
    }
}

impl core::fmt::Display for LatchEnd {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            LatchEnd::Plunger(PlungerEnd::ShortOfPlunger) => "short of its ball plunger",
            LatchEnd::Plunger(PlungerEnd::OnRamp) => "on its ball plunger's entry ramp",
            LatchEnd::Plunger(PlungerEnd::Held) => "held past its ball plunger's crest",
            LatchEnd::Pawl(PawlEnd::ShortOfCam) => "short of its pawl's cam",
            LatchEnd::Pawl(PawlEnd::OnCam) => "on its pawl's cam, short of the notch",
            LatchEnd::Pawl(PawlEnd::InNotch) => "locked by its pawl in the notch",
            LatchEnd::Pawl(PawlEnd::Broken) => "free, its pawl broken",
        })
    }
}

/// What a physical latch did over a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LatchOutcome {
    /// Arrivals on the stop (contact onsets).
    pub impacts: usize,
    /// Passes back out over the crest after having been in.
    pub escapes: usize,
    /// Passes in over the crest.
    pub engagements: usize,
    /// Closings of the switch.
    pub switch_closings: usize,
    /// Where the joint ended, in the words of its latch.
    pub end: LatchEnd,
    /// Drops of a pawl into its notch (0 or 1; 0 for a ball plunger).
    pub pawl_drops: usize,
    /// When its pawl dropped into the notch \[s\], `None` if it did not:
    /// the joint is locked from then on, whatever its switch reads.
    pub pawl_dropped_s: Option<f64>,
    /// When a pawl broke \[s\], `None` if it did not.
    pub pawl_broke_s: Option<f64>,
    /// The travel from the stop at the end \[deg\].
    pub end_travel_deg: f64,
}

impl LatchRun {
    /// What the physical latch `latch` of joint `joint` (1-based) did, from
    /// its events and where the run ended ([`LatchRun::end_phi_deg`]: a run
    /// ended held for good is read where it ended). `None` for a joint the
    /// run does not have.
    pub fn outcome(&self, joint: usize, latch: &PhysicalLatch<f64>) -> Option<LatchOutcome> {
        let phi_deg = *self.end_phi_deg.get(joint.checked_sub(1)?)?;
        let mine = || self.events.iter().filter(|e| e.joint == joint);
        let count = |m: LatchMark, inward: bool| {
            mine()
                .filter(|e| e.kind == LatchEventKind::Mark(m) && (e.rate_rad_s < 0.0) == inward)
                .count()
        };
        let u = latch.travel(phi_deg.to_radians());
        let pawl_drops = mine()
            .filter(|e| e.kind == LatchEventKind::PawlDrop)
            .count();
        let pawl_broke_s = mine()
            .find(|e| e.kind == LatchEventKind::PawlBreak)
            .map(|e| e.t_s);
        let pawl_dropped_s = mine()
            .find(|e| e.kind == LatchEventKind::PawlDrop)
            .map(|e| e.t_s);
        let segment = latch.plunger_segment(u);
        let end = match latch.pawl() {
            Some(_) => LatchEnd::Pawl(match pawl_broke_s {
                Some(_) => PawlEnd::Broken,
                None if pawl_drops > 0 || u <= latch.plunger.crest_rad => PawlEnd::InNotch,
                None if segment == PlungerSegment::Entry => PawlEnd::OnCam,
                None => PawlEnd::ShortOfCam,
            }),
            None => LatchEnd::Plunger(match segment {
                _ if u <= latch.plunger.crest_rad => PlungerEnd::Held,
                PlungerSegment::Entry => PlungerEnd::OnRamp,
                _ => PlungerEnd::ShortOfPlunger,
            }),
        };
        Some(LatchOutcome {
            impacts: count(LatchMark::Stop, true),
            escapes: count(LatchMark::Crest, false),
            engagements: count(LatchMark::Crest, true),
            switch_closings: count(LatchMark::Switch, true),
            end,
            pawl_drops,
            pawl_dropped_s,
            pawl_broke_s,
            end_travel_deg: u.to_degrees(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ledger_step_factor_brings_the_drift_to_its_safety_share() {
        // A step whose drift is the budget times 0.8⁵ is kept as long.
        let at_safety = LEDGER_SAFETY.powf(1.0 / LEDGER_EXPONENT);
        assert!((ledger_step_factor(at_safety) - 1.0).abs() < 1e-12);
        // Over budget: shorter; under: longer; the further, the more.
        assert!(ledger_step_factor(2.0) < 1.0);
        assert!(ledger_step_factor(32.0) < ledger_step_factor(2.0));
        assert!(ledger_step_factor(0.01) > 1.0);
        // Within its range, whatever the ratio.
        let (lo, hi) = LEDGER_FACTOR_RANGE;
        for r in [0.0, 1e-30, 1e30, f64::INFINITY, f64::NAN] {
            let f = ledger_step_factor(r);
            assert!((lo..=hi).contains(&f), "ratio {r}: {f}");
        }
        assert_eq!(ledger_step_factor(1e30), lo);
        assert_eq!(ledger_step_factor(0.0), hi);
    }
}
