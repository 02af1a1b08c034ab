//! `deploywatch simulate --from FINDINGS.json [--at RUN.csv]`: the model a
//! diagnosis (or an identification) found, simulated from its JSON alone.
//! `--from` adds the effects the file names to the `--effect`s (read by the
//! findings' one reader, `FoundEffect::to_effect`); `--at` simulates them
//! as the diagnosis did — at the run's own time stamps, with the fit's
//! integration settings, the encoder offsets applied, the encoders' delay
//! taken out where the diagnosis took one out, over the free motion
//! the diagnosis fitted when its runs have a physical latch — writes the
//! model's true angles and prints its RMS against the run, the number the
//! diagnosis gives as the extended model's (`docs/diagnosis.md`).

use super::simulate_args::SimulateArgs;
use super::{outln, CliError, Console};
use crate::analysis::campaign_sim::CampaignSim;
use crate::analysis::diagnose::latch_window::{self, RunWindow};
use crate::analysis::diagnose::{encoder_delay, free_play, FreePlayOffset};
use crate::data::campaign::Campaign;
use crate::model::effect::{Effect, EffectKind};
use crate::model::findings::{Diagnosis, Findings};
use crate::model::mechanism::Mechanism;
use crate::report::files::Outputs;
use crate::simulate::sensor::{self, SensorModel};
use std::path::Path;

/// What `--from` names: the effects of the model it found, and the
/// diagnosis itself (`None` for an identification) for its free windows.
pub struct FoundModel {
    /// The effects, in the file's order.
    pub effects: Vec<Effect>,
    /// The entry of the file each effect comes from, for errors:
    /// `effects[0] (coulomb_friction)`, `joints[1] (coulomb_friction)`.
    pub entries: Vec<String>,
    /// The diagnosis, when the file is one.
    pub diagnosis: Option<Diagnosis>,
}

/// Reads `--from`: a diagnose JSON (its named effects; `"unexplained"` is
/// no effect and is left out) or an identify JSON (one `coulomb_friction`
/// per joint identified).
pub fn read(path: &Path) -> Result<FoundModel, CliError> {
    let at = |m: String| CliError::input(format!("--from {}: {m}", path.display()));
    let text = std::fs::read_to_string(path).map_err(|e| at(format!("cannot read: {e}")))?;
    match Findings::from_json_str(&text).map_err(|e| at(e.to_string()))? {
        Findings::Diagnosis(d) => {
            let (mut effects, mut entries) = (Vec::new(), Vec::new());
            for (i, f) in d.effects.iter().enumerate() {
                if let Some(e) = f.to_effect(i).map_err(|e| at(e.to_string()))? {
                    effects.push(e);
                    entries.push(format!("effects[{i}] ({})", f.name));
                }
            }
            Ok(FoundModel {
                effects,
                entries,
                diagnosis: Some(*d),
            })
        }
        Findings::Identify(id) => Ok(FoundModel {
            effects: id
                .joints
                .iter()
                .map(|j| Effect::joint(EffectKind::CoulombFriction, j.joint, j.coulomb_nm))
                .collect(),
            entries: (0..id.joints.len())
                .map(|i| format!("joints[{i}] ({})", EffectKind::CoulombFriction.name()))
                .collect(),
            diagnosis: None,
        }),
    }
}

/// Checks each effect `found` names against `mech`, as `--effect`'s are
/// checked, naming the file `path` and the entry it comes from.
fn check_found(found: &FoundModel, mech: &Mechanism, path: &Path) -> Result<(), CliError> {
    for (e, entry) in found.effects.iter().zip(&found.entries) {
        e.validate(mech.effect_joints())
            .map_err(|m| CliError::input(format!("--from {}: {entry}: {m}", path.display())))?;
    }
    Ok(())
}

