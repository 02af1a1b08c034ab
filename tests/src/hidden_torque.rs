//! Hidden unnamed torques of forms of our own, for the discovery tests.
//!
//! Each form is written here as a closure and sampled into a dense
//! `torque_table` (eight points at places of its own: over the feature,
//! not over the stroke); the diagnosis never sees the forms, the seeds or
//! the truth. Families:
//! - `narrow`: a bump or a dip over a tenth to a sixth of the stroke;
//! - `spring dip`: a torque proportional to the hinge spring's, over a third
//!   of the stroke (the spring weaker there);
//! - `hump`: a resisting rate law peaked at a low rate (a breakaway /
//!   Stribeck-like hump), `c (v/r) e^{1 − v/r}`;
//! - `quadratic`: a resisting rate law `c (v/R)²`;
//! - `beside named`: one of the above beside one or two named effects;
//! - `two joints`: two of the above at two joints;
//! - `null`: nothing hidden.

// Per-joint series are indexed in lockstep with their offsets.
#![allow(clippy::needless_range_loop)]

use crate::data_dir;
use deploywatch_core::Branch;
use deploywatch_sim::deployment::{self, SimOptions};
use deploywatch_sim::effect::{self, Effect, EffectKind};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::run::Run;
use deploywatch_sim::sensor::{self, SensorModel};
use deploywatch_sim::torque_table::{HostTable as Table, HostTorqueTable as TorqueTable};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The mechanism pairs the campaigns are drawn on.
pub const PAIRS: [[&str; 2]; 2] = [
    ["seed001_T01", "seed001_T02"],
    ["seed000_case1", "seed000_case3"],
];

/// A hidden torque's form.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Form {
    /// A bump or dip over a tenth to a sixth of the stroke.
    Narrow,
    /// A torque proportional to the spring's over a third of the stroke.
    SpringDip,
    /// A resisting rate law peaked at a low rate.
    Hump,
    /// A resisting rate law quadratic in the rate.
    Quadratic,
}

/// The forms, in the order the families cycle through them.
pub const FORMS: [Form; 4] = [Form::Narrow, Form::SpringDip, Form::Hump, Form::Quadratic];

/// A campaign family.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Family {
    /// One unnamed torque of one form alone.
    Alone(usize),
    /// One unnamed torque beside one or two named effects.
    BesideNamed,
    /// Two unnamed torques at two joints.
    TwoJoints,
    /// Nothing hidden.
    Null,
}

impl Family {
    /// The family in words.
    pub fn name(&self) -> String {
        match self {
            Family::Alone(k) => format!("{:?} alone", FORMS[*k % FORMS.len()]),
            Family::BesideNamed => "beside named".into(),
            Family::TwoJoints => "two joints".into(),
            Family::Null => "null".into(),
        }
    }
}

/// The two mechanisms of pair `pair`.
pub fn mechanisms(pair: usize) -> Vec<Mechanism> {
    PAIRS[pair]
        .iter()
        .map(|m| Mechanism::load(&data_dir().join(format!("mechanisms/{m}.toml"))).unwrap())
        .collect()
}

/// Eight points of `y` at `xs`.
fn table_at(xs: &[f64], y: impl Fn(f64) -> f64) -> Table {
    let ys: Vec<f64> = xs.iter().map(|&x| y(x)).collect();
    Table::new(xs, &ys).unwrap()
}

/// Eight points evenly over `[lo, hi]`.
fn even(lo: f64, hi: f64) -> Vec<f64> {
    (0..8).map(|i| lo + (hi - lo) * i as f64 / 7.0).collect()
}

/// The unfolding spring torque of joint `j` (0-based) of `m` at `phi_deg` [N·m].
fn spring_nm(m: &Mechanism, j: usize, phi_deg: f64) -> f64 {
    m.joints[j]
        .spring
        .to_spring()
        .map(|s| s.torque(phi_deg.to_radians(), Branch::Unfold))
        .unwrap_or(0.0)
}

