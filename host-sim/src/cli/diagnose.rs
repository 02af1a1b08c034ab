//! `deploywatch diagnose`: what the simulation gets wrong on measured runs,
//! the named cause, the extended model and its gain — as the diagnosis JSON
//! of `docs/spec/formats.md` and a Markdown report with plots beside it.

use super::{diagnose_latch, diagnose_torque, outln, CliError};
use crate::analysis::campaign_sim::CampaignSim;
use crate::analysis::diagnose::{self, Candidate, DiagnoseOptions, Outcome, MIN_DELTA_BIC};
use crate::analysis::evidence::{self, JointEvidence, CORRELATES};
use crate::analysis::metrics::{self, TimeWindow};
use crate::analysis::residual_torque::{self, JointTorque};
use crate::analysis::table_export::{self, TableExport};
use crate::data::campaign::Campaign;
use crate::model::effect::{Effect, EffectKind};
use crate::model::findings::diagnosis::{
    Diagnosis, Evidence, Fit, FoundEffect, Gain, MonitorTable, Named, ResidualTorque, Round, Score,
};
use crate::model::findings::rounded;
use crate::model::torque_table::{HostTable, HostTorqueTable};
use crate::report::files::Outputs;
use crate::report::markdown;
use crate::report::plot::{self, Mark, Panel, Series};
use std::fmt::Write as _;
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
    /// Most effects to report.
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

/// The search's options: `--max-effects`, `--max-seconds`, and a stop
/// flag raised by Ctrl-C (the best set so far is then written, marked).
fn options(args: &DiagnoseArgs) -> Result<DiagnoseOptions, CliError> {
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
        ..DiagnoseOptions::default()
    })
}

/// Runs `deploywatch diagnose`.
pub fn run(args: &DiagnoseArgs) -> Result<(), CliError> {
    if args.max_effects == 0 || args.max_effects > 3 {
        return Err(CliError::input("--max-effects: expected 1, 2 or 3"));
    }
    super::check_output("--json", &args.json)?;
    super::check_output("the report beside --json", &args.json.with_extension("md"))?;
    let campaign = load_campaign(args)?;
    if !args.quiet {
        eprintln!(
            "diagnosing {} run(s) on {} worker threads",
            campaign.runs.len(),
            rayon::current_num_threads()
        );
    }
    let opts = options(args)?;
    let bar = diagnose_latch::Spinner::new(args.quiet);
    let sink = |line: &str| bar.line(line);
    let outcome = diagnose::diagnose(&campaign, &opts, &sink);
    bar.finish();
    // Runs of a physical latch: everything below is of the free motion the
    // effects were fitted on; the latch findings are of the whole runs.
    let campaign = match &outcome.free_window {
        Some(w) => diagnose::latch_window::apply(&campaign, w),
        None => campaign,
    };
    if !outcome.baseline.sse.is_finite() {
        return Err(CliError::failed(
            "the mechanisms as given cannot be simulated against these runs",
        ));
    }
    let before = evidence::analyse(&campaign, &[], outcome.noise_sigma_deg);
    let ext_effects = outcome.extended.effects();
    let after = evidence::analyse(&campaign, &ext_effects, outcome.noise_sigma_deg);
    let torque = [
        residual_torque::residual_torque(&campaign, &[]),
        residual_torque::residual_torque(&campaign, &ext_effects),
    ];
    let exports = table_export::export_tables(&campaign, &ext_effects);
    // All or none: the JSON, the report and its plots are staged and moved
    // into place together, the report last.
    let mut outs = Outputs::new();
    write_json(
        &outs.path(&args.json)?,
        &campaign,
        &outcome,
        &before,
        &torque,
        &exports,
    )?;
    let report = args.json.with_extension("md");
    let staged = outs.path(&report)?;
    write_report(
        &staged,
        &campaign,
        &outcome,
        [&before, &after],
        &torque,
        &next_step(args),
    )?;
    // On the zero-g rig: the margin on orbit beside the margin on the rig.
    let rig = crate::report::rig_split::add_to_report(&campaign, &ext_effects, &staged)
        .map_err(|e| CliError::failed(e.to_string()))?;
    outs.commit()?;

    print_outcome(args, &outcome, &exports, &report);
    if let Some(sec) = &rig {
        super::print_out(format_args!("\n{sec}"));
    }
    Ok(())
}

