//! Torque margins of a spring-driven deployment: the papers' two forms and
//! the uncertainty-factor form of the flight standards (`physics.md` 9,
//! `docs/margin.md`).
//!
//! # The papers' forms
//!
//! - **Torque form**, seed 001 Eq. 7: `TM = (T_D / T_R − 1) · 100 %`, `T_D` the
//!   spring torque at the stowed angle [N·m], `T_R` the resistance (the
//!   equivalent friction torque, EFT) [N·m].
//! - **Energy form**, seed 000 Eqs. 17–21: `TM = (E_D / E_R − 1) · 100 %` with
//!   `E_D = ∫_0^stroke T_D dθ` the energy the spring releases over the joint's
//!   stroke and `E_R = ∫_0^stroke T_R dθ = T_R · stroke` for a constant
//!   friction \[J\].
//!
//! A joint passes when its margin is ≥ 0 (the papers: "if the torque margin
//! value was negative, then the deployment … would not be achieved").
//!
//! # The standards' form
//!
//! NASA-STD-5017 (Rev B, Eq. 4-1) and ECSS-E-ST-33-01C (motorisation,
//! clause 4.7.5) both multiply each kind of resistance by its own uncertainty
//! factor before the ratio:
//!
//! ```text
//! MoS = D_min / Σ_i (FoS_i · R_i) − 1 ≥ MoS_required
//! ```
//!
//! with `D` and `R_i` torques [N·m] or energies \[J\]. [`Standard`] gives each
//! standard's default [`Factors`] and required minimum; both are plain data
//! and can be changed (`deploywatch margin --factor friction=2.5`). Which
//! numbers are confirmed and which are assumed is recorded on
//! [`Standard::factors`] and in `docs/margin.md`: treat the defaults as
//! configuration, not as a quotation of the standards.

use deploywatch_core::monitor::standards;
use deploywatch_core::{Branch, Spring};
use std::fmt;
use std::str::FromStr;

mod data_source;
pub use data_source::DataSource;

/// A kind of resistance, each with its own uncertainty factor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Resistance {
    /// Inertia: the torque to reach a required acceleration (NASA "acceleration").
    Inertia,
    /// A spring that resists the motion (NASA "fixed/known").
    Spring,
    /// Friction: joint Coulomb/viscous friction, the papers' EFT.
    Friction,
    /// Hysteresis losses (e.g. of a tape-spring hinge).
    Hysteresis,
    /// Harness (cable) stiffness and drag.
    Harness,
    /// Adhesion / stiction after a long dwell (cold welding).
    Adhesion,
    /// Any other resistance (ECSS "other forces").
    Other,
}

impl Resistance {
    /// Every kind, in the order of [`Factors`].
    pub const ALL: [Resistance; 7] = [
        Resistance::Inertia,
        Resistance::Spring,
        Resistance::Friction,
        Resistance::Hysteresis,
        Resistance::Harness,
        Resistance::Adhesion,
        Resistance::Other,
    ];

    /// The name used on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            Resistance::Inertia => "inertia",
            Resistance::Spring => "spring",
            Resistance::Friction => "friction",
            Resistance::Hysteresis => "hysteresis",
            Resistance::Harness => "harness",
            Resistance::Adhesion => "adhesion",
            Resistance::Other => "other",
        }
    }
}

impl fmt::Display for Resistance {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A name that is not a [`Resistance`] or a [`Standard`].
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum NameError {
    /// Not a kind of resistance.
    #[error("unknown resistance `{name}`: expected one of {}", Resistance::ALL.map(|r| r.name()).join(", "))]
    Resistance {
        /// The name given.
        name: String,
    },
    /// Not a standard.
    #[error(
        "unknown standard `{name}`: expected none, nasa-std-5017, ecss-e-st-33-01c or aiaa-s-114"
    )]
    Standard {
        /// The name given.
        name: String,
    },
}

