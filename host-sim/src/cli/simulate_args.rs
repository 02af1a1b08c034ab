//! The arguments of `deploywatch simulate` and the run its sensors record,
//! shared by the chain (`cli::simulate`) and the truss wing
//! (`cli::simulate_truss`).

use crate::data::run::Run;
use crate::model::effect::{self, Effect, EffectKind};
use crate::model::mechanism::Mechanism;
use crate::simulate::deployment;
use crate::simulate::fault_injection::SensorFault;
use crate::simulate::sensor::{self, SensorModel};
use std::path::PathBuf;

/// Arguments of `deploywatch simulate`.
#[derive(Clone, Debug, clap::Args)]
pub struct SimulateArgs {
    /// The mechanism (TOML, see docs/spec/formats.md).
    pub mechanism: PathBuf,
    /// Where to write the run (CSV).
    #[arg(long, short)]
    pub out: PathBuf,
    /// An extra effect, `NAME[:joint=J]:value=V[:alpha_deg=A]`, repeatable
    /// (the help lists every NAME with the unit of V: [`effect_help`]).
    #[arg(long = "effect", value_name = "EFFECT", help = effect_help())]
    pub effects: Vec<Effect>,
    /// A sensor fault, `KIND:key=value:...`, repeatable (docs/robustness.md),
    /// e.g. `dropout:joint=1:start=0.5:duration=0.1:mode=stale`. Drawn from
    /// `--seed`. With a fault the run goes on to the mechanism's
    /// `duration_s`, so that what the sensors do after the latch is recorded.
    #[arg(long = "fault", value_name = "FAULT")]
    pub faults: Vec<SensorFault>,
    /// Seed of the sensor noise (the same seed gives the same file).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Write the true angles: no noise, no quantisation.
    #[arg(long)]
    pub no_noise: bool,
    /// Sample rate in Hz; the mechanism's `[run] sample_hz` by default.
    #[arg(long)]
    pub rate: Option<f64>,
    /// Also draw the joint angles and latch events into this PNG.
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// No chatter: the summary of the run is printed, errors and warnings
    /// too, nothing else; the run (and the plot) are written as usual.
    #[arg(long, short)]
    pub quiet: bool,
    /// Simulate the flight unit: the mechanism's `[rig]` taken out (only
    /// what flies; `docs/simulator.md`, "Rig").
    #[arg(long)]
    pub flight: bool,
    /// Add the model a diagnosis (or an identification) found: the effects
    /// of `deploywatch diagnose --json` (or `identify --json`), read from
    /// the file alone, added to the `--effect`s.
    #[arg(long, value_name = "FINDINGS.json")]
    pub from: Option<PathBuf>,
    /// Simulate as the diagnosis does, at this run's own time stamps (with
    /// the fit's integration settings, over the free motion it fitted when
    /// `--from` gives one), write the model's angles (no noise) and print
    /// its RMS against the run.
    #[arg(long, value_name = "RUN.csv", conflicts_with_all = ["faults", "rate", "plot"])]
    pub at: Option<PathBuf>,
}

/// The help of `--effect`, generated from the effect table
/// ([`EffectKind::ALL`] with [`EffectKind::unit`]) so that it cannot drift
/// from what the parser accepts.
pub fn effect_help() -> String {
    let mut s = String::from(
        "An extra effect, NAME[:joint=J]:value=V[:alpha_deg=A], repeatable \
         (docs/spec/physics.md section 6), e.g. coulomb_friction:joint=1:value=2.63. \
         NAME and the unit of V:",
    );
    for k in EffectKind::ALL
        .into_iter()
        .chain([EffectKind::QuadraticDamping])
    {
        let unit = match k.unit() {
            "1" => "V dimensionless, a fraction".to_string(),
            u => format!("V in {u}"),
        };
        let scope = if k.per_joint() {
            "per joint, joint=J"
        } else {
            "global, no joint"
        };
        let extra = if k == EffectKind::RigTilt {
            "; alpha_deg=A: direction [deg]"
        } else {
            ""
        };
        s += &format!("\n  {:<18} {unit} ({scope}{extra})", k.name());
    }
    s += &format!(
        "\n  {:<18} torque_table:joint=J:angle_deg=A1,A2,..:torque_nm=T1,T2,..\
         [:rate_deg_s=R1,R2,..:rate_torque_nm=G1,G2,..]: torque in N·m vs angle [deg] \
         and/or rate [deg/s], 2 to 24 points each (per joint, joint=J, no value)",
        EffectKind::TorqueTable.name()
    );
    s += &format!(
        "\n  {:<18} V = kinetic T_C in N·m, excess_nm=E: break-away T_brk − T_C in N·m, \
         stribeck_rad_s=W: Stribeck velocity in rad/s, e.g. \
         stribeck_friction:joint=2:value=0.3:excess_nm=0.4:stribeck_rad_s=0.05 (per joint, joint=J)",
        EffectKind::StribeckFriction.name()
    );
    for k in EffectKind::LATCH {
        s += &format!(
            "\n  {:<18} V dimensionless, a fraction 0 to 1 (per joint, joint=J; a joint \
             with a physical latch, docs/simulator.md)",
            k.name()
        );
    }
    s += &format!(
        "\n  {:<18} V = Δμ added to every rail's dynamic friction coefficient, dimensionless \
         (global, no joint; a mechanism with a [rig], physics.md §11.7)\n  {:<18} V = ΔL in m \
         added to every wire (global, no joint; a mechanism with a [rig])\n  {:<18} V = Δd in m \
         by which every test frame stands nearer the panels (global, no joint; a mechanism with \
         a [rig])",
        EffectKind::RigFriction.name(),
        EffectKind::WireLength.name(),
        EffectKind::FrameOffset.name()
    );
    s
}

/// The run the sensors record of `traj`, with its metadata (mechanism,
/// source, effects, sensor).
pub fn measure(args: &SimulateArgs, mech: &Mechanism, traj: &deployment::Trajectory) -> Run {
    let sensor = if args.no_noise {
        SensorModel::IDEAL
    } else {
        SensorModel::REFERENCE
    };
    let offsets = effect::encoder_offsets_deg(&args.effects, mech.joint_count());
    let mut run = sensor::measure(traj, &offsets, &sensor, args.seed);
    run.set_meta("mechanism", &mech.name);
    run.set_meta("source", "deploywatch simulate");
    let effects: Vec<String> = args.effects.iter().map(|e| e.to_string()).collect();
    run.set_meta(
        "effects",
        &if effects.is_empty() {
            "none".to_string()
        } else {
            effects.join("; ")
        },
    );
    run.set_meta(
        "sensor",
        &if args.no_noise {
            "ideal (true angles)".to_string()
        } else {
            format!(
                "noise sigma {} deg, resolution {} deg, seed {}",
                sensor.noise_sigma_deg, sensor.resolution_deg, args.seed
            )
        },
    );
    run
}
