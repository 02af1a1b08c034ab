//! `deploywatch replay`: a recorded run through the on-board monitor, on the
//! host (`f32`) or on the example firmware under QEMU, with the check that
//! QEMU's statuses are bit-identical with the host's.

use super::{check_output, outln, CliError, Console, Output};
use crate::model::mechanism::Mechanism;
use crate::onboard::firmware;
use crate::onboard::replay::{self, Prepared, ReplayError};
use crate::report::files::Outputs;
use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

/// Where the monitor runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Target {
    /// The host's `f32` run of the core's monitor.
    Host,
    /// The example firmware (Cortex-M4F) on QEMU's mps2-an386, compared
    /// with the host's run.
    Qemu,
}

/// Arguments of `deploywatch replay`.
#[derive(Debug, clap::Args)]
pub struct ReplayArgs {
    /// The run (CSV, docs/spec/formats.md); missing samples (`NaN`) allowed.
    pub run: PathBuf,
    /// The run's mechanism (TOML).
    #[arg(long)]
    pub mechanism: PathBuf,
    /// Where the monitor runs. `qemu` also runs the host and fails (exit 1)
    /// unless the status frames are bit-identical.
    #[arg(long, value_enum, default_value_t = Target::Host)]
    pub target: Target,
    /// Write the whole status stream as CSV (the target's; equal for both).
    #[arg(long, short, value_name = "STATUS.csv")]
    pub out: Option<PathBuf>,
    /// Draw angles, friction estimates and margins into this PNG.
    #[arg(long, value_name = "PNG")]
    pub plot: Option<PathBuf>,
    /// With `--target host`: also run the firmware's own replay loop on the
    /// host over the same frames and require bit-identity (with `qemu` the
    /// comparison with the host is always made).
    #[arg(long)]
    pub compare: bool,
    /// The firmware ELF (`scripts/firmware.sh build`); by default
    /// firmware-example/target/thumbv7em-none-eabihf/release/deploywatch-firmware-example.
    #[arg(long, value_name = "ELF")]
    pub elf: Option<PathBuf>,
    /// Keep the frames in this directory: input.bin (configuration + sample
    /// frames), host.bin, and qemu.bin / qemu.defmt or firmware-loop.bin.
    /// Without it they go to a temporary directory, removed afterwards.
    #[arg(long, value_name = "DIR")]
    pub keep: Option<PathBuf>,
    /// Longest QEMU run in seconds.
    #[arg(long, default_value_t = 300)]
    pub timeout: u64,
    /// No progress and no chatter (QEMU's log, which file was written
    /// where): the per-joint summary, the comparison verdict, errors and
    /// warnings only; the files are written as usual.
    #[arg(long, short)]
    pub quiet: bool,
}

/// Checks every output before the work: the files' folders exist and can
/// be written; the `--keep` folder is created (not its parents).
fn check_outputs(args: &ReplayArgs) -> Result<(), CliError> {
    let inputs: Vec<&Path> = [&args.run, &args.mechanism]
        .into_iter()
        .chain(&args.elf)
        .map(|p| p.as_path())
        .collect();
    if let Some(d) = &args.keep {
        if d.exists() && !d.is_dir() {
            return Err(CliError::input(format!(
                "--keep {}: a file; expected a folder to keep the replay's files in (an existing one, or a new one this creates)",
                d.display()
            )));
        }
        if !d.is_dir() {
            check_output("--keep", d, &inputs)?;
            std::fs::create_dir(d)
                .map_err(|e| CliError::input(format!("--keep {}: {e}", d.display())))?;
        }
    }
    let outputs: Vec<Output> = (args.out.as_deref().map(|p| Output::file("--out", p)))
        .into_iter()
        .chain(args.plot.as_deref().map(|p| Output::plot("--plot", p)))
        .collect();
    super::check_outputs(&outputs, &inputs)
}

/// A temporary directory removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new() -> Self {
        let nanos = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| d.subsec_nanos());
        TempDir(
            std::env::temp_dir().join(format!("deploywatch-replay-{}-{nanos}", std::process::id())),
        )
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn cli_error(e: ReplayError) -> CliError {
    match e {
        ReplayError::Input(_) | ReplayError::Setup(_) => CliError::input(e.to_string()),
        _ => CliError::failed(e.to_string()),
    }
}

fn write(path: &Path, bytes: &[u8]) -> Result<(), CliError> {
    std::fs::write(path, bytes).map_err(|e| CliError::input(format!("{}: {e}", path.display())))
}

/// A run noisier than the monitor is tuned for, in words: the monitor's
/// friction, margins and states of it are not to be trusted.
fn noise_note(run: &crate::data::run::Run, path: &Path) -> Option<String> {
    use crate::analysis::evidence::{run_noise_sigma, NOISE_ABOVE_MONITOR_FACTOR};
    let tuned = f64::from(deploywatch_core::monitor::SensorConfig::default().encoder_sd_deg);
    let sigma = run_noise_sigma(run)?;
    (sigma > NOISE_ABOVE_MONITOR_FACTOR * tuned).then(|| {
        format!(
            "{}: the encoders' noise, σ̂ = {sigma:.3} deg (third differences at rest on the stops), is more than \
             {NOISE_ABOVE_MONITOR_FACTOR} times the {tuned:.3} deg the monitor is tuned for: its \
             friction observer rejects most fits (an estimate left at its prior, ± about 2 N·m, \
             learned nothing) and its stall rule may not fire; its friction, margins and \
             states of this run are not to be trusted",
            path.display()
        )
    })
}

