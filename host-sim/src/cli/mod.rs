//! The `deploywatch` command line: one module per subcommand, each with its
//! `clap` arguments and a `run` function. `main.rs` only dispatches.

pub mod diagnose;
pub mod identify;
pub mod margin;
pub mod replay;
pub mod simulate;
pub mod truss;

use clap::{Parser, Subcommand};

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

/// Runs a parsed command line.
pub fn run(cli: Cli) -> Result<(), CliError> {
    match cli.command {
        Command::Simulate(a) => simulate::run(&a),
        Command::Diagnose(a) => diagnose::run(&a),
        Command::Identify(a) => identify::run(&a),
        Command::Margin(a) => margin::run(&a),
        Command::Replay(a) => replay::run(&a),
    }
}
