//! The words of the diagnosis's typed findings: why a search stopped
//! before its end ([`HaltReason`]), what stays unexplained
//! ([`Unexplained`]), what each round tried ([`what_words`]) and what
//! became of each of its candidates ([`Verdict`]). The analysis decides
//! and holds the facts; the report, the JSON and the summary say them with
//! these words.

use crate::analysis::diagnose::ambiguity::Ambiguity;
use crate::analysis::diagnose::evidence::{ResidualPlace, StrokeThird};
use crate::analysis::diagnose::{
    Candidate, FittedSet, HaltReason, Kept, Move, Rejection, Round, Unexplained, UnexplainedShape,
    Verdict, MIN_DELTA_BIC,
};
use std::fmt;

/// The words of the JSON's `partial`, the report's bold line and the
/// summary's `PARTIAL:` (they name the command line's `--max-seconds`).
impl fmt::Display for HaltReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            HaltReason::Interrupted => f.write_str("interrupted (Ctrl-C)"),
            HaltReason::TimeLimit { limit_s: _ } => {
                f.write_str("stopped at the time limit (--max-seconds)")
            }
        }
    }
}

/// A set in words with values: `coulomb_friction at joint 2 = 0.4991`.
pub fn values_words(f: &FittedSet) -> String {
    let e = f.effects();
    if e.is_empty() {
        return "nothing".into();
    }
    e.iter()
        .map(|e| match e.joint {
            Some(j) => format!("{} at joint {j} = {:.4}", e.kind(), e.value()),
            None => format!("{} = {:.4}", e.kind(), e.value()),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// How the sets of an ambiguity group explain the runs alike: by a BIC
/// within [`MIN_DELTA_BIC`] of the set found (the group's first), or, when
/// one fits better by more and is listed, better and not taken
/// (`docs/diagnosis.md`, "Ambiguity", says when).
pub fn alike_words(g: &Ambiguity) -> &'static str {
    let first = g.sets.first().map_or(0.0, FittedSet::bic);
    if g.sets.iter().any(|s| s.bic() - first <= -MIN_DELTA_BIC) {
        "BIC within 10 of the set found, or better by more but not taken; docs/diagnosis.md, \"Ambiguity\", says when"
    } else {
        "BIC within 10 of the set found"
    }
}

/// `a, b, c` of a set in words ([`Candidate::words`]); `nothing` for the
/// empty set.
fn set_words(set: &[Candidate]) -> String {
    if set.is_empty() {
        return "nothing".to_string();
    }
    set.iter().map(|c| c.words()).collect::<Vec<_>>().join(", ")
}

/// What a round tried, in words: its move and the set it started from
/// (the JSON's `round`, the report's heading of the round, an effect's
/// evidence).
pub fn what_words(r: &Round) -> String {
    let set = set_words(&r.start);
    match r.what {
        Move::Add => format!("add to {set}"),
        Move::Pair | Move::PairAfterSwap => format!("add a pair to {set}"),
        Move::Swap => format!("swap one of {set}"),
        Move::Proposed => format!("replace {set} by a pair the residual torque proposes"),
        Move::JointPairs => {
            format!("named pairs at a joint in place of its named effects in {set}")
        }
        Move::Table | Move::EvenTable | Move::TablePair => {
            format!("discover a torque beside {set}")
        }
        Move::NamedForTable => format!("a named effect in place of a table of {set}"),
        Move::Refine => format!("refine a table of {set}"),
        Move::StandInTable => format!("a table in place of a global stand-in in {set}"),
        Move::StandIn => format!("a table with its refinement in place of the stand-in of {set}"),
        Move::FrictionForms => format!("a friction form in {set}"),
        Move::Simpler => format!("a simpler law in place of a friction form of {set}"),
        Move::Drop => format!("drop an effect of {set}"),
        Move::DropClaim => format!("drop a claim of {set} the data do not support"),
        Move::SetAside => format!("set aside a claim of {set} within the discrepancy"),
        Move::Restart => format!("a second start's set in place of {set}"),
        Move::Alternative => {
            format!("an alternative of the ambiguity stage in place of {set}")
        }
        Move::Partner => format!(
            "an alternative of the ambiguity stage in place of {set}, after the drawing's tolerances"
        ),
    }
}

/// A third of the stroke in words.
pub fn third_words(t: StrokeThird) -> &'static str {
    match t {
        StrokeThird::First => "the first third of the stroke (near the stowed angle)",
        StrokeThird::Middle => "the middle third of the stroke",
        StrokeThird::Last => "the last third of the stroke (near the latch)",
    }
}

/// Where a residual is largest, in words (`"joint 2, mostly in the middle
/// third of the stroke"`).
pub fn place_words(p: ResidualPlace) -> String {
    match p.let_go_s {
        Some(t) => format!(
            "joint {}, mostly after its latch let go at {t:.3} s (a latch the model holds)",
            p.joint
        ),
        None => format!("joint {}, mostly in {}", p.joint, third_words(p.third)),
    }
}

/// The JSON's `unexplained` description, the report's **Unexplained:** and
/// the summary's `unexplained:`: the residual's RMS against the noise
/// floor, then what it shows.
impl fmt::Display for Unexplained {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (rms, sigma) = (self.rms_deg, self.noise_sigma_deg);
        write!(
            f,
            "the residual stays at {rms:.4} deg RMS, {:.1} times the noise floor ({sigma:.4} deg)",
            rms / sigma.max(1e-9),
        )?;
        match &self.shape {
            UnexplainedShape::AboveNoise { largest_at } => {
                if let Some(p) = largest_at {
                    write!(f, ", largest at {}", place_words(*p))?;
                }
                f.write_str(", and no further candidate earns its keep")
            }
            UnexplainedShape::StandIn { torque } => write!(
                f,
                ", and without its global effect the residual torque is significant at joint {}, which holds no effect found, largest in {} ({}); no further candidate earns its keep",
                torque.joint,
                torque.stroke_third().map_or("the stroke", third_words),
                torque.describe()
            ),
        }
    }
}

