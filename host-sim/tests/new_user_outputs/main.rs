//! What a new user runs into at the command line with outputs: `margin
//! --from`, help texts, words instead of Rust debug output, `--quiet`,
//! plots, identify's residual warning. The `deploywatch` binary is run as a black box on the
//! bundled data; every test checks the exit code, the message and that
//! nothing panicked.//!
//! One module per area: `outputs_checked`, `margin_from`, `words`, `plots`;
//! the helpers they share are here.

mod margin_from;
mod outputs_checked;
mod plots;
mod words;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use deploywatch_sim::effect::EffectKind;
use serde_json::Value;

fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../data")
        .join(rel)
}

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

fn deploywatch(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_deploywatch"))
        .args(args)
        .output()
        .expect("run deploywatch")
}

fn stdout(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Asserts success without a panic; returns stdout.
fn succeeds(out: &Output) -> String {
    let err = stderr(out);
    assert!(!err.contains("panicked"), "panic:\n{err}");
    assert!(
        out.status.success(),
        "exit {:?}; stderr:\n{err}",
        out.status
    );
    stdout(out)
}

/// Asserts a clean failure with exit code `code` and stderr containing
/// every one of `says`; returns stderr.
fn fails(out: &Output, code: i32, says: &[&str]) -> String {
    let err = stderr(out);
    assert!(!err.contains("panicked"), "panic:\n{err}");
    assert_eq!(out.status.code(), Some(code), "exit code; stderr:\n{err}");
    for w in says {
        assert!(err.contains(w), "stderr lacks {w:?}:\n{err}");
    }
    err
}

const T01: &str = "mechanisms/seed001_T01.toml";
const T02: &str = "mechanisms/seed001_T02.toml";

/// The identify arguments of the bundled EFT campaign (example a).
fn identify_a(extra: &[&str]) -> Output {
    let (m1, m2) = (data(T01), data(T02));
    let (r1, r2) = (
        data("examples/a_seed001_eft/seed001_T01.csv"),
        data("examples/a_seed001_eft/seed001_T02.csv"),
    );
    let mut args = vec![
        "identify",
        "--mechanism",
        s(&m1),
        "--mechanism",
        s(&m2),
        s(&r1),
        s(&r2),
    ];
    args.extend_from_slice(extra);
    deploywatch(&args)
}

/// The height [px] of a PNG, from its IHDR chunk.
fn png_height(path: &Path) -> u32 {
    let bytes = std::fs::read(path).expect("png written");
    assert_eq!(&bytes[1..4], b"PNG", "{} is not a PNG", path.display());
    u32::from_be_bytes(bytes[20..24].try_into().expect("IHDR"))
}

/// Runs `margin --mechanism seed001_T01 --from FILE --json margins.json`
/// (beside FILE).
fn run_margin_from(file: &Path, extra: &[&str]) -> Output {
    let margins = file.with_file_name("margins.json");
    let mech = data(T01);
    let mut args = vec![
        "margin",
        "--mechanism",
        s(&mech),
        "--from",
        s(file),
        "--json",
        s(&margins),
    ];
    args.extend_from_slice(extra);
    deploywatch(&args)
}

/// The bundled run of example c at T01, diagnosed alone (about a second).
fn diagnose_t01(json: &Path) -> Output {
    let run = data("examples/c_seed001_friction_harness/seed001_T01.csv");
    deploywatch(&[
        "diagnose",
        "-q",
        "--mechanism",
        s(&data(T01)),
        "--json",
        s(json),
        s(&run),
    ])
}