/// ` N·m` after a value, or `, a dimensionless fraction` for unit `1` (as
/// `simulate --help` says it).
fn unit_words(kind: EffectKind) -> String {
    match kind.unit() {
        "1" => ", a dimensionless fraction".to_string(),
        u => format!(" {u}"),
    }
}

fn effect_line(e: &Effect, o: &Outcome, k: usize) -> String {
    let (lo, hi) = ci_of(o, k);
    let mut s = format!(
        "{}{} = {:.5}{} (95 % CI {:.5} .. {:.5})",
        e.kind,
        e.joint
            .map(|j| format!(" at joint {j}"))
            .unwrap_or_default(),
        e.value,
        unit_words(e.kind),
        lo,
        hi
    );
    if e.kind == EffectKind::RigTilt {
        s += &format!(", alpha {:.1} deg", e.alpha_deg);
    }
    if let Some((_, shape, _)) = o.extended.table_of(k) {
        s += &format!(" (largest torque; {shape})");
    }
    if e.kind.is_rig() {
        s += " — of the test rig, not of the flight unit";
    }
    s
}

/// The 95 % interval of the k-th selected effect's value.
fn ci_of(o: &Outcome, k: usize) -> (f64, f64) {
    let ([lo, hi], _) = o.extended.effect_ci(k);
    (lo, hi)
}

/// Other candidates that explained the data as well (ΔBIC within
/// [`MIN_DELTA_BIC`] of the chosen one) in the round that chose `c`.
fn alternatives(o: &Outcome, c: Candidate) -> Vec<(Candidate, f64)> {
    for r in &o.rounds {
        if let Some(win) = r.scores.iter().find(|s| s.accepted && s.candidate == c) {
            return r
                .scores
                .iter()
                .filter(|s| s.candidate != c && win.delta_bic - s.delta_bic < MIN_DELTA_BIC)
                .map(|s| (s.candidate, win.delta_bic - s.delta_bic))
                .collect();
        }
    }
    Vec::new()
}

fn evidence_of(o: &Outcome, k: usize, c: Candidate) -> String {
    let mut s = String::new();
    for r in &o.rounds {
        if let Some(win) = r.scores.iter().find(|s| s.accepted && s.candidate == c) {
            let _ = write!(
                s,
                "{}: RMS {:.4} -> {:.4} deg, BIC gain {:.1}",
                r.what,
                r.start_rms_deg,
                win.fitted.rms(),
                win.delta_bic
            );
            if let Some(h) = win.held_out_rms_deg {
                let _ = write!(s, ", held-out RMS {h:.4} deg");
            }
        }
    }
    let _ = write!(
        s,
        "; without it the extended model's RMS is {:.4} deg",
        o.strength_rms_deg.get(k).copied().unwrap_or(f64::NAN)
    );
    let alt = alternatives(o, c);
    if !alt.is_empty() {
        let names: Vec<String> = alt
            .iter()
            .map(|(a, d)| format!("{} (BIC {d:.1} worse)", a.words()))
            .collect();
        let _ = write!(s, "; nearly as good: {}", names.join(", "));
    }
    s
}

/// Trajectory error per joint (seed 000 Eq. 14), averaged over the runs.
fn te_per_joint(c: &Campaign, effects: &[Effect]) -> Vec<Option<f64>> {
    let n = c.max_joints();
    let mut acc = vec![(0.0, 0usize); n];
    for i in 0..c.runs.len() {
        let Ok(traj) = c.simulate(i, effects) else {
            continue;
        };
        let r = &c.runs[i].run;
        if let Ok(te) = metrics::trajectory_errors_pct(
            &r.t_s,
            &traj.phi_deg,
            &r.phi_deg,
            &r.latch,
            TimeWindow::ALL,
        ) {
            for (j, v) in te.iter().enumerate() {
                if let Some(v) = v {
                    acc[j].0 += v;
                    acc[j].1 += 1;
                }
            }
        }
    }
    acc.iter()
        .map(|(s, k)| (*k > 0).then(|| s / *k as f64))
        .collect()
}

