//! deploywatch example firmware for a Cortex-M4F (thumbv7em-none-eabihf),
//! run on QEMU's mps2-an386 board.
//!
//! It replays a recorded run: it reads the sample frames from the file named
//! by the first semihosting argument, runs them through the on-board monitor
//! configured for the built-in mechanism named by the third, and writes the
//! status frames to the file named by the second (see `src/lib.rs`).
//! It logs with defmt over semihosting stdout (decode with `defmt-print`) and
//! ends QEMU with a semihosting exit: 0 on success, 1 on an error, 101 on a
//! panic, 134 on a fault.
//!
//! ```text
//! qemu-system-arm -cpu cortex-m4 -machine mps2-an386 -nographic \
//!   -semihosting-config enable=on,target=native,arg=fw,arg=IN.bin,arg=OUT.bin,arg=seed001-T01 \
//!   -kernel ELF | defmt-print -e ELF
//! ```
#![no_std]
#![no_main]

use core::ffi::CStr;

// The critical-section implementation (single core) that defmt-semihosting uses.
use cortex_m as _;
use cortex_m_rt::{entry, exception, ExceptionFrame};
use defmt_semihosting as _;
use deploywatch_core::monitor::MonitorConfig;
use deploywatch_firmware_example::{mechanism, run, Error, JOINTS};
use semihosting::experimental::env;
use semihosting::fs::File;
use semihosting::io::{Read, Write};
use semihosting::process;

/// Longest accepted path argument, NUL excluded [bytes].
const MAX_PATH: usize = 127;

#[entry]
fn main() -> ! {
    defmt::info!("deploywatch firmware example: replay");
    let code = match replay() {
        Ok(samples) => {
            defmt::info!("replayed {=u32} samples", samples);
            0
        }
        Err(e) => {
            defmt::error!("replay failed: {=str}", e.as_str());
            if let Error::Frame { index } = e {
                defmt::error!("at frame {=u32}", index);
            }
            1
        }
    };
    process::exit(code)
}

/// Why the replay could not start.
enum Setup {
    /// Wrong or missing semihosting arguments.
    Usage,
    /// The mechanism is not built in.
    Mechanism,
    /// The input file could not be opened.
    Open,
    /// The output file could not be created.
    Create,
}

fn replay() -> Result<u32, Error> {
    let (mut input, mut output, config) = match setup() {
        Ok(setup) => setup,
        Err(Setup::Usage) => {
            defmt::error!("usage: semihosting arguments PROGRAM INPUT OUTPUT MECHANISM (paths up to 127 bytes)");
            return Err(Error::Read);
        }
        Err(Setup::Mechanism) => {
            defmt::error!("unknown mechanism; built in: {}", mechanism::NAMES);
            return Err(Error::Config);
        }
        Err(Setup::Open) => {
            defmt::error!("cannot open the input file");
            return Err(Error::Read);
        }
        Err(Setup::Create) => {
            defmt::error!("cannot create the output file");
            return Err(Error::Write);
        }
    };
    run(
        &config,
        |buf| input.read(buf).map_err(|_| ()),
        |frame| output.write_all(frame).map_err(|_| ()),
    )
}

/// Opens the input, creates the output and configures the monitor, as the
/// semihosting command line `PROGRAM INPUT OUTPUT MECHANISM` says.
fn setup() -> Result<(File, File, MonitorConfig<JOINTS>), Setup> {
    let args = env::args::<512>().map_err(|_| Setup::Usage)?;
    let mut it = (&args).into_iter().skip(1);
    let mut in_path = [0u8; MAX_PATH + 1];
    let mut out_path = [0u8; MAX_PATH + 1];
    let input = c_path(it.next(), &mut in_path)?;
    let output = c_path(it.next(), &mut out_path)?;
    let name = it.next().and_then(|a| a.ok()).ok_or(Setup::Usage)?;
    let config = mechanism::config(name).ok_or(Setup::Mechanism)?;
    defmt::info!("mechanism {=str}", name);
    let input = File::open(input).map_err(|_| Setup::Open)?;
    let output = File::create(output).map_err(|_| Setup::Create)?;
    Ok((input, output, config))
}

/// Copies a path argument into `buf` with a terminating NUL.
fn c_path<'b, E>(
    arg: Option<Result<&str, E>>,
    buf: &'b mut [u8; MAX_PATH + 1],
) -> Result<&'b CStr, Setup> {
    let path = arg.and_then(|a| a.ok()).ok_or(Setup::Usage)?.as_bytes();
    let dst = buf.get_mut(..path.len()).ok_or(Setup::Usage)?;
    dst.copy_from_slice(path);
    let end = path.len() + 1;
    CStr::from_bytes_with_nul(buf.get(..end).ok_or(Setup::Usage)?).map_err(|_| Setup::Usage)
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    match info.location() {
        Some(l) => defmt::error!("panicked at {=str}:{=u32}", l.file(), l.line()),
        None => defmt::error!("panicked"),
    }
    process::exit(101)
}

#[exception]
unsafe fn HardFault(frame: &ExceptionFrame) -> ! {
    defmt::error!("HardFault at pc {=u32:#010x}", frame.pc());
    process::exit(134)
}
