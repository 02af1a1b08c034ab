//! Crate-private logging shim (after embassy-time's `src/fmt.rs`).
//!
//! With the `defmt` feature the macros forward to `defmt`; without it they
//! still type-check their arguments against `core::fmt` (so a log line cannot
//! rot unnoticed) but emit nothing and cost nothing at run time. Use `{}`
//! placeholders only: they mean the same to both. `lib.rs` declares this
//! module first with `#[macro_use]`, so the macros are in scope everywhere.
#![allow(unused_macros)]

macro_rules! debug {
    ($($arg:tt)*) => {{
        #[cfg(feature = "defmt")]
        ::defmt::debug!($($arg)*);
        #[cfg(not(feature = "defmt"))]
        {
            let _ = ::core::format_args!($($arg)*);
        }
    }};
}

macro_rules! info {
    ($($arg:tt)*) => {{
        #[cfg(feature = "defmt")]
        ::defmt::info!($($arg)*);
        #[cfg(not(feature = "defmt"))]
        {
            let _ = ::core::format_args!($($arg)*);
        }
    }};
}

macro_rules! warn {
    ($($arg:tt)*) => {{
        #[cfg(feature = "defmt")]
        ::defmt::warn!($($arg)*);
        #[cfg(not(feature = "defmt"))]
        {
            let _ = ::core::format_args!($($arg)*);
        }
    }};
}