impl FromStr for Resistance {
    type Err = NameError;
    fn from_str(s: &str) -> Result<Self, NameError> {
        Resistance::ALL
            .into_iter()
            .find(|r| r.name().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| NameError::Resistance {
                name: s.to_string(),
            })
    }
}

/// Uncertainty factors `FoS_i` \[1\] per kind of resistance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Factors {
    /// On inertia (acceleration) torques.
    pub inertia: f64,
    /// On resisting springs.
    pub spring: f64,
    /// On friction.
    pub friction: f64,
    /// On hysteresis.
    pub hysteresis: f64,
    /// On harness resistance.
    pub harness: f64,
    /// On adhesion / stiction.
    pub adhesion: f64,
    /// On other resistances.
    pub other: f64,
}

impl Factors {
    /// All factors 1: the papers' unfactored margin.
    pub const UNITY: Factors = Factors {
        inertia: 1.0,
        spring: 1.0,
        friction: 1.0,
        hysteresis: 1.0,
        harness: 1.0,
        adhesion: 1.0,
        other: 1.0,
    };

    /// The factor of one kind.
    pub fn get(&self, kind: Resistance) -> f64 {
        match kind {
            Resistance::Inertia => self.inertia,
            Resistance::Spring => self.spring,
            Resistance::Friction => self.friction,
            Resistance::Hysteresis => self.hysteresis,
            Resistance::Harness => self.harness,
            Resistance::Adhesion => self.adhesion,
            Resistance::Other => self.other,
        }
    }

    /// Sets the factor of one kind.
    pub fn set(&mut self, kind: Resistance, value: f64) {
        match kind {
            Resistance::Inertia => self.inertia = value,
            Resistance::Spring => self.spring = value,
            Resistance::Friction => self.friction = value,
            Resistance::Hysteresis => self.hysteresis = value,
            Resistance::Harness => self.harness = value,
            Resistance::Adhesion => self.adhesion = value,
            Resistance::Other => self.other = value,
        }
    }
}

/// Which flight standard's factors and required minimum margin apply.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Standard {
    /// No standard: the papers' unfactored margins, pass at ≥ 0.
    #[default]
    None,
    /// NASA-STD-5017B (2022), Design and Development Requirements for
    /// Mechanisms, torque/force margin (Eq. 4-1, Table 1).
    NasaStd5017,
    /// ECSS-E-ST-33-01C, Space engineering — Mechanisms, motorisation
    /// margin (clause 4.7.5).
    EcssEST3301C,
    /// AIAA S-114-2005 (as NASA-STD-5017, 2006): a 100 % static torque
    /// margin at any position (available ≥ 2 × resisting, detent and
    /// backdrive included) and a 25 % dynamic margin.
    AiaaS114,
}

impl Standard {
    /// Every standard.
    pub const ALL: [Standard; 4] = [
        Standard::None,
        Standard::NasaStd5017,
        Standard::EcssEST3301C,
        Standard::AiaaS114,
    ];