/// A list of numbers for the JSON, each [`rounded`].
fn rounded_all(x: &[f64]) -> Vec<Option<f64>> {
    x.iter().map(|y| rounded(*y)).collect()
}

/// A discovered `torque_table` in the JSON (`docs/spec/formats.md`): its
/// tables, the 95 % band of each knot, and the shape in one sentence.
fn add_tables(v: &mut FoundEffect, shape: &str, t: &[HostTorqueTable; 3]) {
    if let (Some(f), Some(lo), Some(hi)) = (&t[0].angle, &t[1].angle, &t[2].angle) {
        v.angle_deg = Some(rounded_all(f.xs()));
        v.torque_nm = Some(rounded_all(f.ys()));
        v.torque_ci95_nm = Some([rounded_all(lo.ys()), rounded_all(hi.ys())]);
    }
    if let (Some(g), Some(lo), Some(hi)) = (&t[0].rate, &t[1].rate, &t[2].rate) {
        v.rate_deg_s = Some(rounded_all(g.xs()));
        v.rate_torque_nm = Some(rounded_all(g.ys()));
        v.rate_torque_ci95_nm = Some([rounded_all(lo.ys()), rounded_all(hi.ys())]);
    }
    v.shape = Some(shape.to_string());
}

/// The monitor's export of a discovered table, in one line.
fn export_line(x: &TableExport) -> String {
    let points = |t: &Option<deploywatch_core::Table<f64>>| t.as_ref().map_or(0, |t| t.xs().len());
    let (na, nr) = (points(&x.table.angle), points(&x.table.rate));
    if !x.compressed {
        return format!(
            "monitor table at joint {}: as found ({na} angle and {nr} rate points), no loss",
            x.joint
        );
    }
    format!(
        "monitor table at joint {}: compressed to {na} angle and {nr} rate points; torque difference RMS {:.4} N·m (max {:.4}), re-simulated angles RMS {} deg",
        x.joint,
        x.torque_rms_nm,
        x.torque_max_nm,
        x.angle_rms_deg
            .map_or("n/a".to_string(), |a| format!("{a:.4}"))
    )
}

/// Puts each table's monitor export beside its `torque_table` in the JSON.
fn add_monitor_tables(effects: &mut [FoundEffect], exports: &[TableExport]) {
    for x in exports {
        let Some(v) = effects
            .iter_mut()
            .find(|e| e.name == EffectKind::TorqueTable.name() && e.joint == Some(x.joint))
        else {
            continue;
        };
        let xs = |t: &Option<deploywatch_core::Table<f64>>| t.as_ref().map(|t| rounded_all(t.xs()));
        let ys = |t: &Option<deploywatch_core::Table<f64>>| t.as_ref().map(|t| rounded_all(t.ys()));
        v.monitor_table = Some(MonitorTable {
            angle_deg: xs(&x.table.angle),
            torque_nm: ys(&x.table.angle),
            rate_deg_s: xs(&x.table.rate),
            rate_torque_nm: ys(&x.table.rate),
            compressed: x.compressed,
            torque_rms_diff_nm: rounded(x.torque_rms_nm),
            torque_max_diff_nm: rounded(x.torque_max_nm),
            angle_rms_diff_deg: x.angle_rms_deg.and_then(rounded),
        });
    }
}

/// Every round's candidates with their scores, for the JSON.
fn candidates_json(o: &Outcome) -> Vec<Round> {
    o.rounds
        .iter()
        .map(|r| Round {
            round: r.what.clone(),
            start_rms_deg: rounded(r.start_rms_deg),
            scores: r
                .scores
                .iter()
                .map(|s| Score {
                    candidate: s.candidate.label(),
                    rms_deg: rounded(s.fitted.rms()),
                    delta_bic: rounded(s.delta_bic),
                    held_out_rms_deg: s.held_out_rms_deg.and_then(rounded),
                    verdict: s.verdict.clone(),
                })
                .collect(),
        })
        .collect()
}

