//! The diagnosis JSON (`deploywatch diagnose --json`, `docs/spec/formats.md`
//! "Diagnosis: JSON", with the project's fields of "Findings JSON"): written
//! by `cli::diagnose`, read by `margin --from`. Only `effects` (and each
//! effect's `name`) is required on reading; numbers are rounded to 6
//! decimals ([`super::numbers::rounded`]) and `null` where not finite.

use serde::de::{MapAccess, Visitor};
use serde::ser::SerializeMap;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// A diagnosis.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Diagnosis {
    /// The first run's mechanism (`formats.md`).
    #[serde(default)]
    pub mechanism: String,
    /// Every mechanism of the campaign, in run order, without repeats.
    #[serde(default)]
    pub mechanisms: Vec<String>,
    /// The runs' file names.
    #[serde(default)]
    pub runs: Vec<String>,
    /// The noise floor: standard deviation of the angle noise \[deg\].
    #[serde(default)]
    pub noise_sigma_deg: Option<f64>,
    /// The mechanisms as given.
    #[serde(default)]
    pub baseline: Fit,
    /// The causes found, strongest first.
    pub effects: Vec<FoundEffect>,
    /// The mechanisms with the effects added and fitted.
    #[serde(default)]
    pub extended: Fit,
    /// What the effects gain.
    #[serde(default)]
    pub gain: Gain,
    /// Every round of the search with its candidates' scores.
    #[serde(default)]
    pub candidates: Vec<Round>,
    /// What the residuals of the baseline show, per run and joint.
    #[serde(default)]
    pub evidence: Vec<Evidence>,
    /// Campaign simulations the diagnosis took.
    #[serde(default)]
    pub simulations: usize,
    /// Its wall-clock time \[s\].
    #[serde(default)]
    pub wall_s: Option<f64>,
    /// The joint torque the baseline and the extended model lack, estimated
    /// from the runs (`docs/diagnosis.md`, "The residual torque from the
    /// data").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub residual_torque: Option<ResidualTorque>,
    /// Why the search stopped before its end (a time limit, Ctrl-C): the
    /// effects are then the best found so far. Absent for a search that
    /// ran to its end.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub partial: Option<String>,
    /// The encoders' delay behind their latch switches, when the ideal
    /// latches' closings name one (`docs/diagnosis.md`, "An encoder late on
    /// its switch"): a discrepancy, not an effect.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub encoder_delay: Option<EncoderDelayJson>,
    /// Flexible panels, when the set found left the runs clearly above the
    /// noise and the wing with its first mode fitted took much of that out
    /// (`docs/diagnosis.md`, "Flexible panels"): a discrepancy, not an
    /// effect; the effects and every fit figure are of the flexible wing.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flexible_panels: Option<FlexiblePanelsJson>,
    /// Runs of a physical latch: the free motion of each run, up to the
    /// first instant a joint enters its latch's reach; the effects were
    /// fitted on it unless `fitted_whole`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub free_window: Vec<FreeWindow>,
    /// Runs of a physical latch fitted whole: the model found closes each
    /// latch switch as often as every run does, so the effects and every
    /// fit figure are of the whole runs (`docs/diagnosis.md`, "Runs of a
    /// physical latch", 5).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub fitted_whole: bool,
    /// Runs of a physical latch fitted up to where the model found follows
    /// each run's latch history (`docs/diagnosis.md`, "Runs of a physical
    /// latch", 6): each run's window, longer than its free motion; the
    /// effects and every fit figure are of these windows. Empty otherwise.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub fitted_window: Vec<FreeWindow>,
    /// Runs of a physical latch: the model found over the whole runs, the
    /// motion after each free window shot from the measured state
    /// (`docs/diagnosis.md`, "The whole run").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub whole_run: Option<WholeRunJson>,
    /// Each physical latch's events against its drawing's.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub latches: Vec<LatchReport>,
    /// Sets of causes that explain the runs alike.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub ambiguities: Vec<AmbiguityGroup>,
    /// Claims the runs cannot tell from the discrepancy the set found
    /// leaves above the noise, set aside (`docs/diagnosis.md`, "Claims
    /// within the discrepancy"): not effects, not read by `margin --from`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub set_aside: Vec<SetAsideJson>,
    /// Encoder readings off their panels within the joints'
    /// declared free-play (`docs/diagnosis.md`, "Free-play held to one
    /// side"): a discrepancy, not an effect; the angles were compared with
    /// each taken out.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub free_play: Vec<FreePlayJson>,
    /// What the drawing's declared tolerances (panels' mass and inertia,
    /// springs' torque) add to each effect's interval (`docs/diagnosis.md`,
    /// "What the drawing's tolerances add"): the `ci95` of `effects`
    /// include it. Read from `mass_tolerance` too, its earlier name.
    #[serde(
        default,
        alias = "mass_tolerance",
        skip_serializing_if = "Vec::is_empty"
    )]
    pub tolerance: Vec<ToleranceJson>,
    /// Named effects the drawing's declared tolerances alone
    /// could make, taken out of the set found (`docs/diagnosis.md`, "What
    /// the drawing's tolerances add"): not effects, not read by `margin
    /// --from`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub within_tolerance: Vec<WithinToleranceJson>,
}

