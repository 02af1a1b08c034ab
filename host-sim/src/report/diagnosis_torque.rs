//! The residual torque in the diagnosis report and JSON
//! ([`crate::analysis::residual_torque`]): per joint, the torque the
//! baseline and the extended model lack, against angle and against rate,
//! with its band, and whether it is significant.

use crate::analysis::residual_torque::{Bin, JointTorque, TorqueSample};
use crate::model::findings::diagnosis::{JointResidualTorque, TorqueBin};
use crate::report::markdown::{file_name, image};
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

/// Bin centres, the bin means, and the outline of the mean ± 2 se band
/// ([`plot::band`]) of one axis.
fn bin_lines(bins: &[Bin]) -> [Xy; 2] {
    let used: Vec<&Bin> = bins.iter().filter(|b| b.n > 0).collect();
    let x: Vec<f64> = used
        .iter()
        .map(|b| 0.5 * (b.range[0] + b.range[1]))
        .collect();
    let m = used.iter().map(|b| b.mean_nm).collect();
    let lo: Vec<f64> = used.iter().map(|b| b.mean_nm - 2.0 * b.se_nm).collect();
    let hi: Vec<f64> = used.iter().map(|b| b.mean_nm + 2.0 * b.se_nm).collect();
    let band = plot::band(&x, &lo, &hi);
    [(x, m), band]
}

/// The samples of one axis, thinned to [`MAX_DOTS`].
fn dots(s: &[TorqueSample], key: fn(&TorqueSample) -> f64) -> Xy {
    let step = s.len().div_ceil(MAX_DOTS).max(1);
    s.iter()
        .step_by(step)
        .map(|t| (key(t), t.torque_nm))
        .unzip()
}

/// The points of a joint's figure, per axis (angle, rate): the samples,
/// the bin means, the ±2 se band's outline.
type FigureData = Vec<(Xy, [Xy; 2])>;

/// The two axes of a joint's figure: angle and rate.
fn axes(t: &JointTorque) -> [Axis<'_>; 2] {
    [
        ("angle [deg]", |s| s.phi_deg, &t.by_angle),
        ("rate [deg/s]", |s| s.rate_deg_s, &t.by_rate),
    ]
}

/// The points drawn in a joint's figure ([`torque_panels`]).
fn figure_data(t: &JointTorque) -> FigureData {
    axes(t)
        .iter()
        .map(|(_, key, bins)| (dots(&t.samples, *key), bin_lines(bins)))
        .collect()
}

/// One joint's figure: residual torque against angle and against rate,
/// each panel over its own x axis; samples as dots, the bin means as a
/// line, their ±2 se band filled, the zero line unlabelled.
fn torque_panels<'a>(
    t: &JointTorque,
    data: &'a FigureData,
) -> Vec<(Panel<'a>, YAxis, &'static str)> {
    let axis = YAxis {
        limits: Some(y_limits(t)),
        lines: vec![(0.0, String::new())],
    };
    let names = [("angle", "angle [deg]"), ("rate", "rate [deg/s]")];
    data.iter()
        .zip(names)
        .map(|((d, b), (what, x_label))| {
            let panel = Panel {
                title: format!("joint {}: residual torque vs {what}", t.joint),
                y_label: "torque [N·m]".into(),
                series: vec![
                    Series::new("samples", &d.0, &d.1, Mark::Dots, 5),
                    Series::new("±2 se of the bin mean", &b[1].0, &b[1].1, Mark::Band, 6),
                    Series::new("bin mean", &b[0].0, &b[0].1, Mark::Line, 0),
                ],
                markers: Vec::new(),
            };
            (panel, axis.clone(), x_label)
        })
        .collect()
}

/// Draws one joint's figure ([`torque_panels`]) to `path`.
fn joint_figure(path: &Path, label: &str, t: &JointTorque) -> Result<(), plot::PlotError> {
    let data = figure_data(t);
    let title = format!("residual torque at joint {} ({label})", t.joint);
    plot::draw_panels(path, &title, &torque_panels(t, &data))
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
) -> Result<(), plot::PlotError> {
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
            let alt = format!("residual torque at joint {} ({label})", t.joint);
            let _ = writeln!(md, "{}\n", image(&alt, &file_name(&file)));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bin(range: [f64; 2], mean_nm: f64) -> Bin {
        Bin {
            range,
            n: 10,
            mean_nm,
            se_nm: 0.01,
        }
    }

    /// The figure a reader sees: each panel over its own axis, a legend
    /// without an empty entry, the ±2 se band one filled entry.
    #[test]
    fn the_torque_figure_labels_each_axis_and_draws_the_band_as_one_area() {
        let t = JointTorque {
            joint: 2,
            stowed_deg: 90.0,
            samples: Vec::new(),
            by_angle: vec![bin([0.0, 10.0], 0.1), bin([10.0, 20.0], 0.2)],
            by_rate: vec![bin([-5.0, 0.0], 0.0), bin([0.0, 5.0], 0.3)],
            chi2: 0.0,
            max_z: 0.0,
            significant: false,
            rms_nm: 0.0,
        };
        let data = figure_data(&t);
        let panels = torque_panels(&t, &data);
        let x_labels: Vec<&str> = panels.iter().map(|p| p.2).collect();
        assert_eq!(x_labels, ["angle [deg]", "rate [deg/s]"]);
        for (panel, axis, _) in &panels {
            let legend = plot::legend_entries(panel, axis);
            assert_eq!(legend, ["±2 se of the bin mean", "bin mean", "samples"]);
            let band = &panel.series[1];
            assert_eq!(band.mark, Mark::Band);
            // The outline: lower edge forward, upper edge back.
            assert_eq!(band.x.len(), 4);
            assert!(
                band.y[0] < band.y[3] && band.y[1] < band.y[2],
                "{:?}",
                band.y
            );
        }
    }
}
