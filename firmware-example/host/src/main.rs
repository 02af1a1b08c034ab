//! Host side of the firmware replay (the frames: `../src/lib.rs`).
//!
//! ```text
//! deploywatch-replay encode RUN.csv FRAMES.bin            run CSV -> sample frames
//! deploywatch-replay host MECH.toml RUN.csv STATUS.bin    the host's f32 monitor run
//! deploywatch-replay decode STATUS.bin                    status frames -> JSON lines on stdout
//! deploywatch-replay run FRAMES.bin MECHANISM STATUS.bin  the firmware's loop, on the host
//! deploywatch-replay compare A.bin B.bin                  exit 0 iff byte-identical
//! deploywatch-replay mechanism RUN.csv                    the run's mechanism name
//! ```
//!
//! `host` runs the simulator's own path (`deploywatch_sim::monitor_config`:
//! the mechanism file converted to a `MonitorConfig<3>`, the run's samples,
//! `Monitor::update` in `f32`), after checking that the firmware's built-in
//! configuration of that mechanism is the same value. Its output compared
//! with the QEMU output is the bit-identity check.

use std::fs;
use std::io::Write;
use std::path::Path;
use std::process::ExitCode;

use deploywatch_core::telemetry;
use deploywatch_core::{Monitor, Sample, Status};
use deploywatch_firmware_example::{mechanism, JOINTS, SAMPLE_FRAME_MAX, STATUS_FRAME_MAX};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::monitor_config::{monitor_config, samples};
use deploywatch_sim::run::Run;

const USAGE: &str = "usage:
  deploywatch-replay encode RUN.csv FRAMES.bin           run CSV -> sample frames for the firmware
  deploywatch-replay host MECH.toml RUN.csv STATUS.bin   the host's f32 monitor run, as status frames
  deploywatch-replay decode STATUS.bin                   status frames -> JSON lines on stdout
  deploywatch-replay run FRAMES.bin MECHANISM STATUS.bin the firmware's replay loop, on the host
  deploywatch-replay compare A.bin B.bin                 exit 0 iff the files are byte-identical
  deploywatch-replay mechanism RUN.csv                   print the run's mechanism name";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let argv: Vec<&str> = args.iter().map(String::as_str).collect();
    let result = match argv.as_slice() {
        ["encode", csv, out] => encode(Path::new(csv), Path::new(out)),
        ["host", mech, csv, out] => host(Path::new(mech), Path::new(csv), Path::new(out)),
        ["decode", input] => decode(Path::new(input)),
        ["run", input, name, out] => run_lib(Path::new(input), name, Path::new(out)),
        ["compare", a, b] => compare(Path::new(a), Path::new(b)),
        ["mechanism", csv] => load_run(Path::new(csv)).and_then(|run| {
            let name = run
                .mechanism()
                .ok_or_else(|| format!("{csv}: the run names no mechanism"))?;
            println!("{name}");
            Ok(())
        }),
        ["-h" | "--help"] => {
            println!("{USAGE}");
            return ExitCode::SUCCESS;
        }
        _ => Err(USAGE.to_string()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("deploywatch-replay: {e}");
            ExitCode::FAILURE
        }
    }
}

fn load_run(path: &Path) -> Result<Run, String> {
    Run::load(path).map_err(|e| e.to_string())
}

/// The run's samples as the monitor receives them.
fn run_samples(path: &Path) -> Result<Vec<Sample<JOINTS>>, String> {
    let run = load_run(path)?;
    samples::<JOINTS>(&run).ok_or_else(|| {
        format!(
            "{}: the run has {} joints; the firmware example monitors {JOINTS}",
            path.display(),
            run.joints()
        )
    })
}

fn write_file(path: &Path, bytes: &[u8]) -> Result<(), String> {
    fs::write(path, bytes).map_err(|e| format!("{}: cannot write: {e}", path.display()))
}

fn encode(csv: &Path, out: &Path) -> Result<(), String> {
    let samples = run_samples(csv)?;
    let mut bytes = Vec::new();
    let mut buf = [0u8; SAMPLE_FRAME_MAX];
    for (i, s) in samples.iter().enumerate() {
        let frame = telemetry::encode(s, &mut buf).map_err(|e| format!("sample {i}: {e}"))?;
        bytes.extend_from_slice(frame);
    }
    write_file(out, &bytes)?;
    eprintln!(
        "{}: {} sample frames, {} bytes",
        out.display(),
        samples.len(),
        bytes.len()
    );
    Ok(())
}