/// A named effect the panels' declared tolerances alone could make.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WithinToleranceJson {
    /// Its name (`physics.md` section 6).
    pub name: String,
    /// 1-based joint, `null` for a global effect.
    pub joint: Option<usize>,
    /// Its value as fitted, in `unit`.
    pub value: Option<f64>,
    /// The unit of `value`.
    pub unit: String,
    /// What the tolerances alone move each of its parameters by, at 95 %.
    pub tolerance95: Vec<Option<f64>>,
    /// The tolerance that moves it most, in words.
    pub largest: String,
    /// The effect that took its place in the set found, in words
    /// (`coulomb_friction at joint 4`), when one did: a Stribeck friction
    /// gives way to Coulomb friction at its kinetic level.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub in_its_place: Option<String>,
}

/// What the panels' declared mass-property tolerances add to one effect's
/// interval.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ToleranceJson {
    /// The effect, in words (`viscous_damping at joint 3`).
    pub effect: String,
    /// The standard uncertainty of each of its parameters from the
    /// tolerances, in the parameter's unit.
    pub sd: Vec<Option<f64>>,
    /// The tolerance that moves it most (`panel 2's inertia (±1 %) of
    /// seed001-T01`).
    pub largest: String,
}

/// An encoder reading off its panel within the hinge's declared
/// free-play.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FreePlayJson {
    /// 1-based joint.
    pub joint: usize,
    /// The reading's offset from the panel's angle \[deg\] (reading =
    /// angle + offset), written in full.
    pub offset_deg: Option<f64>,
    /// Its 95 % interval \[deg\].
    pub ci95: [Option<f64>; 2],
    /// The free-play the mechanisms declare at the joint (the least of
    /// them), a half band \[deg\].
    pub play_deg: Option<f64>,
}

/// A claim set aside within the discrepancy.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SetAsideJson {
    /// Its name (`physics.md` section 6).
    pub name: String,
    /// 1-based joint, `null` for a global effect.
    pub joint: Option<usize>,
    /// Its value as fitted, in `unit`.
    pub value: Option<f64>,
    /// The unit of `value`.
    pub unit: String,
    /// 95 % interval of `value` as fitted.
    pub ci95: [Option<f64>; 2],
    /// The named effects put in its place, in words (`coulomb_friction at
    /// joint 2`); empty when it was dropped.
    #[serde(default)]
    pub replaced_by: Vec<String>,
    /// What it accounted for: the RMS of the SSE its loss added \[deg\].
    pub explained_deg: Option<f64>,
    /// The residual its set left above the noise, as RMS \[deg\].
    pub discrepancy_deg: Option<f64>,
}

