//! `deploywatch identify`: the equivalent friction torque (EFT, `physics.md`
//! 4) of each joint from measured runs, by the direct least-squares method or
//! by the response surface of seed 000 ([`crate::analysis::identify`]).
//!
//! Prints a table of EFTs per joint (with 95 % intervals for `direct`), the
//! fit quality (RMS before/after, seed 000 Eq. 14 trajectory errors), the
//! number of simulations and the wall time; writes the same as JSON with
//! `--json` and a PNG of measured vs simulated angles before and after
//! (like seed 001 Figs. 10/11) with `--plot`, by default beside the JSON
//! (both written by [`crate::report::identify`]).

use super::{check_outputs, CliError, Console, Output};
use crate::analysis::diagnose::latch_window::free_campaign;
use crate::analysis::identify::by_rsm::{centre_beyond, identify_rsm};
use crate::analysis::identify::direct::identify_direct;
use crate::analysis::identify::{
    self, BeyondDesign, DirectOptions, Identification, Method, ParseNameError, RsmOptions,
    RsmResponse,
};
use crate::analysis::identify_edge;
use crate::data::campaign::Campaign;
use crate::report::files::Outputs;
use crate::report::identify::{plot_fit, summary};
use crate::report::text::list;
use std::path::PathBuf;

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
    /// per-joint best of a scan of uniform EFTs (0 to 3.2 N·m), or its best
    /// uniform value where that fits better.
    #[arg(
        long,
        value_name = "NM,NM,..",
        value_delimiter = ',',
        allow_hyphen_values = true
    )]
    pub start: Option<Vec<f64>>,

    /// rsm: design centre [N·m], one value per identified joint; default:
    /// the per-joint best of a scan of uniform EFTs (at least 0.025 N·m).
    #[arg(
        long,
        alias = "centre",
        value_name = "NM,NM,..",
        value_delimiter = ',',
        allow_hyphen_values = true
    )]
    pub center: Option<Vec<f64>>,

    /// rsm: half-ranges [N·m] (coded ±1), one value per identified joint;
    /// default: half the centre (seed 000 Table 9's relative ranges).
    #[arg(
        long,
        value_name = "NM,NM,..",
        value_delimiter = ',',
        allow_hyphen_values = true
    )]
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

/// The campaign to fit: runs of a physical latch cut to their free motion
/// (after the first contact the impact sequence is chaotic,
/// docs/identification.md), each run's window said; others as they are.
fn free_motion(campaign: Campaign, console: &Console) -> Campaign {
    match free_campaign(&campaign) {
        Some((free, windows)) => {
            for (cr, w) in campaign.runs.iter().zip(&windows) {
                if let Some(words) = w.words(&cr.name()) {
                    console.say(words);
                }
            }
            free
        }
        None => campaign,
    }
}

