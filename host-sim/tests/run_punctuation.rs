//! A run saved with stray punctuation, checked on the `deploywatch` binary
//! as a black box: a comma at the end of every row, of the header, of a
//! metadata line, and an empty line before the header. Each is refused
//! (exit 2) at its line with what the file has there and what was expected,
//! not with the hint of another mistake (decimal commas, a header for one
//! joint).
//!
//! `cargo test -p deploywatch-sim --test run_punctuation`

mod common;

use std::path::Path;
use std::process::Output;

use common::{deploywatch, fails, s, t01_mechanism, t01_run_text, write};

/// `identify` of `run` on seed 001 T01, as a user starts it.
fn identify(run: &Path) -> Output {
    deploywatch(&["identify", "-q", "--mechanism", s(&t01_mechanism()), s(run)])
}

/// The bundled run's metadata lines, header and rows.
fn parts() -> (Vec<String>, String, Vec<String>) {
    let text = t01_run_text();
    let meta = text
        .lines()
        .filter(|l| l.starts_with('#'))
        .map(String::from)
        .collect::<Vec<_>>();
    let mut body = text.lines().filter(|l| !l.starts_with('#'));
    let header = body.next().expect("header").to_string();
    (meta, header, body.map(String::from).collect())
}

/// The run from its parts, one per line.
fn join(meta: &[String], header: &str, rows: &[String]) -> String {
    let mut out = String::new();
    for l in meta.iter().chain([header.to_string()].iter()).chain(rows) {
        out.push_str(l);
        out.push('\n');
    }
    out
}

#[test]
fn a_comma_ending_every_row_is_refused_naming_the_trailing_comma() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (meta, header, rows) = parts();
    let rows: Vec<String> = rows.iter().map(|r| format!("{r},")).collect();
    let run = write(dir.path(), "rows.csv", join(&meta, &header, &rows));
    let first_row = meta.len() + 2;
    let err = fails(
        &identify(&run),
        2,
        &[
            &format!("rows.csv:{first_row}:"),
            "found 8",
            "ends with `,`",
        ],
    );
    assert!(!err.contains("decimal commas"), "{err}");
}

#[test]
fn a_comma_ending_the_header_is_refused_at_the_header() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (_, header, rows) = parts();
    let rows: Vec<String> = rows.iter().map(|r| format!("{r},")).collect();
    let run = write(
        dir.path(),
        "header.csv",
        join(&[], &format!("{header},"), &rows),
    );
    let err = fails(
        &identify(&run),
        2,
        &["header.csv:1:", "without a comma at its end", &header],
    );
    assert!(!err.contains("extra column"), "{err}");
}

#[test]
fn a_comma_ending_a_metadata_line_is_refused_naming_the_comma() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (meta, header, rows) = parts();
    let meta: Vec<String> = meta.iter().map(|m| format!("{m},")).collect();
    let run = write(dir.path(), "meta.csv", join(&meta, &header, &rows));
    fails(&identify(&run), 2, &["meta.csv:1:", "no comma at the end"]);
}

#[test]
fn an_empty_line_before_the_header_is_refused_naming_the_header() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (meta, header, rows) = parts();
    let mut with_blank = meta.clone();
    with_blank.push(String::new());
    let run = write(dir.path(), "blank.csv", join(&with_blank, &header, &rows));
    let line = meta.len() + 1;
    let err = fails(
        &identify(&run),
        2,
        &[
            &format!("blank.csv:{line}:"),
            "expected the header",
            "empty line",
        ],
    );
    assert!(!err.contains("1 joint(s)"), "{err}");
}
