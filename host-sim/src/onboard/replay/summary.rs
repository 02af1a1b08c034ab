//! What a replay says about each joint: first and final latch, final
//! estimates, margins, prediction, faults and the statuses it was
//! unresolved in.

use super::status::StatusRow;

/// What a replay says about one joint.
#[derive(Clone, Debug, PartialEq)]
pub struct JointSummary {
    /// 1-based joint.
    pub joint: usize,
    /// First time the state is `latched` \[s\].
    pub latched_s: Option<f32>,
    /// Time from which the state stays `latched` to the end \[s\]: later
    /// than [`JointSummary::latched_s`] when the joint escaped its latch
    /// and latched again; `None` when it is not latched at the end.
    pub latched_final_s: Option<f32>,
    /// The state at the end.
    pub final_state: &'static str,
    /// Final Coulomb estimate and its standard deviation [N·m].
    pub coulomb_nm: (f32, f32),
    /// Final viscous estimate and its standard deviation [N·m·s/rad].
    pub viscous_nms: (f32, f32),
    /// Smallest torque margin of the run and the last one [%].
    pub margin_pct: (Option<f32>, Option<f32>),
    /// The last prediction.
    pub prediction: &'static str,
    /// Its confidence \[0, 1\] (0.5 a best estimate only, the configured
    /// level when confirmed, 1 once latched: `docs/monitor.md` §1.1).
    pub confidence: f32,
    /// Every fault flag raised during the run.
    pub faults: String,
    /// Statuses in which the joint is
    /// [`Resolution::Unresolved`](deploywatch_core::monitor::Resolution): shaken
    /// faster than the samples resolve, its outlier checks off.
    pub unresolved: usize,
}

// Its words: `onboard::summary_words`.

/// The per-joint summary of a status stream.
pub fn summary(statuses: &[StatusRow]) -> Vec<JointSummary> {
    let joints = statuses.first().map_or(0, |s| s.joints.len());
    (0..joints)
        .map(|j| {
            let (mut latched_s, mut latched_final_s) = (None, None);
            let mut min_margin: Option<f32> = None;
            let mut faults = deploywatch_core::monitor::FaultFlags::EMPTY;
            let mut unresolved = 0;
            for s in statuses {
                let js = &s.joints[j];
                if js.latch == deploywatch_core::monitor::LatchState::Latched {
                    latched_s = latched_s.or(Some(s.t_s));
                    latched_final_s = latched_final_s.or(Some(s.t_s));
                } else {
                    latched_final_s = None;
                }
                if let Some(m) = js.margin_pct.filter(|m| m.is_finite()) {
                    min_margin = Some(min_margin.map_or(m, |x| x.min(m)));
                }
                faults = faults.union(js.faults);
                unresolved +=
                    usize::from(js.resolution == deploywatch_core::monitor::Resolution::Unresolved);
            }
            let last = statuses.last().map(|s| s.joints[j]).unwrap_or_default();
            JointSummary {
                joint: j + 1,
                latched_s,
                latched_final_s,
                final_state: last.latch.as_str(),
                coulomb_nm: (last.coulomb_nm, last.coulomb_sd_nm),
                viscous_nms: (last.viscous_nms, last.viscous_sd_nms),
                margin_pct: (min_margin, last.margin_pct),
                prediction: last.prediction.as_str(),
                confidence: last.confidence,
                faults: faults
                    .iter()
                    .map(|f| f.as_str())
                    .collect::<Vec<_>>()
                    .join("|"),
                unresolved,
            }
        })
        .collect()
}