/// The firmware's own replay loop, run on the host: tells a difference of
/// target (QEMU vs. this) from a difference of code path (this vs. `host`).
fn run_lib(input: &Path, name: &str, out: &Path) -> Result<(), String> {
    let config = mechanism::config(name)
        .ok_or_else(|| format!("`{name}` is not built into the firmware"))?;
    let bytes = fs::read(input).map_err(|e| format!("{}: {e}", input.display()))?;
    let mut rest: &[u8] = &bytes;
    let mut output = Vec::new();
    let n = deploywatch_firmware_example::run(
        &config,
        |buf| {
            let k = buf.len().min(rest.len());
            buf[..k].copy_from_slice(&rest[..k]);
            rest = &rest[k..];
            Ok(k)
        },
        |frame| {
            output.extend_from_slice(frame);
            Ok(())
        },
        &mut (),
    )
    .map_err(|e| format!("{}: {e}", input.display()))?;
    write_file(out, &output)?;
    eprintln!(
        "{}: {n} status frames (firmware replay loop on the host)",
        out.display()
    );
    Ok(())
}

fn host(mech_path: &Path, csv: &Path, out: &Path) -> Result<(), String> {
    let mech = Mechanism::load(mech_path).map_err(|e| e.to_string())?;
    let config =
        monitor_config::<JOINTS>(&mech).map_err(|e| format!("{}: {e}", mech_path.display()))?;
    // The firmware has no file system: its configuration is compiled in.
    // Replaying against a different one would compare two different monitors.
    match mechanism::config(&mech.name) {
        Some(builtin) if builtin == config => {}
        Some(_) => {
            return Err(format!(
                "{}: the firmware's built-in configuration of `{}` differs from this file's \
                 (update firmware-example/src/mechanism.rs)",
                mech_path.display(),
                mech.name
            ))
        }
        None => {
            return Err(format!(
                "{}: `{}` is not built into the firmware (built in: {})",
                mech_path.display(),
                mech.name,
                mechanism::NAMES.join(", ")
            ))
        }
    }
    let run = load_run(csv)?;
    if run.mechanism() != Some(mech.name.as_str()) {
        return Err(format!(
            "{}: the run is of mechanism `{}`, not `{}`",
            csv.display(),
            run.mechanism().unwrap_or("(none)"),
            mech.name
        ));
    }
    let mut monitor = Monitor::new(&config).map_err(|e| format!("{}: {e}", mech_path.display()))?;
    let mut bytes = Vec::new();
    let mut buf = [0u8; STATUS_FRAME_MAX];
    let samples = run_samples(csv)?;
    for (i, s) in samples.iter().enumerate() {
        let status = monitor.update(s);
        let frame = telemetry::encode(&status, &mut buf).map_err(|e| format!("status {i}: {e}"))?;
        bytes.extend_from_slice(frame);
    }
    write_file(out, &bytes)?;
    eprintln!(
        "{}: {} status frames (host f32 run)",
        out.display(),
        samples.len()
    );
    Ok(())
}

/// Splits a file into its frames, each with its `0x00`.
fn frames(bytes: &[u8]) -> impl Iterator<Item = &[u8]> {
    bytes.split_inclusive(|&b| b == 0)
}

fn decode(input: &Path) -> Result<(), String> {
    let bytes = fs::read(input).map_err(|e| format!("{}: {e}", input.display()))?;
    let stdout = std::io::stdout();
    let mut w = std::io::BufWriter::new(stdout.lock());
    for (i, f) in frames(&bytes).enumerate() {
        let mut frame = f.to_vec();
        let s: Status<JOINTS> = telemetry::decode(&mut frame)
            .map_err(|e| format!("{}: frame {i}: {e}", input.display()))?;
        serde_json::to_writer(&mut w, &s).map_err(|e| e.to_string())?;
        writeln!(w).map_err(|e| e.to_string())?;
    }
    w.flush().map_err(|e| e.to_string())
}