/// The evidence of each run and joint before the diagnosis, for the JSON.
fn evidence_json(before: &[JointEvidence]) -> Vec<Evidence> {
    before
        .iter()
        .map(|e| Evidence {
            run: e.run.clone(),
            joint: e.joint,
            rms_deg: rounded(e.rms_deg),
            stroke_thirds_rms_deg: rounded_all(&e.stroke_thirds_rms_deg),
            near_latch_rms_deg: rounded(e.near_latch_rms_deg),
            at_release_mean_deg: rounded(e.at_release_mean_deg),
            after_latch_mean_deg: rounded(e.after_latch_mean_deg),
            latch_lead_s: e.latch_lead_s.and_then(rounded),
            correlation: Named(
                CORRELATES
                    .iter()
                    .zip(e.correlation)
                    .map(|(n, r)| (n.to_string(), rounded(r)))
                    .collect(),
            ),
            summary: e.summary.clone(),
        })
        .collect()
}

/// The effects found, for the JSON: each with its interval and evidence,
/// then the residual none of them explains.
fn effects_json(o: &Outcome, before: &[JointEvidence]) -> Vec<FoundEffect> {
    let mut effects: Vec<FoundEffect> = o
        .extended
        .effects()
        .iter()
        .enumerate()
        .map(|(k, e)| {
            let (lo, hi) = ci_of(o, k);
            let mut v = FoundEffect {
                name: e.kind.name().to_string(),
                joint: e.joint,
                value: rounded(e.value),
                unit: Some(e.kind.unit().to_string()),
                ci95: Some([rounded(lo), rounded(hi)]),
                evidence: evidence_of(o, k, o.extended.set[k]),
                ..FoundEffect::default()
            };
            if let Some((_, shape, t)) = o.extended.table_of(k) {
                add_tables(&mut v, &shape, &t);
            }
            if e.kind == EffectKind::RigTilt {
                v.alpha_deg = rounded(e.alpha_deg);
                if let (_, Some(ci)) = o.extended.effect_ci(k) {
                    v.alpha_ci95_deg = Some([rounded(ci[0]), rounded(ci[1])]);
                }
            }
            v
        })
        .collect();
    if let Some(u) = &o.unexplained {
        effects.push(FoundEffect {
            name: "unexplained".to_string(),
            description: Some(u.clone()),
            evidence: before
                .iter()
                .filter(|e| e.rms_deg > UNEXPLAINED_NOISE_FACTOR * o.noise_sigma_deg)
                .map(|e| format!("{}: {}", e.run, e.summary))
                .collect::<Vec<_>>()
                .join("; "),
            ..FoundEffect::default()
        });
    }
    effects
}

/// A joint's baseline residual is named in the evidence of an
/// `"unexplained"` effect when its RMS exceeds this many noise standard
/// deviations (ratio): above what noise alone leaves.
pub const UNEXPLAINED_NOISE_FACTOR: f64 = 3.0;

/// Smallest extended RMS the gain's ratio divides by [deg]: a perfect fit
/// gives a large finite ratio, not infinity.
pub const MIN_RMS_DEG: f64 = 1e-12;

/// The diagnosis JSON (`docs/spec/formats.md`), with the extra fields the
/// project adds (noise floor, candidates, evidence).
pub fn to_json(c: &Campaign, o: &Outcome, before: &[JointEvidence]) -> Diagnosis {
    let te = |effects: &[Effect]| -> Vec<Option<f64>> {
        te_per_joint(c, effects)
            .into_iter()
            .map(|v| v.and_then(rounded))
            .collect()
    };
    let mut mechs: Vec<String> = c.runs.iter().map(|r| r.mechanism.name.clone()).collect();
    mechs.dedup();
    Diagnosis {
        mechanism: mechs.first().cloned().unwrap_or_default(),
        mechanisms: mechs,
        runs: c.runs.iter().map(|r| r.name()).collect(),
        noise_sigma_deg: rounded(o.noise_sigma_deg),
        baseline: Fit {
            rms_deg: rounded(o.baseline.rms()),
            trajectory_error_pct: te(&[]),
        },
        effects: effects_json(o, before),
        extended: Fit {
            rms_deg: rounded(o.extended.rms()),
            trajectory_error_pct: te(&o.extended.effects()),
        },
        gain: Gain {
            rms_ratio: rounded(o.baseline.rms() / o.extended.rms().max(MIN_RMS_DEG)),
            held_out_rms_deg: o.held_out_rms_deg.and_then(rounded),
        },
        candidates: candidates_json(o),
        evidence: evidence_json(before),
        simulations: o.simulations,
        wall_s: rounded(o.wall_s),
        residual_torque: None,
        partial: o.partial.clone(),
        free_window: diagnose_latch::windows_json(c, o),
        latches: diagnose_latch::latches_json(o),
        ambiguities: diagnose_latch::ambiguities_json(o),
    }
}