    /// The name on the command line: `none`, `nasa-std-5017`, `ecss-e-st-33-01c`.
    pub fn name(self) -> &'static str {
        match self {
            Standard::None => "none",
            Standard::NasaStd5017 => "nasa-std-5017",
            Standard::EcssEST3301C => "ecss-e-st-33-01c",
            Standard::AiaaS114 => "aiaa-s-114",
        }
    }

    /// What of [`Standard::reference`] and [`Standard::factors_for`] is
    /// confirmed from the standard's text, printed with every margin
    /// (`docs/margin.md`, "What is confirmed and what is assumed").
    pub fn confirmation(self) -> &'static str {
        match self {
            Standard::None => "the seeds' own equations (seed 001 Eq. 7, seed 000 Eqs. 17-21)",
            Standard::NasaStd5017 => {
                "Eq. 4-1 and the Table 1 factors from a secondary source (a transcription): not confirmed from the text of NASA-STD-5017B"
            }
            Standard::EcssEST3301C => {
                "the ratio of clause 4.7.5 from a secondary source; the factor values as commonly quoted, from memory: not confirmed from the text of ECSS-E-ST-33-01C (Rev. 2)"
            }
            Standard::AiaaS114 => {
                "checked in the Aerospace Corporation's Mission Assurance Baseline item 4.4.4.5-6 citing AIAA S-114-2005; not confirmed from the text of AIAA S-114 itself"
            }
        }
    }

    /// [`Standard::reference`] with the row of factors `source` selects
    /// where the standard has rows (NASA-STD-5017B's Table 1).
    pub fn reference_for(self, source: DataSource) -> String {
        match self {
            Standard::NasaStd5017 => format!(
                "NASA-STD-5017B, torque/force margin Eq. 4-1, Table 1 (row: {})",
                source.row()
            ),
            _ => self.reference().to_string(),
        }
    }

    /// Whether the factors depend on the data source (only
    /// NASA-STD-5017B's have rows here).
    pub fn has_rows(self) -> bool {
        self == Standard::NasaStd5017
    }

    /// The document and clause the factors come from (the analysis row
    /// of NASA-STD-5017B; [`Standard::reference_for`] names the row).
    pub fn reference(self) -> &'static str {
        match self {
            Standard::None => "seed 001 Eq. 7 / seed 000 Eq. 21, no uncertainty factors",
            Standard::NasaStd5017 => {
                "NASA-STD-5017B, torque/force margin Eq. 4-1, Table 1 (row: theory or analysis)"
            }
            Standard::EcssEST3301C => {
                "ECSS-E-ST-33-01C, clause 4.7.5 motorisation, table of minimum uncertainty factors"
            }
            Standard::AiaaS114 => {
                "AIAA S-114-2005 via Mission Assurance Baseline item 4.4.4.5-6: 100 % static torque margin at any position (factor 2 on every resistance), 25 % dynamic (inertia 1.25)"
            }
        }
    }

    /// The factors with resistances known from `source`: the standard's
    /// row of NASA-STD-5017B Table 1 (fixed, variable, acceleration:
    /// analysis 1.5/3.0/1.25, tests 1.35/2.5/1.15, acceptance at
    /// environmental extremes 1.25/2.0/1.10) on its kinds. ECSS-E-ST-33-01C,
    /// AIAA S-114 and `None` have one row here: their factors whatever the
    /// source (a resistance measured on the flight hardware is taken at a
    /// lower factor only by `--factor`, the reviewer's own figure,
    /// `docs/margin.md`).
    pub fn factors_for(self, source: DataSource) -> Factors {
        let analysis = self.factors();
        let (fixed, variable, accel) = match source {
            DataSource::Analysis => return analysis,
            DataSource::Test => (1.35, 2.5, 1.15),
            DataSource::AcceptanceExtremes => (1.25, 2.0, 1.10),
        };
        match self {
            Standard::None | Standard::AiaaS114 | Standard::EcssEST3301C => analysis,
            Standard::NasaStd5017 => Factors {
                inertia: accel,
                spring: fixed,
                friction: variable,
                hysteresis: variable,
                harness: variable,
                adhesion: variable,
                other: variable,
            },
        }
    }

    /// The default uncertainty factors: all 1 for `None`, otherwise the
    /// standard's row in [`deploywatch_core::monitor::standards`] (the one source,
    /// with the provenance of each value; `docs/margin.md` lists them).
    pub fn factors(self) -> Factors {
        match self {
            Standard::None => Factors::UNITY,
            Standard::NasaStd5017 => Factors {
                inertia: standards::NASA_STD_5017B_ACCELERATION,
                spring: standards::NASA_STD_5017B_FIXED,
                friction: standards::NASA_STD_5017B_VARIABLE,
                hysteresis: standards::NASA_STD_5017B_VARIABLE,
                harness: standards::NASA_STD_5017B_VARIABLE,
                adhesion: standards::NASA_STD_5017B_VARIABLE,
                other: standards::NASA_STD_5017B_VARIABLE,
            },
            Standard::EcssEST3301C => Factors {
                inertia: standards::ECSS_E_ST_33_01C_INERTIA,
                spring: standards::ECSS_E_ST_33_01C_SPRING,
                friction: standards::ECSS_E_ST_33_01C_FRICTION,
                hysteresis: standards::ECSS_E_ST_33_01C_HYSTERESIS,
                harness: standards::ECSS_E_ST_33_01C_HARNESS,
                adhesion: standards::ECSS_E_ST_33_01C_ADHESION,
                other: standards::ECSS_E_ST_33_01C_OTHER,
            },
            Standard::AiaaS114 => Factors {
                inertia: 1.25,
                spring: 2.0,
                friction: 2.0,
                hysteresis: 2.0,
                harness: 2.0,
                adhesion: 2.0,
                other: 2.0,
            },
        }
    }

    /// The required minimum margin of safety `MoS_required` \[1\] (0: the
    /// reserve lies in the factors). The same for every standard here.
    pub fn required_margin(self) -> f64 {
        0.0
    }
}

