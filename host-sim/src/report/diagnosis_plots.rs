//! The diagnosis report's figures: each discovered torque against angle and
//! rate with its 95 % band, and each run's angles and residuals with the
//! baseline and the extended model.

use crate::analysis::diagnose::Outcome;
use crate::analysis::diagnosis_details::RunModels;
use crate::data::campaign::Campaign;
use crate::model::torque_table::HostTable;
use crate::report::markdown;
use crate::report::plot::{self, Mark, Panel, PlotError, Series};
use std::fmt::Write as _;
use std::path::Path;

/// The points of one table as plot series: the fitted table and its band,
/// extended flat by a tenth of the span beyond the end points (the table is
/// held constant there).
fn table_series(tables: &[Option<&HostTable>; 3]) -> Option<[(Vec<f64>, Vec<f64>); 3]> {
    let mid = tables[0]?;
    let (x0, x1) = (mid.xs()[0], mid.xs()[mid.xs().len() - 1]);
    let pad = 0.1 * (x1 - x0);
    let xs: Vec<f64> = (0..=100)
        .map(|i| x0 - pad + (x1 - x0 + 2.0 * pad) * i as f64 / 100.0)
        .collect();
    let line = |t: Option<&HostTable>| {
        let t = t.unwrap_or(mid);
        (
            xs.clone(),
            xs.iter().map(|&x| t.eval(x)).collect::<Vec<f64>>(),
        )
    };
    Some([line(Some(mid)), line(tables[1]), line(tables[2])])
}

/// Discovered torques: the shape in words, and a plot of the torque against
/// angle and rate with its 95 % band, drawn into `dir` as `STEM_tableK_*.png`.
pub fn report_tables(
    md: &mut String,
    dir: &Path,
    stem: &str,
    o: &Outcome,
) -> Result<(), PlotError> {
    for k in 0..o.extended.members.len() {
        let Some((_, shape, t)) = o.extended.table_of(k) else {
            continue;
        };
        let _ = writeln!(
            md,
            "## Discovered torque at joint {}\n\n{shape}.\n",
            o.extended.members[k].candidate.joint.unwrap_or(0)
        );
        let angle = table_series(&[
            t[0].angle.as_ref(),
            t[1].angle.as_ref(),
            t[2].angle.as_ref(),
        ]);
        let rate = table_series(&[t[0].rate.as_ref(), t[1].rate.as_ref(), t[2].rate.as_ref()]);
        for (what, unit, series) in [
            ("angle", "angle [deg]", angle),
            ("rate", "rate [deg/s]", rate),
        ] {
            let Some(s) = series else { continue };
            let file = dir.join(format!("{stem}_table{}_{what}.png", k + 1));
            let panel = Panel {
                title: format!("torque vs {what} (95 % band)"),
                y_label: "torque [N·m]".into(),
                series: ["found", "lower 95 %", "upper 95 %"]
                    .iter()
                    .zip(&s)
                    .enumerate()
                    .map(|(i, (label, (x, y)))| Series {
                        label: (*label).into(),
                        x,
                        y,
                        mark: Mark::Line,
                        color: if i == 0 { 0 } else { 6 },
                    })
                    .collect(),
                markers: Vec::new(),
            };
            plot::draw(&file, &format!("discovered torque: {what}"), unit, &[panel])?;
            let _ = writeln!(
                md,
                "{}\n",
                markdown::image(&format!("torque vs {what}"), &markdown::file_name(&file))
            );
        }
    }
    Ok(())
}

/// Model minus measurement \[deg\], `[joint][sample]`.
fn residuals_of(model: &[Vec<f64>], measured: &[Vec<f64>]) -> Vec<Vec<f64>> {
    model
        .iter()
        .zip(measured)
        .map(|(m, y)| m.iter().zip(y).map(|(a, b)| a - b).collect())
        .collect()
}

/// Run `i`'s plots: measured vs baseline vs extended angles, and the
/// residuals before and after; nothing when a model could not simulate it.
pub fn report_run_plots(
    md: &mut String,
    dir: &Path,
    stem: &str,
    c: &Campaign,
    i: usize,
    models: &RunModels,
) -> Result<(), PlotError> {
    let (Some(base), Some(extd)) = (&models.baseline, &models.extended) else {
        return Ok(());
    };
    let run = &c.runs[i].run;
    let name = c.runs[i].name().trim_end_matches(".csv").to_string();
    // A label that tells runs apart by their folders names one file.
    let file = name.replace(['/', '\\'], "_");
    let rb = residuals_of(&base.phi_deg, &run.phi_deg);
    let re = residuals_of(&extd.phi_deg, &run.phi_deg);
    let mut pa = Vec::new();
    let mut pr = Vec::new();
    for j in 0..run.joints() {
        pa.push(Panel {
            title: format!("joint {}", j + 1),
            y_label: "angle [deg]".into(),
            series: vec![
                Series {
                    mark: Mark::Dots,
                    ..line("measured", &run.t_s, &run.phi_deg[j], 6)
                },
                line("baseline", &base.t_s, &base.phi_deg[j], 1),
                line("extended", &extd.t_s, &extd.phi_deg[j], 0),
            ],
            markers: Vec::new(),
        });
        pr.push(Panel {
            title: format!("joint {}: model − measured", j + 1),
            y_label: "residual [deg]".into(),
            series: vec![
                line("baseline", &run.t_s, &rb[j], 1),
                line("extended", &run.t_s, &re[j], 0),
            ],
            markers: Vec::new(),
        });
    }
    let angles = dir.join(format!("{stem}_{file}_angles.png"));
    let resid = dir.join(format!("{stem}_{file}_residuals.png"));
    let title = format!("{name}: measured vs baseline vs extended");
    plot::draw(&angles, &title, "time [s]", &pa)?;
    let title = format!("{name}: residuals before and after");
    plot::draw(&resid, &title, "time [s]", &pr)?;
    let _ = writeln!(
        md,
        "### {name}\n\n{}\n\n{}\n",
        markdown::image("angles", &markdown::file_name(&angles)),
        markdown::image("residuals", &markdown::file_name(&resid))
    );
    Ok(())
}

/// A line series.
fn line<'a>(label: &str, x: &'a [f64], y: &'a [f64], color: usize) -> Series<'a> {
    Series::new(label, x, y, Mark::Line, color)
}
