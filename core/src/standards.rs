//! Uncertainty factors of the flight standards for mechanism margins: the one
//! definition that the host's design margin (`deploywatch margin`) and the
//! on-board energy margin ([`crate::margin::UncertaintyFactors`]) both use.
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

/// Uncertainty factors `FoS_i` [1] of one standard, per kind of resistance.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StandardFactors {
    /// Inertia: the torque to reach a required acceleration.
    pub inertia: f64,
    /// A spring that resists the motion (a known, fixed torque).
    pub spring: f64,
    /// Friction (Coulomb and viscous).
    pub friction: f64,
    /// Hysteresis of a spring or a damper.
    pub hysteresis: f64,
    /// Harness (cable) stiffness and drag.
    pub harness: f64,
    /// Adhesion (cold welding, stiction).
    pub adhesion: f64,
    /// Any other resistance.
    pub other: f64,
}

/// NASA-STD-5017B (2022), *Design and Development Requirements for
/// Mechanisms*, torque/force margin Eq. 4-1, Table 1, row "theory or
/// analysis" (initial sizing): acceleration 1.25, fixed/known 1.5, variable
/// 3.0. Friction, harness, hysteresis, adhesion and other are "variable"
/// (this project's mapping). Values from a secondary source quoting Table 1,
/// not checked against the standard's text (`docs/margin.md`).
pub const NASA_STD_5017B: StandardFactors = StandardFactors {
    inertia: NASA_STD_5017B_ACCELERATION,
    spring: NASA_STD_5017B_FIXED,
    friction: NASA_STD_5017B_VARIABLE,
    hysteresis: NASA_STD_5017B_VARIABLE,
    harness: NASA_STD_5017B_VARIABLE,
    adhesion: NASA_STD_5017B_VARIABLE,
    other: NASA_STD_5017B_VARIABLE,
};

/// NASA-STD-5017B Table 1, column "acceleration" (inertia torques), row
/// "theory or analysis" [1].
pub const NASA_STD_5017B_ACCELERATION: f64 = 1.25;

/// NASA-STD-5017B Table 1, column "fixed/known" (e.g. springs), row "theory
/// or analysis" [1].
pub const NASA_STD_5017B_FIXED: f64 = 1.5;

/// NASA-STD-5017B Table 1, column "variable" (friction, harness, ...), row
/// "theory or analysis" [1].
pub const NASA_STD_5017B_VARIABLE: f64 = 3.0;

/// ECSS-E-ST-33-01C (2009), *Space engineering — Mechanisms*, clause 4.7.5
/// (motorisation), table of minimum uncertainty factors, design stage: inertia
/// 1.1, spring 1.2, friction 3, hysteresis 3, harness 3, adhesion 3, other
/// forces 3. Recalled from the standard's table and **not confirmed** from
/// its text; some summaries give 1.5 for hysteresis (`docs/margin.md`).
pub const ECSS_E_ST_33_01C: StandardFactors = StandardFactors {
    inertia: 1.1,
    spring: 1.2,
    friction: 3.0,
    hysteresis: 3.0,
    harness: 3.0,
    adhesion: 3.0,
    other: 3.0,
};