/// The JSON's `verdict` of a candidate, the report's and the progress's.
impl fmt::Display for Verdict {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Verdict::Screened => f.write_str("screened out by the coarse scan"),
            Verdict::NotJudged => Ok(()),
            Verdict::NotTheBest { delta_bic } => write!(f, "dBIC {delta_bic:.1}, not the best"),
            Verdict::Rejected(r) => r.fmt(f),
            Verdict::Accepted(Kept::Added) => f.write_str("earns its keep: added"),
            Verdict::Accepted(Kept::Refined) => f.write_str("earns its keep: refined"),
            Verdict::Accepted(Kept::Dropped) => f.write_str("explains the runs as well: taken"),
        }
    }
}

/// Why a judged move was not taken, in words.
impl fmt::Display for Rejection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Rejection::BicGain { delta_bic, min } => write!(f, "BIC gain {delta_bic:.1} ≤ {min}"),
            Rejection::IntervalHoldsZero => f.write_str("a 95 % interval contains zero"),
            Rejection::RmsShare { rms_deg, limit_deg } => {
                write!(f, "RMS {rms_deg:.4} deg above {limit_deg:.4} deg")
            }
            Rejection::AboveNoise { rms_deg } => {
                write!(f, "residual {rms_deg:.4} deg stays above the noise")
            }
            Rejection::HeldOut {
                held_deg,
                current_deg,
            } => write!(
                f,
                "held-out RMS {held_deg:.4} deg does not beat {current_deg:.4} deg"
            ),
            Rejection::StandInLeft => {
                f.write_str("a global effect still stands in for a joint torque")
            }
            Rejection::UnsupportedClaim => {
                f.write_str("it adds a claim its joint shows no evidence of")
            }
            Rejection::BeyondDiscrepancy {
                explained_deg,
                discrepancy_deg,
            } => write!(
                f,
                "it accounts for {explained_deg:.4} deg RMS, not less than the \
                 {discrepancy_deg:.4} deg the set leaves unexplained"
            ),
            Rejection::WithinDiscrepancy {
                gained_deg,
                discrepancy_deg,
            } => write!(
                f,
                "it gains {gained_deg:.4} deg RMS, less than the {discrepancy_deg:.4} deg \
                 it leaves unexplained: the runs cannot tell the sets apart beyond that"
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_halt_reason_has_the_words_of_the_json() {
        assert_eq!(HaltReason::Interrupted.to_string(), "interrupted (Ctrl-C)");
        assert_eq!(
            HaltReason::TimeLimit { limit_s: 0.3 }.to_string(),
            "stopped at the time limit (--max-seconds)"
        );
    }

    #[test]
    fn verdicts_have_the_words_of_the_json() {
        // Words of host-sim/tests/data/diagnosis_friction_harness.json.
        let words = |v: Verdict| v.to_string();
        assert_eq!(
            words(Verdict::Accepted(Kept::Added)),
            "earns its keep: added"
        );
        assert_eq!(
            words(Verdict::Accepted(Kept::Refined)),
            "earns its keep: refined"
        );
        assert_eq!(
            words(Verdict::NotTheBest { delta_bic: 6181.46 }),
            "dBIC 6181.5, not the best"
        );
        assert_eq!(words(Verdict::Screened), "screened out by the coarse scan");
        assert_eq!(words(Verdict::NotJudged), "");
        assert_eq!(
            words(Verdict::Rejected(Rejection::BicGain {
                delta_bic: 3.12,
                min: 10.0
            })),
            "BIC gain 3.1 ≤ 10"
        );
    }

    #[test]
    fn a_round_says_its_move_and_the_set_it_started_from() {
        // Words of the JSON's `round` the search wrote with the words made
        // in the analysis.
        use crate::model::effect::EffectKind;
        let at = |kind, joint| Candidate {
            kind,
            joint: Some(joint),
            table: None,
        };
        let round = |what, start| Round {
            what,
            start,
            start_rms_deg: 0.1,
            scores: Vec::new(),
        };
        assert_eq!(what_words(&round(Move::Add, Vec::new())), "add to nothing");
        let set = vec![
            at(EffectKind::ViscousDamping, 1),
            at(EffectKind::HarnessStiffness, 1),
        ];
        assert_eq!(
            what_words(&round(Move::Swap, set.clone())),
            "swap one of viscous_damping at joint 1, harness_stiffness at joint 1"
        );
        assert_eq!(
            what_words(&round(Move::PairAfterSwap, set.clone())),
            "add a pair to viscous_damping at joint 1, harness_stiffness at joint 1"
        );
        assert_eq!(
            what_words(&round(Move::EvenTable, set)),
            "discover a torque beside viscous_damping at joint 1, harness_stiffness at joint 1"
        );
    }

    fn unexplained(shape: UnexplainedShape) -> Unexplained {
        Unexplained {
            rms_deg: 0.826_84,
            noise_sigma_deg: 0.021_87,
            shape,
        }
    }

    #[test]
    fn a_residual_above_the_noise_says_its_size_and_where_it_is_largest() {
        // The words `diagnose --max-seconds 0.3` wrote on the bundled
        // example (c) before the finding was typed.
        let u = unexplained(UnexplainedShape::AboveNoise {
            largest_at: Some(ResidualPlace {
                joint: 2,
                third: StrokeThird::Last,
                let_go_s: None,
            }),
        });
        assert_eq!(u.joint(), Some(2));
        assert_eq!(
            u.to_string(),
            "the residual stays at 0.8268 deg RMS, 37.8 times the noise floor (0.0219 deg), largest at joint 2, mostly in the last third of the stroke (near the latch), and no further candidate earns its keep"
        );
        let nowhere = unexplained(UnexplainedShape::AboveNoise { largest_at: None });
        assert_eq!(nowhere.joint(), None);
        assert_eq!(
            nowhere.to_string(),
            "the residual stays at 0.8268 deg RMS, 37.8 times the noise floor (0.0219 deg), and no further candidate earns its keep"
        );
    }

    #[test]
    fn a_stand_in_names_the_joint_the_third_and_the_torque() {
        use crate::analysis::residual_torque::{Bin, JointTorque};
        let bin = |range: [f64; 2], mean_nm: f64| Bin {
            range,
            n: 40,
            mean_nm,
            se_nm: 0.002,
        };
        let torque = JointTorque {
            joint: 3,
            stowed_deg: -90.0,
            samples: Vec::new(),
            by_angle: vec![bin([-88.0, -82.0], 0.001), bin([-48.0, -42.0], -0.05)],
            by_rate: Vec::new(),
            chi2: 625.0,
            max_z: 25.0,
            significant: true,
            rms_nm: 0.035,
        };
        let u = unexplained(UnexplainedShape::StandIn {
            torque: torque.clone(),
        });
        assert_eq!(u.joint(), Some(3));
        assert_eq!(
            u.to_string(),
            format!(
                "the residual stays at 0.8268 deg RMS, 37.8 times the noise floor (0.0219 deg), and without its global effect the residual torque is significant at joint 3, which holds no effect found, largest in the middle third of the stroke ({}); no further candidate earns its keep",
                torque.describe()
            )
        );
    }
}
