//! What people look at: PNG plots shared by every command that draws.
pub mod plot;