/// Flexible panels named by a diagnosis (`physics.md` §12).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FlexiblePanelsJson {
    /// The deployed wing's first mode, every hinge latched \[Hz\].
    pub first_mode_hz: Option<f64>,
    /// That mode's damping ratio \[1\].
    pub damping_ratio: Option<f64>,
    /// RMS \[deg\] of the rigid wing's set found.
    pub rigid_rms_deg: Option<f64>,
    /// RMS \[deg\] of that set refitted on the flexible wing.
    pub flexible_rms_deg: Option<f64>,
}

/// The encoders' delay behind their latch switches.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct EncoderDelayJson {
    /// The delay \[s\] (negative: the switches are late on the encoders).
    pub delay_s: Option<f64>,
    /// The delays every agreeing latching allows: lower end \[s\].
    pub lo_s: Option<f64>,
    /// Upper end \[s\].
    pub hi_s: Option<f64>,
    /// The runs' sample period \[s\].
    pub period_s: Option<f64>,
    /// True when the angles were compared at their stamps minus the delay.
    pub taken_out: bool,
    /// The latchings that agree.
    pub agreeing: usize,
    /// Every latching read.
    pub latchings: Vec<LatchingJson>,
}

/// One ideal latch closing, as the encoder and the switch saw it.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct LatchingJson {
    /// The run's file name.
    pub run: String,
    /// 1-based joint.
    pub joint: usize,
    /// Where the encoder's approach crosses its latched level \[s\].
    pub crossing_s: Option<f64>,
    /// The same extrapolation's least and greatest error on the model's
    /// own run, over the phases of the sample clock \[s\]: the delay the
    /// latching allows is widened by it (`None`: the model does not latch
    /// there).
    #[serde(default)]
    pub model_error_s: Option<[f64; 2]>,
    /// The last sample with the switch open \[s\].
    pub open_s: Option<f64>,
    /// The first sample with the switch closed \[s\].
    pub closed_s: Option<f64>,
    /// The approach rate \[deg/s\].
    pub rate_deg_s: Option<f64>,
}

/// The whole-run check of runs of a physical latch.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WholeRunJson {
    /// Stretches after the free windows simulated from the measured state.
    pub shots: usize,
    /// Seconds of the runs they cover \[s\].
    pub shot_s: Option<f64>,
    /// Each joint's residual over the free windows and over the shots.
    pub joints: Vec<WholeRunJoint>,
}

/// One joint's fit over the whole runs.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WholeRunJoint {
    /// 1-based joint.
    pub joint: usize,
    /// Residual RMS over the free windows \[deg\].
    pub free_rms_deg: Option<f64>,
    /// Residual RMS over the shots where it swings clear of its latch
    /// \[deg\] (`null`: too few samples to judge).
    pub after_rms_deg: Option<f64>,
    /// Samples behind `after_rms_deg`.
    pub after_samples: usize,
}

/// The free motion of one run of a physical latch.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FreeWindow {
    /// The run's file name.
    pub run: String,
    /// Samples fitted (from the release).
    pub samples: usize,
    /// Samples in the run.
    pub of: usize,
    /// End of the window \[s\] (`null`: the whole run).
    #[serde(default)]
    pub end_s: Option<f64>,
    /// The joint whose latch ends it.
    #[serde(default)]
    pub joint: Option<usize>,
}

/// One joint's latch events in one run.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct LatchEventsJson {
    /// First impact \[s\].
    #[serde(default)]
    pub first_contact_s: Option<f64>,
    /// Impacts (switch closings).
    pub impacts: usize,
    /// Escapes back over the crest.
    pub escapes: usize,
    /// Largest rebound that stayed inside the crest \[deg\].
    #[serde(default)]
    pub largest_rebound_deg: Option<f64>,
    /// Held from \[s\] (`null`: not held at the end).
    #[serde(default)]
    pub hold_s: Option<f64>,
    /// Travel from the stop at the end \[deg\].
    #[serde(default)]
    pub end_travel_deg: Option<f64>,
}

