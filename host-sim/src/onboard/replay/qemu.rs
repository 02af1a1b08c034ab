//! The firmware under QEMU: its ELF found, its input and output handed over
//! by semihosting, QEMU run with a timeout, and its defmt log decoded.

use std::io;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use super::error::ReplayError;

/// The QEMU program the firmware runs on.
pub const QEMU: &str = "qemu-system-arm";

/// What to run when the firmware ELF or QEMU is missing.
pub(crate) const SETUP_HINT: &str =
    "run scripts/embedded-toolchain.sh (once per machine), then scripts/firmware.sh build";

/// A firmware ELF: `elf` when given, else `default` (a path relative to
/// the repository) under the current directory, else under the source tree
/// this program was built from; the error names the paths tried and `hint`.
pub(crate) fn find_firmware(
    elf: Option<&Path>,
    default: &str,
    hint: &str,
) -> Result<PathBuf, ReplayError> {
    let candidates: Vec<PathBuf> = match elf {
        Some(e) => vec![e.to_path_buf()],
        None => vec![
            PathBuf::from(default),
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("..")
                .join(default),
        ],
    };
    candidates
        .iter()
        .find(|p| p.is_file())
        .cloned()
        .ok_or_else(|| {
            ReplayError::Setup(format!(
                "no firmware ELF at {}: {hint}",
                candidates
                    .iter()
                    .map(|p| p.display().to_string())
                    .collect::<Vec<_>>()
                    .join(" or ")
            ))
        })
}

/// What a QEMU run of the firmware gave.
#[derive(Clone, Debug)]
pub struct QemuRun {
    /// The status frames the firmware wrote.
    pub frames: Vec<u8>,
    /// The firmware's defmt log, decoded when `defmt-print` is installed,
    /// else a note where the raw log is.
    pub log: String,
}

/// QEMU's `-semihosting-config` value that hands the firmware its input and
/// output files (each path without white space, at most 127 bytes, commas
/// doubled).
fn semihosting_args(in_path: &Path, out_path: &Path) -> Result<String, ReplayError> {
    let mut args = "enable=on,target=native,arg=deploywatch-firmware-example".to_string();
    for p in [&in_path, &out_path] {
        let s = p
            .to_str()
            .ok_or_else(|| ReplayError::Input(format!("{}: not UTF-8", p.display())))?;
        if s.chars().any(char::is_whitespace) || s.len() > 127 {
            return Err(ReplayError::Input(format!(
                "{s}: a semihosting argument may not contain spaces nor exceed 127 bytes \
                 (choose another directory to keep the files in, or TMPDIR)"
            )));
        }
        args.push_str(",arg=");
        args.push_str(&s.replace(',', ",,"));
    }
    Ok(args)
}

/// Waits for QEMU to exit, killing it after `timeout`.
fn wait_for(
    child: &mut std::process::Child,
    timeout: Duration,
) -> Result<std::process::ExitStatus, ReplayError> {
    let start = Instant::now();
    let status = loop {
        match child.try_wait() {
            Ok(Some(st)) => break st,
            Ok(None) if start.elapsed() > timeout => {
                let _ = child.kill();
                let _ = child.wait();
                return Err(ReplayError::Target(format!(
                    "the firmware did not finish within {} s (QEMU killed)",
                    timeout.as_secs()
                )));
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(20)),
            Err(e) => return Err(ReplayError::Target(format!("waiting for {QEMU}: {e}"))),
        }
    };
    Ok(status)
}

/// Runs the firmware `elf` under QEMU on `input` (the files go to `dir`:
/// `input.bin`, `qemu.bin`, `qemu.defmt`), waiting at most `timeout`.
pub fn run_qemu(
    elf: &Path,
    input: &[u8],
    dir: &Path,
    timeout: Duration,
) -> Result<QemuRun, ReplayError> {
    let io_err = |p: &Path, e: io::Error| ReplayError::Input(format!("{}: {e}", p.display()));
    std::fs::create_dir_all(dir).map_err(|e| io_err(dir, e))?;
    let abs = |p: PathBuf| std::path::absolute(&p).unwrap_or(p);
    let in_path = abs(dir.join("input.bin"));
    let out_path = abs(dir.join("qemu.bin"));
    let log_path = dir.join("qemu.defmt");
    std::fs::write(&in_path, input).map_err(|e| io_err(&in_path, e))?;
    let _ = std::fs::remove_file(&out_path);
    let args = semihosting_args(&in_path, &out_path)?;
    let log = std::fs::File::create(&log_path).map_err(|e| io_err(&log_path, e))?;
    let mut child = Command::new(QEMU)
        .args(["-cpu", "cortex-m4", "-machine", "mps2-an386", "-nographic"])
        // One instruction per 8 ns of virtual time (5 a SysTick tick): the
        // firmware's instruction count of Monitor::update relies on it;
        // an idle `wfi` skips to the next tick (no real-time wait).
        .args([
            "-icount",
            "shift=3,sleep=off",
            "-semihosting-config",
            &args,
            "-kernel",
        ])
        .arg(elf)
        .stdin(Stdio::null())
        .stdout(log)
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| match e.kind() {
            io::ErrorKind::NotFound => {
                ReplayError::Setup(format!("{QEMU} is not installed: {SETUP_HINT}"))
            }
            _ => ReplayError::Setup(format!("cannot start {QEMU}: {e}")),
        })?;
    let status = wait_for(&mut child, timeout)?;
    let mut stderr = String::new();
    if let Some(mut e) = child.stderr.take() {
        let _ = io::Read::read_to_string(&mut e, &mut stderr);
    }
    let log = decode_log(elf, &log_path);
    match status.code() {
        Some(0) => {}
        code => {
            let what = match code {
                Some(1) => "the firmware reported an error".to_string(),
                Some(101) => "the firmware panicked".to_string(),
                Some(134) => "the firmware hit a hard fault".to_string(),
                Some(c) => format!("QEMU exited with {c}"),
                None => "QEMU was killed by a signal".to_string(),
            };
            return Err(ReplayError::Target(format!("{what}\n{log}{stderr}")));
        }
    }
    let frames = std::fs::read(&out_path).map_err(|e| io_err(&out_path, e))?;
    Ok(QemuRun { frames, log })
}

/// The firmware's log: `defmt-print -e ELF < LOG` when it is installed.
fn decode_log(elf: &Path, log_path: &Path) -> String {
    let decoded = std::fs::File::open(log_path).ok().and_then(|f| {
        Command::new("defmt-print")
            .arg("-e")
            .arg(elf)
            .stdin(f)
            .stderr(Stdio::null())
            .output()
            .ok()
    });
    match decoded {
        Some(o) => String::from_utf8_lossy(&o.stdout).into_owned(),
        None => format!(
            "(defmt-print not installed: raw log in {}; decode with defmt-print -e {})\n",
            log_path.display(),
            elf.display()
        ),
    }
}
