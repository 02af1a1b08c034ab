//! The replay application, the same for every joint count: each binary
//! (`src/main.rs` for 3 joints, `src/bin/replay6/main.rs` for 6, ...)
//! sets `JOINTS`, the `N` of its one `Monitor<N>`, and includes this file.
//! What it does, and how to run it: `src/main.rs`.

use core::cell::RefCell;
use core::ffi::CStr;

// The critical-section implementation (single core) that defmt-semihosting uses.
use cortex_m::interrupt::{self, Mutex};
use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::SYST;
use cortex_m_rt::{entry, exception, ExceptionFrame};
use defmt_semihosting as _;
use deploywatch_core::telemetry::counted::CountedSample;
use deploywatch_core::telemetry::replay::{
    configure, read_header, run_paths, ConfigStore, Error, Meter, MonitorStore, Paths, Source, Work,
};

use super::JOINTS;
use semihosting::experimental::env;
use semihosting::fs::File;
use semihosting::io::{Read, Write};
use semihosting::process;

/// Longest accepted path argument, NUL excluded \[bytes\].
const MAX_PATH: usize = 127;

/// SysTick's period, the replay's sample clock [core clock ticks]: 16,384
/// ticks, 81,920 instructions under `-icount shift=3` (0.66 ms of virtual
/// time), nearly three times the longest `learn_or_predict` slice of 6 joints
/// (29,120), which the meter needs (it measures modulo the period). In
/// flight it is the sample interval (250,000 ticks for 100 Hz at 25 MHz);
/// in the replay the samples come from a file as fast as the main loop
/// reads them, and the period only paces the handover (QEMU's
/// `sleep=off` skips the `wfi` to the next tick at once).
const SAMPLE_TICKS: u32 = 16_384;

/// What the sample interrupt and the main loop share.
struct Shared {
    /// The monitor (static memory: it is kilobytes).
    monitor: MonitorStore<JOINTS>,
    /// The sample handed to the interrupt, and its answer.
    mailbox: Mailbox,
    /// The instruction counts of both paths.
    meter: WorkMeter,
}

/// The one monitor of the application, shared by the SysTick exception
/// (`update`) and the main loop (`learn_or_predict`, the status).
static SHARED: Mutex<RefCell<Shared>> = Mutex::new(RefCell::new(Shared {
    monitor: MonitorStore::Empty,
    mailbox: Mailbox::Empty,
    meter: WorkMeter::new(),
}));

/// The handover of one sample from the main loop to the sample interrupt.
// `repr(u8)`: `Empty` is tag 0, so `SHARED` starts all zeros (.bss).
#[derive(Clone, Copy)]
#[repr(u8)]
enum Mailbox {
    /// Nothing to do.
    Empty,
    /// A sample (of the monitor's joint count) for `Monitor::update`.
    Sample(CountedSample),
    /// `Monitor::update` has run on the sample, or could not (a sample of
    /// another joint count).
    Done(Result<(), Error>),
}

/// Runs `f` on the shared state inside a critical section; `None` if it is
/// already borrowed (cannot happen: every borrow is inside one critical
/// section on a single core).
fn with_shared<T>(f: impl FnOnce(&mut Shared) -> T) -> Option<T> {
    interrupt::free(|cs| {
        SHARED
            .borrow(cs)
            .try_borrow_mut()
            .ok()
            .map(|mut s| f(&mut s))
    })
}

/// The sample-rate path: on each timer tick, `Monitor::update` on the
/// sample in the mailbox, if there is one.
#[exception]
fn SysTick() {
    with_shared(|sh| {
        let Shared {
            monitor,
            mailbox,
            meter,
        } = sh;
        if let Mailbox::Sample(s) = mailbox {
            *mailbox = Mailbox::Done(monitor.update(s, meter));
        }
    });
}

/// The main loop's side of the two paths (`telemetry::replay::Paths`):
/// samples to the interrupt, `learn_or_predict` slices and the status here. One
/// copy of the loop; the monitor is the build's (`JOINTS`).
struct Application;

impl Paths for Application {
    fn joints(&mut self) -> Result<usize, Error> {
        with_shared(|sh| sh.monitor.joints()).ok_or(Error::Config)
    }

    fn slices_per_sample(&mut self) -> Result<u8, Error> {
        with_shared(|sh| sh.monitor.slices_per_sample())
            .flatten()
            .ok_or(Error::Config)
    }

    fn update(&mut self, sample: &CountedSample) -> Result<(), Error> {
        with_shared(|sh| sh.mailbox = Mailbox::Sample(*sample)).ok_or(Error::Config)?;
        loop {
            // Sleeps until an interrupt; the timer's comes within a period.
            cortex_m::asm::wfi();
            let done = with_shared(|sh| match sh.mailbox {
                Mailbox::Done(result) => {
                    sh.mailbox = Mailbox::Empty;
                    Some(result)
                }
                _ => None,
            });
            if let Some(result) = done.ok_or(Error::Config)? {
                return result;
            }
        }
    }

    fn learn_or_predict(&mut self) -> Result<(), Error> {
        // One bounded slice per critical section: the sample interrupt
        // waits at most this long.
        with_shared(|sh| sh.monitor.learn_or_predict(&mut sh.meter)).ok_or(Error::Config)?
    }

    fn status_frame(&mut self, out: &mut [u8]) -> Result<usize, Error> {
        with_shared(|sh| sh.monitor.status_frame(out)).ok_or(Error::Config)?
    }
}

