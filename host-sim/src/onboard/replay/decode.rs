//! Status frames read back: split at their `0x00` and decoded into
//! [`StatusRow`]s.

use deploywatch_core::monitor::Status;
use deploywatch_core::telemetry;

use super::error::ReplayError;
use super::status::StatusRow;
use crate::model::mechanism::with_joints;

/// Splits frames, each with its `0x00`.
pub fn frames(bytes: &[u8]) -> impl Iterator<Item = &[u8]> {
    bytes.split_inclusive(|&b| b == 0)
}

fn decode_n<const N: usize>(bytes: &[u8]) -> Result<Vec<StatusRow>, ReplayError> {
    frames(bytes)
        .enumerate()
        .map(|(i, f)| {
            let mut f = f.to_vec();
            telemetry::decode::<Status<N>>(&mut f)
                .map(|s| StatusRow::from(&s))
                .map_err(|e| ReplayError::Target(format!("status frame {i}: {e}")))
        })
        .collect()
}

/// Decodes status frames of `joints` joints.
pub fn decode_statuses(bytes: &[u8], joints: usize) -> Result<Vec<StatusRow>, ReplayError> {
    with_joints!(joints, N => decode_n::<N>(bytes), else Err(ReplayError::Input(format!("{joints} joints"))))
}
