//! What people look at, and the files it is written to. The leaf
//! utilities, usable from every layer: PNG plots shared by every command
//! that draws ([`plot`]), Markdown links ([`markdown`]), the progress lines
//! of long work ([`progress`]), numbers written for people ([`text`]), and
//! [`files::Outputs`], through which every command writes its outputs all
//! or none. Above the analysis, the report writers: the diagnosis report,
//! its plots and its JSON ([`diagnosis`] and the `diagnosis_*` modules;
//! [`diagnosis_outcome`] the words of its typed findings),
//! the margin table and its JSON ([`margin`]) and its plot along the
//! stroke ([`margin_plot`]), every standard side by side
//! ([`margin_standards`]), the identification's summary
//! and plot ([`identify`]), a simulated run's plot ([`run_plot`]).
pub mod diagnosis;
pub mod diagnosis_delay;
pub mod diagnosis_flex;
pub mod diagnosis_free_play;
pub mod diagnosis_json;
pub mod diagnosis_latch;
pub mod diagnosis_outcome;
pub mod diagnosis_plots;
pub mod diagnosis_set_aside;
pub mod diagnosis_tolerance;
pub mod diagnosis_torque;
pub mod diagnosis_words;
pub mod evidence_words;
pub mod files;
pub mod identify;
pub mod margin;
pub mod margin_plot;
pub mod margin_standards;
pub mod markdown;
pub mod plot;
pub mod progress;
pub mod rig_split;
pub mod run_plot;
pub mod text;
