//! Encoder readings off their panels within the hinges' declared
//! free-play, in the diagnosis summary, report and JSON
//! (`docs/diagnosis.md`, "Free-play held to one side").

use crate::analysis::diagnose::{free_play, Outcome};
use crate::model::findings::diagnosis::FreePlayJson;
use crate::model::findings::{exact, rounded};
use crate::report::markdown::table;
use std::fmt::Write as _;

/// The summary's lines, one per joint.
pub fn summary_lines(o: &Outcome) -> Vec<String> {
    o.free_play
        .iter()
        .map(|l| format!("discrepancy (not an effect): {}", free_play::words(l)))
        .collect()
}

/// The report's section (none without such a reading).
pub fn report(md: &mut String, o: &Outcome) {
    if o.free_play.is_empty() {
        return;
    }
    let _ = writeln!(md, "## Free-play held to one side\n");
    let _ = writeln!(
        md,
        "A hinge with free-play whose encoder reads its spring side reads the panel's angle plus the play for as long as the band stays closed on one side: the spring side leads its panel toward the latch while the spring drives it (and after the latching, where the spring goes on pushing), and trails it while the panel is driven back against its spring. Runs that keep one side cannot tell that from an encoder offset. These offsets lie within the free-play the mechanisms declare at their joints: they are reported as that discrepancy, not claimed, and the angles below are compared with each taken out.\n"
    );
    let rows: Vec<Vec<String>> = o
        .free_play
        .iter()
        .map(|l| {
            vec![
                l.joint.to_string(),
                format!("{:+.4}", l.offset_deg),
                format!("{:+.4} .. {:+.4}", l.ci95_deg[0], l.ci95_deg[1]),
                format!("{:.4}", l.play_deg),
            ]
        })
        .collect();
    md.push_str(&table(
        &[
            "joint",
            "reading off the panel [deg]",
            "95 % CI [deg]",
            "declared free-play [deg]",
        ],
        &rows,
    ));
    let _ = writeln!(md);
}

/// The readings in the JSON.
pub fn json(o: &Outcome) -> Vec<FreePlayJson> {
    o.free_play
        .iter()
        .map(|l| FreePlayJson {
            joint: l.joint,
            offset_deg: exact(l.offset_deg),
            ci95: [rounded(l.ci95_deg[0]), rounded(l.ci95_deg[1])],
            play_deg: exact(l.play_deg),
        })
        .collect()
}