/// The method's options: each given only with its method, and in range.
fn check_options(args: &IdentifyArgs) -> Result<(), CliError> {
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
    for (flag, values) in [("--start", &args.start), ("--center", &args.center)] {
        if let Some(bad) = values
            .iter()
            .flatten()
            .find(|x| !(**x >= 0.0 && x.is_finite()))
        {
            return Err(CliError::input(format!(
                "{flag} {bad}: expected friction torques ≥ 0 [N·m], one per identified joint"
            )));
        }
    }
    if let Some(bad) = args
        .range
        .iter()
        .flatten()
        .find(|r| !(**r > 0.0 && r.is_finite()))
    {
        return Err(CliError::input(format!(
            "--range {bad}: expected positive half-ranges [N·m], one per identified joint"
        )));
    }
    // Without --range each half-range is half its centre: a centre of 0
    // leaves the design no range.
    if args.range.is_none() {
        if let Some(bad) = args.center.iter().flatten().find(|x| **x == 0.0) {
            return Err(CliError::input(format!(
                "--center {bad}: a centre of 0 N·m leaves the default half-range \
                 (half the centre) at 0; give a positive centre, or --range"
            )));
        }
    }
    Ok(())
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
    check_options(args)?;
    let png = args
        .plot
        .clone()
        .or_else(|| args.json.as_ref().map(|j| j.with_extension("png")));
    let inputs: Vec<&std::path::Path> = args
        .mechanisms
        .iter()
        .chain(&args.runs)
        .map(|p| p.as_path())
        .collect();
    let plot_flag = if args.plot.is_some() {
        "--plot"
    } else {
        "the plot beside --json"
    };
    let outputs: Vec<Output> = (args.json.as_deref().map(|p| Output::file("--json", p)))
        .into_iter()
        .chain(png.as_deref().map(|p| Output::plot(plot_flag, p)))
        .collect();
    check_outputs(&outputs, &inputs)?;
    let console = Console::new(args.quiet);
    for w in crate::data::inputs::campaign_warnings(&args.mechanisms, &campaign) {
        console.warn(w);
    }
    let campaign = free_motion(campaign, &console);
    let id = identify_with(args, &campaign, &joints, &console)?;
    super::print_out(format_args!("{}", summary(&campaign, &id)));
    // On the zero-g rig: the margin on orbit beside the margin on the rig.
    if let Some(sec) =
        crate::report::rig_split::for_campaign(&campaign, &id.effects(), console.progress())
    {
        super::print_out(format_args!("\n{sec}"));
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
    let edge = identify_edge::at_design_edge(id);
    if !edge.is_empty() {
        console.warn(format_args!(
            "the EFT of joint(s) {} is at the edge of the design box: the best value may lie \
             beyond it; move --center or widen --range",
            list(&edge)
        ));
    }
    if let Some(text) = held_at_zero_over_the_file(campaign, id) {
        console.warn(text);
    }
    if let Some(text) = never_moved(campaign, id) {
        console.warn(text);
    }
    if crate::analysis::evidence::noise_sigma_estimate(campaign).is_none() {
        console.warn(format_args!(
            "the runs are too short to estimate their noise (fewer than {} samples a joint): \
             the residual the fit leaves is not judged against it",
            crate::analysis::evidence::MIN_NOISE_DIFFERENCES + 3
        ));
        return;
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
    match id
        .rsm
        .as_ref()
        .and_then(|r| Some((r, r.beyond_design.as_ref()?)))
    {
        Some((r, b)) => text += &beyond_design_text(b, &r.centre_nm),
        None => {
            text += "\nfriction alone does not explain these runs: `deploywatch diagnose` \
                     (same --mechanism and runs, --json OUT.json) looks for the cause";
        }
    }
    console.warn(text);
}

/// The identified joints whose readings move by less than
/// [`crate::data::run::MIN_MOTION_DEG`] in every run, in a warning: any
/// friction that holds such a joint fits its runs, so its EFT and interval
/// are the solver's, not the runs' (a failed release, a stuck hinge).
fn never_moved(campaign: &Campaign, id: &Identification) -> Option<String> {
    let still = |j: usize| {
        campaign.runs.iter().all(|r| {
            r.run.phi_deg.get(j.wrapping_sub(1)).is_none_or(|phi| {
                let (lo, hi) = phi
                    .iter()
                    .filter(|x| x.is_finite())
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &x| {
                        (l.min(x), h.max(x))
                    });
                !(hi - lo >= crate::data::run::MIN_MOTION_DEG)
            })
        })
    };
    let joints: Vec<String> = id
        .joints
        .iter()
        .filter(|j| j.joint <= campaign.max_joints() && still(j.joint))
        .map(|j| format!("joint {} ({:.6} N·m)", j.joint, j.coulomb_nm))
        .collect();
    (!joints.is_empty()).then(|| {
        format!(
            "never moves by {} deg in these runs: {}. Any friction that holds it fits them: \
             its EFT is one such value, not a measurement, and its interval says nothing; the \
             runs say only that its friction is at least what holds it (a failed release, a \
             stuck hinge), and the other joints' EFTs are fitted with it held",
            crate::data::run::MIN_MOTION_DEG,
            joints.join(", ")
        )
    })
}

/// The joints the direct method fixed at the bound 0, their last free
/// fit's whole interval below 0, whose mechanism gives a friction of its
/// own, in a warning: the EFT is added to that friction and bounded at 0,
/// so runs that hold less friction than the file gives cannot show it
/// there (the others take up the difference). A joint fixed at 0 within
/// its noise is no finding.
fn held_at_zero_over_the_file(campaign: &Campaign, id: &Identification) -> Option<String> {
    let fixed = &id.direct.as_ref()?.clearly_below_zero;
    let own = |j: usize| campaign.own_coulomb_nm(j);
    let said: Vec<String> = fixed
        .iter()
        .filter(|&&j| own(j) > 0.0)
        .map(|&j| format!("joint {j} ({} N·m in the mechanism)", own(j)))
        .collect();
    (!said.is_empty()).then(|| {
        format!(
            "fixed at 0 on top of the mechanism's own friction: {}. The EFT is what the runs \
             add to that friction, at least 0: runs holding less friction than the file gives \
             show it as 0 here and move the other joints' EFTs. To find a joint's whole EFT, \
             identify against the mechanism with its `coulomb_nm` at 0",
            said.join(", ")
        )
    })
}

/// What the warning adds when least squares from the surface explains the
/// runs: its EFTs, and the `--center` to use unless that is the design's own.
fn beyond_design_text(b: &BeyondDesign, used: &[f64]) -> String {
    let advice = match centre_beyond(b, used) {
        Some(centre) => format!(
            "centre the design there (--center {}) or use --method direct",
            centre
                .iter()
                .map(|c| format!("{c:.3}"))
                .collect::<Vec<_>>()
                .join(",")
        ),
        None => "the design is already centred as near as it can be; use --method direct".into(),
    };
    format!(
        "\nfriction alone explains these runs where the response surface did not find it: least \
         squares \
         from {} gives {} N·m (RMS {:.4} deg, within {} times the noise at every joint); {advice}",
        b.start,
        b.coulomb_nm
            .iter()
            .map(|c| format!("{c:.4}"))
            .collect::<Vec<_>>()
            .join(", "),
        b.rms_deg,
        identify::residual_check::RESIDUAL_WARN_FACTOR,
    )
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
