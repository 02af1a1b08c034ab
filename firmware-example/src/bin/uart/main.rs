//! deploywatch firmware on a serial line (hardware in the loop), for a
//! Cortex-M4F (thumbv7em-none-eabihf): QEMU's mps2-an386 today, a board
//! tomorrow (`board.rs` is the one file to change).
//!
//! It serves the core's live link (`deploywatch_core::telemetry::link`) on
//! UART0: the host (`deploywatch hil`) sends the monitor configuration
//! frames, the firmware builds the monitor and answers "ready" (a link
//! report), then the host streams the run's sample frames at their own
//! time stamps, in real time.
//!
//! - **receive interrupt** (UART0 RX): every byte into a lock-free
//!   single-producer single-consumer queue (`heapless::spsc`); a byte that
//!   finds it full, or that the UART overran, is counted as an overrun;
//! - **main loop** (thread mode): frames cut from the queue at their
//!   `0x00`; a sample frame that decodes goes through `Monitor::update`
//!   and its status frame is written back at once; then the prediction's
//!   slices of `Monitor::learn_or_predict` run in the idle time before the next
//!   sample; a frame that does not decode is counted and skipped, and the
//!   monitor goes on (`docs/robustness.md`); an empty frame asks for the
//!   link report (counts of samples, corrupted, too long, overruns). With
//!   the queue empty the core sleeps (`wfi`) until the next byte.
//!
//! A configuration that does not decode or that the monitor refuses is
//! logged and the firmware waits for the next configuration header.
//! It logs with defmt over semihosting (QEMU: `-semihosting-config
//! enable=on`; on a board without a debugger, swap `defmt-semihosting` for
//! `defmt-rtt`).
//!
//! ```text
//! qemu-system-arm -cpu cortex-m4 -machine mps2-an386 -nographic \
//!   -semihosting-config enable=on,target=native \
//!   -chardev socket,id=hil,host=127.0.0.1,port=PORT,nodelay=on -serial chardev:hil \
//!   -kernel deploywatch-firmware-uart
//! ```
#![no_std]
#![no_main]

mod board;

/// Joints of this build's monitor (the joint count is the firmware's
/// choice; this serial-link build carries one of 3 joints,
/// `deploywatch-firmware-uart-6` one of 6).
const JOINTS: usize = 3;

/// Receive queue \[bytes\]: 20 sample frames of 3 joints (25 bytes each),
/// so a main loop busy with the prediction's slices loses nothing.
const RX_QUEUE: usize = 512;

#[path = "../../uart_app.rs"]
mod uart_app;
