//! Shared helpers of the cross-crate tests: where the bundled data lives,
//! and the small deterministic generator of their Monte-Carlo draws.
#![deny(missing_docs)]

use std::path::PathBuf;

/// The repository root.
pub fn repo_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(|p| p.to_path_buf())
        .unwrap_or_default()
}

/// `data/` in the repository (copies of `shared/`, see `data/README.md`).
pub fn data_dir() -> PathBuf {
    repo_root().join("data")
}

/// The bundled mechanism `data/mechanisms/NAME.toml` (panics when it does
/// not load: a test's own data).
pub fn mechanism(name: &str) -> deploywatch_sim::mechanism::Mechanism {
    deploywatch_sim::mechanism::Mechanism::load(
        &data_dir().join("mechanisms").join(format!("{name}.toml")),
    )
    .expect("mechanism file")
}

/// Coulomb friction `values[j]` \[N·m\] at joint `j + 1`, one effect a joint.
pub fn coulomb(values: &[f64]) -> Vec<deploywatch_sim::effect::Effect> {
    use deploywatch_sim::effect::{Effect, EffectKind};
    values
        .iter()
        .enumerate()
        .map(|(j, &v)| Effect::joint(EffectKind::CoulombFriction, j + 1, v))
        .collect()
}

/// The drawings of the physical-latch campaigns, two families (seed 001
/// T01 + T02; two runs of seed 000 case 1), each drawing with its
/// ideal-latch twin: names of `data/mechanisms/NAME.toml`.
pub const PHYSICAL_LATCH_FAMILIES: [[(&str, &str); 2]; 2] = [
    [
        ("seed001_T01_physical_latch", "seed001_T01"),
        ("seed001_T02_physical_latch", "seed001_T02"),
    ],
    [
        ("seed000_case1_physical_latch", "seed000_case1"),
        ("seed000_case1_physical_latch", "seed000_case1"),
    ],
];

/// Extends a trajectory by `hold_s` \[s\] at its rest state, a sample
/// every `dt` \[s\]: latched joints at their latch (0°), the others where
/// they ended, every rate 0 (a monitor keeps sampling after the
/// deployment).
pub fn hold_at_rest(traj: &mut deploywatch_sim::deployment::Trajectory, hold_s: f64, dt: f64) {
    let Some(&t_last) = traj.t_s.last() else {
        return;
    };
    let n = traj.joints();
    let mut t = t_last;
    let mut k = 0;
    while t < t_last + hold_s - 1e-9 {
        k += 1;
        t = t_last + k as f64 * dt;
        traj.t_s.push(t);
        for j in 0..n {
            let latched = traj.latched[j].last().copied().unwrap_or(false);
            let phi = traj.phi_deg[j].last().copied().unwrap_or(0.0);
            traj.phi_deg[j].push(if latched { 0.0 } else { phi });
            traj.latched[j].push(latched);
            traj.rate_deg_s[j].push(0.0);
        }
    }
}

/// The monitor's status at every sample of `run`
/// ([`deploywatch_core::monitor::Monitor::replay_step`]); panics when the
/// configuration or the joint count is wrong (a test's own setup).
pub fn replay<const N: usize>(
    cfg: &deploywatch_core::monitor::MonitorConfig<N>,
    run: &deploywatch_sim::run::Run,
) -> Vec<deploywatch_core::monitor::Status<N>> {
    let mut m = deploywatch_core::monitor::Monitor::new(cfg).expect("monitor config");
    deploywatch_sim::monitor_config::samples::<N>(run)
        .expect("joint count")
        .iter()
        .map(|s| m.replay_step(s))
        .collect()
}

/// The diagnosis settings of a test: the defaults, with every score and
/// verdict of each round in the progress when `DEPLOYWATCH_TRACE` is set
/// and the friction forms' regressions on stderr with
/// `DEPLOYWATCH_TRACE_FORMS` (as the command line maps them).
pub fn diagnose_options() -> deploywatch_sim::diagnose::DiagnoseOptions {
    deploywatch_sim::diagnose::DiagnoseOptions {
        trace: std::env::var_os("DEPLOYWATCH_TRACE").is_some(),
        trace_forms: std::env::var_os("DEPLOYWATCH_TRACE_FORMS").is_some(),
        ..Default::default()
    }
}

pub mod after_contact;
pub mod cli_run;
pub mod hidden_effect;
pub mod hidden_torque;
pub mod holds_less;
pub mod record;
pub mod wing_gen;

/// splitmix64 (Steele, Lea and Flood 2014): a small deterministic generator
/// for the tests' Monte-Carlo draws; the state is the seed.
pub struct SplitMix(pub u64);

impl SplitMix {
    /// A uniform draw in [0, 1), 53 bits.
    pub fn next_f64(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A uniform draw in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }
}
