//! deploywatch example firmware for a Cortex-M4F (thumbv7em-none-eabihf),
//! run on QEMU's mps2-an386 board: this binary's monitor has 3 joints
//! (`JOINTS`); `deploywatch-firmware-example-2` and `-6` (src/bin/) are
//! the same application built for 2 and 6. The joint count is the
//! firmware's choice, a const generic of the core's stores
//! (`MonitorStore<N>`): one monitor, compiled once, per binary.
//!
//! It replays a recorded run: it reads the file named by the first
//! semihosting argument (the monitor configuration frames, then the sample
//! frames), runs the samples through the on-board monitor of that
//! configuration, and writes the status frames to the file named by the
//! second. The protocol and the loop are the core's
//! (`deploywatch_core::telemetry::replay`); this binary only gives them
//! files, static storage for the monitors, a meter and a log.
//!
//! It runs the monitor's two paths as a flight application does, at two
//! priorities sharing one monitor:
//!
//! - **the sample-rate path** — `Monitor::update` — in the SysTick
//!   exception, the timer interrupt of the sampling;
//! - **the prediction** — slices of `Monitor::learn_or_predict` of bounded cost — in
//!   the main (idle) loop, at thread priority.
//!
//! The monitor is shared through a `cortex_m::interrupt::Mutex<RefCell<..>>`
//! (`SHARED`): each `learn_or_predict` slice runs in a critical section, so the
//! sample interrupt waits at most one slice (bounded, `docs/performance.md`)
//! and never sees a half-advanced rollout. Flight code would read the
//! sensors in the interrupt; here the sensor is the replay file, which
//! semihosting can only read from thread mode: the main loop decodes the
//! next sample into the mailbox (`Mailbox`) and sleeps (`wfi`) until the
//! next timer tick has run `Monitor::update` on it. The order of the work
//! — `update`, then `margin.rollout.slices_per_sample` slices, then the
//! status — is the core's loop (`telemetry::replay::run_paths`), the one the
//! host runs too, so the replay is deterministic and bit-identical with the
//! host whatever the timer's period.
//! It logs with defmt over semihosting stdout (decode with `defmt-print`) and
//! ends QEMU with a semihosting exit: 0 on success, 1 on an error, 101 on a
//! panic, 134 on a fault.
//!
//! ```text
//! qemu-system-arm -cpu cortex-m4 -machine mps2-an386 -nographic -icount shift=3,sleep=off \
//!   -semihosting-config enable=on,target=native,arg=fw,arg=IN.bin,arg=OUT.bin \
//!   -kernel ELF | defmt-print -e ELF
//! ```
#![no_std]
#![no_main]

/// Joints of this build's monitor.
const JOINTS: usize = 3;

mod replay_app;