/// The arguments with the effects of `--from` added to the `--effect`s,
/// and what `--from` found (`None` without `--from`). A diagnosis found on
/// other mechanisms than `mech` is warned of (its effects still added).
pub fn with_found(
    args: &SimulateArgs,
    mech: &Mechanism,
) -> Result<(SimulateArgs, Option<FoundModel>), CliError> {
    let mut with = args.clone();
    let found = match &args.from {
        Some(path) => {
            let found = read(path)?;
            check_found(&found, mech, path)?;
            Some(found)
        }
        None => None,
    };
    if let Some(f) = &found {
        with.effects.extend(f.effects.iter().cloned());
        let on = f
            .diagnosis
            .as_ref()
            .map(|d| d.found_on())
            .unwrap_or_default();
        if !on.is_empty() && !on.contains(&mech.name) {
            Console::new(args.quiet).warn(format_args!(
                "--from: found on {}, not on {}: its effects are added all the same",
                on.join(", "),
                mech.name
            ));
        }
    }
    Ok((with, found))
}

/// The delay \[s\] a diagnosis took out of the encoders' stamps (its JSON's
/// `encoder_delay`, when `taken_out` and positive).
fn delay_taken_out(found: Option<&Diagnosis>) -> Option<f64> {
    found
        .and_then(|d| d.encoder_delay.as_ref())
        .filter(|d| d.taken_out)
        .and_then(|d| d.delay_s)
        .filter(|d| d.is_finite() && *d > 0.0)
}

/// `mech` with the flexible panels of the diagnosis `found` named
/// (`flexible_panels` of its JSON), said on the console; as it is without
/// them. A mechanism that cannot take them (`[flexible_panels]` refused
/// there) is an input error.
pub fn with_flexible(
    mut mech: Mechanism,
    found: Option<&FoundModel>,
    quiet: bool,
) -> Result<Mechanism, CliError> {
    let Some(f) = found
        .and_then(|f| f.diagnosis.as_ref())
        .and_then(|d| d.flexible_panels.as_ref())
    else {
        return Ok(mech);
    };
    let (Some(hz), Some(zeta)) = (f.first_mode_hz, f.damping_ratio) else {
        return Ok(mech);
    };
    let flex = crate::model::flex::PanelFlex {
        first_mode_hz: hz,
        damping_ratio: zeta,
    };
    if !mech.can_be_flexible() {
        return Err(CliError::input(format!(
            "--from: the diagnosis found flexible panels (first mode {hz:.3} Hz), which `{}` cannot take (a physical latch, a truss, an enabled rig or more than {} panels)",
            mech.name,
            crate::model::flex::MAX_FLEXIBLE_PANELS
        )));
    }
    Console::new(quiet).say(format_args!(
        "--from: flexible panels, first mode {hz:.3} Hz, damping ratio {:.2} %, as the diagnosis found them",
        100.0 * zeta
    ));
    mech.flexible = Some(flex);
    Ok(mech)
}

/// The encoder offsets within the declared free-play a diagnosis took out
/// of the angles (its JSON's `free_play`; an entry with a number missing
/// is skipped).
fn free_play_offsets(found: Option<&Diagnosis>) -> Vec<FreePlayOffset> {
    found
        .map(|d| &d.free_play[..])
        .unwrap_or_default()
        .iter()
        .filter_map(|f| {
            Some(FreePlayOffset {
                joint: f.joint,
                offset_deg: f.offset_deg?,
                ci95_deg: [f.ci95[0]?, f.ci95[1]?],
                play_deg: f.play_deg?,
            })
        })
        .collect()
}

/// The window the diagnosis `found` fitted run `name` on: its free motion
/// or the run up to where the model follows it (`None` when it fitted the
/// whole run).
fn fitted_window<'a>(
    found: Option<&'a Diagnosis>,
    name: &str,
) -> Option<&'a crate::model::findings::diagnosis::FreeWindow> {
    let d = found.filter(|d| !d.fitted_whole)?;
    let windows = if d.fitted_window.is_empty() {
        &d.free_window
    } else {
        &d.fitted_window
    };
    windows.iter().find(|w| w.run == name)
}

