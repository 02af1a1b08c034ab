//! A joint's residual evidence in words: its [`Reading`] with the numbers
//! of its [`JointEvidence`] (the report's "What the baseline gets wrong"
//! and the JSON's `summary`).

use crate::analysis::evidence::{JointEvidence, LatchTiming, Reading, CORRELATES};

/// The evidence of one joint in one run in words, e.g. `joint 2: residual
/// 0.412 deg RMS; largest late in the stroke (0.611 deg); zero at release,
/// grows with the motion: dynamic`.
pub fn evidence_words(e: &JointEvidence) -> String {
    let (joint, total) = (e.joint, e.rms_deg);
    let (largest, near_latch, zero_at_release, latch, correlate) = match e.reading {
        Reading::AtNoise { sigma_deg } => {
            return format!(
                "joint {joint}: residual {total:.3} deg RMS, at the noise ({sigma_deg:.3} deg)"
            )
        }
        Reading::LetGo {
            closed_s,
            opened_s,
            left_deg,
            after_rms_deg,
        } => {
            return format!(
                "joint {joint}: residual {total:.3} deg RMS, {after_rms_deg:.3} deg RMS from {opened_s:.3} s on: its latch let go (the switch closed at {closed_s:.3} s, opened again at {opened_s:.3} s, and the reading left the stop by up to {left_deg:.2} deg); the model's ideal latch holds, so no effect explains the run after {opened_s:.3} s"
            )
        }
        Reading::Sensor => {
            return format!(
                "joint {joint}: residual {total:.3} deg RMS; already {:+.3} deg at release and {:+.3} deg after the latch: a sensor effect (offset), not dynamics",
                e.at_release_mean_deg, e.after_latch_mean_deg
            )
        }
        Reading::Dynamic {
            largest,
            near_latch,
            zero_at_release,
            latch,
            correlate,
        } => (largest, near_latch, zero_at_release, latch, correlate),
    };
    let mut s = format!("joint {joint}: residual {total:.3} deg RMS");
    if let Some(t) = largest {
        let k = t.index();
        let name = ["early", "mid", "late"][k];
        s += &format!(
            "; largest {name} in the stroke ({:.3} deg)",
            e.stroke_thirds_rms_deg[k]
        );
    }
    if near_latch {
        s += &format!(
            ", {:.3} deg within 5 deg of the latch",
            e.near_latch_rms_deg
        );
    }
    if zero_at_release {
        s += "; zero at release, grows with the motion: dynamic";
    }
    match (latch, e.latch_lead_s) {
        (Some(LatchTiming::Early), Some(l)) => {
            s += &format!("; the model latches {:.3} s early (runs ahead)", -l)
        }
        (Some(LatchTiming::Late), Some(l)) => {
            s += &format!("; the model latches {l:.3} s late (lags)")
        }
        _ => {}
    }
    if let Some(k) = correlate {
        s += &format!(
            "; correlates most with {} (r = {:+.2})",
            CORRELATES[k], e.correlation[k]
        );
    }
    s
}
