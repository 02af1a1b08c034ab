//! The `deploywatch` command line: one module per subcommand, each with its
//! `clap` arguments and a `run` function. `main.rs` only dispatches.
//!
//! Conventions shared by every command (README, "The commands"):
//!
//! - exit code 0 on success, 2 for input the user can fix (a file, an
//!   argument, an output path that cannot be written), 1 when the work
//!   itself fails;
//! - every output path is checked with [`check_output`] before any work:
//!   its folder must exist (folders are never created, except the one
//!   `replay --keep` names) and a file must be creatable there; with
//!   [`check_outputs`], a plot's name gives its format and no two outputs
//!   name one file;
//! - `--quiet` ([`Console`]): no progress and no chatter (which file was
//!   written where); the result a command prints on stdout, errors and
//!   warnings stay, and the result files are written;
//! - outputs are written all or none through
//!   [`crate::report::files::Outputs`] (staged, then renamed into place);
//! - the result goes to stdout through [`outln!`](outln), never `println!`:
//!   a closed stdout (`deploywatch simulate … | head -1`) does not stop the
//!   work; the files are still written and the command exits quietly.

pub(crate) mod diagnose;
pub(crate) mod hil;
pub mod identify;
pub(crate) mod margin;
pub(crate) mod reliability;
pub(crate) mod replay;
pub(crate) mod simulate;
pub(crate) mod simulate_args;
pub(crate) mod simulate_from;
pub(crate) mod simulate_rig;
pub(crate) mod simulate_truss;
pub(crate) mod spinner;

use crate::report::progress::{self, Progress};
use clap::{Parser, Subcommand};
use std::io::Write as _;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::OnceLock;

/// Set once stdout is found closed (a broken pipe): later lines are dropped.
static STDOUT_CLOSED: AtomicBool = AtomicBool::new(false);

/// The first error writing stdout other than a broken pipe (a full disk).
static STDOUT_ERROR: OnceLock<String> = OnceLock::new();

/// Writes `text` to stdout. A closed stdout (`BrokenPipe`: the reader of a
/// pipe is gone) is not an error: the line is dropped, as every later one,
/// and the command goes on to write its files. Any other write error is
/// kept for [`stdout_error`].
pub fn print_out(text: std::fmt::Arguments) {
    if STDOUT_CLOSED.load(Ordering::Relaxed) {
        return;
    }
    if let Err(e) = std::io::stdout().lock().write_fmt(text) {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            STDOUT_CLOSED.store(true, Ordering::Relaxed);
        } else {
            let _ = STDOUT_ERROR.set(e.to_string());
            STDOUT_CLOSED.store(true, Ordering::Relaxed);
        }
    }
}

/// The error that stopped stdout, other than a closed pipe: `main` reports
/// it (exit 1) after the work is done and the files are written.
pub fn stdout_error() -> Option<&'static str> {
    STDOUT_ERROR.get().map(String::as_str)
}

/// `println!` for a command's result: through [`print_out`], so that a
/// closed stdout neither panics nor stops the work.
macro_rules! outln {
    () => {
        $crate::cli::print_out(format_args!("\n"))
    };
    ($($arg:tt)*) => {
        $crate::cli::print_out(format_args!("{}\n", format_args!($($arg)*)))
    };
}
pub(crate) use outln;

/// deploywatch: simulate, identify and diagnose spacecraft panel deployments.
#[derive(Debug, Parser)]
#[command(name = "deploywatch", version, about, long_about = None)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Simulate one deployment of a mechanism and write it as a run CSV.
    Simulate(simulate::SimulateArgs),
    /// Diagnose measured runs: what the simulation gets wrong, the named
    /// cause, the extended model and its gain (JSON + Markdown report).
    Diagnose(diagnose::DiagnoseArgs),
    /// Identify the equivalent friction torque (EFT) of each joint from
    /// measured runs: direct least squares (with 95 % intervals) or the
    /// response surface of seed 000 (JSON + PNG of measured vs simulated).
    Identify(identify::IdentifyArgs),
    /// Torque margins of every joint (torque and energy forms, optional
    /// NASA-STD-5017 / ECSS-E-ST-33-01C uncertainty factors).
    Margin(margin::MarginArgs),
    /// Replay a run through the on-board monitor on the host or on the
    /// example firmware under QEMU (bit-identical with the host): per-joint
    /// summary, status CSV, PNG.
    Replay(replay::ReplayArgs),
    /// Hardware in the loop: stream a run in real time to the serial-link
    /// firmware (QEMU over TCP, or a board on a serial device) and report
    /// latency, deadline misses, lost/corrupted frames and bit-identity.
    Hil(hil::HilArgs),
    /// The probability that a deployment fails from the uncertainty of its
    /// parameters: crude Monte-Carlo or subset simulation (JSON).
    Reliability(reliability::ReliabilityArgs),
}