/// A physical latch as built against its drawing.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct LatchReport {
    /// Joint, from 1.
    pub joint: usize,
    /// Measured events, run by run.
    pub measured: Vec<LatchEventsJson>,
    /// The drawing's latch with the effects found, run by run.
    pub drawing: Vec<Option<LatchEventsJson>>,
    /// What the drawing gives within its tolerances: `[least, most]` of
    /// impacts, escapes, runs ending within the crest, restitution.
    pub drawing_spread: serde_json::Value,
    /// Measured apparent restitution: median and 95 % interval.
    #[serde(default)]
    pub restitution: Option<[Option<f64>; 3]>,
    /// Measured deceleration of the rebounds that stayed in [deg/s²]:
    /// median and 95 % interval (`null` with fewer than 3 rebounds of 5
    /// samples or more).
    #[serde(default)]
    pub hold_deceleration_deg_s2: Option<[Option<f64>; 3]>,
    /// What differs from the drawing (empty: nothing its tolerances do not give).
    pub differs: Vec<String>,
    /// Statistics outside the drawing's spread but within a reading's
    /// margin of it: the runs cannot tell (left out when none).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub undecided: Vec<String>,
    /// What that says of the latch as built.
    #[serde(default)]
    pub cause: Option<String>,
    /// Plunger weakenings consistent with the measured events `[least, most]`.
    #[serde(default)]
    pub plunger_weakening: Option<[Option<f64>; 2]>,
}

/// Sets of causes that explain the runs alike.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AmbiguityGroup {
    /// The joint whose named effects the sets exchange.
    pub joint: usize,
    /// The set found first, then the alternatives.
    pub sets: Vec<AmbiguousSet>,
    /// The test that would separate them.
    pub separating_test: String,
}

/// One set of an ambiguity group with its fit.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AmbiguousSet {
    /// Its effects (`name`, `joint`, `value`, `ci95`).
    pub effects: Vec<serde_json::Value>,
    /// RMS of its fit \[deg\].
    #[serde(default)]
    pub rms_deg: Option<f64>,
    /// Its BIC minus the set found's.
    #[serde(default)]
    pub delta_bic: Option<f64>,
}

/// The residual torque against the baseline and against the extended model.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ResidualTorque {
    /// Against the mechanisms as given, one entry per joint.
    pub baseline: Vec<JointResidualTorque>,
    /// Against the mechanisms with the effects found, one entry per joint.
    pub extended: Vec<JointResidualTorque>,
}

/// One joint's residual torque, summarised and binned.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct JointResidualTorque {
    /// Joint, from 1.
    pub joint: usize,
    /// Significant against its own band (`χ²` of the bin means and one bin
    /// beyond 3 standard errors).
    pub significant: bool,
    /// `χ²` of the angle bins' means against zero.
    #[serde(default)]
    pub chi2: Option<f64>,
    /// Largest `|mean| / se` of one bin.
    #[serde(default)]
    pub max_bin_z: Option<f64>,
    /// RMS of the residual torque samples [N·m].
    #[serde(default)]
    pub rms_nm: Option<f64>,
    /// Samples used.
    #[serde(default)]
    pub samples: usize,
    /// One sentence: where in the stroke, at which rates, resisting or driving.
    #[serde(default)]
    pub description: String,
    /// Bins over the angle \[deg\].
    #[serde(default)]
    pub by_angle_deg: Vec<TorqueBin>,
    /// Bins over the rate [deg/s].
    #[serde(default)]
    pub by_rate_deg_s: Vec<TorqueBin>,
}

/// One bin of the residual torque.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TorqueBin {
    /// Lower edge (deg or deg/s).
    #[serde(default)]
    pub from: Option<f64>,
    /// Upper edge (deg or deg/s).
    #[serde(default)]
    pub to: Option<f64>,
    /// Samples in the bin.
    pub n: usize,
    /// Mean residual torque [N·m].
    #[serde(default)]
    pub mean_nm: Option<f64>,
    /// Standard error of the mean [N·m].
    #[serde(default)]
    pub se_nm: Option<f64>,
}

