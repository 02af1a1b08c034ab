//! The status CSV: one row per status, the per-joint columns in
//! [`JOINT_COLUMNS`].

use std::io::{self, Write};

use deploywatch_core::monitor::JointStatus;

use super::status::StatusRow;

/// A value of the status CSV: `f32` in Rust's shortest form that reads back
/// to the same value, so equal statuses give equal text.
fn num(x: f32) -> String {
    if x.is_nan() {
        "NaN".into()
    } else {
        format!("{x}")
    }
}

/// The per-joint columns of the status CSV: name before the joint number,
/// name after it, and the value. The one place to change when the core's
/// `JointStatus` changes.
type Column = (&'static str, &'static str, fn(&JointStatus) -> String);

/// The per-joint columns, in order (documented in `docs/monitor.md` §1.1).
pub const JOINT_COLUMNS: [Column; 14] = [
    ("phi", "_deg", |s| num(s.phi_deg)),
    ("rate", "_deg_s", |s| num(s.rate_deg_s)),
    ("coulomb", "_nm", |s| num(s.coulomb_nm)),
    ("coulomb", "_sd_nm", |s| num(s.coulomb_sd_nm)),
    ("viscous", "_nms", |s| num(s.viscous_nms)),
    ("viscous", "_sd_nms", |s| num(s.viscous_sd_nms)),
    ("viscous", "_obs", |s| s.viscous.as_str().into()),
    ("latch", "", |s| s.latch.as_str().into()),
    ("margin", "_pct", |s| {
        s.margin_pct.map(num).unwrap_or_default()
    }),
    ("prediction", "", |s| s.prediction.as_str().into()),
    ("confidence", "", |s| num(s.confidence)),
    ("time_to_latch", "_s", |s| {
        s.time_to_latch_s.map(num).unwrap_or_default()
    }),
    ("faults", "", |s| fault_names(s)),
    ("resolution", "", |s| s.resolution.as_str().into()),
];

fn fault_names(s: &JointStatus) -> String {
    s.faults
        .iter()
        .map(|f| f.as_str())
        .collect::<Vec<_>>()
        .join("|")
}

/// The header of the status CSV for `joints` joints.
pub fn status_header(joints: usize) -> Vec<String> {
    let mut h = vec!["t_s".to_string()];
    for j in 1..=joints {
        for (pre, post, _) in JOINT_COLUMNS {
            h.push(format!("{pre}{j}{post}"));
        }
    }
    h
}

/// Writes the status stream as CSV: [`status_header`], then one row per status.
pub fn write_status_csv<W: Write>(out: W, statuses: &[StatusRow]) -> io::Result<()> {
    let joints = statuses.first().map_or(0, |s| s.joints.len());
    let mut w = csv::Writer::from_writer(out);
    w.write_record(status_header(joints))?;
    for s in statuses {
        let mut row = vec![num(s.t_s)];
        for js in &s.joints {
            row.extend(JOINT_COLUMNS.iter().map(|(_, _, f)| f(js)));
        }
        w.write_record(row)?;
    }
    w.flush()
}