/// An error a subcommand reports to the user (printed, exit code 1 or 2).
#[derive(Debug)]
pub struct CliError {
    /// What went wrong, for a person.
    pub message: String,
    /// 2 for bad input (files, arguments), 1 for a failed analysis.
    pub code: u8,
}

impl CliError {
    /// Bad input: a file or an argument the user can fix.
    pub fn input(message: impl Into<String>) -> Self {
        CliError {
            message: message.into(),
            code: 2,
        }
    }
    /// The work itself failed.
    pub fn failed(message: impl Into<String>) -> Self {
        CliError {
            message: message.into(),
            code: 1,
        }
    }
}

impl std::fmt::Display for CliError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for CliError {}

impl From<crate::report::files::FileError> for CliError {
    /// An output that cannot be written is input the user can fix (exit 2).
    fn from(e: crate::report::files::FileError) -> Self {
        CliError::input(e.to_string())
    }
}

/// The extensions a plot's file name may end in, the formats the plots are
/// written in (plotters' bitmap encoder: the `image` crate's PNG, JPEG and
/// BMP); the format is read from the name.
pub const PLOT_EXTENSIONS: [&str; 4] = ["png", "jpg", "jpeg", "bmp"];

/// One output of a command: the flag that names it (e.g. `--plot`, or
/// "the report beside --json"), its path, and whether it is a plot.
#[derive(Clone, Copy, Debug)]
pub struct Output<'a> {
    flag: &'a str,
    path: &'a Path,
    plot: bool,
}

impl<'a> Output<'a> {
    /// A file written as it is (CSV, JSON, Markdown).
    pub fn file(flag: &'a str, path: &'a Path) -> Self {
        Output {
            flag,
            path,
            plot: false,
        }
    }

    /// A plot, its format read from its extension ([`PLOT_EXTENSIONS`]).
    pub fn plot(flag: &'a str, path: &'a Path) -> Self {
        Output {
            flag,
            path,
            plot: true,
        }
    }
}

/// Checks a command's outputs before any work: each with [`check_output`];
/// a plot's name ends in one of [`PLOT_EXTENSIONS`], a text file's in none
/// of them; and no two outputs
/// name one file (the one written last would replace the other: checked
/// by the folder as resolved and the file name, so before either exists).
pub fn check_outputs(outputs: &[Output], inputs: &[&Path]) -> Result<(), CliError> {
    for (i, o) in outputs.iter().enumerate() {
        let bad = |why: String| CliError::input(format!("{} {}: {why}", o.flag, o.path.display()));
        if o.plot && image_extension(o.path).is_none() {
            return Err(bad(format!(
                "expected a file name ending in .{}: a plot's format is read from its name",
                PLOT_EXTENSIONS.join(", .")
            )));
        }
        check_output(o.flag, o.path, inputs)?;
        if let Some(first) = outputs[..i].iter().find(|f| same_file(f.path, o.path)) {
            return Err(bad(format!(
                "is also {}'s file; expected another file, or one would replace the other",
                first.flag
            )));
        }
    }
    // After the clashes: `--out x.png --plot x.png` is told the clash.
    for o in outputs.iter().filter(|o| !o.plot) {
        if let Some(e) = image_extension(o.path) {
            return Err(CliError::input(format!(
                "{} {}: the file is written as text (CSV, JSON or Markdown), not as an image; \
                 expected a name that does not end in .{e} (a figure, where the command draws \
                 one, is --plot's)",
                o.flag,
                o.path.display()
            )));
        }
    }
    Ok(())
}

/// The extension of `path`, in lower case, when it is one of
/// [`PLOT_EXTENSIONS`].
fn image_extension(path: &Path) -> Option<String> {
    let ext = path.extension()?.to_str()?.to_ascii_lowercase();
    PLOT_EXTENSIONS.contains(&ext.as_str()).then_some(ext)
}

/// True when `a` and `b` name one file, whether or not it exists: their
/// folders resolved (links and `.`), and the same file name in them.
fn same_file(a: &Path, b: &Path) -> bool {
    let key = |p: &Path| {
        let dir = p.parent().filter(|d| !d.as_os_str().is_empty());
        let dir = std::fs::canonicalize(dir.unwrap_or(Path::new("."))).ok()?;
        Some((dir, p.file_name()?.to_os_string()))
    };
    if let (Ok(x), Ok(y)) = (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        return x == y;
    }
    matches!((key(a), key(b)), (Some(x), Some(y)) if x == y)
}

