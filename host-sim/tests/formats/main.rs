//! The interchange formats of `docs/spec/formats.md`: the bundled mechanisms
//! and runs read, write and read back unchanged; every kind of bad input is
//! rejected with an error naming the file, the line or key, and what was
//! expected.//!
//! One module per kind of check: `mechanism_files`, `mechanism_errors`,
//! `run_files`, `run_errors`, `mutations`; the helpers they share are here.

mod mechanism_errors;
mod mechanism_files;
mod mutations;
mod run_errors;
mod run_files;

use std::path::{Path, PathBuf};

use deploywatch_core::Interp;
use deploywatch_sim::mechanism::{Mechanism, SpringSpec};
use deploywatch_sim::mechanism_toml::{MechanismError, MechanismErrorKind};
use deploywatch_sim::run::{pair_runs, Run, RunError, RunErrorKind};

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../data")
}

/// The files of `dir` with extension `ext`, sorted.
fn files(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("dir entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == ext))
        .collect();
    v.sort();
    v
}

fn mechanisms() -> Vec<Mechanism> {
    // The truss wings (`*_truss*.toml`) are tested in tests/truss.rs and
    // host-sim/tests/truss_cli.rs; the project's own
    // `reliability_one_panel.toml` (not a seed mechanism) in tests/reliability.rs;
    // the physical-latch examples (`*_physical_latch.toml`) in tests/physical_latch.rs;
    // the rig examples (`*_rig.toml`) in host-sim/tests/rig.rs;
    // the pawl examples (`*_pawl.toml`) in tests/latch_pawl.rs.
    files(&data().join("mechanisms"), "toml")
        .iter()
        .filter(|p| !p.to_string_lossy().contains("_truss"))
        .filter(|p| !p.to_string_lossy().contains("_physical_latch"))
        .filter(|p| !p.to_string_lossy().ends_with("_rig.toml"))
        .filter(|p| !p.to_string_lossy().ends_with("_pawl.toml"))
        .filter(|p| {
            p.file_name()
                .is_some_and(|f| f.to_string_lossy().starts_with("seed"))
        })
        .map(|p| Mechanism::load(p).unwrap_or_else(|e| panic!("{e}")))
        .collect()
}

/// `data/reference/*.csv` and `data/examples/*/*.csv` (but the
/// physical-latch runs `data/examples/latch_*`, tested in
/// tests/physical_latch.rs with their own mechanisms).
fn bundled_runs() -> Vec<PathBuf> {
    let mut v = files(&data().join("reference"), "csv");
    for d in std::fs::read_dir(data().join("examples")).expect("examples") {
        let d = d.expect("entry").path();
        let latch = d
            .file_name()
            .is_some_and(|f| f.to_string_lossy().starts_with("latch_"));
        if d.is_dir() && !latch {
            v.extend(files(&d, "csv"));
        }
    }
    v.sort();
    v
}

/// 1-based line of the first line of `text` containing `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .unwrap_or_else(|| panic!("{needle:?} not in text"))
        + 1
}

// ---------------------------------------------------------------------------
// Mechanisms.

fn t01_text() -> String {
    std::fs::read_to_string(data().join("mechanisms/seed001_T01.toml")).expect("T01")
}

/// T01 with the first `from` replaced by `to`.
fn t01_with(from: &str, to: &str) -> String {
    let text = t01_text();
    assert!(text.contains(from), "{from:?} not in T01");
    text.replacen(from, to, 1)
}

fn bad_mech(text: &str) -> MechanismError {
    match Mechanism::from_toml_str(text, "bad.toml") {
        Ok(m) => panic!("accepted: {m:?}"),
        Err(e) => e,
    }
}

const GOOD: &str = "# mechanism = \"seed000-case1-open\"\n\
# source = \"hand-written, \\\"quoted\\\" \\u00b0\"\n\
t_s,phi1_deg,phi2_deg,latch1,latch2\n\
0.000,90.0,-180.0,0,0\n\
0.010,89.5,-179.0,0,0\n\
0.020,89.0,-178.5,0,0\n";

fn bad_run(text: &str) -> RunError {
    match Run::parse(text, "bad.csv") {
        Ok(r) => panic!("accepted: {r:?}"),
        Err(e) => e,
    }
}
