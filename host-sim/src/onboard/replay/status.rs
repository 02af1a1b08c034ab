//! One status of any joint count: what everything after the frames works on.

use deploywatch_core::monitor::{JointStatus, Status};

/// One status of any joint count, as the replay's modules use it.
#[derive(Clone, Debug, PartialEq)]
pub struct StatusRow {
    /// Time of the sample \[s\].
    pub t_s: f32,
    /// Samples seen.
    pub samples: u32,
    /// Per joint.
    pub joints: Vec<JointStatus>,
}

impl<const N: usize> From<&Status<N>> for StatusRow {
    fn from(s: &Status<N>) -> Self {
        StatusRow {
            t_s: s.t_s,
            samples: s.samples,
            joints: s.joints.to_vec(),
        }
    }
}