impl fmt::Display for Standard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Standard {
    type Err = NameError;
    fn from_str(s: &str) -> Result<Self, NameError> {
        let t = s.trim().to_ascii_lowercase().replace('_', "-");
        match t.as_str() {
            "none" => Ok(Standard::None),
            "nasa-std-5017" | "nasa-std-5017b" | "nasa" => Ok(Standard::NasaStd5017),
            "ecss-e-st-33-01c" | "ecss" => Ok(Standard::EcssEST3301C),
            "aiaa-s-114" | "aiaa" => Ok(Standard::AiaaS114),
            _ => Err(NameError::Standard {
                name: s.to_string(),
            }),
        }
    }
}

/// `(driving / resisting − 1) · 100` [%]: seed 001 Eq. 7 with torques, seed
/// 000 Eq. 21 with energies. `+∞` when `resisting = 0 < driving`.
pub fn margin_pct(driving: f64, resisting: f64) -> f64 {
    (ratio(driving, resisting) - 1.0) * 100.0
}

/// `driving / resisting`, with a zero resistance of either sign giving `+∞`
/// for a positive driving term (an empty `f64` sum is `−0.0`).
fn ratio(driving: f64, resisting: f64) -> f64 {
    if resisting == 0.0 && driving > 0.0 {
        f64::INFINITY
    } else {
        driving / resisting
    }
}

/// The kind a physical latch's engagement counts as: the standards'
/// "variable" (NASA-STD-5017B) / "other forces" (ECSS-E-ST-33-01C) factor,
/// 3 by default (`docs/margin.md`, "The latch's engagement").
pub const LATCH_KIND: Resistance = Resistance::Other;

/// A physical latch's engagement as a resistance (`physics.md` §10.3): zero
/// for the ideal latch.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct LatchResistance {
    /// The entry torque `(P0 + k_p h) r_p tan α_e` [N·m]: the torque form's
    /// resistance.
    pub entry_torque_nm: f64,
    /// The engagement energy `P0 h + ½ k_p h²` \[J\]: the energy form's.
    pub engagement_energy_j: f64,
    /// Where the entry ramp starts, the crest's travel from the stop \[rad\].
    pub entry_from_rad: f64,
    /// Where it ends, crest plus the ramp's width \[rad\].
    pub entry_to_rad: f64,
}

