//! The board: the one file to change for another MCU (`docs/firmware.md`,
//! "On a board"). Here QEMU's `mps2-an386` (AN386 FPGA image on the MPS2
//! board, QEMU `hw/arm/mps2.c`): UART0 is a CMSDK APB UART (Arm DDI0479C
//! §4.3, QEMU `hw/char/cmsdk-apb-uart.c`) at `0x4000_4000`, its receive
//! interrupt is IRQ 0 (transmit IRQ 1, the overruns of UARTs 0–2 ORed on
//! IRQ 12), its clock the 25 MHz system clock.
//!
//! What the application needs of a board: [`Uart::init`] (8N1 at
//! [`BAUD`], receive interrupt on), [`Uart::drain_rx`] (in the receive
//! interrupt: every byte received, and whether one was lost), and
//! [`Uart::write_all`] (blocking transmit), plus the receive interrupt's
//! number [`RX_IRQ`].

use cortex_m::interrupt::InterruptNumber;

/// UART0's registers [address].
const UART0: usize = 0x4000_4000;

/// The CMSDK APB UART's registers, each its offset from [`UART0`] \[bytes\].
#[derive(Clone, Copy)]
#[repr(usize)]
enum Reg {
    Data = 0x00,
    State = 0x04,
    Ctrl = 0x08,
    IntStatus = 0x0c,
    BaudDiv = 0x10,
}

/// Bits of STATE.
mod state {
    pub const TX_FULL: u32 = 1 << 0;
    pub const RX_FULL: u32 = 1 << 1;
    pub const RX_OVERRUN: u32 = 1 << 3;
}

/// Bits of CTRL: transmitter and receiver on, receive interrupt on.
mod ctrl {
    pub const TX_EN: u32 = 1 << 0;
    pub const RX_EN: u32 = 1 << 1;
    pub const RX_INTEN: u32 = 1 << 3;
}

/// The bit of the receive interrupt in INTSTATUS (write 1 to clear).
const INT_RX: u32 = 1 << 1;

/// The UART's clock \[Hz\] (mps2-an386's SYSCLK).
const PCLK_HZ: u32 = 25_000_000;
/// The line's rate \[baud\]. QEMU passes the bytes at the speed of its
/// character back-end whatever the divider; on a board it is the wire's
/// rate (8N1: 10 bits a byte).
pub const BAUD: u32 = 921_600;

/// The receive interrupt's number (NVIC line).
pub const RX_IRQ: u16 = 0;

/// The receive interrupt as the NVIC takes it.
#[derive(Clone, Copy)]
pub struct RxIrq;

// SAFETY: RX_IRQ is an interrupt line of this board (mps2-an386 has 64
// external interrupts), the number the vector table dispatches.
unsafe impl InterruptNumber for RxIrq {
    fn number(self) -> u16 {
        RX_IRQ
    }
}

/// The UART (a handle: the registers are the state).
#[derive(Clone, Copy)]
pub struct Uart;

impl Uart {
    fn read(reg: Reg) -> u32 {
        // SAFETY: an aligned register of UART0, readable at any time.
        unsafe { core::ptr::read_volatile((UART0 + reg as usize) as *const u32) }
    }

    fn write(reg: Reg, value: u32) {
        // SAFETY: an aligned register of UART0; the values written are the
        // ones its manual defines.
        unsafe { core::ptr::write_volatile((UART0 + reg as usize) as *mut u32, value) }
    }

    /// Sets the rate, clears stale state, and turns on the transmitter,
    /// the receiver and the receive interrupt (the NVIC line is the
    /// caller's).
    pub fn init() -> Self {
        Self::write(Reg::Ctrl, 0);
        Self::write(Reg::BaudDiv, (PCLK_HZ / BAUD).max(16));
        Self::write(Reg::State, state::RX_OVERRUN);
        Self::write(Reg::IntStatus, INT_RX);
        Self::write(Reg::Ctrl, ctrl::TX_EN | ctrl::RX_EN | ctrl::RX_INTEN);
        Uart
    }

    /// In the receive interrupt: clears the interrupt, then hands every
    /// byte waiting to `take`, and returns whether the UART lost a byte (an
    /// overrun: a byte came before the previous one was read). Clearing
    /// first: a byte that arrives after the last read raises the interrupt
    /// again. (Cleared after the reads, a byte arriving in between would
    /// sit in DATA with its interrupt cleared, and the CMSDK UART, with no
    /// FIFO, takes no other byte until DATA is read: the link would stall.)
    pub fn drain_rx(&self, mut take: impl FnMut(u8)) -> bool {
        Self::write(Reg::IntStatus, INT_RX);
        while Self::read(Reg::State) & state::RX_FULL != 0 {
            take((Self::read(Reg::Data) & 0xff) as u8);
        }
        let overrun = Self::read(Reg::State) & state::RX_OVERRUN != 0;
        if overrun {
            Self::write(Reg::State, state::RX_OVERRUN);
        }
        overrun
    }

    /// Sends `bytes`, waiting for room before each.
    pub fn write_all(&self, bytes: &[u8]) {
        for &b in bytes {
            while Self::read(Reg::State) & state::TX_FULL != 0 {}
            Self::write(Reg::Data, u32::from(b));
        }
    }
}
