//! Helpers shared by the black-box tests of the `deploywatch` binary
//! (`robustness.rs`, `new_user_inputs.rs`).
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The bundled data folder.
pub fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../data")
}

/// seed001 T01's mechanism file (3 joints).
pub fn t01_mechanism() -> PathBuf {
    data().join("mechanisms/seed001_T01.toml")
}

/// A measured-looking run of seed001 T01 (3 joints, 100 Hz) as CSV text.
pub fn t01_run_text() -> String {
    std::fs::read_to_string(data().join("examples/a_seed001_eft/seed001_T01.csv"))
        .expect("bundled run")
}

/// Runs the `deploywatch` binary.
pub fn deploywatch(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_deploywatch"))
        .args(args)
        .output()
        .expect("run deploywatch")
}

/// Asserts a clean failure: exit code `code`, no panic, and stderr
/// containing every one of `says`. Returns stderr.
pub fn fails(out: &Output, code: i32, says: &[&str]) -> String {
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!err.contains("panicked"), "panic:\n{err}");
    assert_eq!(out.status.code(), Some(code), "exit code; stderr:\n{err}");
    for s in says {
        assert!(err.contains(s), "stderr lacks {s:?}:\n{err}");
    }
    err
}

/// Writes a test file `dir/name`.
pub fn write(dir: &Path, name: &str, text: impl AsRef<[u8]>) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).expect("write test file");
    p
}

/// A path as a command-line argument.
pub fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}
