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

    /// The plot's marks of the joint's latch, \[s\] and label: `latch J`
    /// when it latched once and stayed; `latch J, first` and `latch J, for
    /// good` when it left the latched state in between; `latch J, lost`
    /// when it did not stay latched to the end (a pawl that broke, a
    /// plunger it escaped over): never a plain `latch J` for a latch lost.
    pub fn latch_marks(&self) -> Vec<(f64, String)> {
        let j = self.joint;
        match (self.latched_s, self.latched_final_s) {
            (None, _) => Vec::new(),
            (Some(a), Some(b)) if a == b => vec![(f64::from(a), format!("latch {j}"))],
            (Some(a), Some(b)) => vec![
                (f64::from(a), format!("latch {j}, first")),
                (f64::from(b), format!("latch {j}, for good")),
            ],
            (Some(a), None) => vec![(f64::from(a), format!("latch {j}, lost"))],
        }
    }
}

impl std::fmt::Display for JointSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let opt = |x: Option<f32>, unit: &str| x.map_or("-".into(), |v| format!("{v:.1}{unit}"));
        write!(
            f,
            "joint {}: {} ({}), Coulomb {:.3} ± {:.3} N·m, viscous {:.4} ± {:.4} N·m·s/rad, \
             margin min {} last {}, prediction {} (confidence {:.1}), faults {}, unresolved in {} statuses",
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
            self.confidence,
            if self.faults.is_empty() {
                "none"
            } else {
                &self.faults
            },
            self.unresolved,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn joint(latched_s: Option<f32>, latched_final_s: Option<f32>) -> JointSummary {
        JointSummary {
            joint: 2,
            latched_s,
            latched_final_s,
            final_state: "escaped",
            coulomb_nm: (0.0, 0.0),
            viscous_nms: (0.0, 0.0),
            margin_pct: (None, None),
            prediction: "latch",
            confidence: 0.9,
            faults: String::new(),
            unresolved: 0,
        }
    }

    #[test]
    fn the_line_gives_the_prediction_with_its_confidence() {
        let mut j = joint(None, None);
        j.prediction = "stall";
        j.confidence = 0.5;
        assert!(
            j.to_string()
                .contains(", prediction stall (confidence 0.5), faults none,"),
            "{j}"
        );
    }

    #[test]
    fn a_lost_latch_is_never_marked_as_a_latch() {
        assert_eq!(
            joint(Some(3.5), None).latch_marks(),
            vec![(3.5, "latch 2, lost".to_string())]
        );
        assert_eq!(
            joint(Some(3.5), Some(3.5)).latch_marks(),
            vec![(3.5, "latch 2".to_string())]
        );
        assert_eq!(
            joint(Some(1.5), Some(3.5)).latch_marks(),
            vec![
                (1.5, "latch 2, first".to_string()),
                (3.5, "latch 2, for good".to_string())
            ]
        );
        assert!(joint(None, None).latch_marks().is_empty());
    }
}