fn compare(a: &Path, b: &Path) -> Result<(), String> {
    let read = |p: &Path| fs::read(p).map_err(|e| format!("{}: {e}", p.display()));
    let (x, y) = (read(a)?, read(b)?);
    let (fx, fy): (Vec<_>, Vec<_>) = (frames(&x).collect(), frames(&y).collect());
    if x == y {
        println!("identical: {} frames, {} bytes", fx.len(), x.len());
        return Ok(());
    }
    match fx.iter().zip(fy.iter()).position(|(p, q)| p != q) {
        Some(i) => Err(format!(
            "{} and {} differ first at frame {i} (of {} and {})",
            a.display(),
            b.display(),
            fx.len(),
            fy.len()
        )),
        None => Err(format!(
            "{} has {} frames, {} has {}; the common ones are equal",
            a.display(),
            fx.len(),
            b.display(),
            fy.len()
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use deploywatch_firmware_example::{run, Error, Framer};

    fn config() -> deploywatch_core::MonitorConfig<JOINTS> {
        mechanism::config("seed001-T01").expect("built in")
    }

    /// The frames of `n` samples of a deployment starting at the stowed angles.
    fn input(n: usize) -> Vec<u8> {
        let mut bytes = Vec::new();
        let mut buf = [0u8; SAMPLE_FRAME_MAX];
        for i in 0..n {
            let t = i as f32 * 0.01;
            let s = Sample::new(
                t,
                [-90.0 + 10.0 * t, 180.0 - 5.0 * t, -180.0 + 5.0 * t],
                [false; 3],
            );
            bytes.extend_from_slice(telemetry::encode(&s, &mut buf).expect("fits"));
        }
        bytes
    }

    /// Runs the firmware's loop over `bytes`, read `chunk` bytes at a time.
    fn replay(bytes: &[u8], chunk: usize) -> Result<(u32, Vec<u8>), Error> {
        let mut rest = bytes;
        let mut out = Vec::new();
        let n = run(
            &config(),
            |buf| {
                let k = buf.len().min(rest.len()).min(chunk);
                buf[..k].copy_from_slice(&rest[..k]);
                rest = &rest[k..];
                Ok(k)
            },
            |f| {
                out.extend_from_slice(f);
                Ok(())
            },
            &mut (),
        )?;
        Ok((n, out))
    }

    #[test]
    fn loop_matches_the_monitor_whatever_the_read_size() {
        let bytes = input(50);
        let mut monitor = Monitor::new(&config()).unwrap();
        let mut want = Vec::new();
        let mut buf = [0u8; STATUS_FRAME_MAX];
        let mut inb = bytes.clone();
        for f in inb.split_inclusive_mut(|&b| b == 0) {
            let s: Sample<JOINTS> = telemetry::decode(f).unwrap();
            want.extend_from_slice(telemetry::encode(&monitor.update(&s), &mut buf).unwrap());
        }
        for chunk in [1, 7, 256] {
            let (n, out) = replay(&bytes, chunk).unwrap();
            assert_eq!(n, 50);
            assert!(out == want, "chunk {chunk}");
        }
    }

    #[test]
    fn truncated_input_is_an_error() {
        let bytes = input(3);
        assert_eq!(
            replay(&bytes[..bytes.len() - 2], 256),
            Err(Error::Truncated)
        );
    }

    #[test]
    fn corrupted_frame_is_an_error_with_its_index() {
        let mut bytes = input(3);
        // Flip a payload bit of the second frame: its CRC no longer matches.
        let second = bytes.iter().position(|&b| b == 0).unwrap() + 3;
        bytes[second] ^= 0x10;
        assert_eq!(replay(&bytes, 256), Err(Error::Frame { index: 1 }));
        // A frame longer than any sample.
        let long = [1u8; SAMPLE_FRAME_MAX + 5]
            .iter()
            .copied()
            .chain([0])
            .collect::<Vec<_>>();
        assert_eq!(replay(&long, 256), Err(Error::Frame { index: 0 }));
    }

    #[test]
    fn empty_input_is_no_samples() {
        assert_eq!(replay(&[], 256), Ok((0, Vec::new())));
    }

    #[test]
    fn framer_splits_on_zero() {
        let mut framer = Framer::<4>::new();
        let mut seen = Vec::new();
        framer
            .feed(&[1, 2, 0, 3], |f| {
                seen.push(f.map(|f| f.to_vec()));
                Ok::<(), ()>(())
            })
            .unwrap();
        assert!(framer.is_pending());
        framer
            .feed(&[0, 9, 9, 9, 9, 9, 0], |f| {
                seen.push(f.map(|f| f.to_vec()));
                Ok::<(), ()>(())
            })
            .unwrap();
        assert_eq!(seen, vec![Some(vec![1, 2, 0]), Some(vec![3, 0]), None]);
        assert!(!framer.is_pending());
    }

    #[test]
    fn builtin_mechanisms_match_the_files() {
        let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/mechanisms");
        for name in mechanism::NAMES {
            let file = data.join(format!("{}.toml", name.replace('-', "_")));
            let mech = Mechanism::load(&file).unwrap();
            assert_eq!(mech.name, name);
            assert!(
                mechanism::config(name) == Some(monitor_config::<JOINTS>(&mech).unwrap()),
                "{name}"
            );
        }
        assert!(mechanism::config("seed000-case1").is_none());
    }
}