/// A table of form `form` at 0-based joint `j` with amplitude `amp` [N·m].
fn draw_table(rng: &mut ChaCha8Rng, form: Form, m: &Mechanism, j: usize, amp: f64) -> TorqueTable {
    let stowed = m.joints[j].stowed_deg;
    let motion = -stowed.signum();
    let at = |f: f64| stowed * (1.0 - f);
    match form {
        Form::Narrow => {
            let c = at(rng.gen_range(0.2..0.85));
            let w = stowed.abs() * rng.gen_range(0.025..0.045); // 4w: a tenth to a sixth
            let s = if rng.gen::<bool>() { -motion } else { motion };
            let xs = even(c - 2.0 * w, c + 2.0 * w);
            let angle = table_at(&xs, move |x| s * amp * (-((x - c) / w).powi(2)).exp());
            TorqueTable {
                angle: Some(angle),
                rate: None,
            }
        }
        Form::SpringDip => {
            let start = rng.gen_range(0.1..0.6);
            let (a, b) = (at(start), at(start + 0.33));
            let (lo, hi) = (a.min(b), a.max(b));
            let xs = even(lo, hi);
            let mech = m.clone();
            let frac = amp; // a fraction of the spring's torque
            let angle = table_at(&xs, move |x| {
                let window = (std::f64::consts::PI * (x - lo) / (hi - lo)).sin().max(0.0);
                -frac * window * spring_nm(&mech, j, x)
            });
            TorqueTable {
                angle: Some(angle),
                rate: None,
            }
        }
        Form::Hump => {
            let r = rng.gen_range(6.0..30.0);
            let mags = [
                0.0,
                0.4 * r,
                r,
                1.8 * r,
                3.0 * r,
                5.0 * r,
                9.0 * r,
                20.0 * r,
            ];
            let xs: Vec<f64> = if motion > 0.0 {
                mags.to_vec()
            } else {
                mags.iter().rev().map(|v| -v).collect()
            };
            let rate = table_at(&xs, move |x| {
                let v = x.abs() / r;
                -motion * amp * v * (1.0 - v).exp()
            });
            TorqueTable {
                angle: None,
                rate: Some(rate),
            }
        }
        Form::Quadratic => {
            let big = rng.gen_range(100.0..300.0);
            let xs: Vec<f64> = if motion > 0.0 {
                even(0.0, big)
            } else {
                even(-big, 0.0)
            };
            let rate = table_at(&xs, move |x| -motion * amp * (x / big).powi(2));
            TorqueTable {
                angle: None,
                rate: Some(rate),
            }
        }
    }
}

/// How far effects move the pair of runs [deg RMS], noise-free.
pub fn effect_size(mechs: &[Mechanism], effects: &[Effect]) -> f64 {
    let opts = SimOptions {
        stop_when_deployed: false,
        ..SimOptions::default()
    };
    let (mut sse, mut n) = (0.0, 0usize);
    for m in mechs {
        let (Ok(a), Ok(b)) = (
            deployment::simulate(m, &[], &opts),
            deployment::simulate(m, effects, &opts),
        ) else {
            return 0.0;
        };
        let off = effect::encoder_offsets_deg(effects, m.joint_count());
        for j in 0..m.joint_count() {
            for (x, y) in a.phi_deg[j].iter().zip(&b.phi_deg[j]) {
                sse += (x - y - off[j]).powi(2);
                n += 1;
            }
        }
    }
    (sse / n.max(1) as f64).sqrt()
}

/// One hidden torque of `form` at 1-based joint `j`, its amplitude raised
/// until it moves the runs by at least 0.3° RMS.
pub fn hidden_torque(seed: u64, form: Form, mechs: &[Mechanism], j: usize) -> Effect {
    let mut amp = if form == Form::SpringDip { 0.05 } else { 0.03 };
    loop {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let table = draw_table(&mut rng, form, &mechs[0], j - 1, amp);
        let e = Effect {
            kind: EffectKind::TorqueTable,
            joint: Some(j),
            value: amp,
            table,
            ..Effect::default()
        };
        if effect_size(mechs, &[e]) >= 0.3 || amp > 2.0 {
            return e;
        }
        amp *= 1.4;
    }
}

/// A named effect of the vocabulary at a random joint, moving the runs by
/// at least 0.3° RMS on its own.
fn named(rng: &mut ChaCha8Rng, mechs: &[Mechanism], joints: usize) -> Effect {
    let j = rng.gen_range(1..=joints);
    let mut e = match rng.gen_range(0..5) {
        0 => Effect::joint(EffectKind::CoulombFriction, j, 0.1),
        1 => Effect::joint(EffectKind::ViscousDamping, j, 0.1),
        2 => Effect::joint(EffectKind::HarnessStiffness, j, 0.05),
        3 => Effect::global(EffectKind::AirDrag, 0.1),
        _ => Effect {
            alpha_deg: rng.gen_range(0.0..360.0),
            ..Effect::global(EffectKind::RigTilt, 0.03)
        },
    };
    for _ in 0..12 {
        if effect_size(mechs, &[e]) >= 0.3 {
            break;
        }
        e.value *= 1.5;
    }
    e
}

