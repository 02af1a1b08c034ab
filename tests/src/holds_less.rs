//! Campaigns whose latch at one joint holds less than drawn, the population
//! a diagnosis of the latch as built is measured on: its plunger, its
//! magnet or both built at 15–50 % of the drawing, every latch also as
//! built within its tolerances, kept only where that plainly changes the
//! runs at that joint against the same latches without the weakening. Used
//! by `tests/diagnosis_physical_latch.rs` (never an effect, never another
//! joint) and `tests/examples/latch_holds_less.rs` (how often the joint is
//! named, and where its events fall in the drawing's tolerance spread).

use crate::PHYSICAL_LATCH_FAMILIES;
use deploywatch_sim::deployment::{self, SimOptions, Trajectory};
use deploywatch_sim::effect::{Effect, EffectKind};
use deploywatch_sim::latch::LatchTolerance;
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::run::Run;
use deploywatch_sim::sensor::{self, SensorModel};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// What is weakened at the joint.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Weakened {
    /// The plunger's preload and rate.
    Plunger,
    /// The magnet's pull.
    Magnet,
    /// Both.
    Both,
}

/// One campaign of [`generate`].
#[derive(Clone, Debug)]
pub struct HoldsLess {
    /// The drawings, one per run.
    pub drawings: Vec<Mechanism>,
    /// The measured runs (reference sensor noise).
    pub runs: Vec<Run>,
    /// The joint whose latch holds less (1-based).
    pub joint: usize,
    /// What is weakened there.
    pub what: Weakened,
    /// Its strength, a share of the drawing's \[1\].
    pub strength: f64,
    /// Escapes over the campaign at that joint without and with the
    /// weakening (the same as-built latches).
    pub escapes: (usize, usize),
    /// It ends off its latch in a run where the same latches without the
    /// weakening hold.
    pub opened: bool,
}

/// The escapes over the crest of joint `j` (0-based) in a trajectory, and
/// whether it ends within the crest: the test's own count from the
/// simulator's samples (travel from the stop `u = s φ`, `s` the stowed
/// side; an escape is a sample past the crest after one within it, once
/// the switch has closed).
pub fn escapes_and_end(m: &Mechanism, traj: &Trajectory, j: usize) -> (usize, bool) {
    let (Some(latch), Some(spec)) = (m.latch(j), m.joints.get(j)) else {
        return (0, false);
    };
    let crest = latch.hold_limit_deg(spec.stowed_deg);
    let s = if spec.stowed_deg >= 0.0 { 1.0 } else { -1.0 };
    let u: Vec<f64> = traj.phi_deg[j].iter().map(|p| s * p).collect();
    let Some(first) = traj.latched[j].iter().position(|&l| l) else {
        return (0, false);
    };
    let escapes = (first.max(1)..u.len())
        .filter(|&i| u[i - 1] <= crest && u[i] > crest)
        .count();
    (escapes, u.last().is_some_and(|&x| x <= crest))
}

/// One as-built latch set per drawing (seed 000's two runs are of one wing).
pub fn as_built(drawings: &[Mechanism], uniform: &mut impl FnMut() -> f64) -> Vec<Mechanism> {
    let tol = LatchTolerance::default();
    if drawings.len() == 2 && drawings[0].name == drawings[1].name {
        let b = drawings[0].as_built(&tol, uniform);
        vec![b.clone(), b]
    } else {
        drawings.iter().map(|d| d.as_built(&tol, uniform)).collect()
    }
}

/// The campaign of `seed` in `family` of [`PHYSICAL_LATCH_FAMILIES`], kept
/// when the weakening plainly changes the runs at its joint against the
/// same as-built latches without it: it ends off its latch in a run where
/// they hold, or its escapes over the campaign at least double (and by 2 or
/// more). `None`: not kept, or a draw the simulator refuses.
pub fn generate(seed: u64, family: usize, opts: &SimOptions) -> Option<HoldsLess> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let drawings: Vec<Mechanism> = PHYSICAL_LATCH_FAMILIES[family]
        .iter()
        .map(|(d, _)| crate::mechanism(d))
        .collect();
    let joint = rng.gen_range(1..=drawings[0].joint_count());
    let strength = rng.gen_range(0.15..0.5);
    let what = [Weakened::Plunger, Weakened::Magnet, Weakened::Both][rng.gen_range(0..3)];
    let w = 1.0 - strength;
    let weak = |k| Effect::joint(k, joint, w);
    let effects = match what {
        Weakened::Plunger => vec![weak(EffectKind::PlungerWeakening)],
        Weakened::Magnet => vec![weak(EffectKind::MagnetWeakening)],
        Weakened::Both => vec![
            weak(EffectKind::PlungerWeakening),
            weak(EffectKind::MagnetWeakening),
        ],
    };
    let mut uniform = || rng.gen::<f64>();
    let built = as_built(&drawings, &mut uniform);
    let noise_seed = rng.gen::<u64>() % 1_000_000;
    let (mut with_e, mut without_e, mut opened) = (0, 0, false);
    let mut runs = Vec::new();
    for (r, m) in built.iter().enumerate() {
        let with = deployment::simulate(m, &effects, opts).ok()?;
        let without = deployment::simulate(m, &[], opts).ok()?;
        let (e1, held1) = escapes_and_end(m, &with, joint - 1);
        let (e0, held0) = escapes_and_end(m, &without, joint - 1);
        with_e += e1;
        without_e += e0;
        opened |= held0 && !held1;
        let zero = vec![0.0; m.joint_count()];
        let mut run = sensor::measure(&with, &zero, &SensorModel::REFERENCE, noise_seed + r as u64);
        run.set_meta("mechanism", &m.name);
        runs.push(run);
    }
    let doubled = with_e >= 2 * without_e && with_e >= without_e + 2;
    (opened || doubled).then_some(HoldsLess {
        drawings,
        runs,
        joint,
        what,
        strength,
        escapes: (without_e, with_e),
        opened,
    })
}
