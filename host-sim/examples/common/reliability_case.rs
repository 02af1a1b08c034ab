//! The reliability case the throughput is measured on (docs/reliability.md
//! §6): seed 001 T01 with its identified friction at 5 % lognormal
//! dispersion, `--fail not_latched`. Shared by `benches/reliability.rs`,
//! `examples/ideal_ledger.rs` and `examples/ideal_profile.rs` (included
//! with `#[path = ...] mod`).

use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::reliability::Problem;
use std::path::{Path, PathBuf};

/// The mechanism of the case, relative to the crate's manifest.
pub const T01: &str = "../data/mechanisms/seed001_T01.toml";

/// The case's laws: each joint's identified friction at 5 % dispersion.
pub const T01_VARY: [&str; 3] = [
    "coulomb_friction:joint=1:lognormal(2.63,0.05)",
    "coulomb_friction:joint=2:lognormal(1.7,0.05)",
    "coulomb_friction:joint=3:lognormal(0.001,0.05)",
];

/// The reliability problem of the mechanism at `path` with the laws
/// `vary` (the syntax of `--vary`) and `--fail not_latched`; an error
/// says which input is wrong.
pub fn problem(path: &Path, vary: &[String]) -> Result<Problem, String> {
    let mech = Mechanism::load(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let vary = vary
        .iter()
        .map(|v| v.parse().map_err(|e| format!("{v}: {e}")))
        .collect::<Result<_, String>>()?;
    Ok(Problem {
        mech,
        vary,
        fixed: Vec::new(),
        fail: vec!["not_latched"
            .parse()
            .map_err(|e| format!("not_latched: {e}"))?],
        corr: Vec::new(),
    })
}

/// The ideal-latch problem of the command line `[DRAWS [MECH.toml
/// VARY...]]` (the case above without a mechanism; DRAWS `default`
/// without one), its draws and the mechanism's name; an error to print,
/// after `example: `, with exit code 2.
#[allow(dead_code)] // the examples', not the bench's
pub fn ideal_from_args(default: usize) -> Result<(Problem, usize, String), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let draws: usize = args.first().and_then(|a| a.parse().ok()).unwrap_or(default);
    let (path, vary) = match args.get(1) {
        Some(mech) => (PathBuf::from(mech), args[2..].to_vec()),
        None => (
            PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(T01),
            T01_VARY.iter().map(|v| v.to_string()).collect(),
        ),
    };
    let problem = problem(&path, &vary)?;
    if problem.vary.is_empty() || problem.mech.has_physical_latch() {
        return Err("a mechanism with ideal latches only and at least one law to vary".into());
    }
    let name = path
        .file_stem()
        .map_or(String::new(), |s| s.to_string_lossy().into_owned());
    Ok((problem, draws, name))
}
