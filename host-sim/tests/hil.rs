//! Hardware in the loop (`deploywatch hil`), the parts that need no QEMU:
//! the firmware's link loop (`deploywatch_core::telemetry::link::serve`)
//! run on the host over the bytes a lossy link delivers, and the latch
//! rule "never `latched` while out" on escapes replayed with the latch
//! drawn ideal and physical. The real-time runs on QEMU are
//! `scripts/firmware.sh test` (docs/firmware.md).

use std::path::{Path, PathBuf};
use std::process::Command;

use deploywatch_core::monitor::LatchState;
use deploywatch_core::telemetry::link::{read_report, read_shed, serve, LinkReport, Shed};
use deploywatch_core::telemetry::replay::{
    configure, read_header, ConfigStore, Direct, MonitorStore, Source,
};
use deploywatch_sim::hil::{self, Fate, Inject};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::replay::{self, StatusRow};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// A source over `bytes`.
fn source(mut rest: &[u8]) -> Source<impl FnMut(&mut [u8]) -> Result<usize, ()> + '_> {
    Source::new(move |buf: &mut [u8]| {
        let k = buf.len().min(rest.len());
        buf[..k].copy_from_slice(&rest[..k]);
        rest = &rest[k..];
        Ok(k)
    })
}

/// How the bytes reach the firmware's loop: each read of the source
/// brings `frames(r)` whole frames (read `r`, counted from 0; 1: a link
/// whose frames come one by one, as on a firmware that keeps up; more: a
/// burst, the frames that queued while it was busy), and `pending(c)` says
/// whether the receiver holds bytes at the `c`-th check (the firmware's
/// receive queue).
struct Arrival<'a> {
    frames: &'a dyn Fn(usize) -> usize,
    pending: &'a dyn Fn(usize) -> bool,
}

/// Frames one by one, nothing else waiting.
const PACED: Arrival<'static> = Arrival {
    frames: &|_| 1,
    pending: &|_| false,
};

/// What the firmware's loop writes: the statuses (and mid-stream reports),
/// the shed frames, and its last report.
struct Written {
    frames: Vec<Vec<u8>>,
    sheds: Vec<Shed>,
    report: LinkReport,
}

/// The frames the firmware's loop writes for `bytes` (configuration,
/// samples, then one report request), arriving as `arrival` says: a
/// firmware built for the joint count of the configuration's header.
fn firmware_loop(bytes: &[u8], arrival: &Arrival) -> Written {
    let joints = read_header(&mut source(bytes)).expect("header").joints;
    match joints {
        2 => firmware_loop_n::<2>(bytes, arrival),
        3 => firmware_loop_n::<3>(bytes, arrival),
        n => panic!("no firmware loop of {n} joints in this test"),
    }
}

/// [`firmware_loop`] of a firmware built for `N` joints.
fn firmware_loop_n<const N: usize>(bytes: &[u8], arrival: &Arrival) -> Written {
    let mut rest = bytes;
    let mut read = 0;
    let mut src = Source::new(|buf: &mut [u8]| {
        // Whole frames: up to the `frames(read)`-th 0x00 (within `buf`).
        let mut k = 0;
        for _ in 0..(arrival.frames)(read).max(1) {
            match rest[k..].iter().position(|b| *b == 0) {
                Some(z) => k += z + 1,
                None => k = rest.len(),
            }
        }
        let k = k.min(buf.len());
        read += 1;
        buf[..k].copy_from_slice(&rest[..k]);
        rest = &rest[k..];
        Ok(k)
    });
    let header = read_header(&mut src).expect("header");
    let mut config = ConfigStore::<N>::Empty;
    let mut store = MonitorStore::<N>::Empty;
    configure(&header, &mut src, &mut config, &mut store).expect("configuration");
    let mut out = Vec::new();
    let mut report = LinkReport::READY;
    let mut paths = Direct {
        store: &mut store,
        meter: &mut (),
    };
    let checks = std::cell::Cell::new(0);
    serve(
        &mut paths,
        &mut src,
        |f| {
            out.push(f.to_vec());
            Ok(())
        },
        &mut report,
        || 0,
        || {
            checks.set(checks.get() + 1);
            (arrival.pending)(checks.get() - 1)
        },
    )
    .expect("the link ends with its input");
    let mut last = out.pop().expect("the report");
    assert_eq!(
        read_report(&mut last),
        Some(report),
        "the last frame is the report"
    );
    let (mut frames, mut sheds) = (Vec::new(), Vec::new());
    for f in out {
        match read_shed(&mut f.clone()) {
            Some(s) => sheds.push(s),
            None => frames.push(f),
        }
    }
    Written {
        frames,
        sheds,
        report,
    }
}