/// The window `w` the diagnosis `found` fitted a run on, in words.
fn window_note(
    found: Option<&Diagnosis>,
    w: &crate::model::findings::diagnosis::FreeWindow,
) -> String {
    let what = match found.is_some_and(|d| !d.fitted_window.is_empty()) {
        true => "window",
        false => "free motion",
    };
    format!(
        " (the {what} the diagnosis fitted, {} of {} samples)",
        w.samples, w.of
    )
}

/// `--at RUN.csv`: the mechanism with `args.effects` (the `--from` ones
/// among them) simulated as the diagnosis simulates a run, written to
/// `--out` (the model's angles, no noise) and its RMS against the run
/// printed.
pub fn run_at(
    args: &SimulateArgs,
    mech: &Mechanism,
    found: Option<&FoundModel>,
    at: &Path,
) -> Result<(), CliError> {
    let found = found.and_then(|f| f.diagnosis.as_ref());
    let mut campaign = Campaign::load(std::slice::from_ref(&args.mechanism), &[at.to_path_buf()])
        .map_err(|e| CliError::input(format!("--at: {e}")))?;
    let name = campaign.runs[0].name();
    campaign.runs[0].mechanism = mech.clone();
    // Encoders the diagnosis found late on their switches: the model at
    // each stamp minus the delay, written at the run's own stamps.
    let stamps = campaign.runs[0].run.t_s.clone();
    let delay_s = delay_taken_out(found);
    if let Some(d) = delay_s {
        campaign = encoder_delay::shifted(&campaign, d);
    }
    // Encoders the diagnosis found off their panels within the
    // declared free-play: the angles with that taken out, as it compared.
    let offsets = free_play_offsets(found);
    campaign = free_play::apply(&campaign, &offsets);
    let window = fitted_window(found, &name);
    if let Some(w) = window {
        let cut = RunWindow {
            kept: w.samples,
            of: w.of,
            end_s: w.end_s,
            joint: w.joint,
        };
        campaign = latch_window::apply(&campaign, &[cut]);
    }
    let traj = campaign
        .simulate(0, &args.effects)
        .map_err(|e| CliError::failed(e.to_string()))?;
    let rms = campaign
        .rms(&args.effects)
        .ok_or_else(|| CliError::failed(format!("{name}: the model's run does not cover it")))?;
    let zero = vec![0.0; mech.joint_count()];
    let mut run = sensor::measure(&traj, &zero, &SensorModel::IDEAL, 0);
    run.t_s = stamps.get(..run.t_s.len()).map_or(run.t_s, <[f64]>::to_vec);
    run.set_meta("mechanism", &mech.name);
    run.set_meta("source", "deploywatch simulate --at");
    let effects: Vec<String> = args.effects.iter().map(|e| e.to_string()).collect();
    run.set_meta("effects", &effects.join("; "));
    run.set_meta("sensor", "ideal (true angles)");
    let mut outs = Outputs::new();
    let csv = run
        .checked_csv(&args.out.display().to_string())
        .map_err(|e| CliError::input(e.to_string()))?;
    outs.write(&args.out, csv)?;
    outs.commit()?;
    outln!(
        "{}: the model at the {} time stamps of {}{} to {}",
        mech.name,
        run.len(),
        at.display(),
        window.map_or(String::new(), |w| window_note(found, w)),
        args.out.display()
    );
    if let Some(d) = delay_s {
        outln!(
            "  the encoders {:.3} ms late on their switches, as the diagnosis took out",
            d * 1e3
        );
    }
    for l in &offsets {
        outln!(
            "  joint {}'s readings {:+.4} deg off its panel within the declared free-play, as the diagnosis took out",
            l.joint,
            l.offset_deg
        );
    }
    for e in &args.effects {
        outln!("  effect {e}");
    }
    outln!("  RMS against {name}: {rms:.9} deg");
    Ok(())
}
