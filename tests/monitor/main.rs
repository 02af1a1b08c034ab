//! The on-board monitor (`deploywatch_core::monitor`) on runs of the
//! simulator with its reference sensor model.
//!
//! One module per suite: `prediction`, `latch` (latch declarations), `past_crest` (a physical
//! latch's joint back past its crest), `light_wings` (fast light
//! wings: rollouts and clean runs), `footprint` (RAM and
//! frames), `properties` (proptest), `clean` (no fault flag on clean runs), `refresh`; the
//! shared run helpers are here.

mod clean;
mod footprint;
mod latch;
mod light_wings;
mod past_crest;
mod prediction;
mod properties;
mod refresh;

use deploywatch_core::monitor::Fault;
use deploywatch_core::monitor::LatchState;
use deploywatch_core::monitor::{
    Monitor, MonitorConfig, Observability, Prediction, Sample, Status,
};
use deploywatch_sim::deployment::{simulate, SimOptions, Trajectory};
use deploywatch_sim::effect::{Effect, EffectKind};
use deploywatch_sim::fault_injection::{apply, SensorFault};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::monitor_config::{monitor_config, samples};
use deploywatch_sim::run::Run;
use deploywatch_sim::sensor::{measure, SensorModel};
use deploywatch_tests::{coulomb, data_dir, hold_at_rest, mechanism, replay, SplitMix};

/// The papers' identified friction, seed 001 (N·m at joints 1–3).
const SEED001_FRICTION: [f64; 3] = [2.63, 1.7, 0.001];

/// Simulates a mechanism with extra effects and measures it with the
/// reference sensor. The simulator ends a run at the last latch; the run is
/// extended by `HOLD_S` of samples at the rest state (latched joints at 0,
/// switches closed, sensor noise going on), as a real monitor keeps sampling.
fn simulate_run(mech: &Mechanism, effects: &[Effect], seed: u64) -> (Trajectory, Run) {
    let mut traj = simulate_truth(mech, effects);
    hold_at_rest(&mut traj, HOLD_S, 1.0 / mech.sample_hz);
    let run = measure(&traj, &[], &SensorModel::REFERENCE, seed);
    (traj, run)
}

/// The simulated deployment over the whole run (not stopped at the last
/// latch).
fn simulate_truth(mech: &Mechanism, effects: &[Effect]) -> Trajectory {
    let opts = SimOptions {
        stop_when_deployed: false,
        ..SimOptions::default()
    };
    simulate(mech, effects, &opts).expect("simulation")
}

/// Samples the monitor keeps receiving after the last latch \[s\].
const HOLD_S: f64 = 0.2;

/// Index of the first sample at which joint `j` has covered half its stroke
/// (|φ| ≤ ½ |φ_stowed|, true angle).
fn half_stroke_index(traj: &Trajectory, stowed_deg: f64, j: usize) -> Option<usize> {
    traj.phi_deg[j]
        .iter()
        .position(|p| p.abs() <= 0.5 * stowed_deg.abs())
}

/// The scatter of one Monte-Carlo run of seed001_T01: the paper's friction
/// scaled by U(0.5, 1.5) and each spring by U(0.9, 1.1) (as
/// `spring_softening` s ∈ [−0.1, 0.1]), joint by joint. Effect `2j` is joint
/// j's Coulomb torque, `2j + 1` its softening.
fn scatter(rng: &mut SplitMix) -> Vec<Effect> {
    let mut effects = Vec::new();
    for (j, base) in SEED001_FRICTION.iter().enumerate() {
        effects.push(Effect::joint(
            EffectKind::CoulombFriction,
            j + 1,
            base * rng.uniform(0.5, 1.5),
        ));
        let soft = rng.uniform(-0.1, 0.1);
        effects.push(Effect::joint(EffectKind::SpringSoftening, j + 1, soft));
    }
    effects
}

/// Runs in each Monte-Carlo.
const MC_RUNS: usize = 200;

/// The rollout of `cfg` with schedule `rc` (its horizon the deadline, all
/// its work at once) from the simulated true state at sample `i`, with
/// Coulomb torques `coulomb_nm` \[N·m\], no viscous term and springs
/// scaled by `spring_scale`, run to the end: each joint's latch instant
/// \[s\], if it latches (before or after the deadline).
fn rollout_latches<const N: usize>(
    cfg: &MonitorConfig<N>,
    mut rc: deploywatch_core::monitor::RolloutConfig,
    traj: &Trajectory,
    i: usize,
    coulomb_nm: [f32; N],
    spring_scale: [f32; N],
) -> [Option<f64>; N] {
    use deploywatch_core::internals::{Rollout, RolloutStart};
    use deploywatch_core::ChainState;
    let chain = cfg.chain().unwrap();
    rc.horizon_s = (f64::from(cfg.margin.deadline_s) - traj.t_s[i]) as f32;
    rc.steps_per_slice = u8::MAX;
    let mut r = Rollout::new(RolloutStart {
        state: ChainState {
            phi: std::array::from_fn(|q| traj.phi_deg[q][i].to_radians() as f32),
            phi_dot: std::array::from_fn(|q| traj.rate_deg_s[q][i].to_radians() as f32),
        },
        latched: std::array::from_fn(|q| traj.latched[q][i]),
        coulomb_nm,
        viscous_nms: [0.0; N],
        spring_scale,
        capture_rad: std::array::from_fn(|q| cfg.joints[q].capture_deg.to_radians()),
    });
    for _ in 0..10_000 {
        if r.is_done() {
            break;
        }
        r.advance(&chain, &rc);
    }
    assert!(r.is_done(), "rollout unfinished");
    let o = r.outcome();
    std::array::from_fn(|q| {
        o[q].latches
            .then(|| traj.t_s[i] + f64::from(o[q].latch_after_s))
    })
}
