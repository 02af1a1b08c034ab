//! The warnings about a command's inputs, gathered before any work: the
//! mechanisms' unlikely values ([`crate::model::plausibility`]) and the
//! runs' findings against their mechanisms ([`crate::data::consistency`]).
//! The CLI prints each on stderr as `warning: ...`, `--quiet` or not.

use std::path::{Path, PathBuf};

use crate::data::campaign::{Campaign, CampaignRun};
use crate::data::consistency;
use crate::data::run::{check_run_of, Run, RunError};
use crate::model::mechanism::Mechanism;
use crate::model::plausibility;

/// The warnings of a campaign loaded by [`Campaign::load`] from
/// `mechanisms` (the paths, read again for the lines of the keys). Its runs
/// passed [`consistency::check`] already, which is what refuses them.
pub fn campaign_warnings(mechanisms: &[PathBuf], campaign: &Campaign) -> Vec<String> {
    let mut out = Vec::new();
    for path in mechanisms {
        if let Ok(m) = Mechanism::load(path) {
            out.extend(plausibility::warnings(&m, path));
        }
    }
    out.extend(campaign.notes.iter().cloned());
    for r in &campaign.runs {
        let file = r.source.display().to_string();
        if let Ok(w) = consistency::check(&r.run, &r.mechanism, &file) {
            out.extend(w);
        }
    }
    out.extend(mixed_wings(campaign));
    out
}

/// A campaign whose runs are of wings of different joint counts: its
/// effects are common to every run by joint number (`formats.md`: the same
/// rig, the same hardware), which such wings cannot share.
fn mixed_wings(campaign: &Campaign) -> Option<String> {
    let count = |r: &CampaignRun| r.mechanism.joint_count();
    let first = campaign.runs.first()?;
    let other = campaign.runs.iter().find(|r| count(r) != count(first))?;
    let said = |r: &CampaignRun| {
        format!(
            "{} ({}, {} joint{})",
            r.name(),
            r.mechanism.name,
            count(r),
            if count(r) == 1 { "" } else { "s" }
        )
    };
    Some(format!(
        "the runs are of wings of different joint counts ({} and {}): the effects found are \
         common to every run by joint number, as for one wing's hardware; give the runs of \
         different wings to separate commands",
        said(first),
        said(other)
    ))
}

/// Checks that `run` (from `run_path`) is of `mechanism` (from
/// `mechanism_path`): [`check_run_of`], then [`consistency::check`].
/// Returns the warnings of both files, or the first error.
pub fn check_pair(
    mechanism: &Mechanism,
    mechanism_path: &Path,
    run: &Run,
    run_path: &Path,
) -> Result<Vec<String>, RunError> {
    let file = run_path.display().to_string();
    check_run_of(mechanism, run, &file)?;
    let mut out = plausibility::warnings(mechanism, mechanism_path);
    out.extend(consistency::check(run, mechanism, &file)?);
    Ok(out)
}
