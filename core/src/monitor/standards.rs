//! Uncertainty factors of the flight standards for mechanism margins: the one
//! definition that the host's design margin (`deploywatch margin`) and the
//! on-board energy margin ([`crate::monitor::margin::UncertaintyFactors`]) both use.
//!
//! ```text
//! MoS = D_min / Σ_i (FoS_i · R_i) − 1  ≥  MoS_required
//! ```
//!
//! Provenance (`docs/margin.md`, "What is confirmed and what is assumed"):
//! neither standard's text could be read for this work; each value says
//! which row of which table it stands for and where the number was taken
//! from. Treat them as configuration with a stated source, and check them
//! against the issue of the standard that applies.

// NASA-STD-5017B (2022), *Design and Development Requirements for
// Mechanisms*, torque/force margin Eq. 4-1, Table 1. The host maps friction,
// harness, hysteresis, adhesion and "other" to "variable", a resisting
// spring to "fixed", inertia to "acceleration" (this project's mapping).
// Values from a secondary source quoting Table 1, not checked against the
// standard's text (`docs/margin.md`).

/// NASA-STD-5017B Table 1, column "acceleration" (inertia torques), row
/// "theory or analysis" (initial sizing) \[1\].
pub const NASA_STD_5017B_ACCELERATION: f64 = 1.25;

/// NASA-STD-5017B Table 1, column "fixed/known" (e.g. springs), row "theory
/// or analysis" \[1\].
pub const NASA_STD_5017B_FIXED: f64 = 1.5;

/// NASA-STD-5017B Table 1, column "variable" (friction, harness, ...), row
/// "theory or analysis" \[1\].
pub const NASA_STD_5017B_VARIABLE: f64 = 3.0;

// ECSS-E-ST-33-01C (2009), *Space engineering — Mechanisms*, clause 4.7.5
// (motorisation), table of minimum uncertainty factors, design stage.
// Recalled from the standard's table and **not confirmed** from its text
// (`docs/margin.md`).

/// ECSS-E-ST-33-01C 4.7.5 uncertainty factor table, row "inertia" \[1\].
pub const ECSS_E_ST_33_01C_INERTIA: f64 = 1.1;

/// ECSS-E-ST-33-01C 4.7.5 uncertainty factor table, row "spring" \[1\].
pub const ECSS_E_ST_33_01C_SPRING: f64 = 1.2;

/// ECSS-E-ST-33-01C 4.7.5 uncertainty factor table, row "friction" \[1\].
pub const ECSS_E_ST_33_01C_FRICTION: f64 = 3.0;

/// ECSS-E-ST-33-01C 4.7.5 uncertainty factor table, row "hysteresis" \[1\]
/// (some summaries give 1.5; the conservative 3 is kept).
pub const ECSS_E_ST_33_01C_HYSTERESIS: f64 = 3.0;

/// ECSS-E-ST-33-01C 4.7.5 uncertainty factor table, row "harness" \[1\].
pub const ECSS_E_ST_33_01C_HARNESS: f64 = 3.0;

/// ECSS-E-ST-33-01C 4.7.5 uncertainty factor table, row "adhesion" \[1\].
pub const ECSS_E_ST_33_01C_ADHESION: f64 = 3.0;

/// ECSS-E-ST-33-01C 4.7.5 uncertainty factor table, row "other forces" \[1\].
pub const ECSS_E_ST_33_01C_OTHER: f64 = 3.0;