/// One hidden campaign: the pair, the truth, the measured runs and the RMS
/// of the sensor noise they carry.
pub struct Case {
    /// The family it was drawn from.
    pub family: Family,
    /// Index into [`PAIRS`].
    pub pair: usize,
    /// What was hidden.
    pub truth: Vec<Effect>,
    /// The measured runs (reference sensor).
    pub runs: Vec<Run>,
    /// RMS of the noise the sensor added [deg].
    pub noise_rms_deg: f64,
}

/// Simulates the truth on pair `pair` and measures it with the reference
/// sensor.
pub fn generate(family: Family, seed: u64, pair: usize, truth: Vec<Effect>) -> Case {
    let mechs = mechanisms(pair);
    let (mut sse, mut n) = (0.0, 0usize);
    let runs = mechs
        .iter()
        .enumerate()
        .map(|(r, m)| {
            let traj = deployment::simulate(m, &truth, &SimOptions::default()).unwrap();
            let offsets = effect::encoder_offsets_deg(&truth, m.joint_count());
            let mut run = sensor::measure(
                &traj,
                &offsets,
                &SensorModel::REFERENCE,
                seed * 10 + r as u64,
            );
            for j in 0..m.joint_count() {
                for (y, x) in run.phi_deg[j].iter().zip(&traj.phi_deg[j]) {
                    sse += (y - x - offsets[j]).powi(2);
                    n += 1;
                }
            }
            run.set_meta("mechanism", &m.name);
            run
        })
        .collect();
    Case {
        family,
        pair,
        truth,
        runs,
        noise_rms_deg: (sse / n.max(1) as f64).sqrt(),
    }
}

/// The `k`-th campaign of family `family` (seeded by `k`).
pub fn case(family: Family, k: u64) -> Case {
    let seed = 9100 + 37 * k + 1000 * family_index(family);
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5eed);
    let pair = rng.gen_range(0..2);
    let mechs = mechanisms(pair);
    let joints = mechs[0].joint_count();
    let j = rng.gen_range(1..=joints);
    let form = FORMS[rng.gen_range(0..FORMS.len())];
    let truth = match family {
        Family::Alone(f) => vec![hidden_torque(seed, FORMS[f % FORMS.len()], &mechs, j)],
        Family::BesideNamed => {
            let mut t = vec![hidden_torque(seed, form, &mechs, j)];
            for _ in 0..rng.gen_range(1..=2) {
                let e = named(&mut rng, &mechs, joints);
                if !t.iter().any(|x| x.kind == e.kind && x.joint == e.joint) {
                    t.push(e);
                }
            }
            t
        }
        Family::TwoJoints => {
            let other = 1 + j % joints;
            let form2 = FORMS[rng.gen_range(0..FORMS.len())];
            vec![
                hidden_torque(seed, form, &mechs, j),
                hidden_torque(seed + 1, form2, &mechs, other),
            ]
        }
        Family::Null => Vec::new(),
    };
    generate(family, seed, pair, truth)
}

fn family_index(f: Family) -> u64 {
    match f {
        Family::Alone(k) => k as u64,
        Family::BesideNamed => 4,
        Family::TwoJoints => 5,
        Family::Null => 6,
    }
}

/// Every family: the four forms alone, beside named, two joints, null.
pub fn families() -> Vec<Family> {
    let mut v: Vec<Family> = (0..FORMS.len()).map(Family::Alone).collect();
    v.extend([Family::BesideNamed, Family::TwoJoints, Family::Null]);
    v
}

/// The joints (1-based) that hold a per-joint effect of `effects`.
pub fn joints_of(effects: &[Effect]) -> Vec<usize> {
    let mut j: Vec<usize> = effects
        .iter()
        .filter(|e| e.kind != EffectKind::EncoderOffset || e.value != 0.0)
        .filter_map(|e| e.joint)
        .collect();
    j.sort();
    j.dedup();
    j
}
