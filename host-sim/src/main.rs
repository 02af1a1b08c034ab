//! `deploywatch`: the command line. See `deploywatch --help`.
use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = deploywatch_sim::cli::Cli::parse();
    match deploywatch_sim::cli::run(cli) {
        // A closed stdout (a pipe whose reader is gone) is no error: the
        // work is done and its files written. Any other failure to write
        // the result is, once the files are written.
        Ok(()) => match deploywatch_sim::cli::stdout_error() {
            None => ExitCode::SUCCESS,
            Some(e) => {
                eprintln!("error: cannot write the result to standard output: {e}");
                ExitCode::FAILURE
            }
        },
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.code)
        }
    }
}
