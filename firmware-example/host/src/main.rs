//! Host side of the firmware replay (the frames: `../src/lib.rs`).
//!
//! ```text
//! deploywatch-replay encode RUN.csv FRAMES.bin            run CSV -> sample frames
//! deploywatch-replay host MECH.toml RUN.csv STATUS.bin    the host's f32 monitor run
//! deploywatch-replay decode STATUS.bin                    status frames -> CSV on stdout
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
  deploywatch-replay decode STATUS.bin                   status frames -> CSV on stdout
  deploywatch-replay compare A.bin B.bin                 exit 0 iff the files are byte-identical
  deploywatch-replay mechanism RUN.csv                   print the run's mechanism name";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let argv: Vec<&str> = args.iter().map(String::as_str).collect();
    let result = match argv.as_slice() {
        ["encode", csv, out] => encode(Path::new(csv), Path::new(out)),
        ["host", mech, csv, out] => host(Path::new(mech), Path::new(csv), Path::new(out)),
        ["decode", input] => decode(Path::new(input)),
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
    eprintln!("{}: {} sample frames, {} bytes", out.display(), samples.len(), bytes.len());
    Ok(())
}

fn host(mech_path: &Path, csv: &Path, out: &Path) -> Result<(), String> {
    let mech = Mechanism::load(mech_path).map_err(|e| e.to_string())?;
    let config = monitor_config::<JOINTS>(&mech).map_err(|e| format!("{}: {e}", mech_path.display()))?;
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
    eprintln!("{}: {} status frames (host f32 run)", out.display(), samples.len());
    Ok(())
}

/// Splits a file into its frames, each with its `0x00`.
fn frames(bytes: &[u8]) -> impl Iterator<Item = &[u8]> {
    bytes.split_inclusive(|&b| b == 0)
}

fn opt(v: Option<f32>) -> String {
    v.map(|x| format!("{x:e}")).unwrap_or_default()
}

fn decode(input: &Path) -> Result<(), String> {
    let bytes = fs::read(input).map_err(|e| format!("{}: {e}", input.display()))?;
    let stdout = std::io::stdout();
    let mut w = std::io::BufWriter::new(stdout.lock());
    let mut head = vec!["t_s".to_string(), "samples".to_string()];
    for j in 1..=JOINTS {
        for f in [
            "phi_deg",
            "rate_deg_s",
            "coulomb_nm",
            "coulomb_sd_nm",
            "viscous_nms",
            "viscous_sd_nms",
            "friction_torque_nm",
            "latch",
            "margin_pct",
            "prediction",
            "latch_probability",
            "time_to_latch_s",
            "faults",
        ] {
            head.push(format!("{f}{j}"));
        }
    }
    let io = |e: std::io::Error| e.to_string();
    writeln!(w, "{}", head.join(",")).map_err(io)?;
    for (i, f) in frames(&bytes).enumerate() {
        let mut frame = f.to_vec();
        let s: Status<JOINTS> =
            telemetry::decode(&mut frame).map_err(|e| format!("{}: frame {i}: {e}", input.display()))?;
        let mut row = vec![format!("{:e}", s.t_s), s.samples.to_string()];
        for js in &s.joints {
            row.extend([
                format!("{:e}", js.phi_deg),
                format!("{:e}", js.rate_deg_s),
                format!("{:e}", js.coulomb_nm),
                format!("{:e}", js.coulomb_sd_nm),
                format!("{:e}", js.viscous_nms),
                format!("{:e}", js.viscous_sd_nms),
                format!("{:e}", js.friction_torque_nm),
                format!("{:?}", js.latch),
                opt(js.margin_pct),
                js.prediction.as_str().to_string(),
                format!("{:e}", js.latch_probability),
                opt(js.time_to_latch_s),
                format!("{:#06x}", js.faults.0),
            ]);
        }
        writeln!(w, "{}", row.join(",")).map_err(io)?;
    }
    w.flush().map_err(io)
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
