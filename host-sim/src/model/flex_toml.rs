//! Reading and writing the `[flexible_panels]` table of a mechanism file
//! (`docs/spec/formats.md`, "Flexible panels", this project's extension).
//!
//! ```toml
//! [flexible_panels]
//! first_mode_hz = 8.0     # the deployed wing's first mode, every hinge latched
//! damping_ratio = 0.02    # optional, that mode's ζ (2 % by default)
//! ```

use crate::model::flex::{PanelFlex, DEFAULT_DAMPING_RATIO, MAX_FLEXIBLE_PANELS};
use crate::model::latch::LatchSpec;
use crate::model::mechanism_error::MechanismErrorKind;
use crate::model::toml_tree::{Bound, Cx, Res, Sp};

const FLEX_KEYS: &[&str] = &["first_mode_hz", "damping_ratio"];

/// Highest first mode a file may declare \[Hz\]: far above any panel's and
/// any sample rate's Nyquist frequency (the flex joints would only make
/// every step short).
const MAX_FIRST_MODE_HZ: f64 = 1_000.0;

/// The `[flexible_panels]` table `sp` of a wing of `panels` panels with
/// `latches`, a truss or not and an enabled rig or not; every error names
/// its line.
pub(crate) fn read(
    cx: &Cx<'_>,
    sp: &Sp,
    panels: usize,
    latches: &[Option<LatchSpec>],
    truss: bool,
    rig: bool,
) -> Res<PanelFlex> {
    let t = cx.table(sp, "flexible_panels", FLEX_KEYS)?;
    let hz = cx.req_number(&t, "first_mode_hz", Bound::Positive, "Hz")?;
    if hz > MAX_FIRST_MODE_HZ {
        if let Some(v) = t.get("first_mode_hz") {
            return Err(cx.invalid(v, &t.key("first_mode_hz"), "a number > 0 and ≤ 1000 [Hz]"));
        }
    }
    let zeta = cx
        .opt_number(&t, "damping_ratio", Bound::NonNegative, "")?
        .unwrap_or(DEFAULT_DAMPING_RATIO);
    if zeta >= 1.0 {
        if let Some(v) = t.get("damping_ratio") {
            return Err(cx.invalid(v, &t.key("damping_ratio"), "a number ≥ 0 and < 1"));
        }
    }
    let physical: Vec<String> = (1..=latches.len())
        .filter(|&j| latches.get(j - 1).is_some_and(Option::is_some))
        .map(|j| j.to_string())
        .collect();
    let why = if panels > MAX_FLEXIBLE_PANELS {
        Some(format!("the wing has {panels} panels"))
    } else if !physical.is_empty() {
        Some(format!(
            "joint(s) {} have a physical latch ([joint.latch])",
            physical.join(", ")
        ))
    } else if truss {
        Some("the wing has a [truss]".to_string())
    } else if rig {
        Some("the wing has an enabled [rig]".to_string())
    } else {
        None
    };
    if let Some(why) = why {
        return Err(cx.err(cx.line(sp), MechanismErrorKind::FlexibleUnsupported { why }));
    }
    Ok(PanelFlex {
        first_mode_hz: hz,
        damping_ratio: zeta,
    })
}

/// Appends `f` as a `[flexible_panels]` table.
pub(crate) fn write(f: &PanelFlex, out: &mut String) {
    use crate::model::toml_tree::num;
    out.push_str(&format!(
        "\n[flexible_panels]\nfirst_mode_hz = {}\ndamping_ratio = {}\n",
        num(f.first_mode_hz),
        num(f.damping_ratio)
    ));
}