/// Writes the diagnosis JSON ([`to_json`], with the residual torque of the
/// baseline and of the extended model under `residual_torque`).
fn write_json(
    path: &Path,
    c: &Campaign,
    o: &Outcome,
    before: &[JointEvidence],
    torque: &[Vec<JointTorque>; 2],
    exports: &[TableExport],
) -> Result<(), CliError> {
    let mut doc = to_json(c, o, before);
    add_monitor_tables(&mut doc.effects, exports);
    doc.residual_torque = Some(ResidualTorque {
        baseline: diagnose_torque::torque_json(&torque[0]),
        extended: diagnose_torque::torque_json(&torque[1]),
    });
    let text = serde_json::to_string_pretty(&doc).map_err(|e| CliError::failed(e.to_string()))?;
    std::fs::write(path, text + "\n")
        .map_err(|e| CliError::input(format!("{}: cannot write: {e}", path.display())))
}

/// Writes the Markdown report and its plots: header, causes, discovered
/// torques, what the baseline gets wrong, per-run plots, every round.
fn write_report(
    path: &Path,
    c: &Campaign,
    o: &Outcome,
    [before, after]: [&[JointEvidence]; 2],
    torque: &[Vec<JointTorque>; 2],
    next: &str,
) -> Result<(), CliError> {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "diagnosis".into());
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut md = String::new();
    report_header(&mut md, c, o);
    diagnose_latch::report(&mut md, c, o);
    report_causes(&mut md, o);
    report_tables(&mut md, &dir, &stem, o)?;
    report_evidence(&mut md, before, after);
    diagnose_torque::report_torque(&mut md, &dir, &stem, &torque[0], &torque[1])?;
    let _ = writeln!(md, "\n## Plots\n");
    let ext = o.extended.effects();
    for i in 0..c.runs.len() {
        report_run_plots(&mut md, &dir, &stem, c, i, &ext)?;
    }
    report_rounds(&mut md, o);
    let _ = writeln!(md, "{} simulations in {:.2} s.\n", o.simulations, o.wall_s);
    md.push_str(next);
    std::fs::write(path, md)
        .map_err(|e| CliError::input(format!("{}: cannot write: {e}", path.display())))
}

/// The result on stdout: the headline numbers, the causes found, what is
/// unexplained, the exported tables, where the files went.
fn print_outcome(args: &DiagnoseArgs, outcome: &Outcome, exports: &[TableExport], report: &Path) {
    let ext_effects = outcome.extended.effects();
    outln!(
        "baseline RMS {:.4} deg -> extended {:.4} deg (x{:.1}); noise floor {:.4} deg",
        outcome.baseline.rms(),
        outcome.extended.rms(),
        outcome.baseline.rms() / outcome.extended.rms().max(MIN_RMS_DEG),
        outcome.noise_sigma_deg
    );
    for (k, e) in ext_effects.iter().enumerate() {
        outln!("  {}", effect_line(e, outcome, k));
    }
    if ext_effects.is_empty() && outcome.unexplained.is_none() {
        outln!("  no effect: the mechanisms as given explain the runs to the noise");
    }
    if let Some(u) = &outcome.unexplained {
        outln!("  unexplained: {u}");
    }
    for line in diagnose_latch::summary_lines(outcome) {
        outln!("  {line}");
    }
    for x in exports {
        outln!("  {}", export_line(x));
    }
    outln!(
        "{} simulations in {:.2} s; JSON {}; report {}",
        outcome.simulations,
        outcome.wall_s,
        args.json.display(),
        report.display()
    );
}

