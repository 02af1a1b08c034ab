//! The serial-link firmware's application (`src/bin/uart/main.rs` says
//! what it does): each serial-link binary sets `JOINTS`, the `N` of its one
//! `Monitor<N>`, and `RX_QUEUE`, declares its `board` and includes this file.

use core::cell::RefCell;
use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m::interrupt::{self, Mutex};
use cortex_m::peripheral::NVIC;
use cortex_m_rt::{entry, exception, ExceptionFrame};
use defmt_semihosting as _;
use deploywatch_core::telemetry::link::{report_frame, serve, LinkReport, LINK_REPORT_FRAME_MAX};
use deploywatch_core::telemetry::replay::{
    configure, read_header, ConfigStore, Direct, Error, MonitorStore, Source,
};
use heapless::spsc::{Consumer, Producer, Queue};

use super::board::{self, RxIrq, Uart};
use super::{JOINTS, RX_QUEUE};

/// The queue's producer, the receive interrupt's (moved there at start-up).
static RX: Mutex<RefCell<Option<Producer<'static, u8>>>> = Mutex::new(RefCell::new(None));

/// Bytes lost on reception: the queue full or the UART overrun.
static OVERRUN: AtomicU32 = AtomicU32::new(0);

/// Bytes the receive interrupt put into the queue (wrapping).
static QUEUED: AtomicU32 = AtomicU32::new(0);

/// Bytes the main loop took from the queue (wrapping): the queue holds
/// bytes while it differs from [`QUEUED`].
static TAKEN: AtomicU32 = AtomicU32::new(0);

/// Every interrupt without a handler of its own comes here (no device
/// crate: cortex-m-rt's vector table points all of them to it); the
/// UART's receive interrupt is served, any other is ignored.
#[exception]
unsafe fn DefaultHandler(irqn: i16) {
    if irqn != board::RX_IRQ as i16 {
        return;
    }
    interrupt::free(|cs| {
        let mut rx = RX.borrow(cs).borrow_mut();
        let (mut lost, mut queued) = (0u32, 0u32);
        let overrun = Uart.drain_rx(|b| {
            if rx.as_mut().is_some_and(|p| p.enqueue(b).is_ok()) {
                queued += 1;
            } else {
                lost += 1;
            }
        });
        lost += u32::from(overrun);
        if lost > 0 {
            OVERRUN.fetch_add(lost, Ordering::Relaxed);
        }
        QUEUED.fetch_add(queued, Ordering::Release);
    });
}

/// Stops on a start-up failure that cannot happen (a singleton taken
/// twice): logs it and ends the QEMU run.
fn halt(what: &str) -> ! {
    defmt::error!("{=str}", what);
    semihosting::process::exit(1)
}

#[entry]
fn main() -> ! {
    defmt::info!("deploywatch firmware example: serial link on UART0");
    let Some(queue) = cortex_m::singleton!(: Queue<u8, RX_QUEUE> = Queue::new()) else {
        halt("the receive queue is already taken")
    };
    let (producer, consumer) = queue.split();
    interrupt::free(|cs| RX.borrow(cs).replace(Some(producer)));
    // Static memory for the configuration and the monitor (kilobytes).
    let Some(config) = cortex_m::singleton!(: ConfigStore<JOINTS> = ConfigStore::Empty) else {
        halt("the configuration storage is already taken")
    };
    let Some(store) = cortex_m::singleton!(: MonitorStore<JOINTS> = MonitorStore::Empty) else {
        halt("the monitor storage is already taken")
    };
    let uart = Uart::init();
    // SAFETY: the handler of the line (DefaultHandler) touches only the
    // queue's producer, in a critical section.
    unsafe { NVIC::unmask(RxIrq) };
    let mut src = Source::new(receiver(consumer));
    loop {
        match session(&mut src, config, store, uart) {
            Ok(()) => defmt::info!("the link ended; waiting for a configuration"),
            Err(e) => defmt::error!("{=str}; waiting for a configuration", e.as_str()),
        }
    }
}

/// The byte source of the frames: what the queue holds, at least one byte,
/// sleeping until the receive interrupt brings some.
fn receiver(mut rx: Consumer<'static, u8>) -> impl FnMut(&mut [u8]) -> Result<usize, ()> {
    move |buf: &mut [u8]| loop {
        let mut n = 0;
        for slot in buf.iter_mut() {
            let Some(b) = rx.dequeue() else { break };
            *slot = b;
            n += 1;
        }
        if n > 0 {
            TAKEN.fetch_add(n as u32, Ordering::Relaxed);
            return Ok(n);
        }
        // Interrupts masked between the check and the sleep: a byte that
        // arrives in between leaves its interrupt pending, which ends the
        // `wfi` at once (then it is served as the mask lifts).
        interrupt::free(|_| {
            if !rx.ready() {
                cortex_m::asm::wfi();
            }
        });
    }
}

/// One configuration and the link that follows it, until the host closes
/// it or a frame of the configuration fails.
fn session<R>(
    src: &mut Source<R>,
    config: &mut ConfigStore<JOINTS>,
    store: &mut MonitorStore<JOINTS>,
    uart: Uart,
) -> Result<(), Error>
where
    R: FnMut(&mut [u8]) -> Result<usize, ()>,
{
    let header = read_header(src)?;
    configure(&header, src, config, store)?;
    defmt::info!("monitor of {=u8} joints; ready", header.joints,);
    let mut report = LinkReport::READY;
    let mut buf = [0u8; LINK_REPORT_FRAME_MAX];
    let n = report_frame(&report, &mut buf)?;
    uart.write_all(buf.get(..n).ok_or(Error::Encode)?);
    let mut paths = Direct {
        store,
        meter: &mut (),
    };
    let write = |frame: &[u8]| {
        uart.write_all(frame);
        Ok(())
    };
    // The prediction's slices yield to a frame that is waiting.
    let pending = || QUEUED.load(Ordering::Acquire) != TAKEN.load(Ordering::Relaxed);
    serve(
        &mut paths,
        src,
        write,
        &mut report,
        || OVERRUN.load(Ordering::Relaxed),
        pending,
    )
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    match info.location() {
        Some(l) => defmt::error!("panicked at {=str}:{=u32}", l.file(), l.line()),
        None => defmt::error!("panicked"),
    }
    semihosting::process::exit(101)
}

#[exception]
unsafe fn HardFault(frame: &ExceptionFrame) -> ! {
    defmt::error!("HardFault at pc {=u32:#010x}", frame.pc());
    semihosting::process::exit(134)
}
