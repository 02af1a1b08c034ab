//! deploywatch example firmware for a Cortex-M4F (thumbv7em-none-eabihf),
//! run on QEMU's mps2-an386 board.
//!
//! It replays a recorded run: it reads the file named by the first
//! semihosting argument (the monitor configuration frames, then the sample
//! frames), runs the samples through the on-board monitor of that
//! configuration, and writes the status frames to the file named by the
//! second. The protocol and the loop are the core's
//! (`deploywatch_core::telemetry::replay`); this binary only gives them
//! files, static storage for the monitors, a meter and a log.
//!
//! The loop runs the monitor's two paths as a flight application does:
//! `Monitor::update` once per sample (the sample-rate path: in flight, the
//! timer interrupt of the sampling), then slices of `Monitor::predict` of
//! bounded cost (in flight, the idle loop or a low-priority task, until the
//! next sample). The number of slices per sample is fixed by the
//! configuration (`margin.rollout.slices_per_sample`), so that the replay is
//! deterministic and bit-identical with the host's.
//! It logs with defmt over semihosting stdout (decode with `defmt-print`) and
//! ends QEMU with a semihosting exit: 0 on success, 1 on an error, 101 on a
//! panic, 134 on a fault.
//!
//! ```text
//! qemu-system-arm -cpu cortex-m4 -machine mps2-an386 -nographic -icount shift=0 \
//!   -semihosting-config enable=on,target=native,arg=fw,arg=IN.bin,arg=OUT.bin \
//!   -kernel ELF | defmt-print -e ELF
//! ```
#![no_std]
#![no_main]

use core::ffi::CStr;

// The critical-section implementation (single core) that defmt-semihosting uses.
use cortex_m as _;
use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::SYST;
use cortex_m_rt::{entry, exception, ExceptionFrame};
use defmt_semihosting as _;
use deploywatch_core::telemetry::replay::{
    replay as replay_input, ConfigHeader, Error, Meter, MonitorStore, Work,
};
use semihosting::experimental::env;
use semihosting::fs::File;
use semihosting::io::{Read, Write};
use semihosting::process;

/// Longest accepted path argument, NUL excluded [bytes].
const MAX_PATH: usize = 127;

