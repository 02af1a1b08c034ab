//! Campaigns whose latch at one joint holds less than drawn, the population
//! a diagnosis of the latch as built is measured on: its plunger, its
//! magnet or both built at 15–50 % of the drawing, every latch also as
//! built within its tolerances, kept only where that plainly changes the
//! runs at that joint: its escapes over the campaign beyond those of every
//! one of [`SPREAD_DRAWS`] as-built draws of the drawing by more than one,
//! or fewer runs ending held than in any of them (what no set of latches
//! within the drawing's tolerances gives, so what runs can tell at all).
//! Used
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
    /// weakening (the same as-built latches and sensor noise), as the
    /// measured runs show them ([`reading`]).
    pub escapes: (usize, usize),
    /// It ends off its latch in a run where the same latches without the
    /// weakening hold.
    pub opened: bool,
    /// Runs ending within the crest at that joint, with the weakening, as
    /// the measured runs show it ([`reading`]).
    pub held: usize,
    /// The drawing's spread at that joint over [`SPREAD_DRAWS`] as-built
    /// draws and the campaign's own latches without the weakening, as
    /// measured runs show it ([`drawing_spread`]).
    pub spread: DrawingSpread,
}

/// As-built draws of the drawing whose spread a weakening must leave to be
/// kept.
pub const SPREAD_DRAWS: u64 = 40;

/// The spread of one joint's events over as-built draws of the drawing:
/// escapes over the campaign and runs ending within the crest, `[least,
/// most]` of each.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DrawingSpread {
    /// Escapes over the campaign's runs.
    pub escapes: [usize; 2],
    /// Runs ending within the crest.
    pub held: [usize; 2],
}

impl DrawingSpread {
    /// Whether `escapes` and `held` (runs ending within the crest) lie
    /// outside this spread the way a latch that holds less makes them:
    /// more escapes than any draw by more than one (a count read at the
    /// encoder's resolution moves by one), or fewer runs held.
    pub fn plainly_weaker(&self, escapes: usize, held: usize) -> bool {
        escapes > self.escapes[1] + 1 || held < self.held[0]
    }

    /// This spread and `other` together.
    pub fn widened(&self, other: &DrawingSpread) -> DrawingSpread {
        let both = |a: [usize; 2], b: [usize; 2]| [a[0].min(b[0]), a[1].max(b[1])];
        DrawingSpread {
            escapes: both(self.escapes, other.escapes),
            held: both(self.held, other.held),
        }
    }
}

/// The spread of joint `joint` (1-based) of the campaign of `drawings`
/// over [`SPREAD_DRAWS`] as-built draws of every latch within its
/// tolerances, as measured runs show it ([`reading`]; draw `k` seeded
/// `0x5eed_0000 + k`).
/// `None`: a draw the simulator refuses.
pub fn drawing_spread(
    drawings: &[Mechanism],
    joint: usize,
    opts: &SimOptions,
) -> Option<DrawingSpread> {
    use rayon::prelude::*;
    let per_draw: Option<Vec<(usize, usize)>> = (0..SPREAD_DRAWS)
        .into_par_iter()
        .map(|k| {
            let mut rng = ChaCha8Rng::seed_from_u64(0x5eed_0000 + k);
            let mut uniform = || rng.gen::<f64>();
            let built = as_built(drawings, &mut uniform);
            let (mut e, mut h) = (0, 0);
            for (r, m) in built.iter().enumerate() {
                let t = deployment::simulate(m, &[], opts).ok()?;
                let (a, b) = reading(&drawings[r], &t, 0x5eed_0000 + 2 * k + r as u64, joint - 1);
                e += a;
                h += usize::from(b);
            }
            Some((e, h))
        })
        .collect();
    let d = per_draw?;
    let range =
        |f: fn(&(usize, usize)) -> usize| Some([d.iter().map(f).min()?, d.iter().map(f).max()?]);
    Some(DrawingSpread {
        escapes: range(|x| x.0)?,
        held: range(|x| x.1)?,
    })
}

/// How far past the crest an excursion must go to count as an escape
/// \[deg\]: the encoder's resolution (0.022° at 14 bits), as the
/// diagnosis reads escapes from measured angles; an excursion within it
/// of the crest is not one that runs show.
pub const RESOLUTION_DEG: f64 = 0.03;

