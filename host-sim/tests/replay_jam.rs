//! A joint jammed in a recorded run, replayed through the on-board monitor
//! as a black box (`deploywatch replay`): the bundled run of seed 001 T01
//! with joint 3's readings held where they were at one instant (a small
//! wobble of the encoder's noise on them, its switch open) to the end of
//! the run. Jammed mid-stroke or 2° short of its ideal latch (inside the
//! zone where the tracker calls it `latching`), the joint ends `stalled`,
//! not latched: a stopped joint is reported whatever its filtered rate.
//!
//! `cargo test -p deploywatch-sim --test replay_jam`

mod common;

use std::path::Path;

use common::{deploywatch, s, t01_mechanism, t01_run_text, write};

/// The bundled run with joint 3 held from the first row where `from`
/// (its reading) holds: the reading of that row with a wobble of ±0.02°,
/// the switch open.
fn jammed(from: impl Fn(f64) -> bool) -> String {
    let wobble = [0.0, 0.02, -0.02, 0.01, -0.01];
    let mut held: Option<f64> = None;
    let mut out = String::new();
    let mut k = 0;
    for line in t01_run_text().lines() {
        let mut f: Vec<String> = line.split(',').map(String::from).collect();
        let row = !line.starts_with('#') && f[0].parse::<f64>().is_ok();
        if row {
            let phi3: f64 = f[3].parse().expect("phi3_deg");
            if held.is_none() && from(phi3) {
                held = Some(phi3);
            }
            if let Some(h) = held {
                f[3] = format!("{:.4}", h + wobble[k % wobble.len()]);
                f[6] = "0".to_string();
                k += 1;
            }
        }
        out.push_str(&f.join(","));
        out.push('\n');
    }
    assert!(held.is_some(), "joint 3 never reached the jam");
    out
}

/// `replay` of `run` on T01: joint 3's line of the summary.
fn joint_3(dir: &Path, run: &Path) -> String {
    let status = dir.join("status.csv");
    let out = deploywatch(&[
        "replay",
        s(run),
        "--mechanism",
        s(&t01_mechanism()),
        "--out",
        s(&status),
        "-q",
    ]);
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    text.lines()
        .find(|l| l.trim_start().starts_with("joint 3:"))
        .unwrap_or_else(|| panic!("no line of joint 3:\n{text}"))
        .to_string()
}

#[test]
fn a_joint_jammed_short_of_its_latch_ends_stalled() {
    let dir = tempfile::tempdir().expect("temp dir");
    // Joint 3 is stowed at -180 deg: 2 deg short of its latch is -2 deg.
    let run = write(dir.path(), "short.csv", jammed(|phi| phi >= -2.0));
    let line = joint_3(dir.path(), &run);
    assert!(line.contains("stalled (not latched)"), "{line}");
}

#[test]
fn a_joint_jammed_mid_stroke_ends_stalled() {
    let dir = tempfile::tempdir().expect("temp dir");
    let run = write(dir.path(), "mid.csv", jammed(|phi| phi >= -90.0));
    let line = joint_3(dir.path(), &run);
    assert!(line.contains("stalled (not latched)"), "{line}");
}

#[test]
fn the_bundled_run_replayed_as_recorded_ends_latched() {
    let dir = tempfile::tempdir().expect("temp dir");
    let run = write(dir.path(), "clean.csv", t01_run_text());
    let line = joint_3(dir.path(), &run);
    assert!(line.contains("latched (latched at"), "{line}");
    assert!(line.contains("prediction latch"), "{line}");
}
