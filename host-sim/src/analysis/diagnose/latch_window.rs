//! The free motion of runs of a physical latch: each run up to the first
//! instant a joint enters the reach of its latch (`docs/diagnosis.md`,
//! "Runs of a physical latch").
//!
//! After a joint touches its plunger, magnet or stop, what follows is an
//! impact sequence that the smallest difference changes (rebounds, escapes,
//! re-latches): a model cannot be compared with it sample by sample, and the
//! latch as built differs from its drawing by the tolerances of a real
//! plunger and magnet. Before that instant the wing moves free of every
//! latch: its motion is what the springs, the friction, the harness, the
//! air and the rig make of it, the same in the model whatever the latch as
//! built. The search fits the named effects on that window, by simulation,
//! as on runs of ideal latches; the events after it are compared by their
//! statistics ([`super::latch_finding`]).

use crate::analysis::latch_events::{travel_deg, zone_deg};
use crate::data::campaign::{Campaign, CampaignRun};

/// Margin kept from the latch's reach [deg of travel]: an encoder offset of
/// up to this size, or a sample late, does not bring latch physics into the
/// window.
pub const FREE_MARGIN_DEG: f64 = 1.0;

/// Fewest samples a run keeps: the noise floor needs third differences over
/// a few dozen samples, and a fit needs more samples than parameters.
pub const MIN_FREE_SAMPLES: usize = 20;

/// Where one run's free motion ends.
#[derive(Clone, Debug, PartialEq)]
pub struct RunWindow {
    /// Samples kept (from the release).
    pub kept: usize,
    /// Samples in the run.
    pub of: usize,
    /// Time of the first sample left out \[s\] (`None`: the whole run kept).
    pub end_s: Option<f64>,
    /// The joint (1-based) whose latch ends the window.
    pub joint: Option<usize>,
}

impl RunWindow {
    /// The window in words, for the run named `run` (`None` when the run is
    /// kept whole): `"T01.csv: free motion to 2.15 s (215 of 601 samples),
    /// where joint 3 enters its latch's reach"`.
    pub fn words(&self, run: &str) -> Option<String> {
        let (t, j) = (self.end_s?, self.joint?);
        Some(format!(
            "{run}: free motion to {t:.2} s ({} of {} samples), where joint {j} enters its latch's reach",
            self.kept, self.of
        ))
    }
}

/// The first sample of run `cr` at which a joint with a physical latch is
/// within its latch's reach plus [`FREE_MARGIN_DEG`] or has its switch
/// closed, and that joint (1-based).
fn first_contact(cr: &CampaignRun) -> Option<(usize, usize)> {
    let m = &cr.mechanism;
    let run = &cr.run;
    let mut best: Option<(usize, usize)> = None;
    for j in 0..run.joints().min(m.joint_count()) {
        let Some(latch) = m.latch(j) else { continue };
        let reach = zone_deg(latch) + FREE_MARGIN_DEG;
        let stowed = m.joints[j].stowed_deg;
        let switch = run.latch.get(j);
        let hit = (0..run.len()).find(|&i| {
            travel_deg(stowed, run.phi_deg[j][i]) <= reach
                || switch.and_then(|s| s.get(i)).copied().unwrap_or(false)
        });
        if let Some(i) = hit {
            if best.is_none_or(|(b, _)| i < b) {
                best = Some((i, j + 1));
            }
        }
    }
    best
}

/// The campaign cut to its free motion and the window of each run, or
/// `None` when no run's mechanism has a physical latch (the campaign is
/// fitted whole).
pub fn free_campaign(c: &Campaign) -> Option<(Campaign, Vec<RunWindow>)> {
    if !c.runs.iter().any(|r| r.mechanism.has_physical_latch()) {
        return None;
    }
    let windows: Vec<RunWindow> = c
        .runs
        .iter()
        .map(|cr| {
            let of = cr.run.len();
            match first_contact(cr) {
                Some((i, joint)) => {
                    let kept = i.max(MIN_FREE_SAMPLES).min(of);
                    RunWindow {
                        kept,
                        of,
                        end_s: cr.run.t_s.get(kept).copied(),
                        joint: Some(joint),
                    }
                }
                None => RunWindow {
                    kept: of,
                    of,
                    end_s: None,
                    joint: None,
                },
            }
        })
        .collect();
    Some((apply(c, &windows), windows))
}

/// The campaign `c` with each run cut to its window (a run without one is
/// kept whole).
pub fn apply(c: &Campaign, windows: &[RunWindow]) -> Campaign {
    Campaign {
        runs: c
            .runs
            .iter()
            .enumerate()
            .map(|(i, cr)| match windows.get(i) {
                Some(w) if w.kept < cr.run.len() => {
                    let mut cut = cr.clone();
                    let run = &mut cut.run;
                    run.t_s.truncate(w.kept);
                    for s in run.phi_deg.iter_mut() {
                        s.truncate(w.kept);
                    }
                    for s in run.latch.iter_mut() {
                        s.truncate(w.kept);
                    }
                    for x in run.extra.iter_mut() {
                        x.values.truncate(w.kept);
                    }
                    cut
                }
                _ => cr.clone(),
            })
            .collect(),
        notes: c.notes.clone(),
    }
}