/// Both margins of one spring-driven joint against a constant friction
/// and, with a physical latch, its engagement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointMargin {
    /// The stroke `|φ_stowed|` \[rad\].
    pub stroke_rad: f64,
    /// `T_D`: the spring torque at the stowed angle, unfolding branch [N·m].
    pub driving_torque_nm: f64,
    /// `T_R`: the friction (EFT) [N·m].
    pub resisting_torque_nm: f64,
    /// `E_D = ∫_0^stroke T dθ` on the unfolding branch \[J\].
    pub driving_energy_j: f64,
    /// `E_R = T_R · stroke` \[J\].
    pub resisting_energy_j: f64,
    /// The factors applied to the friction.
    pub friction_factor: f64,
    /// The physical latch's engagement (zero for the ideal latch).
    pub latch: LatchResistance,
    /// The factor applied to it (that of [`LATCH_KIND`]).
    pub latch_factor: f64,
    /// Required minimum margin [%] (`MoS_required · 100`).
    pub required_pct: f64,
    /// Resistances of a diagnosis besides the friction and the latch
    /// ([`crate::analysis::effect_margin`]), summed per kind and already
    /// multiplied by their kind's factor: torque [N·m], energy \[J\].
    pub factored_extra: FactoredExtra,
}

/// The factored sum `Σ_i FoS_i · R_i` of extra resistances, both forms.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct FactoredExtra {
    /// In the torque form [N·m].
    pub torque_nm: f64,
    /// In the energy form \[J\].
    pub energy_j: f64,
}

impl JointMargin {
    /// The same margins with a physical latch's engagement.
    pub fn with_latch(mut self, latch: LatchResistance) -> Self {
        self.latch = latch;
        self
    }

    /// Adds a resistance of `kind`, `torque_nm` in the torque form and
    /// `energy_j` in the energy form, each multiplied by `factors`' factor
    /// of its kind.
    pub fn add_resistance(
        &mut self,
        kind: Resistance,
        torque_nm: f64,
        energy_j: f64,
        factors: &Factors,
    ) {
        let f = factors.get(kind);
        self.factored_extra.torque_nm += f * torque_nm;
        self.factored_extra.energy_j += f * energy_j;
    }

    /// Scales the driving spring by `scale` (a softened spring, `1 − s`):
    /// both `T_D` and `E_D`.
    pub fn scale_driving(&mut self, scale: f64) {
        self.driving_torque_nm *= scale;
        self.driving_energy_j *= scale;
    }

    /// The torque-form margin with the factors,
    /// `(T_D / (FoS_f · T_R + FoS_l · T_e) − 1) · 100` [%] (seed 001 Eq. 7
    /// when the factors are 1 and the latch ideal, `T_e = 0`).
    pub fn torque_margin_pct(&self) -> f64 {
        margin_pct(self.driving_torque_nm, self.factored_resisting_torque_nm())
    }

    /// The torque-form denominator, every resistance factored,
    /// `FoS_f · T_R + FoS_l · T_e + Σ FoS_i · T_i` [N·m].
    pub fn factored_resisting_torque_nm(&self) -> f64 {
        self.friction_factor * self.resisting_torque_nm
            + self.latch_factor * self.latch.entry_torque_nm
            + self.factored_extra.torque_nm
    }

    /// The energy-form denominator, every resistance factored,
    /// `FoS_f · E_R + FoS_l · E_eng + Σ FoS_i · E_i` \[J\].
    pub fn factored_resisting_energy_j(&self) -> f64 {
        self.friction_factor * self.resisting_energy_j
            + self.latch_factor * self.latch.engagement_energy_j
            + self.factored_extra.energy_j
    }

    /// The energy-form margin with the factors,
    /// `(E_D / (FoS_f · E_R + FoS_l · E_eng) − 1) · 100` [%] (seed 000
    /// Eq. 21 when the factors are 1 and the latch ideal, `E_eng = 0`).
    pub fn energy_margin_pct(&self) -> f64 {
        margin_pct(self.driving_energy_j, self.factored_resisting_energy_j())
    }

    /// The kinetic energy the joint has left at the latch in the worst
    /// case, `E_D − (FoS_f · E_R + Σ FoS_i · E_i)` \[J\]: the driving
    /// release less the factored resisting work, the latch's not included.
    pub fn arriving_energy_j(&self) -> f64 {
        self.driving_energy_j
            - self.friction_factor * self.resisting_energy_j
            - self.factored_extra.energy_j
    }

