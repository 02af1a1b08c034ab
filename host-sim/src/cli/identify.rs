//! `deploywatch identify`: the equivalent friction torque (EFT, `physics.md`
//! 4) of each joint from measured runs, by the direct least-squares method or
//! by the response surface of seed 000 ([`crate::analysis::identify`]).
//!
//! Prints a table of EFTs per joint (with 95 % intervals for `direct`), the
//! fit quality (RMS before/after, seed 000 Eq. 14 trajectory errors), the
//! number of simulations and the wall time; writes the same as JSON with
//! `--json` and a PNG of measured vs simulated angles before and after
//! (like seed 001 Figs. 10/11) with `--plot`, by default beside the JSON.

use super::{check_output, CliError, Console};
use crate::analysis::campaign_sim::CampaignSim;
use crate::analysis::identify::by_rsm::identify_rsm;
use crate::analysis::identify::direct::identify_direct;
use crate::analysis::identify::{
    self, DirectOptions, Identification, Method, ParseNameError, RsmOptions, RsmResponse,
};
use crate::data::campaign::{Campaign, CampaignRun};
use crate::report::files::Outputs;
use crate::report::plot::{self, Mark, Panel, Series, YAxis};
use crate::report::text::list;
use crate::simulate::deployment::{self, Trajectory};
use std::path::{Path, PathBuf};

/// Arguments of `deploywatch identify`.
#[derive(Debug, clap::Args)]
pub struct IdentifyArgs {
    /// A mechanism file (TOML, docs/spec/formats.md); repeat for runs of
    /// several mechanisms. Each run is paired with the mechanism its
    /// `mechanism` metadata names.
    #[arg(long = "mechanism", value_name = "M.toml", required = true)]
    pub mechanisms: Vec<PathBuf>,

    /// Measured runs (CSV, docs/spec/formats.md). The EFTs are common to all.
    #[arg(value_name = "RUN.csv", required = true)]
    pub runs: Vec<PathBuf>,

    /// `direct` (least squares over the trajectories, with 95 % intervals)
    /// or `rsm` (seed 000's response surface on a central composite design).
    #[arg(long, default_value = "direct", value_parser = parse_method)]
    pub method: Method,

    /// Joints to identify (1-based, comma-separated); default: all.
    #[arg(long, value_name = "J,J,..", value_delimiter = ',')]
    pub joints: Option<Vec<usize>>,

    /// Write the result as JSON here.
    #[arg(long, value_name = "OUT.json")]
    pub json: Option<PathBuf>,

    /// Draw measured vs simulated (before/after) angles into this PNG;
    /// default: beside the JSON (OUT.png), none without --json.
    #[arg(long, value_name = "OUT.png")]
    pub plot: Option<PathBuf>,

    /// direct: start [N·m], one value per identified joint; default: the
    /// per-joint best of a scan of uniform EFTs (0 to 3.2 N·m).
    #[arg(long, value_name = "NM,NM,..", value_delimiter = ',')]
    pub start: Option<Vec<f64>>,

    /// rsm: design centre [N·m], one value per identified joint; default:
    /// the per-joint best of a scan of uniform EFTs (at least 0.025 N·m).
    #[arg(long, alias = "centre", value_name = "NM,NM,..", value_delimiter = ',')]
    pub center: Option<Vec<f64>>,

    /// rsm: half-ranges [N·m] (coded ±1), one value per identified joint;
    /// default: half the centre (seed 000 Table 9's relative ranges).
    #[arg(long, value_name = "NM,NM,..", value_delimiter = ',')]
    pub range: Option<Vec<f64>>,

    /// rsm: the response minimised: `te` (sum of the joints' trajectory
    /// errors, seed 000 Eq. 14) or `mse` (mean squared angle residual).
    #[arg(long, default_value = "te", value_parser = parse_response)]
    pub response: RsmResponse,

    /// rsm: rounds of the design; 1 is seed 000's single CCD, each further
    /// round re-centres on the last minimum with half the half-ranges
    /// (sequential RSM). Default: 1.
    #[arg(long, value_name = "N")]
    pub rounds: Option<usize>,

    /// No progress and no chatter: the result table, errors and warnings
    /// only; the JSON and PNG are written as usual.
    #[arg(long, short)]
    pub quiet: bool,
}

fn parse_method(s: &str) -> Result<Method, ParseNameError> {
    s.parse()
}

fn parse_response(s: &str) -> Result<RsmResponse, ParseNameError> {
    s.parse()
}

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

