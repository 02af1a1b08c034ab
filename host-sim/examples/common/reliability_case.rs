//! The reliability case the throughput is measured on (docs/reliability.md
//! §6): seed 001 T01 with its identified friction at 5 % lognormal
//! dispersion, `--fail not_latched`. Shared by `benches/reliability.rs` and
//! `examples/ideal_ledger.rs` (included with `#[path = ...] mod`).

use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::reliability::Problem;
use std::path::Path;

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
