//! What people look at, and the files it is written to: PNG plots shared
//! by every command that draws, Markdown links, the progress lines of long
//! work, numbers written for people, and [`files::Outputs`], through which
//! every command writes its outputs all or none.
pub mod files;
pub mod markdown;
pub mod plot;
pub mod progress;
pub mod rig_split;
pub mod text;
