//! One set a move proposes ([`Step`]): a base set plus a candidate, with
//! the start values of the candidate's screen. A proposal carries its own
//! starts; nothing is shared between proposals.

use super::candidate::Candidate;
use super::outcome::FittedSet;

/// One set a move proposes: a base set plus a candidate, and where the
/// candidate's screen starts.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Step {
    /// The base set (its values held in the screen).
    pub base: FittedSet,
    /// The candidate added to it.
    pub candidate: Candidate,
    /// The candidate's start values from the data (a table shaped by the
    /// residual torque: its knot torques); `None`: its own scan
    /// ([`Candidate::scan`]).
    pub start: Option<Vec<f64>>,
}

impl Step {
    /// `base` plus `candidate`, screened from the candidate's own scan.
    pub fn new(base: FittedSet, candidate: Candidate) -> Step {
        Step {
            base,
            candidate,
            start: None,
        }
    }

    /// `base` plus `candidate`, screened from `start` (and half of it).
    pub fn from(base: FittedSet, candidate: Candidate, start: Option<Vec<f64>>) -> Step {
        Step {
            base,
            candidate,
            start,
        }
    }

    /// The starting points of the candidate's coarse scan: its start from
    /// the data (and half of it), or its own scan.
    pub fn scan(&self) -> Vec<Vec<f64>> {
        match &self.start {
            Some(p) => vec![p.clone(), p.iter().map(|x| 0.5 * x).collect()],
            None => self.candidate.scan(),
        }
    }
}