#[entry]
fn main() -> ! {
    stack::paint();
    defmt::info!(
        "deploywatch firmware example: replay, monitor of {=usize} joints",
        JOINTS
    );
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
            match e {
                Error::Frame { index } => defmt::error!("at frame {=u32}", index),
                Error::JointCount { expected, found } => defmt::error!(
                    "the input is of {=u8} joints; this firmware is built for {=u8}",
                    found,
                    expected
                ),
                _ => {}
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
    // The configuration is built in static memory (.bss), not on the stack.
    let Some(config) = cortex_m::singleton!(: ConfigStore<JOINTS> = ConfigStore::Empty) else {
        defmt::error!("the configuration storage is already taken");
        return Err(Error::Config);
    };
    let mut src = Source::new(|buf: &mut [u8]| input.read(buf).map_err(|_| ()));
    let header = read_header(&mut src)?;
    defmt::info!(
        "monitor of {=u8} joints, deadline {=f32} s",
        header.joints,
        header.deadline_s
    );
    // Start-up: the timer interrupt is not running yet.
    with_shared(|sh| configure(&header, &mut src, config, &mut sh.monitor))
        .ok_or(Error::Config)??;
    let mut syst = peripherals.SYST;
    let per_tick = calibrate(&mut syst);
    syst.enable_interrupt();
    let write = |frame: &[u8]| output.write_all(frame).map_err(|_| ());
    let result = run_paths(&mut Application, &mut src, write);
    syst.disable_interrupt();
    if let Some(meter) = with_shared(|sh| sh.meter) {
        meter.update.report("Monitor::update", per_tick);
        meter.predict.report("predict", per_tick);
    }
    result
}

/// Calls, total and largest cost of one kind of work [SysTick ticks].
/// The total is a `u32` (saturating, which the report warns of): 4.3·10⁹
/// ticks are 172 s of work at 25 MHz, 180 times the longest replay's
/// (`learn_or_predict` of seed001_T02_eft, 24·10⁶ ticks), and a 64-bit division
/// would take flash the budget does not spare.
#[derive(Clone, Copy)]
struct Tally {
    calls: u32,
    sum: u32,
    max: u32,
}

impl Tally {
    const fn new() -> Self {
        Tally {
            calls: 0,
            sum: 0,
            max: 0,
        }
    }

    fn add(&mut self, ticks: u32) {
        self.calls += 1;
        self.sum = self.sum.saturating_add(ticks);
        self.max = self.max.max(ticks);
    }

    fn report(&self, what: &str, per_tick: u32) {
        if self.calls == 0 {
            defmt::info!("{=str}: 0 calls", what);
            return;
        }
        if self.sum == u32::MAX {
            defmt::warn!("{=str}: the tally saturated, the mean is low", what);
        }
        let mean = self.sum / self.calls;
        defmt::info!(
            "{=str}: {=u32} calls, mean {=u32} max {=u32} instructions ({=u32} per SysTick tick; QEMU -icount shift=3)",
            what,
            self.calls,
            mean * per_tick,
            self.max * per_tick,
            per_tick
        );
    }
}

/// Counts the instructions of every `Monitor::update` and every slice of
/// `Monitor::learn_or_predict` with SysTick on the core clock. QEMU's mps2-an386
/// clocks the core at 25 MHz of virtual time (a tick is 40 ns), and
/// `-icount shift=3` makes every instruction 2³ = 8 ns of it, so one tick
/// is 5 instructions: each call is measured to ±5, the mean far better. SysTick runs with the period
/// [`SAMPLE_TICKS`], so a call is measured modulo it (every call is far
/// shorter). Without `-icount` the figures follow the host's speed and mean
/// nothing.
#[derive(Clone, Copy)]
struct WorkMeter {
    t0: u32,
    update: Tally,
    predict: Tally,
    /// Ticks of an empty start/stop.
    overhead: u32,
}

impl WorkMeter {
    const fn new() -> Self {
        WorkMeter {
            t0: 0,
            update: Tally::new(),
            predict: Tally::new(),
            overhead: 0,
        }
    }

    /// Ticks since [`Meter::start`], less the meter's own.
    #[inline(always)]
    fn elapsed(&self) -> u32 {
        let t1 = SYST::get_current();
        // SysTick counts down from SAMPLE_TICKS − 1 to 0, then reloads.
        let ticks = if self.t0 >= t1 {
            self.t0 - t1
        } else {
            self.t0 + SAMPLE_TICKS - t1
        };
        ticks.saturating_sub(self.overhead)
    }
}

impl Meter for WorkMeter {
    #[inline(always)]
    fn start(&mut self) {
        self.t0 = SYST::get_current();
    }

    #[inline(always)]
    fn stop(&mut self, work: Work) {
        let ticks = self.elapsed();
        match work {
            Work::Update => self.update.add(ticks),
            Work::LearnOrPredict => self.predict.add(ticks),
        }
    }
}

/// Starts SysTick on the core clock with the period [`SAMPLE_TICKS`]
/// (interrupt still off), measures the meter's own cost into the shared
/// meter and returns the instructions per tick, from a loop of known length.
fn calibrate(syst: &mut SYST) -> u32 {
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(SAMPLE_TICKS - 1);
    syst.clear_current();
    syst.enable_counter();
    let mut m = WorkMeter::new();
    m.start();
    m.overhead = m.elapsed();
    // `asm::delay(n)` runs n + 1 turns of a two-instruction loop
    // (subs, bne; cortex-m 0.7.10): 20,000 instructions, under a period.
    const TURNS: u32 = 10_000;
    m.start();
    cortex_m::asm::delay(TURNS - 1);
    let ticks = m.elapsed().max(1);
    with_shared(|sh| sh.meter.overhead = m.overhead);
    (2 * TURNS + ticks / 2) / ticks
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

    /// Size of the stack region \[bytes\].
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

    /// Deepest stack use since [`paint`] \[bytes\].
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
