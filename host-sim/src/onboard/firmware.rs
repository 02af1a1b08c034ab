//! Which firmware replays a run: the example firmware is built once per
//! joint count (the monitor's `N` is the binary's choice), so the host
//! picks the ELF of the run's joint count, and runs the firmware's own
//! replay loop on the host with a monitor of that count.

use std::path::{Path, PathBuf};

use crate::model::mechanism::with_joints;
use crate::onboard::replay::{find_firmware, ReplayError, SETUP_HINT};

/// The replay firmware ELF of 3 joints, relative to the repository root;
/// the firmware of `N` other joints is this path with `-N` appended
/// ([`default_elf`]).
pub const DEFAULT_ELF: &str =
    "firmware-example/target/thumbv7em-none-eabihf/release/deploywatch-firmware-example";

/// The joint counts the example firmware is built for, one binary each
/// (`firmware-example/Cargo.toml`): the firmware chooses its monitor's
/// joint count, and refuses an input of another.
pub const FIRMWARE_JOINTS: [usize; 3] = [2, 3, 6];

/// The replay firmware ELF of `joints` joints, relative to the repository
/// root ([`DEFAULT_ELF`] for 3).
pub fn default_elf(joints: usize) -> String {
    if joints == 3 {
        DEFAULT_ELF.to_string()
    } else {
        format!("{DEFAULT_ELF}-{joints}")
    }
}

/// The firmware's own replay loop (`deploywatch_core::telemetry::replay`), run on
/// the host over `input` with a monitor of `joints` joints (the firmware's
/// choice): against the host's statuses it tells a difference of code path
/// from one of target.
pub fn firmware_loop_on_host(input: &[u8], joints: usize) -> Result<Vec<u8>, ReplayError> {
    with_joints!(joints, N => firmware_loop_n::<N>(input), else Err(ReplayError::Input(format!(
        "{joints} joints; a monitor has 1 to {}",
        deploywatch_core::telemetry::config::MAX_JOINTS
    ))))
}

fn firmware_loop_n<const N: usize>(input: &[u8]) -> Result<Vec<u8>, ReplayError> {
    let mut rest = input;
    let mut out = Vec::new();
    deploywatch_core::telemetry::replay::replay(
        |buf| {
            let k = buf.len().min(rest.len());
            buf[..k].copy_from_slice(&rest[..k]);
            rest = &rest[k..];
            Ok(k)
        },
        |frame| {
            out.extend_from_slice(frame);
            Ok(())
        },
        &mut (),
        &mut deploywatch_core::telemetry::replay::MonitorStore::<N>::Empty,
        |_| {},
    )
    .map_err(|e| ReplayError::Target(format!("the firmware's loop on the host: {e}")))?;
    Ok(out)
}

/// Whether the example firmware is built for `joints` joints.
pub fn firmware_supports(joints: usize) -> bool {
    FIRMWARE_JOINTS.contains(&joints)
}

/// The firmware's joint counts, for messages.
pub fn firmware_joint_counts() -> String {
    let n: Vec<String> = FIRMWARE_JOINTS.iter().map(|n| n.to_string()).collect();
    format!("{} and {}", n[..n.len() - 1].join(", "), n[n.len() - 1])
}

/// The firmware ELF of `joints` joints: `elf` when given, else
/// [`default_elf`] under the current directory, else under the source tree
/// this program was built from.
pub fn find_elf(elf: Option<&Path>, joints: usize) -> Result<PathBuf, ReplayError> {
    find_firmware(elf, &default_elf(joints), SETUP_HINT)
}
