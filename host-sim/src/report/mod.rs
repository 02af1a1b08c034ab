//! What people look at: PNG plots shared by every command that draws, and
//! the progress lines of long work, numbers written for people.
pub mod plot;
pub mod progress;
pub mod text;