/// A path as one shell word: as it is when it holds only characters no
/// shell reads specially, else in single quotes.
fn shell_word(p: &Path) -> String {
    let s = p.display().to_string();
    let plain = |c: char| c.is_ascii_alphanumeric() || "-_./+=:,@%".contains(c);
    if !s.is_empty() && s.chars().all(plain) {
        s
    } else {
        format!("'{}'", s.replace('\'', "'\\''"))
    }
}

/// The report's last section: what to run next with what was found — the
/// torque margins of each mechanism with the diagnosis's resistances
/// (`margin --from`), and the reliability with them.
fn next_step(args: &DiagnoseArgs) -> String {
    let json = shell_word(&args.json);
    let mut s = String::from(
        "## Next step\n\nThe torque margins of each mechanism with the resistances found \
         (friction and damping; `margin` names what it cannot use):\n\n```sh\n",
    );
    for m in &args.mechanisms {
        let _ = writeln!(
            s,
            "deploywatch margin --mechanism {} --from {json} --standard ecss-e-st-33-01c",
            shell_word(m)
        );
    }
    let _ = writeln!(
        s,
        "```\n\nThe probability of a failed deployment with them: `deploywatch reliability \
         MECH.toml --from {json} --vary ... --fail not_latched` (`docs/reliability.md`)."
    );
    s
}

/// Title and headline numbers.
fn report_header(md: &mut String, c: &Campaign, o: &Outcome) {
    let runs: Vec<String> = c.runs.iter().map(|r| r.name()).collect();
    let _ = writeln!(md, "# Diagnosis: {}\n", runs.join(", "));
    let _ = writeln!(
        md,
        "Baseline RMS **{:.4}°** → extended **{:.4}°** (×{:.1}); noise floor estimated from the runs {:.4}°{}.\n",
        o.baseline.rms(),
        o.extended.rms(),
        o.baseline.rms() / o.extended.rms().max(MIN_RMS_DEG),
        o.noise_sigma_deg,
        o.held_out_rms_deg
            .map(|h| format!("; held-out RMS (fit on the other runs) {h:.4}°"))
            .unwrap_or_default()
    );
}

/// The causes found, with values, intervals and evidence; and what stays
/// unexplained.
fn report_causes(md: &mut String, o: &Outcome) {
    let ext = o.extended.effects();
    let _ = writeln!(md, "## Causes found\n");
    if ext.is_empty() {
        let _ = writeln!(
            md,
            "None: the mechanisms as given explain the runs down to the sensor noise.\n"
        );
    } else {
        let _ = writeln!(
            md,
            "| effect | joint | value | 95 % CI | evidence |\n|---|---|---|---|---|"
        );
        for (k, e) in ext.iter().enumerate() {
            let (lo, hi) = ci_of(o, k);
            let extra = match (e.kind, o.extended.table_of(k)) {
                (EffectKind::RigTilt, _) => format!(" (α = {:.1}°)", e.alpha_deg),
                (_, Some((_, shape, _))) => format!(" (largest; {shape})"),
                _ => String::new(),
            };
            let _ = writeln!(
                md,
                "| `{}` | {} | {:.5} {}{} | {:.5} … {:.5} | {} |",
                e.kind,
                e.joint.map(|j| j.to_string()).unwrap_or_else(|| "—".into()),
                e.value,
                match e.kind.unit() {
                    "1" => "(dimensionless)",
                    u => u,
                },
                extra,
                lo,
                hi,
                evidence_of(o, k, o.extended.set[k])
            );
        }
        md.push('\n');
    }
    if let Some(u) = &o.unexplained {
        let _ = writeln!(md, "**Unexplained:** {u}.\n");
    }
}

