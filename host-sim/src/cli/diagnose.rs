//! `deploywatch diagnose`: what the simulation gets wrong on measured runs,
//! the named cause, the extended model and its gain — as the diagnosis JSON
//! of `docs/spec/formats.md` and a Markdown report with plots beside it
//! (written by [`crate::report::diagnosis`]).

use super::spinner::Spinner;
use super::{outln, CliError};
use crate::analysis::diagnose::{self, DiagnoseOptions};
use crate::analysis::diagnosis_details;
use crate::data::campaign::Campaign;
use crate::report::diagnosis::{markdown, next_step};
use crate::report::diagnosis_json::json_text;
use crate::report::diagnosis_words::summary;
use crate::report::files::Outputs;
use crate::report::rig_split;
use std::path::{Path, PathBuf};

/// Arguments of `deploywatch diagnose`.
#[derive(Debug, clap::Args)]
pub struct DiagnoseArgs {
    /// A mechanism (TOML); repeat for campaigns on several mechanisms. Each
    /// run is paired with the mechanism its `mechanism` metadata names.
    #[arg(long = "mechanism", required = true)]
    pub mechanisms: Vec<PathBuf>,
    /// Where to write the diagnosis JSON; the report (`.md`) and its plots
    /// (`.png`) go beside it.
    #[arg(long)]
    pub json: PathBuf,
    /// Most named effects the stepwise search adds (1 to 3; torque tables
    /// aside); a set that explains the runs better may name more, with a
    /// warning.
    #[arg(long, default_value_t = 3)]
    pub max_effects: usize,
    /// No progress on the terminal.
    #[arg(long, short)]
    pub quiet: bool,
    /// Stop the search after this many seconds and write the best model
    /// found so far, marked as such (Ctrl-C does the same).
    #[arg(long)]
    pub max_seconds: Option<f64>,
    /// The measured runs (CSV), one test campaign: the effects found are
    /// common to all of them.
    #[arg(required = true)]
    pub runs: Vec<PathBuf>,
}

/// The campaign of the arguments, with its warnings shown; a run too
/// short to diagnose is an error.
fn load_campaign(args: &DiagnoseArgs) -> Result<Campaign, CliError> {
    let campaign =
        Campaign::load(&args.mechanisms, &args.runs).map_err(|e| CliError::input(e.to_string()))?;
    for w in crate::data::inputs::campaign_warnings(&args.mechanisms, &campaign) {
        super::Console::new(args.quiet).warn(w);
    }
    for cr in &campaign.runs {
        if cr.run.len() < 20 {
            return Err(CliError::input(format!(
                "{}: {} samples is too short to diagnose (expected at least 20)",
                cr.source.display(),
                cr.run.len()
            )));
        }
    }
    Ok(campaign)
}

/// The search's options: `--max-effects`, `--max-seconds`, a stop flag
/// raised by Ctrl-C (the best set so far is then written, marked), and the
/// traces the environment asks for (`DEPLOYWATCH_TRACE`: every score and
/// verdict; `DEPLOYWATCH_TRACE_FORMS`: the friction forms' evidence).
fn options(args: &DiagnoseArgs) -> Result<DiagnoseOptions, CliError> {
    if args.max_effects == 0 || args.max_effects > 3 {
        return Err(CliError::input("--max-effects: expected 1, 2 or 3"));
    }
    if args.max_seconds.is_some_and(|s| !(s > 0.0)) {
        return Err(CliError::input(
            "--max-seconds: expected a positive number of seconds",
        ));
    }
    let stop = diagnose::StopFlag::default();
    let on_signal = stop.clone();
    // A second handler cannot be set (a test harness calling `run` twice):
    // Ctrl-C then ends the process as usual.
    let _ = ctrlc::set_handler(move || on_signal.raise());
    Ok(DiagnoseOptions {
        max_effects: args.max_effects,
        max_seconds: args.max_seconds,
        stop: Some(stop),
        trace: std::env::var_os("DEPLOYWATCH_TRACE").is_some(),
        trace_forms: std::env::var_os("DEPLOYWATCH_TRACE_FORMS").is_some(),
        ..DiagnoseOptions::default()
    })
}

