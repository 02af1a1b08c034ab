//! The residual torque in the diagnosis report and JSON
//! ([`crate::analysis::residual_torque`]): per joint, the torque the
//! baseline and the extended model lack, against angle and against rate,
//! with its band, and whether it is significant.

use super::CliError;
use crate::analysis::residual_torque::{Bin, JointTorque, TorqueSample};
use crate::model::findings::diagnosis::{JointResidualTorque, TorqueBin};
use crate::report::plot::{self, Mark, Panel, Series, YAxis};
use std::fmt::Write as _;
use std::path::Path;

/// Most samples drawn as dots per panel (every k-th beyond it).
const MAX_DOTS: usize = 3000;

/// Points `(x, y)` of one curve.
type Xy = (Vec<f64>, Vec<f64>);

/// One axis of a figure: its label, the sample's value on it, its bins.
type Axis<'a> = (&'a str, fn(&TorqueSample) -> f64, &'a [Bin]);

/// `x` to four decimals, or `None` when it is not finite.
fn r4(x: f64) -> Option<f64> {
    x.is_finite().then(|| (x * 1e4).round() / 1e4)
}

/// The bins that hold samples, for the JSON.
fn bins_json(bins: &[Bin]) -> Vec<TorqueBin> {
    bins.iter()
        .filter(|b| b.n > 0)
        .map(|b| TorqueBin {
            from: r4(b.range[0]),
            to: r4(b.range[1]),
            n: b.n,
            mean_nm: r4(b.mean_nm),
            se_nm: r4(b.se_nm),
        })
        .collect()
}

/// The residual torque of each joint against a model, for the JSON.
pub fn torque_json(res: &[JointTorque]) -> Vec<JointResidualTorque> {
    res.iter()
        .map(|t| JointResidualTorque {
            joint: t.joint,
            significant: t.significant,
            chi2: r4(t.chi2),
            max_bin_z: r4(t.max_z),
            rms_nm: r4(t.rms_nm),
            samples: t.samples.len(),
            description: t.describe(),
            by_angle_deg: bins_json(&t.by_angle),
            by_rate_deg_s: bins_json(&t.by_rate),
        })
        .collect()
}

/// Bin centres, means and the mean ± 2 se band of one axis.
fn bin_lines(bins: &[Bin]) -> [Xy; 3] {
    let used: Vec<&Bin> = bins.iter().filter(|b| b.n > 0).collect();
    let x: Vec<f64> = used
        .iter()
        .map(|b| 0.5 * (b.range[0] + b.range[1]))
        .collect();
    let m = used.iter().map(|b| b.mean_nm).collect();
    let lo = used.iter().map(|b| b.mean_nm - 2.0 * b.se_nm).collect();
    let hi = used.iter().map(|b| b.mean_nm + 2.0 * b.se_nm).collect();
    [(x.clone(), m), (x.clone(), lo), (x, hi)]
}

/// The samples of one axis, thinned to [`MAX_DOTS`].
fn dots(s: &[TorqueSample], key: fn(&TorqueSample) -> f64) -> Xy {
    let step = s.len().div_ceil(MAX_DOTS).max(1);
    s.iter()
        .step_by(step)
        .map(|t| (key(t), t.torque_nm))
        .unzip()
}

/// One joint's figure: residual torque against angle and against rate,
/// samples as dots, bin means with their ±2 se band as lines.
fn joint_figure(path: &Path, label: &str, t: &JointTorque) -> Result<(), CliError> {
    let axes: [Axis; 2] = [
        ("angle [deg]", |s| s.phi_deg, &t.by_angle),
        ("rate [deg/s]", |s| s.rate_deg_s, &t.by_rate),
    ];
    let data: Vec<(Xy, [Xy; 3])> = axes
        .iter()
        .map(|(_, key, bins)| (dots(&t.samples, *key), bin_lines(bins)))
        .collect();
    let panels: Vec<Panel> = axes
        .iter()
        .zip(&data)
        .map(|((what, _, _), (d, b))| Panel {
            title: format!("joint {}: residual torque vs {what}", t.joint),
            y_label: "torque [N·m]".into(),
            series: vec![
                Series {
                    label: "samples".into(),
                    x: &d.0,
                    y: &d.1,
                    mark: Mark::Dots,
                    color: 5,
                },
                Series {
                    label: "bin mean".into(),
                    x: &b[0].0,
                    y: &b[0].1,
                    mark: Mark::Line,
                    color: 0,
                },
                Series {
                    label: "−2 se".into(),
                    x: &b[1].0,
                    y: &b[1].1,
                    mark: Mark::Line,
                    color: 6,
                },
                Series {
                    label: "+2 se".into(),
                    x: &b[2].0,
                    y: &b[2].1,
                    mark: Mark::Line,
                    color: 6,
                },
            ],
            markers: Vec::new(),
        })
        .collect();
    let axis = YAxis {
        limits: Some(y_limits(t)),
        lines: vec![(0.0, String::new())],
    };
    let with_axes: Vec<(Panel, YAxis)> = panels.into_iter().map(|p| (p, axis.clone())).collect();
    let title = format!("residual torque at joint {} ({label})", t.joint);
    plot::draw_with_axes(path, &title, "angle [deg] / rate [deg/s]", &with_axes)
        .map_err(|e| CliError::failed(e.to_string()))
}

/// The y range of a joint's figure [N·m]: the 5th to 95th percentile of
/// its samples, widened by half (the few samples near a latch, whose band
/// is wide, are drawn at the frame instead of squashing the rest).
fn y_limits(t: &JointTorque) -> (f64, f64) {
    let mut v: Vec<f64> = t.samples.iter().map(|s| s.torque_nm).collect();
    v.sort_by(f64::total_cmp);
    let q = |p: f64| {
        v.get(((v.len().saturating_sub(1)) as f64 * p) as usize)
            .copied()
    };
    match (q(0.05), q(0.95)) {
        (Some(a), Some(b)) if b > a => (a - 0.5 * (b - a), b + 0.5 * (b - a)),
        _ => (-1.0, 1.0),
    }
}

/// The report section: per joint, the residual torque the baseline and the
/// extended model leave, in words and plotted against angle and rate.
pub fn report_torque(
    md: &mut String,
    dir: &Path,
    stem: &str,
    before: &[JointTorque],
    after: &[JointTorque],
) -> Result<(), CliError> {
    let _ = writeln!(
        md,
        "## Residual torque from the data\n\nThe torque each model lacks, from the smoothed runs and the chain equations (inverse dynamics), against angle and rate; the band is ±2 standard errors of the bin means.\n"
    );
    for (label, res) in [("baseline", before), ("extended", after)] {
        let _ = writeln!(md, "### {label}\n");
        for t in res {
            let _ = writeln!(md, "- {}", t.describe());
        }
        let _ = writeln!(md);
        for t in res.iter().filter(|t| !t.samples.is_empty()) {
            let file = dir.join(format!("{stem}_torque_{label}_j{}.png", t.joint));
            joint_figure(&file, label, t)?;
            let name = file
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            let _ = writeln!(
                md,
                "![residual torque at joint {} ({label})]({name})\n",
                t.joint
            );
        }
    }
    Ok(())
}