/// Residual evidence before and after the extension.
fn report_evidence(md: &mut String, before: &[JointEvidence], after: &[JointEvidence]) {
    let _ = writeln!(md, "## What the baseline gets wrong\n");
    for e in before {
        let _ = writeln!(md, "- {}: {}", e.run, e.summary);
    }
    let _ = writeln!(md, "\nAfter the extension:\n");
    for e in after {
        let _ = writeln!(md, "- {}: {}", e.run, e.summary);
    }
}

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
/// angle and rate with its 95 % band.
fn report_tables(md: &mut String, dir: &Path, stem: &str, o: &Outcome) -> Result<(), CliError> {
    for k in 0..o.extended.set.len() {
        let Some((_, shape, t)) = o.extended.table_of(k) else {
            continue;
        };
        let _ = writeln!(
            md,
            "## Discovered torque at joint {}\n\n{shape}.\n",
            o.extended.set[k].joint.unwrap_or(0)
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
            plot::draw(&file, &format!("discovered torque: {what}"), unit, &[panel])
                .map_err(|e| CliError::failed(e.to_string()))?;
            let _ = writeln!(
                md,
                "{}\n",
                markdown::image(&format!("torque vs {what}"), &markdown::file_name(&file))
            );
        }
    }
    Ok(())
}

/// Model minus measurement [deg], `[joint][sample]`.
fn residuals_of(model: &[Vec<f64>], measured: &[Vec<f64>]) -> Vec<Vec<f64>> {
    model
        .iter()
        .zip(measured)
        .map(|(m, y)| m.iter().zip(y).map(|(a, b)| a - b).collect())
        .collect()
}

/// One run's plots: measured vs baseline vs extended angles, and the
/// residuals before and after.
fn report_run_plots(
    md: &mut String,
    dir: &Path,
    stem: &str,
    c: &Campaign,
    i: usize,
    ext: &[Effect],
) -> Result<(), CliError> {
    let (Ok(base), Ok(extd)) = (c.simulate(i, &[]), c.simulate(i, ext)) else {
        return Ok(());
    };
    let run = &c.runs[i].run;
    let name = c.runs[i].name().trim_end_matches(".csv").to_string();
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
    let angles = dir.join(format!("{stem}_{name}_angles.png"));
    let resid = dir.join(format!("{stem}_{name}_residuals.png"));
    let title = format!("{name}: measured vs baseline vs extended");
    plot::draw(&angles, &title, "time [s]", &pa).map_err(|e| CliError::failed(e.to_string()))?;
    let title = format!("{name}: residuals before and after");
    plot::draw(&resid, &title, "time [s]", &pr).map_err(|e| CliError::failed(e.to_string()))?;
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
    Series {
        label: label.into(),
        x,
        y,
        mark: Mark::Line,
        color,
    }
}

/// Every candidate of every round, with its score and verdict.
fn report_rounds(md: &mut String, o: &Outcome) {
    let _ = writeln!(md, "## Why the winner won: every candidate, every round\n");
    let _ = writeln!(
        md,
        "An effect is kept only if it improves the BIC by more than {MIN_DELTA_BIC}, its 95 % interval excludes zero, and (with two or more runs) the set it joins predicts held-out runs at least 5 % better. When no single candidate passes, pairs are fitted jointly and the held-out check applies to the pair.\n"
    );
    for r in &o.rounds {
        let _ = writeln!(md, "### {} (start RMS {:.4}°)\n", r.what, r.start_rms_deg);
        let _ = writeln!(
            md,
            "| candidate | RMS [°] | ΔBIC | held-out RMS [°] | verdict |\n|---|---|---|---|---|"
        );
        for s in &r.scores {
            let _ = writeln!(
                md,
                "| {} | {:.4} | {:.1} | {} | {} |",
                labels_of(&s.fitted.set),
                s.fitted.rms(),
                s.delta_bic,
                s.held_out_rms_deg
                    .map(|h| format!("{h:.4}"))
                    .unwrap_or_else(|| "—".into()),
                s.verdict
            );
        }
        md.push('\n');
    }
}

/// `a, b` of a set's labels.
fn labels_of(set: &[Candidate]) -> String {
    set.iter().map(|c| c.words()).collect::<Vec<_>>().join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dimensionless_value_is_said_in_words_not_unit_1() {
        assert_eq!(
            unit_words(EffectKind::SpringSoftening),
            ", a dimensionless fraction"
        );
        assert_eq!(unit_words(EffectKind::CoulombFriction), " N·m");
    }
}
