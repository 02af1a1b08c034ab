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

pub mod hidden_effect;
pub mod hidden_torque;
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
