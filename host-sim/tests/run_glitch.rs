//! A run with one corrupted reading (an encoder's or a logger's glitch),
//! checked on the `deploywatch` binary as a black box: `identify` names the
//! glitch at its line and fits the run as if its row were not there (the
//! same table as the run with that row deleted); `replay` names it too and
//! gives the monitor the run as read.
//!
//! `cargo test -p deploywatch-sim --test run_glitch`

mod common;

use std::path::Path;
use std::process::Output;

use common::{deploywatch, s, t01_mechanism, t01_run_text, write};

fn identify(run: &Path) -> Output {
    deploywatch(&["identify", "-q", "--mechanism", s(&t01_mechanism()), s(run)])
}

/// The bundled run with row `row` (0-based among the data rows) changed by
/// `f`, or deleted where `f` gives `None`; and the line of that row.
fn edited(row: usize, f: impl Fn(&str) -> Option<String>) -> (String, usize) {
    let text = t01_run_text();
    let mut out = String::new();
    let mut data = 0;
    let mut line = 0;
    let mut past_header = false;
    for (n, l) in text.lines().enumerate() {
        let is_row = past_header;
        if !l.starts_with('#') {
            past_header = true;
        }
        if is_row {
            if data == row {
                line = n + 1;
                if let Some(new) = f(l) {
                    out.push_str(&new);
                    out.push('\n');
                }
                data += 1;
                continue;
            }
            data += 1;
        }
        out.push_str(l);
        out.push('\n');
    }
    (out, line)
}

/// Joint 1's reading of a row set to 0 deg (the latched pose).
fn zero_joint_1(row: &str) -> Option<String> {
    let mut f: Vec<String> = row.split(',').map(String::from).collect();
    f[1] = "0.0000".to_string();
    Some(f.join(","))
}

#[test]
fn a_glitch_is_named_at_its_line_and_left_out_of_the_fit() {
    let dir = tempfile::tempdir().expect("temp dir");
    // t = 0.6 s: joint 1 halfway through its stroke, some 30 deg from 0.
    let (glitched, line) = edited(60, zero_joint_1);
    let (deleted, _) = edited(60, |_| None);
    let with = write(dir.path(), "glitch.csv", glitched);
    let without = write(dir.path(), "glitch_deleted.csv", deleted);
    let a = identify(&with);
    let b = identify(&without);
    let err = String::from_utf8_lossy(&a.stderr);
    assert_eq!(a.status.code(), Some(0), "{err}");
    assert!(
        err.contains(&format!("glitch.csv:{line}: column `phi1_deg`")) && err.contains("glitch"),
        "{err}"
    );
    assert!(!String::from_utf8_lossy(&b.stderr).contains("glitch of"));
    // The tables after their first line (which names the file).
    let table = |o: &Output| {
        String::from_utf8_lossy(&o.stdout)
            .lines()
            .skip(1)
            .filter(|l| l.trim_start().starts_with(char::is_numeric))
            .map(String::from)
            .collect::<Vec<_>>()
    };
    assert!(!table(&a).is_empty());
    assert_eq!(table(&a), table(&b));
}

#[test]
fn replay_names_the_glitch_and_runs_the_monitor_on_it() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (glitched, line) = edited(60, zero_joint_1);
    let run = write(dir.path(), "glitch.csv", glitched);
    let status = dir.path().join("status.csv");
    let out = deploywatch(&[
        "replay",
        s(&run),
        "--mechanism",
        s(&t01_mechanism()),
        "--out",
        s(&status),
        "-q",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert!(err.contains(&format!("glitch.csv:{line}:")), "{err}");
    let csv = std::fs::read_to_string(&status).expect("status CSV");
    assert!(csv.contains("encoder_outlier"), "the monitor saw no spike");
}
