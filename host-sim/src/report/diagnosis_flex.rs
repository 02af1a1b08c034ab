//! Flexible panels in the diagnosis report and JSON (`docs/diagnosis.md`,
//! "Flexible panels").

use crate::analysis::diagnose::Outcome;
use crate::model::findings::diagnosis::FlexiblePanelsJson;
use std::fmt::Write as _;

/// The flexible panels in the JSON (`None`: not named).
pub fn json(o: &Outcome) -> Option<FlexiblePanelsJson> {
    let m = o.panel_mode.as_ref()?;
    let finite = |x: f64| x.is_finite().then_some(x);
    Some(FlexiblePanelsJson {
        first_mode_hz: finite(m.flex.first_mode_hz),
        damping_ratio: finite(m.flex.damping_ratio),
        rigid_rms_deg: finite(m.rigid_rms_deg),
        flexible_rms_deg: finite(m.flexible_rms_deg),
    })
}

/// The summary's line (none without flexible panels).
pub fn summary_line(o: &Outcome) -> Option<String> {
    o.panel_mode
        .as_ref()
        .map(|m| format!("discrepancy (not an effect): {}", m.words()))
}

/// The report's section (none without flexible panels).
pub fn report(md: &mut String, o: &Outcome) {
    let Some(m) = &o.panel_mode else { return };
    let _ = writeln!(md, "## Flexible panels\n");
    let _ = writeln!(
        md,
        "A discrepancy named by fitting it, not an effect: {}. Each panel is modelled as two rigid halves on a torsion spring and damper at mid-span (`docs/spec/physics.md` §12), one stiffness for every panel, set by the deployed wing's first mode (every hinge latched); the mode and its damping ratio were fitted to the runs beside the set found. The search then ran on the flexible wing: every figure of this report, the baseline included, is of it. To simulate the wing so, add to each mechanism file:\n\n```toml\n[flexible_panels]\nfirst_mode_hz = {:.3}\ndamping_ratio = {:.4}\n```\n",
        m.words(),
        m.flex.first_mode_hz,
        m.flex.damping_ratio
    );
}
