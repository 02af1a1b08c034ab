//! The `deploywatch` command run in-process, and the angles of a run CSV it
//! writes, for the tests that drive the CLI end to end.

use clap::Parser;
use deploywatch_sim::cli::{self, Cli};
use std::path::Path;

/// Runs `deploywatch ARGS` in-process and returns its exit code; panics
/// when the arguments do not parse (a test's own mistake).
pub fn deploywatch(args: &[&str]) -> i32 {
    let argv = std::iter::once("deploywatch").chain(args.iter().copied());
    match Cli::try_parse_from(argv) {
        Ok(parsed) => cli::run(parsed).map_or_else(|e| i32::from(e.code), |()| 0),
        Err(e) => panic!("deploywatch {args:?}: {e}"),
    }
}

/// The angles \[deg\] of a run CSV, per joint (`joints` columns after `t_s`).
pub fn angles(path: &Path, joints: usize) -> Vec<Vec<f64>> {
    let body = std::fs::read_to_string(path).expect("a run CSV");
    let mut out = vec![Vec::new(); joints];
    for line in body.lines().filter(|l| !l.starts_with('#')).skip(1) {
        let cells: Vec<&str> = line.split(',').collect();
        for (j, col) in out.iter_mut().enumerate() {
            col.push(cells[1 + j].parse::<f64>().expect("an angle"));
        }
    }
    out
}

/// RMS \[deg\] of `a` against `b`, joint by joint, over the samples both
/// have.
pub fn rms_between(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    let (mut sse, mut n) = (0.0, 0usize);
    for (x, y) in a.iter().zip(b) {
        for (p, q) in x.iter().zip(y) {
            sse += (p - q) * (p - q);
            n += 1;
        }
    }
    (sse / n.max(1) as f64).sqrt()
}