fn rows(frames: &[Vec<u8>], joints: usize) -> Vec<StatusRow> {
    replay::decode_statuses(&frames.concat(), joints).expect("statuses decode")
}

/// 1 % of the sample frames dropped and 1 % corrupted on the way in, at
/// 100 Hz and 1 kHz: the firmware's loop counts both exactly, answers every
/// sample it gets with the host core's status for the same samples (bit
/// for bit), declares no latch the whole run does not declare (nor
/// earlier), and raises no fault flag beyond the time-step rules a missing
/// sample triggers (`time_jitter`, `time_gap`).
#[test]
fn a_lossy_link_is_counted_exactly_and_the_monitor_goes_on() {
    let cases = [
        ("data/examples/a_seed001_eft/seed001_T01.csv", "seed001_T01"),
        (
            "data/examples/c_seed001_friction_harness/seed001_T02.csv",
            "seed001_T02",
        ),
        ("data/reference/seed000_case1_eft.csv", "seed000_case1"),
        ("data/reference/seed001_T01_eft.csv", "seed001_T01"),
    ];
    for (run_path, mech) in cases {
        let mech = Mechanism::load(&root().join(format!("data/mechanisms/{mech}.toml"))).unwrap();
        let run = replay::load_run(&root().join(run_path)).unwrap();
        let plan = hil::plan(&mech, &run).unwrap();
        for seed in [3, 11] {
            let out = hil::inject(
                &plan,
                &Inject {
                    drop: 0.01,
                    corrupt: 0.01,
                    seed,
                    ..Inject::default()
                },
            );
            let (dropped, corrupted) = (out.count(Fate::Dropped), out.count(Fate::Corrupted));
            assert!(dropped + corrupted > 0, "{run_path}: nothing injected");
            let mut bytes = plan.config.clone();
            out.bytes.iter().for_each(|f| bytes.extend_from_slice(f));
            bytes.push(0);
            let Written {
                frames,
                sheds,
                report,
            } = firmware_loop(&bytes, &PACED);
            assert!(sheds.is_empty() && report.shed == 0, "{run_path}: shed");
            let keep: Vec<bool> = out.fate.iter().map(|f| f.delivered()).collect();
            let delivered = keep.iter().filter(|k| **k).count();
            assert_eq!(report.samples as usize, delivered, "{run_path}");
            assert_eq!(report.corrupted as usize, corrupted, "{run_path}");
            assert_eq!((report.too_long, report.requests), (0, 1), "{run_path}");
            let reference = hil::reference(&mech, &run, &keep, &[]).unwrap();
            assert!(
                frames == reference,
                "{run_path}: not the host core's statuses"
            );
            let full = hil::reference(&mech, &run, &vec![true; keep.len()], &[]).unwrap();
            let (false_latch, extra) =
                hil::against_full(&rows(&full, plan.joints), &rows(&frames, plan.joints));
            assert!(
                false_latch.is_empty(),
                "{run_path}: false latch {false_latch:?}"
            );
            assert!(
                extra
                    .iter()
                    .all(|(_, f)| f == "time_jitter" || f == "time_gap"),
                "{run_path} seed {seed}: {extra:?}"
            );
        }
    }
}