#[entry]
fn main() -> ! {
    stack::paint();
    defmt::info!("deploywatch firmware example: replay");
    let result = replay();
    defmt::info!(
        "stack: peak {=usize} B of {=usize} B",
        stack::peak(),
        stack::size()
    );
    let code = match result {
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
    /// The input file could not be opened.
    Open,
    /// The output file could not be created.
    Create,
}

fn replay() -> Result<u32, Error> {
    let (mut input, mut output) = match setup() {
        Ok(setup) => setup,
        Err(Setup::Usage) => {
            defmt::error!(
                "usage: semihosting arguments PROGRAM INPUT OUTPUT (paths up to 127 bytes)"
            );
            return Err(Error::Read);
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
    let Some(peripherals) = cortex_m::Peripherals::take() else {
        defmt::error!("the core peripherals are already taken");
        return Err(Error::Config);
    };
    // The monitor lives in static memory (.bss), not on the stack.
    let Some(store) = cortex_m::singleton!(: MonitorStore = MonitorStore::Empty) else {
        defmt::error!("the monitor storage is already taken");
        return Err(Error::Config);
    };
    let mut meter = WorkMeter::new(peripherals.SYST);
    let result = replay_input(
        |buf| input.read(buf).map_err(|_| ()),
        |frame| output.write_all(frame).map_err(|_| ()),
        &mut meter,
        store,
        |h: &ConfigHeader| {
            defmt::info!(
                "monitor of {=u8} joints, deadline {=f32} s",
                h.joints,
                h.deadline_s
            )
        },
    );
    meter.report();
    result.map(|(_, samples)| samples)
}

/// Calls, total and largest cost of one kind of work [SysTick ticks].
#[derive(Clone, Copy, Default)]
struct Tally {
    calls: u32,
    sum: u64,
    max: u32,
}

impl Tally {
    fn add(&mut self, ticks: u32) {
        self.calls += 1;
        self.sum += u64::from(ticks);
        self.max = self.max.max(ticks);
    }

    fn report(&self, what: &str, per_tick: u32) {
        if self.calls == 0 {
            defmt::info!("{=str}: 0 calls", what);
            return;
        }
        let mean = (self.sum / u64::from(self.calls)) as u32;
        defmt::info!(
            "{=str}: {=u32} calls, mean {=u32} max {=u32} instructions ({=u32} per SysTick tick; QEMU -icount shift=0)",
            what,
            self.calls,
            mean * per_tick,
            self.max * per_tick,
            per_tick
        );
    }
}

/// Counts the instructions of every `Monitor::update` and every slice of
/// `Monitor::predict` with SysTick on the core clock. QEMU's mps2-an386
/// clocks the core at 25 MHz of virtual time, and `-icount shift=0` makes
/// every instruction 1 ns of it, so one tick is 40 instructions: each call is
/// measured to ±40, the mean far better. Without `-icount` the figures
/// follow the host's speed and mean nothing.
struct WorkMeter {
    t0: u32,
    update: Tally,
    predict: Tally,
    /// Ticks of an empty start/stop.
    overhead: u32,
    /// Instructions per tick, from a loop of known length.
    per_tick: u32,
}

impl WorkMeter {
    /// SysTick's 24-bit counter.
    const MASK: u32 = 0x00FF_FFFF;

    fn new(mut syst: SYST) -> Self {
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(Self::MASK);
        syst.clear_current();
        syst.enable_counter();
        let mut m = WorkMeter {
            t0: 0,
            update: Tally::default(),
            predict: Tally::default(),
            overhead: 0,
            per_tick: 0,
        };
        m.start();
        m.stop(Work::Update);
        m.overhead = m.update.max;
        // `asm::delay(n)` runs n + 1 turns of a two-instruction loop
        // (subs, bne; cortex-m 0.7.10).
        const TURNS: u32 = 100_000;
        m.update = Tally::default();
        m.start();
        cortex_m::asm::delay(TURNS - 1);
        m.stop(Work::Update);
        let ticks = m.update.max.max(1);
        m.per_tick = (2 * TURNS + ticks / 2) / ticks;
        m.update = Tally::default();
        m
    }

    fn report(&self) {
        self.update.report("Monitor::update", self.per_tick);
        self.predict.report("predict", self.per_tick);
    }
}

impl Meter for WorkMeter {
    #[inline(always)]
    fn start(&mut self) {
        self.t0 = SYST::get_current();
    }

    #[inline(always)]
    fn stop(&mut self, work: Work) {
        let t1 = SYST::get_current();
        // SysTick counts down.
        let ticks = (self.t0.wrapping_sub(t1) & Self::MASK).saturating_sub(self.overhead);
        match work {
            Work::Update => self.update.add(ticks),
            Work::Predict => self.predict.add(ticks),
        }
    }
}

/// Opens the input and creates the output, as the semihosting command line
/// `PROGRAM INPUT OUTPUT` says. Out of line: its argument and path buffers
/// leave the stack before the replay starts.
#[inline(never)]
fn setup() -> Result<(File, File), Setup> {
    let args = env::args::<512>().map_err(|_| Setup::Usage)?;
    let mut it = (&args).into_iter().skip(1);
    let mut in_path = [0u8; MAX_PATH + 1];
    let mut out_path = [0u8; MAX_PATH + 1];
    let input = c_path(it.next(), &mut in_path)?;
    let output = c_path(it.next(), &mut out_path)?;
    let input = File::open(input).map_err(|_| Setup::Open)?;
    let output = File::create(output).map_err(|_| Setup::Create)?;
    Ok((input, output))
}

/// Copies a path argument into `buf` with a terminating NUL.
fn c_path<'b, E>(
    arg: Option<Result<&str, E>>,
    buf: &'b mut [u8; MAX_PATH + 1],
) -> Result<&'b CStr, Setup> {
    let path = arg.and_then(|a| a.ok()).ok_or(Setup::Usage)?.as_bytes();
    if path.len() > MAX_PATH {
        return Err(Setup::Usage);
    }
    for (d, s) in buf.iter_mut().zip(path.iter()) {
        *d = *s;
    }
    let end = path.len() + 1;
    CStr::from_bytes_with_nul(buf.get(..end).ok_or(Setup::Usage)?).map_err(|_| Setup::Usage)
}

/// The stack's high-water mark, by painting: everything below the stack
/// pointer is filled with a pattern at start-up, and the lowest word that no
/// longer holds it at the end is the deepest the stack went. A measurement
/// of this run, not a bound (a path the run did not take is not counted).
mod stack {
    const PAINT: u32 = 0xCAFE_F00D;
    /// Bytes left unpainted below the stack pointer, for `paint`'s own frame.
    const MARGIN: usize = 64;

    extern "C" {
        /// Top of the stack (cortex-m-rt's link.x: the end of RAM).
        static _stack_start: u32;
        /// Lowest address the stack may reach (end of .bss/.uninit).
        static _stack_end: u32;
    }

    fn bounds() -> (usize, usize) {
        // Only the addresses of the linker symbols are taken (safe).
        (
            core::ptr::addr_of!(_stack_end) as usize,
            core::ptr::addr_of!(_stack_start) as usize,
        )
    }

    /// Size of the stack region [bytes].
    pub fn size() -> usize {
        let (bottom, top) = bounds();
        top - bottom
    }

    /// Fills the unused stack below the current stack pointer.
    pub fn paint() {
        let (bottom, _) = bounds();
        let sp = cortex_m::register::msp::read() as usize;
        let mut p = bottom;
        while p + 4 <= sp.saturating_sub(MARGIN) {
            // SAFETY: [bottom, sp − MARGIN) is stack memory that no frame
            // uses yet; word-aligned (link.x asserts _stack_end % 4 == 0).
            unsafe { (p as *mut u32).write_volatile(PAINT) };
            p += 4;
        }
    }

    /// Deepest stack use since [`paint`] [bytes].
    pub fn peak() -> usize {
        let (bottom, top) = bounds();
        let mut p = bottom;
        // SAFETY: reads of word-aligned RAM inside the stack region.
        while p < top && unsafe { (p as *const u32).read_volatile() } == PAINT {
            p += 4;
        }
        top - p
    }
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