impl Diagnosis {
    /// The mechanisms it was found on: `mechanisms`, or `mechanism` in a
    /// file that gives only that (none if neither).
    pub fn found_on(&self) -> Vec<String> {
        if self.mechanisms.is_empty() && !self.mechanism.is_empty() {
            vec![self.mechanism.clone()]
        } else {
            self.mechanisms.clone()
        }
    }
}

/// How well a model reproduces the runs.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Fit {
    /// RMS of model minus measurement over all runs \[deg\].
    #[serde(default)]
    pub rms_deg: Option<f64>,
    /// Trajectory error of each joint, mean over the runs [%].
    #[serde(default)]
    pub trajectory_error_pct: Vec<Option<f64>>,
}

/// What the extended model gains on the baseline.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Gain {
    /// Baseline RMS over extended RMS.
    #[serde(default)]
    pub rms_ratio: Option<f64>,
    /// The extended model's RMS on runs it was not fitted on \[deg\] (`null`
    /// with one run).
    #[serde(default)]
    pub held_out_rms_deg: Option<f64>,
}

/// One effect found (or `"unexplained"`, with its description).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FoundEffect {
    /// Its name (`physics.md` section 6), or `"unexplained"`.
    pub name: String,
    /// 1-based joint, `null` for a global effect.
    #[serde(default)]
    pub joint: Option<usize>,
    /// Its value in `unit` (a table's largest absolute torque).
    #[serde(default)]
    pub value: Option<f64>,
    /// The unit of `value`.
    #[serde(default)]
    pub unit: Option<String>,
    /// 95 % interval of `value`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ci95: Option<[Option<f64>; 2]>,
    /// What the residual none of the effects explains looks like.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// Why it was chosen, in words.
    #[serde(default)]
    pub evidence: String,
    /// A `torque_table`'s angle knots \[deg\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angle_deg: Option<Vec<Option<f64>>>,
    /// Its torque at each angle knot [N·m].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub torque_nm: Option<Vec<Option<f64>>>,
    /// The 95 % band of each angle knot's torque: lower, upper [N·m].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub torque_ci95_nm: Option<[Vec<Option<f64>>; 2]>,
    /// A `torque_table`'s rate knots [deg/s].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rate_deg_s: Option<Vec<Option<f64>>>,
    /// Its torque at each rate knot [N·m].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rate_torque_nm: Option<Vec<Option<f64>>>,
    /// The 95 % band of each rate knot's torque: lower, upper [N·m].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rate_torque_ci95_nm: Option<[Vec<Option<f64>>; 2]>,
    /// A `torque_table`'s shape in one sentence.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shape: Option<String>,
    /// A `torque_table`'s export for the on-board monitor: at most the
    /// monitor's 8 points per table, with the fit loss of the compression.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub monitor_table: Option<MonitorTable>,
    /// `rig_tilt`'s direction α \[deg\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha_deg: Option<f64>,
    /// Its 95 % interval \[deg\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha_ci95_deg: Option<[Option<f64>; 2]>,
    /// `stribeck_friction`'s break-away excess `T_brk − T_C` [N·m]
    /// (`physics.md` §4).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub excess_nm: Option<f64>,
    /// `stribeck_friction`'s Stribeck velocity `ω_st` \[rad/s\]
    /// (`physics.md` §4).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stribeck_rad_s: Option<f64>,
    /// The 95 % interval of `excess_nm` [N·m].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub excess_ci95_nm: Option<[Option<f64>; 2]>,
    /// The 95 % interval of `stribeck_rad_s` \[rad/s\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stribeck_ci95_rad_s: Option<[Option<f64>; 2]>,
}

