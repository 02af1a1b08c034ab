//! The replay's per-joint summary ([`JointSummary`]) in words, as
//! `deploywatch replay` prints it.

use crate::onboard::replay::JointSummary;

impl JointSummary {
    /// When the joint latched: once (`latched at 3.300 s`), or first and
    /// for good when the monitor saw it leave the latched state in between
    /// (`latched first at 5.700 s, for good at 19.900 s`), or first and not
    /// at the end.
    pub fn latch_words(&self) -> String {
        match (self.latched_s, self.latched_final_s) {
            (None, _) => "not latched".into(),
            (Some(a), Some(b)) if a == b => format!("latched at {a:.3} s"),
            (Some(a), Some(b)) => format!("latched first at {a:.3} s, for good at {b:.3} s"),
            (Some(a), None) => format!("latched first at {a:.3} s, not at the end"),
        }
    }
}

impl std::fmt::Display for JointSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let opt = |x: Option<f32>, unit: &str| x.map_or("-".into(), |v| format!("{v:.1}{unit}"));
        write!(
            f,
            "joint {}: {} ({}), Coulomb {:.3} ± {:.3} N·m, viscous {:.4} ± {:.4} N·m·s/rad, \
             margin min {} last {}, prediction {}, faults {}",
            self.joint,
            self.final_state,
            self.latch_words(),
            self.coulomb_nm.0,
            self.coulomb_nm.1,
            self.viscous_nms.0,
            self.viscous_nms.1,
            opt(self.margin_pct.0, " %"),
            opt(self.margin_pct.1, " %"),
            self.prediction,
            if self.faults.is_empty() {
                "none"
            } else {
                &self.faults
            },
        )
    }
}
