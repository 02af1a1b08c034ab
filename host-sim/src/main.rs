//! `deploywatch`: the command line. See `deploywatch --help`.
use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = deploywatch_sim::cli::Cli::parse();
    match deploywatch_sim::cli::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.code)
        }
    }
}
