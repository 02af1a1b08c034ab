//! `deploywatch replay`: the host target's status CSV and summary, the clear
//! error of a missing firmware, and the replay protocol (configuration
//! frames, the firmware's loop run on the host, the comparison). The QEMU
//! run itself is exercised by `scripts/firmware.sh test`.

use std::path::{Path, PathBuf};
use std::process::Command;

use deploywatch_core::monitor::{LatchState, Status};
use deploywatch_core::telemetry;
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::replay::{self, ReplayError};

fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../data")
        .join(rel)
}

fn deploywatch(args: &[&std::ffi::OsStr]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_deploywatch"))
        .arg("replay")
        .args(args)
        .output()
        .expect("runs")
}

fn prepared(run: &str, mech: &str) -> replay::Prepared {
    let mech = Mechanism::load(&data(mech)).unwrap();
    let run = replay::load_run(&data(run)).unwrap();
    replay::prepare(&mech, &run).unwrap()
}

#[test]
fn host_replay_writes_the_status_csv_and_a_summary() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("status.csv");
    let png = dir.path().join("status.png");
    let run = data("examples/a_seed001_eft/seed001_T01.csv");
    let mech = data("mechanisms/seed001_T01.toml");
    let out = deploywatch(&[
        run.as_os_str(),
        "--mechanism".as_ref(),
        mech.as_os_str(),
        "--target".as_ref(),
        "host".as_ref(),
        "--out".as_ref(),
        csv.as_os_str(),
        "--plot".as_ref(),
        png.as_os_str(),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for j in 1..=3 {
        assert!(stdout.contains(&format!("joint {j}: ")), "{stdout}");
    }
    assert!(
        stdout.contains("Coulomb") && stdout.contains("margin"),
        "{stdout}"
    );
    assert!(std::fs::metadata(&png).unwrap().len() > 1000);

    let mut want = vec!["t_s".to_string()];
    for j in 1..=3 {
        for c in [
            "phi{j}_deg",
            "rate{j}_deg_s",
            "coulomb{j}_nm",
            "coulomb{j}_sd_nm",
            "viscous{j}_nms",
            "viscous{j}_sd_nms",
            "viscous{j}_obs",
            "latch{j}",
            "margin{j}_pct",
            "prediction{j}",
            "confidence{j}",
            "time_to_latch{j}_s",
            "faults{j}",
            "resolution{j}",
        ] {
            want.push(c.replace("{j}", &j.to_string()));
        }
    }
    let mut reader = csv::Reader::from_path(&csv).unwrap();
    let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
    assert_eq!(header, want);
    let states = [
        "stowed",
        "deploying",
        "latching",
        "latched",
        "stalled",
        "fault",
    ];
    let predictions = ["latch", "stall", "unknown", "ramp_stop"];
    let fault_names: Vec<&str> = deploywatch_core::monitor::Fault::ALL
        .iter()
        .map(|f| f.as_str())
        .collect();
    let run_len = replay::load_run(&run).unwrap().len();
    let mut rows = 0;
    let mut latched = [false; 3];
    for rec in reader.records() {
        let rec = rec.unwrap();
        rows += 1;
        let _: f32 = rec[0].parse().unwrap();
        for j in 0..3 {
            let col = |k: usize| &rec[1 + 14 * j + k];
            for k in [0, 1, 2, 3, 4, 5] {
                assert!(col(k).parse::<f32>().is_ok(), "{}", col(k));
            }
            assert!(
                ["estimated", "unobservable"].contains(&col(6)),
                "viscous {}",
                col(6)
            );
            assert!(states.contains(&col(7)), "state {}", col(7));
            latched[j] |= col(7) == "latched";
            assert!(
                col(8).is_empty() || col(8).parse::<f32>().is_ok(),
                "{}",
                col(8)
            );
            assert!(predictions.contains(&col(9)), "prediction {}", col(9));
            let confidence: f32 = col(10).parse().unwrap();
            assert!((0.0..=1.0).contains(&confidence), "confidence {}", col(10));
            assert!(
                col(11).is_empty() || col(11).parse::<f32>().is_ok_and(|t| t >= 0.0),
                "time to latch {}",
                col(11)
            );
            assert!(
                col(12).is_empty() || col(12).split('|').all(|f| fault_names.contains(&f)),
                "faults {}",
                col(12)
            );
            assert!(
                deploywatch_core::monitor::Resolution::from_name(col(13)).is_some(),
                "resolution {}",
                col(13)
            );
        }
    }
    assert_eq!(rows, run_len);
    assert!(latched.iter().any(|&l| l), "some joint latches in this run");
}

/// The status CSV of `run` on `mech` (under `data/`), written by `replay --out`,
/// read back: its header and rows (the cells as written).
fn status_csv_of(run: &str, mech: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("status.csv");
    let (run, mech) = (data(run), data(mech));
    let out = deploywatch(&[
        run.as_os_str(),
        "--mechanism".as_ref(),
        mech.as_os_str(),
        "-q".as_ref(),
        "--out".as_ref(),
        csv.as_os_str(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut reader = csv::Reader::from_path(&csv).unwrap();
    let header = reader.headers().unwrap().iter().map(String::from).collect();
    let rows = reader
        .records()
        .map(|r| r.unwrap().iter().map(String::from).collect())
        .collect();
    (header, rows)
}

/// `confidence<j>` and `time_to_latch<j>_s` come right after
/// `prediction<j>`, fourteen columns a joint.
#[test]
fn the_status_csv_has_confidence_and_time_to_latch_after_the_prediction() {
    let (header, _) = status_csv_of(
        "reference/seed000_case1_eft.csv",
        "mechanisms/seed000_case1.toml",
    );
    assert_eq!(header.len(), 1 + 14 * 2, "{header:?}");
    for j in 1..=2 {
        let at = 1 + 14 * (j - 1);
        assert_eq!(
            header[at + 9..at + 13],
            [
                format!("prediction{j}"),
                format!("confidence{j}"),
                format!("time_to_latch{j}_s"),
                format!("faults{j}"),
            ],
            "{header:?}"
        );
    }
}

/// Every row's `confidence<j>` and `time_to_latch<j>_s` are the
/// `JointStatus`'s `confidence` and `time_to_latch_s` (empty for `None`),
/// on a run where the confidence takes each of 0, 0.5, 0.9 and 1 and the
/// time to latch is both given and not.
#[test]
fn the_status_csv_gives_each_statuss_confidence_and_time_to_latch() {
    let (run, mech) = (
        "reference/seed000_case1_eft.csv",
        "mechanisms/seed000_case1.toml",
    );
    let (header, rows) = status_csv_of(run, mech);
    let host = prepared(run, mech).host;
    assert_eq!(rows.len(), host.len());
    let column = |name: String| header.iter().position(|h| *h == name).unwrap();
    let bits = |cell: &str| cell.parse::<f32>().unwrap().to_bits();
    let mut levels = std::collections::BTreeSet::new();
    let (mut given, mut empty) = (0, 0);
    for (row, status) in rows.iter().zip(&host) {
        for (j, js) in status.joints.iter().enumerate() {
            let confidence = &row[column(format!("confidence{}", j + 1))];
            let ttl = &row[column(format!("time_to_latch{}_s", j + 1))];
            let at = format!("t = {} s, joint {}", status.t_s, j + 1);
            assert_eq!(bits(confidence), js.confidence.to_bits(), "{at}");
            levels.insert(js.confidence.to_bits());
            match js.time_to_latch_s {
                Some(t) => {
                    assert_eq!(bits(ttl), t.to_bits(), "{at}");
                    given += 1;
                }
                None => {
                    assert_eq!(ttl, "", "{at}");
                    empty += 1;
                }
            }
        }
    }
    let want: Vec<u32> = [0.0f32, 0.5, 0.9, 1.0].map(f32::to_bits).to_vec();
    assert!(want.iter().all(|w| levels.contains(w)), "{levels:?}");
    assert!(given > 0 && empty > 0, "{given} given, {empty} empty");
}

#[test]
fn qemu_without_firmware_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let elf = dir.path().join("no-such-firmware.elf");
    let run = data("reference/seed001_T01_nominal.csv");
    let mech = data("mechanisms/seed001_T01.toml");
    let out = deploywatch(&[
        run.as_os_str(),
        "--mechanism".as_ref(),
        mech.as_os_str(),
        "--target".as_ref(),
        "qemu".as_ref(),
        "--elf".as_ref(),
        elf.as_os_str(),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(stderr.contains("no firmware ELF"), "{stderr}");
    assert!(stderr.contains("scripts/embedded-toolchain.sh"), "{stderr}");
    assert!(stderr.contains("scripts/firmware.sh build"), "{stderr}");
}

#[test]
fn the_firmware_loop_on_the_host_is_bit_identical_for_every_reference_mechanism() {
    for (run, mech) in [
        (
            "reference/seed000_case1_eft.csv",
            "mechanisms/seed000_case1.toml",
        ),
        (
            "reference/seed000_case3_nominal.csv",
            "mechanisms/seed000_case3.toml",
        ),
        (
            "reference/seed001_T01_eft.csv",
            "mechanisms/seed001_T01.toml",
        ),
        (
            "reference/seed001_T02_nominal.csv",
            "mechanisms/seed001_T02.toml",
        ),
    ] {
        let p = prepared(run, mech);
        assert!(replay::firmware_supports(p.joints), "{run}");
        let fw = replay::firmware_loop_on_host(&p.input, p.joints).unwrap();
        assert_eq!(
            replay::compare(&p.host_frames, &fw, p.joints),
            Ok(p.samples),
            "{run}"
        );
        let decoded = replay::decode_statuses(&fw, p.joints).unwrap();
        assert!(decoded == p.host, "{run}");
    }
}

/// Wings of 4 and 6 panels: the firmware's loop with a monitor
/// of the run's joint count gives the host's statuses bit for bit; with a
/// monitor of another count it refuses the configuration by name.
#[test]
fn the_firmware_loop_takes_any_joint_count_it_is_built_for_and_refuses_another() {
    for (run, mech, joints) in [
        (
            "examples/wing6/wing6_ideal.csv",
            "mechanisms/wing6_ideal.toml",
            6,
        ),
        (
            "examples/wing6/wing6_plunger.csv",
            "mechanisms/wing6_plunger.toml",
            6,
        ),
        (
            "examples/wing4/wing4_ideal.csv",
            "mechanisms/wing4_ideal.toml",
            4,
        ),
    ] {
        let p = prepared(run, mech);
        assert_eq!(p.joints, joints, "{run}");
        assert_eq!(replay::firmware_supports(joints), joints == 6, "{run}");
        let fw = replay::firmware_loop_on_host(&p.input, joints).unwrap();
        assert_eq!(
            replay::compare(&p.host_frames, &fw, joints),
            Ok(p.samples),
            "{run}"
        );
        let err = replay::firmware_loop_on_host(&p.input, 3).unwrap_err();
        assert!(
            err.to_string().contains(&format!(
                "the configuration is of {joints} joints, the monitor of 3"
            )),
            "{run}: {err}"
        );
    }
}

#[test]
fn compare_names_the_first_differing_frame_joint_and_field() {
    let p = prepared(
        "reference/seed001_T01_nominal.csv",
        "mechanisms/seed001_T01.toml",
    );
    let mut frames: Vec<Vec<u8>> = replay::frames(&p.host_frames).map(<[u8]>::to_vec).collect();
    let mut copy = frames[100].clone();
    let mut status: Status<3> = telemetry::decode(&mut copy).unwrap();
    status.joints[1].coulomb_nm = f32::from_bits(status.joints[1].coulomb_nm.to_bits() ^ 1);
    let mut buf = [0u8; 512];
    frames[100] = telemetry::encode(&status, &mut buf).unwrap().to_vec();
    let target: Vec<u8> = frames.concat();
    let m = replay::compare(&p.host_frames, &target, 3).unwrap_err();
    assert_eq!(
        (m.frame, m.joint, m.field.as_str()),
        (100, Some(2), "coulomb_nm")
    );
    // A missing frame at the end.
    let short = &p.host_frames
        [..p.host_frames.len() - replay::frames(&p.host_frames).last().unwrap().len()];
    let m = replay::compare(&p.host_frames, short, 3).unwrap_err();
    assert_eq!(m.field, "number of frames");
}

#[test]
fn damaged_inputs_stop_the_firmware_loop() {
    let p = prepared(
        "reference/seed000_case1_nominal.csv",
        "mechanisms/seed000_case1.toml",
    );
    // Truncated inside the last frame.
    let err = replay::firmware_loop_on_host(&p.input[..p.input.len() - 2], p.joints).unwrap_err();
    assert!(err.to_string().contains("ends inside a frame"), "{err}");
    // A flipped bit in a late sample frame: its CRC fails, with its index.
    let mut bad = p.input.clone();
    let at = bad.len() - 10;
    bad[at] ^= 0x10;
    let err = replay::firmware_loop_on_host(&bad, p.joints).unwrap_err();
    assert!(
        err.to_string()
            .contains(&format!("sample frame {}", p.samples - 1)),
        "{err}"
    );
    // No configuration: the samples alone.
    let config_len: usize = replay::frames(&p.input).take(3).map(<[u8]>::len).sum();
    let err = replay::firmware_loop_on_host(&p.input[config_len..], p.joints).unwrap_err();
    assert!(err.to_string().contains("configuration"), "{err}");
    // An empty input has no configuration either.
    assert!(matches!(
        replay::firmware_loop_on_host(&[], p.joints),
        Err(ReplayError::Target(_))
    ));
}

#[test]
fn summary_reports_the_latch_times_and_the_last_prediction() {
    let p = prepared(
        "reference/seed001_T01_nominal.csv",
        "mechanisms/seed001_T01.toml",
    );
    let s = replay::summary(&p.host);
    assert_eq!(s.len(), 3);
    let last = p.host.last().unwrap();
    for js in &s {
        let status = &last.joints[js.joint - 1];
        assert_eq!(
            (js.prediction, js.confidence.to_bits()),
            (status.prediction.as_str(), status.confidence.to_bits())
        );
        if let Some(t) = js.latched_s {
            let first = p
                .host
                .iter()
                .find(|r| r.joints[js.joint - 1].latch == LatchState::Latched)
                .unwrap();
            assert_eq!(first.t_s, t);
        }
    }
}

#[test]
fn a_run_of_another_mechanism_is_refused() {
    let mech = Mechanism::load(&data("mechanisms/seed001_T02.toml")).unwrap();
    let run = replay::load_run(&data("reference/seed001_T01_nominal.csv")).unwrap();
    assert!(matches!(
        replay::prepare(&mech, &run),
        Err(ReplayError::Input(_))
    ));
}

/// A run on a zero-g rig replayed with its rig mechanism: the monitor
/// models the wing without the rig, and replay says so; a wing without a
/// rig says nothing of it.
#[test]
fn a_replay_on_a_rig_says_the_monitor_has_no_rig() {
    let dir = tempfile::tempdir().unwrap();
    let run = dir.path().join("rig.csv");
    let rig = data("mechanisms/seed001_T01_rig.toml");
    let made = Command::new(env!("CARGO_BIN_EXE_deploywatch"))
        .args([
            "simulate".as_ref(),
            rig.as_os_str(),
            "-o".as_ref(),
            run.as_os_str(),
            "-q".as_ref(),
        ])
        .output()
        .expect("runs");
    assert!(
        made.status.success(),
        "{}",
        String::from_utf8_lossy(&made.stderr)
    );
    let said = "deploys on a zero-g rig: the monitor models the wing without it";
    let out = deploywatch(&[
        run.as_os_str(),
        "--mechanism".as_ref(),
        rig.as_os_str(),
        "-q".as_ref(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success() && err.contains(said), "{err}");
    let plain = data("examples/a_seed001_eft/seed001_T01.csv");
    let t01 = data("mechanisms/seed001_T01.toml");
    let out = deploywatch(&[
        plain.as_os_str(),
        "--mechanism".as_ref(),
        t01.as_os_str(),
        "-q".as_ref(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success() && !err.contains("zero-g rig"), "{err}");
}

/// A run whose encoders are noisier than the monitor is tuned for (σ
/// about 0.06 deg against 0.02) is replayed with a warning that its
/// friction, margins and states are not to be trusted; the bundled run at
/// the reference noise raises none.
#[test]
fn a_run_noisier_than_the_monitor_is_tuned_for_is_said() {
    let dir = tempfile::tempdir().unwrap();
    let plain = data("examples/a_seed001_eft/seed001_T01.csv");
    let t01 = data("mechanisms/seed001_T01.toml");
    // A deterministic noise of ±0.08 deg in a pseudo-random sign pattern
    // on every angle.
    let text = std::fs::read_to_string(&plain).unwrap();
    let mut k: u64 = 7;
    let noisy: Vec<String> = text
        .lines()
        .map(|line| {
            if line.starts_with('#') || line.starts_with("t_s") {
                return line.to_string();
            }
            let mut f: Vec<String> = line.split(',').map(String::from).collect();
            for cell in f.iter_mut().skip(1).take(3) {
                k = k
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let step = if k >> 63 == 1 { 0.08 } else { -0.08 };
                *cell = format!("{:.6}", cell.parse::<f64>().unwrap() + step);
            }
            f.join(",")
        })
        .collect();
    let run = dir.path().join("noisy.csv");
    std::fs::write(&run, noisy.join("\n") + "\n").unwrap();
    let said = "more than 2 times the 0.020 deg the monitor is tuned for";
    for (path, warned) in [(&run, true), (&plain, false)] {
        let out = deploywatch(&[
            path.as_os_str(),
            "--mechanism".as_ref(),
            t01.as_os_str(),
            "-q".as_ref(),
        ]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            out.status.success() && err.contains(said) == warned,
            "{err}"
        );
    }
}