/// A frame cut short, one of garbage, one far too long and an empty
/// request in the middle: each counted as what it is, and the samples
/// around them answered as if they were not there.
#[test]
fn garbage_on_the_link_is_counted_and_skipped() {
    let mech = Mechanism::load(&root().join("data/mechanisms/seed001_T02.toml")).unwrap();
    let run =
        replay::load_run(&root().join("data/examples/a_seed001_eft/seed001_T02.csv")).unwrap();
    let plan = hil::plan(&mech, &run).unwrap();
    let mut bytes = plan.config.clone();
    let mut keep = vec![true; plan.samples.len()];
    for (i, f) in plan.samples.iter().enumerate() {
        match i {
            // Cut short: the first half, then its 0x00.
            10 => {
                bytes.extend_from_slice(&f[..f.len() / 2]);
                bytes.push(0);
                keep[10] = false;
                continue;
            }
            // Garbage longer than any sample frame, up to sample 21's
            // 0x00: sample 20 is not sent and 21 is swallowed.
            20 => {
                bytes.extend_from_slice(&[0x55; 300]);
                keep[20] = false;
                keep[21] = false;
                continue;
            }
            // A report request (an empty frame) between two samples.
            30 => bytes.push(0),
            _ => {}
        }
        bytes.extend_from_slice(f);
    }
    bytes.push(0);
    let Written {
        mut frames, report, ..
    } = firmware_loop(&bytes, &PACED);
    // The report asked for in the middle.
    let mid = frames
        .iter()
        .position(|f| read_report(&mut f.clone()).is_some())
        .expect("a report in the middle");
    frames.remove(mid);
    assert_eq!(
        (report.corrupted, report.too_long, report.requests),
        (1, 1, 2)
    );
    let reference = hil::reference(&mech, &run, &keep, &[]).unwrap();
    assert_eq!(report.samples as usize, reference.len());
    assert!(frames == reference);
}