/// Checks the JSON and the report beside it before the work: writable,
/// and neither of them one of the inputs.
fn check_outputs(args: &DiagnoseArgs) -> Result<(), CliError> {
    let inputs: Vec<&Path> = args
        .mechanisms
        .iter()
        .chain(&args.runs)
        .map(|p| p.as_path())
        .collect();
    let report = args.json.with_extension("md");
    super::check_outputs(
        &[
            super::Output::file("--json", &args.json),
            super::Output::file("the report beside --json", &report),
        ],
        &inputs,
    )
}

/// Runs `deploywatch diagnose`.
pub fn run(args: &DiagnoseArgs) -> Result<(), CliError> {
    let opts = options(args)?;
    check_outputs(args)?;
    let campaign = load_campaign(args)?;
    if !args.quiet {
        eprintln!(
            "diagnosing {} run(s) on {} worker threads",
            campaign.runs.len(),
            rayon::current_num_threads()
        );
    }
    let bar = Spinner::new(args.quiet);
    let sink = |line: &str| bar.line(line);
    let outcome = diagnose::diagnose(&campaign, &opts, &sink);
    bar.finish();
    // Flexible panels named: the wing as the search compared it.
    let campaign = diagnose::panel_mode::apply(&campaign, outcome.panel_mode.as_ref());
    // Encoders late on their switches: the angles as the fit compared them.
    let campaign = diagnose::encoder_delay::apply(&campaign, outcome.encoder_delay.as_ref());
    // Encoders off their panels within the declared free-play: the
    // angles with that taken out, as the fit compared them.
    let campaign = diagnose::free_play::apply(&campaign, &outcome.free_play);
    // Physical latches: all below is of the windows fitted (the free
    // motion, the runs to where the model follows them, or the whole
    // runs); the latch findings are of the whole runs.
    let campaign = match (&outcome.fitted_to, &outcome.free_window) {
        (Some(w), _) => diagnose::latch_window::apply(&campaign, w),
        (None, Some(w)) if !outcome.fitted_whole => diagnose::latch_window::apply(&campaign, w),
        _ => campaign,
    };
    if !outcome.baseline.sse().is_finite() {
        return Err(CliError::failed(
            "the mechanisms as given cannot be simulated against these runs",
        ));
    }
    let details = diagnosis_details::details(&campaign, &outcome);
    // All or none: the JSON, the report and its plots are staged and moved
    // into place together, the report last.
    let mut outs = Outputs::new();
    let json =
        json_text(&campaign, &outcome, &details).map_err(|e| CliError::failed(e.to_string()))?;
    outs.write(&args.json, json)?;
    let report = args.json.with_extension("md");
    let staged = outs.path(&report)?;
    let md = markdown(
        staged.parent().unwrap_or(Path::new(".")),
        &file_stem(&report),
        &campaign,
        &outcome,
        &details,
        &next_step(
            &args.json,
            &args.mechanisms,
            !outcome.extended.effects().is_empty(),
        ),
    )
    .map_err(|e| CliError::failed(e.to_string()))?;
    // On the zero-g rig: the margin on orbit beside the margin on the rig.
    let bar = Spinner::new(args.quiet);
    let sink = |line: &str| bar.line(line);
    let rig = rig_split::for_campaign(&campaign, &outcome.extended.effects(), &sink);
    bar.finish();
    let md = match &rig {
        Some(sec) => format!("{md}\n{sec}"),
        None => md,
    };
    outs.write(&report, md)?;
    outs.commit()?;
    for line in summary(&outcome, &details, &args.json, &report) {
        outln!("{line}");
    }
    if let Some(sec) = &rig {
        outln!("\n{sec}");
    }
    warn_beyond_max_effects(&outcome, args.max_effects);
    Ok(())
}

/// Warns when the diagnosis names more effects than `--max-effects`: the
/// search adds at most that many, a better set found later may name more.
fn warn_beyond_max_effects(outcome: &diagnose::Outcome, max: usize) {
    let members = outcome.extended.members.iter();
    let named = members.filter(|m| m.candidate.table.is_none()).count();
    if named > max {
        super::Console::new(false).warn(format_args!(
            "the diagnosis names {named} effects, more than --max-effects {max}: the search adds \
             at most {max} (torque tables aside), and a set that explains the runs better (an \
             alternative alike, a named law in a table's place) may name more (docs/diagnosis.md)"
        ));
    }
}

/// The file name of `path` without its extension (the prefix of the
/// report's plots).
fn file_stem(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "diagnosis".into())
}
