//! What `deploywatch identify` shows: the table of EFTs per joint (with
//! 95 % intervals for `direct`, the design box for `rsm`), the fit
//! quality, the method's details and cost, and the PNG of measured vs
//! simulated angles before and after (like seed 001 Figs. 10/11).

use crate::analysis::campaign_sim::CampaignSim;
use crate::analysis::identify::{Identification, Method};
use crate::data::campaign::{Campaign, CampaignRun};
use crate::report::plot::{self, Mark, Panel, Series, YAxis};
use crate::report::text::{list, list_4};
use crate::simulate::deployment::{self, Trajectory};
use std::path::Path;

/// Why the fit plot could not be drawn.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PlotFitError {
    /// A run could not be simulated, before or after the fit.
    #[error("cannot simulate run {run} for the plot: {source}")]
    Simulate {
        /// The run's name.
        run: String,
        /// Why.
        #[source]
        source: deployment::SimError,
    },
    /// The PNG could not be drawn.
    #[error(transparent)]
    Plot(#[from] plot::PlotError),
}

/// The summary printed on stdout: EFT table, fit quality, cost.
pub fn summary(campaign: &Campaign, id: &Identification) -> String {
    let runs: Vec<String> = campaign
        .runs
        .iter()
        .map(|r| format!("{} ({})", r.name(), r.mechanism.name))
        .collect();
    format!(
        "EFT identification, method {}, {} run(s): {}\n\n{}\n{}{}cost: {} simulations of the campaign ({} deployments), {:.2} s wall\n",
        id.method.name(),
        runs.len(),
        runs.join(", "),
        eft_table(id) + &node_note(campaign, id) + &own_friction_note(campaign, id),
        fit_quality(id),
        method_details(id),
        id.simulations,
        id.deployments,
        id.wall_s
    )
}

/// Where a mechanism gives its joints a friction of their own: that the
/// EFTs are added to it, with its values (`joint 1 0.8 N·m`); empty
/// otherwise.
fn own_friction_note(campaign: &Campaign, id: &Identification) -> String {
    let own: Vec<String> = id
        .joints
        .iter()
        .filter_map(|j| {
            let nm = campaign.own_coulomb_nm(j.joint);
            (nm > 0.0).then(|| format!("joint {} {nm} N·m", j.joint))
        })
        .collect();
    if own.is_empty() {
        return String::new();
    }
    format!(
        "  the EFTs are added to the mechanism's own Coulomb friction ({})\n",
        own.join(", ")
    )
}

/// For a truss wing: which identified joints are truss friction nodes
/// (`joint 3 (truss node F)`), one line each; empty otherwise.
fn node_note(campaign: &Campaign, id: &Identification) -> String {
    let Some(mech) = campaign.runs.first().map(|r| &r.mechanism) else {
        return String::new();
    };
    id.joints
        .iter()
        .filter(|j| j.joint > mech.joint_count())
        .map(|j| format!("  {}: on each pin at the node\n", mech.joint_label(j.joint)))
        .collect()
}

/// The EFT per joint, with its 95 % interval (direct) or design box (rsm).
fn eft_table(id: &Identification) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    match id.method {
        Method::Direct => {
            let _ = writeln!(
                s,
                "joint   EFT [N·m]     95 % CI [N·m]              sd [N·m]"
            );
            for j in &id.joints {
                let ci = j
                    .ci95
                    .map_or("-".to_string(), |[a, b]| format!("[{a:.6}, {b:.6}]"));
                let sd = j.sd_nm.map_or("-".to_string(), |v| format!("{v:.2e}"));
                let _ = writeln!(s, "{:>5}   {:<12.6}  {ci:<26} {sd}", j.joint, j.coulomb_nm);
            }
        }
        Method::Rsm => {
            let _ = writeln!(s, "joint   EFT [N·m]     design box [N·m]");
            let boxes = id
                .rsm
                .as_ref()
                .map(|r| r.box_nm.clone())
                .unwrap_or_default();
            for (i, j) in id.joints.iter().enumerate() {
                let b = boxes
                    .get(i)
                    .map_or("-".to_string(), |[a, b]| format!("[{a:.4}, {b:.4}]"));
                let _ = writeln!(s, "{:>5}   {:<12.6}  {b}", j.joint, j.coulomb_nm);
            }
        }
    }
    s
}

/// RMS before and after, per run with the trajectory errors.
fn fit_quality(id: &Identification) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let ratio = id.rms_deg_before / id.rms_deg_after;
    let _ = writeln!(
        s,
        "fit: RMS {:.4} deg before (mechanisms as given) -> {:.4} deg after (ratio {ratio:.1})",
        id.rms_deg_before, id.rms_deg_after
    );
    let te = |v: &[Option<f64>]| -> String {
        v.iter()
            .map(|t| t.map_or("-".into(), |t| format!("{t:.2}")))
            .collect::<Vec<_>>()
            .join("/")
    };
    for (b, a) in id.before.runs.iter().zip(&id.after.runs) {
        let (run, rms_b, rms_a) = (&a.run, b.rms_deg, a.rms_deg);
        let (te_b, te_a) = (te(&b.trajectory_error_pct), te(&a.trajectory_error_pct));
        let _ = writeln!(
            s,
            "  {run}: RMS {rms_b:.4} -> {rms_a:.4} deg; trajectory error per joint [%] {te_b} -> {te_a}"
        );
    }
    s
}