/// The escapes over the crest of joint `j` (0-based) in a measured run, and
/// whether it ends within the crest: the test's own count from the
/// samples, read as `docs/diagnosis.md` ("Runs of a physical latch", 2)
/// defines them (travel from the stop `u = s φ`, `s` the stowed side; an
/// escape is an excursion between two closings of the switch, or after
/// the last, whose peak passes the crest by more than [`RESOLUTION_DEG`]).
pub fn escapes_and_end(m: &Mechanism, run: &Run, j: usize) -> (usize, bool) {
    let (Some(latch), Some(spec), Some(phi), Some(switch)) = (
        m.latch(j),
        m.joints.get(j),
        run.phi_deg.get(j),
        run.latch.get(j),
    ) else {
        return (0, false);
    };
    let crest = latch.hold_limit_deg(spec.stowed_deg) + RESOLUTION_DEG;
    let s = if spec.stowed_deg >= 0.0 { 1.0 } else { -1.0 };
    let (mut escapes, mut peak, mut closed_once) = (0, None::<f64>, false);
    for (&p, &closed) in phi.iter().zip(switch) {
        if closed {
            escapes += usize::from(peak.take().is_some_and(|h| h > crest));
            closed_once = true;
        } else if closed_once {
            peak = Some(peak.map_or(s * p, |h| h.max(s * p)));
        }
    }
    escapes += usize::from(peak.is_some_and(|h| h > crest));
    let held = phi.last().is_some_and(|&p| s * p <= crest - RESOLUTION_DEG);
    (escapes, held)
}

/// The run the reference sensor measures of `traj` (noise seeded `seed`).
fn measure(m: &Mechanism, traj: &Trajectory, seed: u64) -> Run {
    let zero = vec![0.0; m.joint_count()];
    sensor::measure(traj, &zero, &SensorModel::REFERENCE, seed)
}

/// Joint `j`'s escapes and whether it ends held, as the run the reference
/// sensor measures of `traj` (noise seeded `seed`) shows them against the
/// crest of `drawing`, the latch the analyst knows ([`escapes_and_end`]):
/// a rebound that stalls at the crest counts as an escape or not by the
/// encoder's noise, and an as-built crest differs from the drawing's, so
/// the counts compared are those runs show.
pub fn reading(drawing: &Mechanism, traj: &Trajectory, seed: u64, j: usize) -> (usize, bool) {
    escapes_and_end(drawing, &measure(drawing, traj, seed), j)
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
/// when the weakening plainly changes the runs at its joint: its escapes
/// over the campaign or its runs ending held, as the measured runs show
/// them ([`reading`]), lie outside those of the same latches without it
/// and outside the
/// drawing's spread over [`SPREAD_DRAWS`] as-built draws the way a weaker
/// latch makes them ([`DrawingSpread::plainly_weaker`]). `None`: not
/// kept, or a draw the simulator refuses.
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
    let (mut with_e, mut without_e, mut opened, mut held, mut held_without) = (0, 0, false, 0, 0);
    let mut runs = Vec::new();
    for (r, m) in built.iter().enumerate() {
        let seed = noise_seed + r as u64;
        let with = deployment::simulate(m, &effects, opts).ok()?;
        let without = deployment::simulate(m, &[], opts).ok()?;
        let mut run = measure(m, &with, seed);
        let (e1, held1) = escapes_and_end(&drawings[r], &run, joint - 1);
        let (e0, held0) = reading(&drawings[r], &without, seed, joint - 1);
        with_e += e1;
        without_e += e0;
        opened |= held0 && !held1;
        held += usize::from(held1);
        held_without += usize::from(held0);
        run.set_meta("mechanism", &m.name);
        runs.push(run);
    }
    // The same latches without the weakening are a draw within the
    // drawing's tolerances too: beside it, no plain change (and the forty
    // draws need not be simulated).
    let own = DrawingSpread {
        escapes: [without_e; 2],
        held: [held_without; 2],
    };
    if !own.plainly_weaker(with_e, held) {
        return None;
    }
    let spread = drawing_spread(&drawings, joint, opts)?.widened(&own);
    spread.plainly_weaker(with_e, held).then_some(HoldsLess {
        drawings,
        runs,
        joint,
        what,
        strength,
        escapes: (without_e, with_e),
        opened,
        held,
        spread,
    })
}
