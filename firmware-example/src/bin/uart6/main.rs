//! The serial-link firmware (`src/bin/uart/main.rs`, which says what it
//! does) built for a monitor of 6 joints: `deploywatch hil` of a six-panel
//! wing.
#![no_std]
#![no_main]

#[path = "../uart/board.rs"]
mod board;

/// Joints of this build's monitor.
const JOINTS: usize = 6;

/// Receive queue \[bytes\]: 20 sample frames of 6 joints (43 bytes each),
/// so a main loop busy with the prediction's slices loses nothing.
const RX_QUEUE: usize = 1024;

#[path = "../../uart_app.rs"]
mod uart_app;