/// Runs `deploywatch identify`.
pub fn run(args: &IdentifyArgs) -> Result<(), CliError> {
    // The loaders' errors name the file, the line or key, and what was expected.
    let campaign =
        Campaign::load(&args.mechanisms, &args.runs).map_err(|e| CliError::input(e.to_string()))?;
    let joints = args
        .joints
        .clone()
        .unwrap_or_else(|| identify::all_joints(&campaign));
    identify::check_joints(&campaign, &joints)
        .map_err(|e| CliError::input(format!("--joints: {e}")))?;
    let direct_only = [("--start", args.start.is_some())];
    let rsm_only = [
        ("--center", args.center.is_some()),
        ("--range", args.range.is_some()),
        ("--rounds", args.rounds.is_some()),
    ];
    let misplaced = match args.method {
        Method::Direct => rsm_only.iter().find(|(_, given)| *given),
        Method::Rsm => direct_only.iter().find(|(_, given)| *given),
    };
    if let Some((flag, _)) = misplaced {
        return Err(CliError::input(format!(
            "{flag} does not apply to --method {}",
            args.method.name()
        )));
    }
    let png = args
        .plot
        .clone()
        .or_else(|| args.json.as_ref().map(|j| j.with_extension("png")));
    if let Some(json) = &args.json {
        check_output("--json", json)?;
    }
    if let Some(png) = &png {
        check_output(
            if args.plot.is_some() {
                "--plot"
            } else {
                "the plot beside --json"
            },
            png,
        )?;
    }
    let console = Console::new(args.quiet);
    for w in crate::data::inputs::campaign_warnings(&args.mechanisms, &campaign) {
        console.warn(w);
    }
    let id = identify_with(args, &campaign, &joints, &console)?;
    super::print_out(format_args!("{}", report(&campaign, &id)));
    // On the zero-g rig: the margin on orbit beside the margin on the rig.
    let quiet = crate::report::progress::quiet;
    if let Some(s) = crate::analysis::rig_margin::split(&campaign, &id.effects(), &quiet) {
        super::print_out(format_args!("\n{}", crate::report::rig_split::section(&s)));
    }
    warn_residuals(&campaign, &id, &console);
    let mut outs = Outputs::new();
    if let Some(path) = &args.json {
        outs.write(path, id.to_json() + "\n")?;
    }
    if let Some(png) = &png {
        plot_fit(&outs.path(png)?, &campaign, &id).map_err(|e| CliError::failed(e.to_string()))?;
    }
    outs.commit()?;
    if let Some(path) = &args.json {
        console.say(format_args!("json: {}", path.display()));
    }
    match png {
        Some(png) => console.say(format_args!("plot: {}", png.display())),
        None => console
            .say("plot: none (give --plot OUT.png, or --json OUT.json to draw OUT.png beside it)"),
    }
    Ok(())
}

/// Warns when the identified friction leaves more than
/// [`identify::residual_check::RESIDUAL_WARN_FACTOR`] × the noise at some joint, and points
/// to `deploywatch diagnose`.
fn warn_residuals(campaign: &Campaign, id: &Identification, console: &Console) {
    let edge = at_design_edge(id);
    if !edge.is_empty() {
        console.warn(format_args!(
            "the EFT of joint(s) {} is at the edge of the design box: the best value may lie \
             beyond it; move --center or widen --range",
            list(&edge)
        ));
    }
    let warnings = identify::residual_check::residual_warnings(campaign, id);
    let Some(first) = warnings.first() else {
        return;
    };
    let mut text = format!(
        "the identified friction leaves more than {} times the noise RMS ({:.3} deg) at:",
        identify::residual_check::RESIDUAL_WARN_FACTOR,
        first.noise_deg
    );
    for w in &warnings {
        text += &format!("\n  {w}");
    }
    text += "\nfriction alone does not explain these runs: `deploywatch diagnose` \
             (same --mechanism and runs, --json OUT.json) looks for the cause";
    console.warn(text);
}

/// The joints whose response-surface EFT lies on the edge of the box the
/// surface was minimised in (not at the bound 0): the design did not
/// reach the minimum.
fn at_design_edge(id: &Identification) -> Vec<usize> {
    let Some(r) = &id.rsm else {
        return Vec::new();
    };
    let on = |v: f64, edge: f64| (v - edge).abs() <= 1e-9 * edge.abs().max(1e-12);
    id.joints
        .iter()
        .zip(&r.box_nm)
        .filter(|(j, [lo, hi])| on(j.coulomb_nm, *hi) || (*lo > 0.0 && on(j.coulomb_nm, *lo)))
        .map(|(j, _)| j.joint)
        .collect()
}

/// Runs the chosen method with the arguments' options.
fn identify_with(
    args: &IdentifyArgs,
    campaign: &Campaign,
    joints: &[usize],
    console: &Console,
) -> Result<Identification, CliError> {
    let result = match args.method {
        Method::Direct => identify_direct(
            campaign,
            joints,
            &DirectOptions {
                start_nm: args.start.clone(),
                ..DirectOptions::default()
            },
            console.progress(),
        ),
        Method::Rsm => identify_rsm(
            campaign,
            joints,
            &RsmOptions {
                centre_nm: args.center.clone(),
                half_range_nm: args.range.clone(),
                response: args.response,
                rounds: args.rounds.unwrap_or(1),
                ..RsmOptions::default()
            },
            console.progress(),
        ),
    };
    result.map_err(|e| match e {
        identify::IdentifyError::BadOption(m) => CliError::input(m),
        other => CliError::failed(other.to_string()),
    })
}

/// The human report: EFT table, fit quality, cost.
pub fn report(campaign: &Campaign, id: &Identification) -> String {
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
        eft_table(id) + &node_note(campaign, id),
        fit_quality(id),
        method_details(id),
        id.simulations,
        id.deployments,
        id.wall_s
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
        let _ = writeln!(
            s,
            "  {}: RMS {:.4} -> {:.4} deg; trajectory error per joint [%] {} -> {}",
            a.run,
            b.rms_deg,
            a.rms_deg,
            te(&b.trajectory_error_pct),
            te(&a.trajectory_error_pct)
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
            list(&d.start_nm),
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
            list(&r.centre_nm),
            list(&r.half_range_nm),
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