/// The solver's verdict (direct) or the design and its surfaces (rsm).
fn method_details(id: &Identification) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    if let Some(d) = &id.direct {
        let _ = writeln!(
            s,
            "  least squares: SSE {:.4} deg² over {} residuals, {}; start {} N·m ({}){}",
            d.sse_deg2,
            d.residuals,
            d.termination,
            list_4(&d.start_nm),
            d.start_rule,
            if d.fixed_at_zero.is_empty() {
                String::new()
            } else {
                format!("; fixed at the bound 0: joints {}", list(&d.fixed_at_zero))
            }
        );
    }
    if let Some(r) = &id.rsm {
        let _ = writeln!(
            s,
            "  design: {} points, α = {:.3}, centre {} ± {} N·m ({})",
            r.points_nm.len(),
            r.alpha,
            list_4(&r.centre_nm),
            list_4(&r.half_range_nm),
            r.design_rule
        );
        let r2: Vec<String> = r
            .responses
            .iter()
            .map(|x| format!("{} {:.4}", x.name, x.r2))
            .collect();
        let _ = writeln!(
            s,
            "  R² of the quadratic (seed 000 Eq. 15): {}",
            r2.join(", ")
        );
        let _ = writeln!(
            s,
            "  minimised {}: surface {:.4} at the minimum, simulated {:.4}",
            r.minimised, r.predicted, r.simulated
        );
    }
    s
}

/// Draws, per run and joint, the measured angles (dots, on top) with the
/// model before (the mechanism as given) and after (with the identified
/// EFTs): the layout of seed 001 Figs. 10/11; then, per run, a panel of
/// the residuals after the fit (model − measured) of every joint.
pub fn plot_fit(png: &Path, campaign: &Campaign, id: &Identification) -> Result<(), PlotFitError> {
    let mut before = Vec::new();
    let mut after = Vec::new();
    for (i, cr) in campaign.runs.iter().enumerate() {
        let failed = |source| PlotFitError::Simulate {
            run: cr.name(),
            source,
        };
        before.push(campaign.simulate(i, &[]).map_err(failed)?);
        after.push(campaign.simulate(i, &id.effects()).map_err(failed)?);
    }
    let residuals: Vec<Vec<Vec<f64>>> = campaign
        .runs
        .iter()
        .zip(&after)
        .map(|(cr, a)| {
            (0..cr.run.joints())
                .map(|j| {
                    a.phi_deg[j]
                        .iter()
                        .zip(&cr.run.phi_deg[j])
                        .map(|(m, y)| m - y)
                        .collect()
                })
                .collect()
        })
        .collect();
    let mut panels = Vec::new();
    for (i, cr) in campaign.runs.iter().enumerate() {
        for j in 0..cr.run.joints() {
            panels.push((
                angle_panel(cr, j, id, &before[i], &after[i]),
                YAxis::default(),
            ));
        }
        panels.push((
            Panel {
                title: format!("{}: residual after the fit (model − measured)", cr.name()),
                y_label: "residual [deg]".into(),
                series: residuals[i]
                    .iter()
                    .enumerate()
                    .map(|(j, r)| Series {
                        label: format!("joint {}", j + 1),
                        x: &cr.run.t_s,
                        y: r,
                        mark: Mark::Line,
                        color: j,
                    })
                    .collect(),
                markers: Vec::new(),
            },
            YAxis {
                limits: None,
                lines: vec![(0.0, "0".into())],
            },
        ));
    }
    plot::draw_with_axes(
        png,
        &format!(
            "EFT identification ({}): RMS {:.3} -> {:.4} deg",
            id.method.name(),
            id.rms_deg_before,
            id.rms_deg_after
        ),
        "time [s]",
        &panels,
    )?;
    Ok(())
}

/// One run's joint `j` (0-based): measured, before and after.
fn angle_panel<'a>(
    cr: &'a CampaignRun,
    j: usize,
    id: &Identification,
    before: &'a Trajectory,
    after: &'a Trajectory,
) -> Panel<'a> {
    let eft = id
        .eft(j + 1)
        .map_or("not identified".to_string(), |v| format!("EFT {v:.4} N·m"));
    Panel {
        title: format!("{} joint {} ({eft})", cr.name(), j + 1),
        y_label: "angle [deg]".into(),
        series: vec![
            Series {
                label: "before (as given)".into(),
                x: &before.t_s,
                y: &before.phi_deg[j],
                mark: Mark::Line,
                color: 1,
            },
            Series {
                label: format!("after ({})", id.method.name()),
                x: &after.t_s,
                y: &after.phi_deg[j],
                mark: Mark::Line,
                color: 0,
            },
            Series {
                label: "measured".into(),
                x: &cr.run.t_s,
                y: &cr.run.phi_deg[j],
                mark: Mark::Dots,
                color: 6,
            },
        ],
        markers: Vec::new(),
    }
}