/// A discovered table as the on-board monitor holds it (at most
/// `deploywatch_core::physics::TABLE_MAX_KNOTS` points per table) and
/// what compressing the host's table to it cost.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct MonitorTable {
    /// Angle knots \[deg\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angle_deg: Option<Vec<Option<f64>>>,
    /// The torque at each angle knot [N·m].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub torque_nm: Option<Vec<Option<f64>>>,
    /// Rate knots [deg/s].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rate_deg_s: Option<Vec<Option<f64>>>,
    /// The torque at each rate knot [N·m].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rate_torque_nm: Option<Vec<Option<f64>>>,
    /// True when the host's table had more points and was compressed.
    #[serde(default)]
    pub compressed: bool,
    /// RMS of the host's minus the exported torque over the stroke and
    /// rates the runs cover [N·m].
    #[serde(default)]
    pub torque_rms_diff_nm: Option<f64>,
    /// Largest absolute difference of the two torques there [N·m].
    #[serde(default)]
    pub torque_max_diff_nm: Option<f64>,
    /// RMS difference of the angles re-simulated on the campaign's runs
    /// with the host's and with the exported table \[deg\].
    #[serde(default)]
    pub angle_rms_diff_deg: Option<f64>,
}

/// One round of the search.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Round {
    /// What the round tried, in words.
    #[serde(default)]
    pub round: String,
    /// The RMS it started from \[deg\].
    #[serde(default)]
    pub start_rms_deg: Option<f64>,
    /// Each candidate's score.
    #[serde(default)]
    pub scores: Vec<Score>,
}

/// One candidate of a round.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Score {
    /// The candidate, e.g. `coulomb_friction at joint 2`.
    #[serde(default)]
    pub candidate: String,
    /// RMS with it fitted \[deg\].
    #[serde(default)]
    pub rms_deg: Option<f64>,
    /// Its BIC gain.
    #[serde(default)]
    pub delta_bic: Option<f64>,
    /// Its RMS on runs it was not fitted on \[deg\].
    #[serde(default)]
    pub held_out_rms_deg: Option<f64>,
    /// What became of it, in words: the search's typed verdict said by
    /// the report, its numbers in it (`"dBIC 436.5, not the best"`); for
    /// people, no reader acts on it (`docs/spec/formats.md`).
    #[serde(default)]
    pub verdict: String,
}

/// What one joint's baseline residual shows on one run.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Evidence {
    /// The run's file name.
    #[serde(default)]
    pub run: String,
    /// 1-based joint.
    #[serde(default)]
    pub joint: usize,
    /// RMS of the residual \[deg\].
    #[serde(default)]
    pub rms_deg: Option<f64>,
    /// RMS over each third of the stroke \[deg\].
    #[serde(default)]
    pub stroke_thirds_rms_deg: Vec<Option<f64>>,
    /// RMS near the latch \[deg\].
    #[serde(default)]
    pub near_latch_rms_deg: Option<f64>,
    /// Mean residual at release \[deg\].
    #[serde(default)]
    pub at_release_mean_deg: Option<f64>,
    /// Mean residual after the latch \[deg\].
    #[serde(default)]
    pub after_latch_mean_deg: Option<f64>,
    /// How much earlier the model latches than the run \[s\].
    #[serde(default)]
    pub latch_lead_s: Option<f64>,
    /// Correlation of the residual with each quantity, by name.
    #[serde(default)]
    pub correlation: Named,
    /// All of it in one sentence.
    #[serde(default)]
    pub summary: String,
}

/// Numbers by name, in order: a JSON object whose key order is kept.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Named(pub Vec<(String, Option<f64>)>);

impl Serialize for Named {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(self.0.len()))?;
        for (k, v) in &self.0 {
            m.serialize_entry(k, v)?;
        }
        m.end()
    }
}

impl<'de> Deserialize<'de> for Named {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Named;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("an object of numbers")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut a: A) -> Result<Named, A::Error> {
                let mut out = Vec::new();
                while let Some(entry) = a.next_entry::<String, Option<f64>>()? {
                    out.push(entry);
                }
                Ok(Named(out))
            }
        }
        d.deserialize_map(V)
    }
}