/// Runs `deploywatch replay`.
pub fn run(args: &ReplayArgs) -> Result<(), CliError> {
    let mech = Mechanism::load(&args.mechanism).map_err(|e| CliError::input(e.to_string()))?;
    let run = replay::load_run(&args.run).map_err(cli_error)?;
    let warnings = crate::data::inputs::check_pair(&mech, &args.mechanism, &run, &args.run)
        .map_err(|e| CliError::input(e.to_string()))?;
    // Everything the QEMU target needs, and every output, is checked
    // before any work.
    let elf = qemu_elf(args, &mech)?;
    check_outputs(args)?;
    let prepared = replay::prepare(&mech, &run).map_err(cli_error)?;
    let console = Console::new(args.quiet);
    for w in warnings
        .into_iter()
        .chain(replay::rig_note(&mech))
        .chain(noise_note(&run, &args.run))
        .chain(crate::data::resolution::note(
            &run,
            &args.run.display().to_string(),
        ))
    {
        console.warn(w);
    }
    let temp;
    let dir = match &args.keep {
        Some(d) => d.clone(),
        None => {
            temp = TempDir::new();
            temp.0.clone()
        }
    };
    if args.keep.is_some() {
        write(&dir.join("input.bin"), &prepared.input)?;
        write(&dir.join("host.bin"), &prepared.host_frames)?;
    }
    console.say(format_args!(
        "{}: {} samples of {} joints, {} ({} input bytes)",
        args.run.display(),
        prepared.samples,
        prepared.joints,
        mech.name,
        prepared.input.len()
    ));
    let (statuses, mismatch) = target_statuses(args, elf, &prepared, &dir, &console)?;
    for s in replay::summary(&statuses) {
        outln!("  {s}");
    }
    write_outputs(args, &mech.name, &statuses, &console)?;
    if args.keep.is_some() {
        console.say(format_args!("  frames: {}", dir.display()));
    }
    match mismatch {
        Some(m) => Err(CliError::failed(m)),
        None => Ok(()),
    }
}

/// The firmware ELF for `--target qemu` (None for the host), after checking
/// that the firmware has a monitor of the mechanism's joint count.
fn qemu_elf(args: &ReplayArgs, mech: &Mechanism) -> Result<Option<PathBuf>, CliError> {
    if args.target == Target::Host {
        return Ok(None);
    }
    if args.elf.is_none() && !firmware::firmware_supports(mech.joint_count()) {
        return Err(CliError::input(format!(
            "{}: {} joints; the example firmware is built for {} joints \
             (one binary per joint count, firmware-example/Cargo.toml; give --elf \
             for a firmware built for {} joints); --target host replays 1 to {}",
            mech.name,
            mech.joint_count(),
            firmware::firmware_joint_counts(),
            mech.joint_count(),
            deploywatch_core::telemetry::config::MAX_JOINTS
        )));
    }
    Ok(Some(
        firmware::find_elf(args.elf.as_deref(), mech.joint_count()).map_err(cli_error)?,
    ))
}

/// The statuses reported (the target's) and, when they were compared with
/// the host's, the message of a mismatch.
fn target_statuses(
    args: &ReplayArgs,
    elf: Option<PathBuf>,
    prepared: &Prepared,
    dir: &Path,
    console: &Console,
) -> Result<(Vec<replay::StatusRow>, Option<String>), CliError> {
    if let Some(elf) = elf {
        let timeout = Duration::from_secs(args.timeout);
        let q = replay::run_qemu(&elf, &prepared.input, dir, timeout).map_err(cli_error)?;
        if !console.quiet {
            eprint!("{}", q.log);
        }
        let statuses = replay::decode_statuses(&q.frames, prepared.joints).map_err(cli_error)?;
        let m = check(prepared, &q.frames, "QEMU (Cortex-M4F firmware)");
        return Ok((statuses, m));
    }
    if args.compare {
        let fw =
            firmware::firmware_loop_on_host(&prepared.input, prepared.joints).map_err(cli_error)?;
        if args.keep.is_some() {
            write(&dir.join("firmware-loop.bin"), &fw)?;
        }
        let m = check(prepared, &fw, "the firmware's replay loop on the host");
        return Ok((prepared.host.clone(), m));
    }
    console.say(format_args!(
        "host f32 run: {} status frames",
        prepared.host.len()
    ));
    Ok((prepared.host.clone(), None))
}

/// Writes the status CSV (`--out`) and the plot (`--plot`).
fn write_outputs(
    args: &ReplayArgs,
    name: &str,
    statuses: &[replay::StatusRow],
    console: &Console,
) -> Result<(), CliError> {
    let mut outs = Outputs::new();
    if let Some(out) = &args.out {
        let bad = |e: std::io::Error| CliError::input(format!("--out {}: {e}", out.display()));
        let file = std::fs::File::create(outs.path(out)?).map_err(bad)?;
        replay::write_status_csv(std::io::BufWriter::new(file), statuses).map_err(bad)?;
    }
    if let Some(png) = &args.plot {
        replay::plot(&outs.path(png)?, name, statuses)
            .map_err(|e| CliError::failed(e.to_string()))?;
    }
    outs.commit()?;
    if let Some(out) = &args.out {
        console.say(format_args!("  status CSV: {}", out.display()));
    }
    if let Some(png) = &args.plot {
        console.say(format_args!("  plot: {}", png.display()));
    }
    Ok(())
}

/// Compares `target` with the host's frames: prints the verdict, returns
/// the error message of a mismatch.
fn check(prepared: &Prepared, target: &[u8], name: &str) -> Option<String> {
    match replay::compare(&prepared.host_frames, target, prepared.joints) {
        Ok(n) => {
            outln!(
                "{name}: {n} status frames, bit-identical with the host's f32 run ({} bytes)",
                target.len()
            );
            None
        }
        Err(m) => Some(format!(
            "{name} differs from the host's f32 run: first at {m}"
        )),
    }
}