/// A firmware that falls behind: the frames come in bursts (several at
/// one read, as they queue while the firmware is busy) or the receiver
/// holds bytes when a slice is due. The prediction's slices yield to every
/// waiting frame: each sample is answered before any slice runs while
/// another waits, every cut is reported (a shed frame, counted in the
/// report), and the statuses are the host core's with the reported slices
/// — and not those of the full schedule, which the firmware did not run.
#[test]
fn a_firmware_behind_its_input_sheds_slices_and_says_which() {
    let mech = Mechanism::load(&root().join("data/mechanisms/seed001_T01.toml")).unwrap();
    let run =
        replay::load_run(&root().join("data/examples/a_seed001_eft/seed001_T01.csv")).unwrap();
    let plan = hil::plan(&mech, &run).unwrap();
    let mut bytes = plan.config.clone();
    plan.samples.iter().for_each(|f| bytes.extend_from_slice(f));
    bytes.push(0);
    let n = plan.samples.len();
    // A hash of the index: bursts of 2 to 4 frames at about one read in
    // five after the configuration; the receiver busy at one check in 13.
    let mix = |i: usize| (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 59;
    let bursts = |r: usize| {
        if r > 4 && mix(r) < 6 {
            2 + mix(r) as usize % 3
        } else {
            1
        }
    };
    let busy = |c: usize| c % 13 == 7;
    let cases: [(&str, Arrival); 2] = [
        (
            "bursts",
            Arrival {
                frames: &bursts,
                pending: &|_| false,
            },
        ),
        (
            "receiver busy",
            Arrival {
                frames: &|_| 1,
                pending: &busy,
            },
        ),
    ];
    for (name, arrival) in cases {
        let w = firmware_loop(&bytes, &arrival);
        assert_eq!(w.report.samples as usize, n, "{name}");
        assert!(w.report.shed > 0, "{name}: nothing shed");
        assert_eq!(w.sheds.len(), w.report.shed as usize, "{name}");
        // Each cut after its own sample, in order, fewer than configured.
        assert!(
            w.sheds.windows(2).all(|p| p[0].sample < p[1].sample),
            "{name}: {:?}",
            w.sheds
        );
        assert!(w.sheds.iter().all(|s| s.slices < 17), "{name}");
        let keep = vec![true; n];
        let reference = hil::reference(&mech, &run, &keep, &w.sheds).unwrap();
        assert!(
            w.frames == reference,
            "{name}: not the host core's statuses with the reported slices"
        );
        let full = hil::reference(&mech, &run, &keep, &[]).unwrap();
        assert!(
            w.frames != full,
            "{name}: the shed slices changed no status (the test would not see a wrong schedule)"
        );
    }
}

/// `mech` with its `[joint.latch]` tables removed: the same mechanism with
/// the latch drawn ideal.
fn ideal(physical: &str) -> String {
    let mut out = String::new();
    let mut skip = false;
    for line in physical.lines() {
        let t = line.trim_start();
        if t.starts_with('[') {
            skip = t.starts_with("[joint.latch");
        }
        if !skip {
            out.push_str(line);
            out.push('\n');
        }
    }
    out
}

/// The joints' statuses of `run` on `mech` (the host's replay).
fn statuses(mech: &Mechanism, run: &deploywatch_sim::run::Run) -> Vec<StatusRow> {
    replay::prepare(mech, run).expect("replays").host
}

/// Counts the samples at which a joint is `latched` while its switch has
/// been open and its reading beyond `travel_deg` for longer than
/// `grace_s` after a closure; returns (such samples, samples out).
fn latched_while_out(
    run: &deploywatch_sim::run::Run,
    st: &[StatusRow],
    travel_deg: f64,
    grace_s: f64,
) -> (usize, usize) {
    let (mut bad, mut out_total) = (0, 0);
    for j in 0..run.joints() {
        let mut closed_once = false;
        let mut out_since: Option<f64> = None;
        for (i, s) in st.iter().enumerate() {
            let (t, sw, phi) = (run.t_s[i], run.latch[j][i], run.phi_deg[j][i]);
            closed_once |= sw;
            let out = closed_once && !sw && phi.abs() > travel_deg;
            out_since = if out { out_since.or(Some(t)) } else { None };
            if out_since.is_some_and(|t0| t - t0 > grace_s) {
                out_total += 1;
                if s.joints[j].latch == LatchState::Latched {
                    bad += 1;
                }
            }
        }
    }
    (bad, out_total)
}

/// An escape (joint 2 of seed 001 T01 rebounds over its plunger and stays
/// out) replayed at 100 Hz and at 1 kHz with the latch drawn ideal and
/// drawn physical: never `latched` while the switch is open and the angle
/// is out of the latch (beyond the ideal drawing's stand-in for a switch
/// travel, `at_latch_deg` = 0.3°, once the debounce time, 30 ms, and one
/// sample have passed); with the ideal drawing the status names the
/// disagreement (`latch_disagree`) when the latch had been declared (at
/// 1 kHz; at 100 Hz the switch's 20 ms closure is chatter, never a latch).
#[test]
fn an_escape_is_never_latched_while_out_with_either_drawing() {
    let phys_path = root().join("data/mechanisms/seed001_T01_physical_latch.toml");
    let phys_text = std::fs::read_to_string(&phys_path).unwrap();
    let dir = std::env::temp_dir().join(format!("deploywatch-hil-escape-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let ideal_path = dir.join("ideal.toml");
    std::fs::write(&ideal_path, ideal(&phys_text)).unwrap();
    let khz = dir.join("escape_1khz.csv");
    let sim = Command::new(env!("CARGO_BIN_EXE_deploywatch"))
        .arg("simulate")
        .arg(&phys_path)
        .args(["--rate", "1000", "--seed", "1", "--out"])
        .arg(&khz)
        .output()
        .unwrap();
    assert!(
        sim.status.success(),
        "{}",
        String::from_utf8_lossy(&sim.stderr)
    );
    let physical = Mechanism::load(&phys_path).unwrap();
    let ideal = Mechanism::load(&ideal_path).unwrap();
    assert!(ideal.joint_count() == 3 && ideal.name == physical.name);
    let runs = [
        root().join("data/examples/latch_escape_never/seed001_T01.csv"),
        khz,
    ];
    for run_path in &runs {
        let run = replay::load_run(run_path).unwrap();
        let period = hil::median_step(&run.t_s);
        for (drawing, mech) in [("ideal", &ideal), ("physical", &physical)] {
            let st = statuses(mech, &run);
            let (bad, out) = latched_while_out(&run, &st, 0.3, 0.03 + 1.5 * period);
            assert!(out > 0, "{}: no escape to judge", run_path.display());
            assert_eq!(
                bad,
                0,
                "{} ({drawing}): latched while out",
                run_path.display()
            );
            let was_latched = st.iter().any(|s| s.joints[1].latch == LatchState::Latched);
            if drawing == "ideal" && was_latched {
                let named = st.iter().any(|s| {
                    s.joints[1].latch == LatchState::Escaped
                        && s.joints[1]
                            .faults
                            .iter()
                            .any(|f| f.as_str() == "latch_disagree")
                });
                assert!(
                    named,
                    "{}: the disagreement is not named",
                    run_path.display()
                );
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
