//! The rig's share of the friction and the margin on orbit beside the
//! margin on the rig ([`crate::analysis::rig_margin`]), as a Markdown
//! section that `diagnose` and `identify` print and `diagnose` adds to its
//! report.

use crate::analysis::rig_margin::{self, RigSplit};
use crate::data::campaign::Campaign;
use crate::model::effect::Effect;
use crate::report::markdown::table;
use std::fmt::Write as _;

/// A margin for people: `123.4 %`, `inf`.
fn pct(v: f64) -> String {
    if v.is_infinite() {
        "inf".into()
    } else {
        format!("{v:.1} %")
    }
}

/// The section: the rig findings (not flight), per joint the hinge
/// friction with the rig taken out, the EFT that lumps the rig's rails in,
/// the rig's share, and per mechanism the torque margins on orbit and on
/// the rig (seed 001 Eq. 7, no factors).
pub fn section(s: &RigSplit) -> String {
    let mut out =
        String::from("## The rig taken out: margin on orbit beside margin on the rig\n\n");
    if s.rig_causes.is_empty() {
        out.push_str("Rig findings: none beyond the rig as drawn.\n");
    } else {
        let names: Vec<String> = s.rig_causes.iter().map(|e| e.to_string()).collect();
        let _ = writeln!(
            out,
            "Rig findings (of the test rig, not of the flight unit; left out on orbit): {}",
            names.join("; ")
        );
    }
    let _ = writeln!(
        out,
        "\nThe hinge friction with the rig modelled (RMS {:.4} deg) against the EFT fitted with the rig's rails frictionless, which lumps their friction into the hinges as the papers' EFT does (RMS {:.4} deg):\n",
        s.found_rms_deg, s.lumped_rms_deg
    );
    out.push_str(&table(
        &[
            "joint",
            "hinge friction, rig taken out [N·m]",
            "EFT lumping the rig [N·m]",
            "rig's share [N·m]",
        ],
        s.joints.iter().map(|j| {
            vec![
                j.joint.to_string(),
                format!("{:.4}", j.hinge_nm),
                format!("{:.4}", j.lumped_nm),
                format!("{:+.4}", j.rig_share_nm()),
            ]
        }),
    ));
    out.push_str("\nTorque margin (seed 001 Eq. 7, no factors; `deploywatch margin` applies the standards):\n\n");
    out.push_str(&table(
        &[
            "mechanism",
            "joint",
            "on orbit (rig taken out)",
            "on the rig (lumped)",
        ],
        s.margins.iter().flat_map(|m| {
            m.orbit_pct
                .iter()
                .zip(&m.rig_pct)
                .enumerate()
                .map(|(k, (o, r))| vec![m.mechanism.clone(), (k + 1).to_string(), pct(*o), pct(*r)])
        }),
    ));
    out
}

/// On a campaign with a rig: the section of the effects `found`
/// ([`rig_margin::split`], its fit reporting to `progress`), for the report
/// and the terminal; `None` without a rig.
pub fn for_campaign(
    campaign: &Campaign,
    found: &[Effect],
    progress: crate::report::progress::Progress,
) -> Option<String> {
    rig_margin::split(campaign, found, progress).map(|s| section(&s))
}
