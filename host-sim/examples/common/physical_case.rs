//! The physical-latch reliability case the rates and verdicts are measured
//! on: seed 001 T01 with its ball plungers and with its pawls, the
//! identified friction of the files given a 5 % normal dispersion, `--fail
//! not_latched`, the crude Monte-Carlo draws of seed 0. Shared by
//! `examples/physical_ledger.rs`, `examples/physical_held.rs` and
//! `examples/physical_tolerance.rs` (included
//! with `#[path = "common/physical_case.rs"] mod case;`).

use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::reliability::mc::draw;
use deploywatch_sim::reliability::Problem;
use std::path::PathBuf;

/// The wings and the 5 % dispersions of their friction [N·m] (0.05 × the
/// identified 2.63, 1.7 and 0.001 N·m of the mechanism files).
pub const WINGS: [(&str, [f64; 3]); 2] = [
    ("seed001_T01_physical_latch", [0.1315, 0.085, 0.00005]),
    ("seed001_T01_pawl", [0.1315, 0.085, 0.00005]),
];

/// The reliability problem of the bundled wing `name`, its friction
/// dispersed by `sd`, and its first `draws` crude Monte-Carlo draws.
pub fn problem(name: &str, sd: [f64; 3], draws: usize) -> Result<(Problem, Vec<Vec<f64>>), String> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../data/mechanisms");
    let mech = Mechanism::load(&root.join(format!("{name}.toml"))).map_err(|e| e.to_string())?;
    let p = Problem {
        mech,
        vary: (0..3)
            .map(|j| format!("coulomb_friction:joint={}:normal(0,{})", j + 1, sd[j]).parse())
            .collect::<Result<_, _>>()
            .map_err(|e| format!("{e}"))?,
        fixed: Vec::new(),
        fail: vec!["not_latched".parse().map_err(|e| format!("{e}"))?],
        corr: Vec::new(),
    };
    let xs = (0..draws as u64)
        .map(|i| p.x_of(&draw(0, 0, i, 3)))
        .collect();
    Ok((p, xs))
}
