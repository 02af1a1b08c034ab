//! The sample rate chooses where a run is sampled, never what happens:
//! the uniform grid covers the whole `duration_s` (its last sample at or
//! after it), so a joint that latches late in the duration latches at the
//! same instant whatever the rate. Seed 001 T01 with Coulomb friction of
//! 2.7 N·m at joint 1 latches that joint at about 5.9 s of its 6 s; at
//! 4.3 Hz the grid's last sample before 6 s is 5.814 s, and a grid that
//! ended there lost the latch. A run at a few samples a second is
//! identified without the warnings meant for runs long enough to tell
//! their noise and their start from.
//!
//! `cargo test --release -p deploywatch-sim --test sample_rate`

use deploywatch_sim::deployment::{simulate, SimOptions};
use deploywatch_sim::effect::Effect;
use deploywatch_sim::mechanism::Mechanism;
use std::path::PathBuf;

fn t01() -> Mechanism {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../data/mechanisms/seed001_T01.toml");
    Mechanism::load(&path).expect("seed001_T01.toml")
}

#[test]
fn a_late_latch_is_kept_at_every_sample_rate() {
    let mech = t01();
    let effects: Vec<Effect> = vec!["coulomb_friction:joint=1:value=2.7"
        .parse()
        .expect("effect")];
    let at = |hz: f64| {
        let opts = SimOptions {
            sample_hz: Some(hz),
            ..SimOptions::default()
        };
        simulate(&mech, &effects, &opts).expect("run")
    };
    let fine = at(1000.0);
    let late = fine.latch_s[0].expect("joint 1 latches within the duration at 1 kHz");
    assert!(
        late > mech.duration_s - 0.5 && late < mech.duration_s,
        "the case is a latch late in the duration: {late} s of {} s",
        mech.duration_s
    );
    for hz in [0.1, 0.7, 4.3, 7.0, 33.0, 100.0] {
        let run = at(hz);
        let last = *run.t_s.last().expect("samples");
        assert!(
            last >= mech.duration_s.min(late) - 1e-12,
            "{hz} Hz: the grid ends at {last} s, before the latch at {late} s"
        );
        for j in 0..mech.joint_count() {
            match (fine.latch_s[j], run.latch_s[j]) {
                (Some(a), Some(b)) => assert!(
                    (a - b).abs() < 1e-6,
                    "{hz} Hz: joint {} latches at {b} s, at 1 kHz {a} s",
                    j + 1
                ),
                (a, b) => assert_eq!(
                    a,
                    b,
                    "{hz} Hz: joint {} latched {b:?}, at 1 kHz {a:?}",
                    j + 1
                ),
            }
        }
    }
}

/// A run of five samples a second (ten in all) is identified without a
/// false alarm: too few samples to estimate the noise from, the fit's
/// residual is not judged against a noise floor of 0.001 deg, and the
/// start is read from the first sample, not from a median over half the
/// deployment.
#[test]
fn identify_of_a_run_at_5_hz_raises_no_false_alarm() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mech = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../data/mechanisms/reliability_one_panel.toml");
    let csv = dir.path().join("5hz.csv");
    let bin = env!("CARGO_BIN_EXE_deploywatch");
    let run = |args: &[&std::ffi::OsStr]| {
        let out = std::process::Command::new(bin)
            .args(args)
            .output()
            .expect("runs");
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(out.status.success(), "{err}");
        err
    };
    let os = |s: &str| std::ffi::OsString::from(s);
    let said = run(&[
        &os("simulate"),
        mech.as_os_str(),
        &os("--effect"),
        &os("coulomb_friction:joint=1:value=0.8"),
        &os("--rate"),
        &os("5"),
        &os("-o"),
        csv.as_os_str(),
        &os("-q"),
    ]);
    assert!(said.is_empty(), "{said}");
    let said = run(&[
        &os("identify"),
        &os("--mechanism"),
        mech.as_os_str(),
        csv.as_os_str(),
        &os("-q"),
    ]);
    assert!(!said.contains("times the noise"), "{said}");
    assert!(!said.contains("the run starts at"), "{said}");
    assert!(said.contains("too short to estimate their noise"), "{said}");
}
