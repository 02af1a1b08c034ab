//! Host side of the firmware replay (see `../src/lib.rs` for the frames).
//!
//! ```text
//! deploywatch-replay encode RUN.csv FRAMES.bin     run CSV -> sample frames
//! deploywatch-replay run FRAMES.bin STATUS.bin     the host f32 reference run
//! deploywatch-replay decode STATUS.bin             status frames -> CSV on stdout
//! deploywatch-replay compare A.bin B.bin           exit 0 iff byte-identical
//! ```
//!
//! `run` executes the same `deploywatch_firmware_example::run` as the
//! firmware, on the host, so `compare` of its output with the QEMU output is
//! the bit-identity check.

use std::fs;
use std::io::{Read, Write};
use std::path::Path;
use std::process::ExitCode;

use deploywatch_firmware_example::{self as replay, Sample, Status, JOINTS, MAX_FRAME};

const USAGE: &str = "usage:
  deploywatch-replay encode RUN.csv FRAMES.bin   run CSV -> input frames for the firmware
  deploywatch-replay run FRAMES.bin STATUS.bin   host reference run (same code as the firmware)
  deploywatch-replay decode STATUS.bin           status frames -> CSV on stdout
  deploywatch-replay compare A.bin B.bin         exit 0 iff the files are byte-identical";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let argv: Vec<&str> = args.iter().map(String::as_str).collect();
    let result = match argv.as_slice() {
        ["encode", csv, out] => encode(Path::new(csv), Path::new(out)),
        ["run", input, out] => run(Path::new(input), Path::new(out)),
        ["decode", input] => decode(Path::new(input)),
        ["compare", a, b] => compare(Path::new(a), Path::new(b)),
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

/// Reads a run CSV (`docs/spec/formats.md`, "Run: CSV") of [`JOINTS`] joints.
fn read_run(path: &Path) -> Result<Vec<Sample>, String> {
    let text = fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let header = loop {
        match lines.next() {
            Some((_, l)) if l.starts_with('#') => continue,
            Some((_, l)) => break l,
            None => return Err(format!("{}: no header line", path.display())),
        }
    };
    let cols: Vec<&str> = header.split(',').map(str::trim).collect();
    let mut want = vec!["t_s".to_string()];
    want.extend((1..=JOINTS).map(|j| format!("phi{j}_deg")));
    want.extend((1..=JOINTS).map(|j| format!("latch{j}")));
    if cols != want {
        return Err(format!(
            "{}: header is `{header}`, expected `{}` (the firmware example replays {JOINTS}-joint runs)",
            path.display(),
            want.join(",")
        ));
    }
    let mut samples = Vec::new();
    for (i, line) in lines {
        let at = || format!("{}:{}", path.display(), i + 1);
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        if f.len() != want.len() {
            return Err(format!("{}: {} fields, expected {}", at(), f.len(), want.len()));
        }
        let num = |k: usize| -> Result<f64, String> {
            f[k].parse::<f64>()
                .map_err(|_| format!("{}: column {} is `{}`, expected a number", at(), want[k], f[k]))
        };
        let mut s = Sample {
            t_s: num(0)? as f32,
            phi_deg: [0.0; JOINTS],
            latch: [false; JOINTS],
        };
        for j in 0..JOINTS {
            s.phi_deg[j] = num(1 + j)? as f32;
            s.latch[j] = match f[1 + JOINTS + j] {
                "0" => false,
                "1" => true,
                other => {
                    return Err(format!(
                        "{}: column {} is `{other}`, expected 0 or 1",
                        at(),
                        want[1 + JOINTS + j]
                    ))
                }
            };
        }
        samples.push(s);
    }
    Ok(samples)
}

fn encode(csv: &Path, out: &Path) -> Result<(), String> {
    let samples = read_run(csv)?;
    let mut bytes = Vec::new();
    let mut buf = [0u8; MAX_FRAME];
    let header = replay::encode(&replay::Header::CURRENT, &mut buf).ok_or("header frame too long")?;
    bytes.extend_from_slice(header);
    for s in &samples {
        bytes.extend_from_slice(replay::encode(s, &mut buf).ok_or("sample frame too long")?);
    }
    fs::write(out, &bytes).map_err(|e| format!("{}: {e}", out.display()))?;
    eprintln!(
        "{}: {} samples, {} bytes",
        out.display(),
        samples.len(),
        bytes.len()
    );
    Ok(())
}

fn run(input: &Path, out: &Path) -> Result<(), String> {
    let mut reader = fs::File::open(input).map_err(|e| format!("{}: {e}", input.display()))?;
    let mut writer = std::io::BufWriter::new(
        fs::File::create(out).map_err(|e| format!("{}: {e}", out.display()))?,
    );
    let n = replay::run(
        |buf| reader.read(buf).map_err(|_| ()),
        |frame| writer.write_all(frame).map_err(|_| ()),
    )
    .map_err(|e| format!("{}: {e}", input.display()))?;
    writer
        .flush()
        .map_err(|e| format!("{}: {e}", out.display()))?;
    eprintln!("{}: {n} status frames", out.display());
    Ok(())
}

/// Splits a file into its COBS frames (the `0x00` excluded).
fn frames(bytes: &[u8]) -> impl Iterator<Item = &[u8]> {
    bytes.split(|&b| b == 0).filter(|f| !f.is_empty())
}

fn decode(input: &Path) -> Result<(), String> {
    let bytes = fs::read(input).map_err(|e| format!("{}: {e}", input.display()))?;
    let stdout = std::io::stdout();
    let mut w = std::io::BufWriter::new(stdout.lock());
    let mut head = vec!["t_s".to_string(), "ok".to_string()];
    head.extend((1..=JOINTS).map(|j| format!("phi_dot{j}_rad_s")));
    head.extend((1..=JOINTS).map(|j| format!("accel{j}_rad_s2")));
    let io = |e: std::io::Error| e.to_string();
    writeln!(w, "{}", head.join(",")).map_err(io)?;
    for (i, f) in frames(&bytes).enumerate() {
        let mut frame = f.to_vec();
        let s: Status = replay::decode(&mut frame)
            .ok_or_else(|| format!("{}: frame {i} does not decode", input.display()))?;
        let mut row = vec![format!("{:e}", s.t_s), u8::from(s.ok).to_string()];
        row.extend(s.phi_dot_rad_s.iter().map(|v| format!("{v:e}")));
        row.extend(s.accel_rad_s2.iter().map(|v| format!("{v:e}")));
        writeln!(w, "{}", row.join(",")).map_err(io)?;
    }
    w.flush().map_err(io)
}

fn compare(a: &Path, b: &Path) -> Result<(), String> {
    let read = |p: &Path| fs::read(p).map_err(|e| format!("{}: {e}", p.display()));
    let (x, y) = (read(a)?, read(b)?);
    if x == y {
        println!(
            "identical: {} frames, {} bytes",
            frames(&x).count(),
            x.len()
        );
        return Ok(());
    }
    let (fx, fy): (Vec<_>, Vec<_>) = (frames(&x).collect(), frames(&y).collect());
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