    /// The latching margin at the end of the stroke,
    /// `(E_arrive / (FoS_l · E_eng) − 1) · 100` [%]
    /// (an energy balance, this project's form, not a standard's clause:
    /// energy passed between the joints of a chain is not counted); `None`
    /// for the ideal latch (nothing to engage).
    pub fn latching_margin_pct(&self) -> Option<f64> {
        (self.latch.engagement_energy_j > 0.0).then(|| {
            margin_pct(
                self.arriving_energy_j(),
                self.latch_factor * self.latch.engagement_energy_j,
            )
        })
    }

    /// True when the latching margin is at least the required minimum (or
    /// the latch is ideal).
    pub fn latching_pass(&self) -> bool {
        self.latching_margin_pct()
            .is_none_or(|m| m >= self.required_pct)
    }

    /// True when the torque-form margin is at least the required minimum.
    pub fn torque_pass(&self) -> bool {
        self.torque_margin_pct() >= self.required_pct
    }

    /// True when the energy-form margin is at least the required minimum.
    pub fn energy_pass(&self) -> bool {
        self.energy_margin_pct() >= self.required_pct
    }
}

/// The margins of a joint driven by `spring` from `|φ| = stroke_rad` to the
/// latch against a constant friction torque `friction_nm` (its only
/// resistance, kind [`Resistance::Friction`]), with `standard`'s friction
/// factor (or `factors` if given) and required minimum.
///
/// `T_D = spring.magnitude(stroke, Unfold)`, `E_D = spring.release(0, stroke)`.
pub fn joint_margin(
    spring: &Spring<f64>,
    stroke_rad: f64,
    friction_nm: f64,
    standard: Standard,
    factors: Option<&Factors>,
) -> JointMargin {
    let stroke = stroke_rad.abs();
    let f = factors.copied().unwrap_or_else(|| standard.factors());
    JointMargin {
        stroke_rad: stroke,
        driving_torque_nm: spring.magnitude(stroke, Branch::Unfold),
        resisting_torque_nm: friction_nm,
        driving_energy_j: spring.release(0.0, stroke),
        resisting_energy_j: friction_nm * stroke,
        friction_factor: f.get(Resistance::Friction),
        latch: LatchResistance::default(),
        latch_factor: f.get(LATCH_KIND),
        required_pct: standard.required_margin() * 100.0,
        factored_extra: FactoredExtra::default(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::{FRAC_PI_2, PI};

    #[test]
    fn margin_formula() {
        assert!((margin_pct(3.0, 1.5) - 100.0).abs() < 1e-12);
        assert!((margin_pct(1.0, 2.0) + 50.0).abs() < 1e-12);
        assert_eq!(margin_pct(1.0, 0.0), f64::INFINITY);
    }

    #[test]
    fn standards_parse_and_have_documented_defaults() {
        for s in Standard::ALL {
            assert_eq!(s.name().parse::<Standard>().unwrap(), s);
            assert_eq!(s.required_margin(), 0.0);
            assert!(!s.reference().is_empty());
        }
        assert!("iso".parse::<Standard>().is_err());
        assert_eq!(Standard::None.factors(), Factors::UNITY);
        assert_eq!(Standard::NasaStd5017.factors().friction, 3.0);
        assert_eq!(Standard::NasaStd5017.factors().spring, 1.5);
        assert_eq!(Standard::NasaStd5017.factors().inertia, 1.25);
        assert_eq!(Standard::EcssEST3301C.factors().friction, 3.0);
        assert_eq!(Standard::EcssEST3301C.factors().inertia, 1.1);
        assert_eq!(Standard::EcssEST3301C.factors().spring, 1.2);
        for r in Resistance::ALL {
            assert_eq!(r.name().parse::<Resistance>().unwrap(), r);
            let mut f = Factors::UNITY;
            f.set(r, 7.0);
            assert_eq!(f.get(r), 7.0);
        }
        assert!("glue".parse::<Resistance>().is_err());
    }

    /// The on-board margin's presets factor each energy as this margin
    /// factors its kind: one rule per standard, on the ground and on board.
    #[test]
    fn the_monitor_presets_take_the_factors_of_the_ground_margin() {
        use deploywatch_core::monitor::UncertaintyFactors as U;
        for (preset, s) in [
            (U::NASA_STD_5017, Standard::NasaStd5017),
            (U::ECSS_E_ST_33_01C, Standard::EcssEST3301C),
        ] {
            let f = s.factors();
            assert_eq!(preset.spring, 1.0, "{s}: the driving spring unfactored");
            assert_eq!(preset.kinetic, f.inertia as f32, "{s}");
            assert_eq!(preset.coulomb, f.friction as f32, "{s}");
            assert_eq!(preset.viscous, f.friction as f32, "{s}");
            assert_eq!(preset.latch, f.other as f32, "{s}");
        }
    }

    #[test]
    fn the_data_source_selects_the_row_and_every_standard_says_its_source() {
        let n = Standard::NasaStd5017;
        assert_eq!(n.factors_for(DataSource::Analysis), n.factors());
        let t = n.factors_for(DataSource::Test);
        assert_eq!((t.spring, t.friction, t.inertia), (1.35, 2.5, 1.15));
        let x = n.factors_for(DataSource::AcceptanceExtremes);
        assert_eq!((x.spring, x.harness, x.inertia), (1.25, 2.0, 1.10));
        let a = Standard::AiaaS114;
        assert_eq!("aiaa".parse::<Standard>().unwrap(), a);
        for s in [a, Standard::EcssEST3301C, Standard::None] {
            for d in DataSource::ALL {
                assert_eq!(s.factors_for(d), s.factors(), "{s} {}", d.name());
                assert_eq!(s.reference_for(d), s.reference());
            }
            assert!(!s.has_rows());
        }
        for d in DataSource::ALL {
            assert!(n.reference_for(d).ends_with(&format!("(row: {})", d.row())));
        }
        assert_eq!((a.factors().friction, a.factors().inertia), (2.0, 1.25));
        for s in Standard::ALL {
            let c = s.confirmation();
            assert!(
                s == Standard::None || c.contains("not confirmed"),
                "{s}: {c}"
            );
        }
    }

    #[test]
    fn joint_margin_of_a_linear_spring() {
        // Seed 000 joint O: 2.17 N·m at 90°, E_D = 2.818 J, EFT 0.54 N·m.
        let s = Spring::Linear {
            preload_nm: 1.41799,
            stiffness_nm_per_rad: 0.478740,
            count: 1.0,
        };
        let m = joint_margin(&s, -FRAC_PI_2, 0.54, Standard::None, None);
        assert!((m.driving_torque_nm - 2.17).abs() < 1e-4);
        assert!((m.driving_energy_j - 2.818).abs() < 1e-3);
        assert!((m.resisting_energy_j - 0.54 * FRAC_PI_2).abs() < 1e-12);
        assert!((m.torque_margin_pct() - (2.17 / 0.54 - 1.0) * 100.0).abs() < 0.1);
        assert!(m.torque_pass() && m.energy_pass());
        // With ECSS factor 3 on friction the torque form still passes
        // (2.17 / 1.62 − 1 = 34 %), and a weaker spring fails.
        let e = joint_margin(&s, FRAC_PI_2, 0.54, Standard::EcssEST3301C, None);
        assert!((e.torque_margin_pct() - (2.17 / 1.62 - 1.0) * 100.0).abs() < 0.1);
        assert!(e.torque_pass());
        let weak = joint_margin(&s, FRAC_PI_2, 0.8, Standard::EcssEST3301C, None);
        assert!(!weak.torque_pass() && !weak.energy_pass());
        // Explicit factors override the standard's.
        let mut f = Factors::UNITY;
        f.friction = 2.0;
        let o = joint_margin(&s, PI / 2.0, 0.54, Standard::EcssEST3301C, Some(&f));
        assert_eq!(o.friction_factor, 2.0);
    }
}