/// Checks, before any work, that the output `path` (given with `flag`,
/// e.g. `--plot`) can be written: its folder exists (it is never created),
/// the path is not a folder nor one of the command's `inputs`, and a file
/// can be created or opened for writing there (a device or a pipe is taken
/// as it is). A file that did not exist is removed again, so a command
/// that fails later leaves nothing behind; an existing file is not changed.
pub fn check_output(flag: &str, path: &Path, inputs: &[&Path]) -> Result<(), CliError> {
    let bad = |why: String| CliError::input(format!("{flag} {}: {why}", path.display()));
    if path.as_os_str().is_empty() {
        return Err(bad("expected a file name".into()));
    }
    if crate::report::files::is_input(path, inputs) {
        return Err(bad(
            "is an input of this command; expected another file for the output".into(),
        ));
    }
    if crate::report::files::is_special(path) {
        // A device or a pipe: written into at the end (`report::files`);
        // opening a pipe here would wait for its reader.
        return Ok(());
    }
    let folder = path.parent().filter(|d| !d.as_os_str().is_empty());
    if let Some(dir) = folder {
        if !dir.is_dir() {
            return Err(bad(format!(
                "the folder {} does not exist (deploywatch does not create folders: \
                 create it first, e.g. `mkdir -p {}`)",
                dir.display(),
                dir.display()
            )));
        }
    }
    if path.is_dir() {
        return Err(bad("is a folder; expected a file name".into()));
    }
    let existed = path.exists();
    std::fs::OpenOptions::new()
        .append(true)
        .create(true)
        .open(path)
        .map_err(|e| bad(format!("cannot be written: {e}")))?;
    if !existed {
        let _ = std::fs::remove_file(path);
    }
    Ok(())
}

/// Where a command's words go: progress and chatter on the terminal unless
/// `--quiet`; warnings always (stderr).
#[derive(Clone, Copy, Debug, Default)]
pub struct Console {
    /// `--quiet`: no progress, no chatter.
    pub quiet: bool,
}

impl Console {
    /// A console for a command given `--quiet` or not.
    pub fn new(quiet: bool) -> Self {
        Console { quiet }
    }

    /// Chatter on stdout (what was written where, summaries): dropped with
    /// `--quiet`.
    pub fn say(&self, line: impl std::fmt::Display) {
        if !self.quiet {
            outln!("{line}");
        }
    }

    /// A warning about the result on stderr, kept with `--quiet`; inside
    /// [`capturing_warnings`] on this thread, kept for its caller instead.
    pub fn warn(&self, line: impl std::fmt::Display) {
        let line = line.to_string();
        let kept = CAPTURED.with(|c| match c.borrow_mut().as_mut() {
            Some(v) => {
                v.push(line.clone());
                true
            }
            None => false,
        });
        if !kept {
            eprintln!("warning: {line}");
        }
    }

    /// The progress sink of the library ([`crate::report::progress`]):
    /// stderr, or nowhere with `--quiet`.
    pub fn progress(&self) -> Progress<'static> {
        if self.quiet {
            &progress::quiet
        } else {
            &progress::stderr
        }
    }
}

thread_local! {
    /// The warnings [`capturing_warnings`] keeps on this thread.
    static CAPTURED: std::cell::RefCell<Option<Vec<String>>> =
        const { std::cell::RefCell::new(None) };
}

/// Runs `f` with the warnings of [`Console::warn`] on this thread kept
/// rather than printed, and returns them beside its result: what Python
/// raises as `UserWarning`s.
pub fn capturing_warnings<T>(f: impl FnOnce() -> T) -> (T, Vec<String>) {
    let before = CAPTURED.with(|c| c.borrow_mut().replace(Vec::new()));
    let out = f();
    let kept = CAPTURED.with(|c| std::mem::replace(&mut *c.borrow_mut(), before));
    (out, kept.unwrap_or_default())
}

/// Runs a parsed command line.
pub fn run(cli: Cli) -> Result<(), CliError> {
    match cli.command {
        Command::Simulate(a) => simulate::run(&a),
        Command::Diagnose(a) => diagnose::run(&a),
        Command::Identify(a) => identify::run(&a),
        Command::Margin(a) => margin::run(&a),
        Command::Replay(a) => replay::run(&a),
        Command::Hil(a) => hil::run(&a),
        Command::Reliability(a) => reliability::run(&a),
    }
}
