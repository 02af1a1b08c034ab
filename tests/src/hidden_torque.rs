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
//! - `quadratic`: quadratic damping `−c φ̇|φ̇|`, over both signs of the
//!   rate, sampled on knots that halve towards rest (so that the table is
//!   quadratic, not linear, near rest);
//! - `breakaway`: friction a tribologist expects, static above kinetic and
//!   falling with rate, in forms that are not the simulator's Stribeck law:
//!   Coulomb friction at the break-away level `T_s` (a named effect) with a
//!   table that takes the excess `ΔT` off as the rate grows, by
//!   `1 − e^{−v/v_s}`, `1 − 1/(1 + (v/v_s)²)` or `1 − e^{−(v/v_s)^δ}`
//!   (δ 0.6–1.8), half of them with viscous damping in the table too;
//! - `snag`: one or two narrow resisting snags, each over a twentieth to a
//!   tenth of the stroke, Gaussian, triangular or flat-topped;
//! - `beside named`: one of the first four beside one or two named effects;
//! - `<form> beside named`: a breakaway, a snag or quadratic damping beside
//!   one or two named effects;
//! - `two joints`: two of the above at two joints;
//! - `null`: nothing hidden.

// Per-joint series are indexed in lockstep with their offsets.
#![allow(clippy::needless_range_loop)]

use crate::data_dir;
use deploywatch_core::Branch;
use deploywatch_sim::deployment::{self, SimOptions};
use deploywatch_sim::effect::{self, Effect, EffectKind, Law};
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
    /// Quadratic damping `−c φ̇|φ̇|`.
    Quadratic,
    /// Static friction above kinetic, falling with rate.
    Breakaway,
    /// One or two narrow resisting snags.
    Snag,
}

/// The forms the `beside named` and `two joints` families draw from.
pub const FORMS: [Form; 4] = [Form::Narrow, Form::SpringDip, Form::Hump, Form::Quadratic];

/// The forms of the `alone` families, by index.
pub const ALONE_FORMS: [Form; 6] = [
    Form::Narrow,
    Form::SpringDip,
    Form::Hump,
    Form::Quadratic,
    Form::Breakaway,
    Form::Snag,
];

/// The friction forms a tribologist names, each also beside named effects.
pub const FRICTION_FORMS: [Form; 3] = [Form::Breakaway, Form::Snag, Form::Quadratic];

/// A campaign family.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Family {
    /// One unnamed torque of one form ([`ALONE_FORMS`]) alone.
    Alone(usize),
    /// One friction form ([`FRICTION_FORMS`]) beside one or two named
    /// effects.
    FrictionBeside(usize),
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
            Family::Alone(k) => format!("{:?} alone", ALONE_FORMS[*k % ALONE_FORMS.len()]),
            Family::FrictionBeside(k) => {
                format!(
                    "{:?} beside named",
                    FRICTION_FORMS[*k % FRICTION_FORMS.len()]
                )
            }
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
            // Knots halving from 800 deg/s towards rest, both signs.
            let mut xs: Vec<f64> = (0..9).map(|k| 800.0 / 2f64.powi(k)).collect();
            xs.extend(xs.clone().iter().map(|v| -v));
            xs.push(0.0);
            xs.sort_by(f64::total_cmp);
            let r = 100.0; // the torque is `amp` at 100 deg/s
            let rate = table_at(&xs, move |x| -amp * x * x.abs() / (r * r));
            TorqueTable {
                angle: None,
                rate: Some(rate),
            }
        }
        Form::Breakaway => breakaway_table(rng, amp).0,
        Form::Snag => snag_table(rng, m, j, amp),
    }
}

/// The rate table of a break-away (module docs) with excess `amp` [N·m]:
/// `+sign(v) ΔT (1 − s(|v|/v_s)) − f v`, zero at rest, so that beside
/// Coulomb friction at the break-away level `T_s` the friction is
/// `T_s − ΔT (1 − s)`: `T_s` at rest, falling to the kinetic `T_s − ΔT`.
/// Returns the table, the ratio `T_s / ΔT` (static over excess, 1.6–3:
/// static 1.5–2.7 times kinetic) and the viscous part `f` [N·m·s/rad].
fn breakaway_table(rng: &mut ChaCha8Rng, amp: f64) -> (TorqueTable, f64, f64) {
    let vs = rng.gen_range(2.0..20.0); // deg/s
    let law = rng.gen_range(0..3);
    let delta = rng.gen_range(0.6..1.8);
    let viscous = if rng.gen::<bool>() {
        amp * rng.gen_range(0.3..1.0) / 100.0 // N·m per deg/s: `amp`·0.3–1 at 100 deg/s
    } else {
        0.0
    };
    let ratio = rng.gen_range(1.6..3.0);
    let s = move |x: f64| match law {
        0 => (-x).exp(),
        1 => 1.0 / (1.0 + x * x),
        _ => (-x.powf(delta)).exp(),
    };
    let mut xs: Vec<f64> = (0..10).map(|k| vs * 2f64.powi(k - 3)).collect();
    xs.extend(xs.clone().iter().map(|v| -v));
    xs.push(0.0);
    xs.sort_by(f64::total_cmp);
    let rate = table_at(&xs, move |x| {
        x.signum() * amp * (1.0 - s(x.abs() / vs)) - viscous * x
    });
    (
        TorqueTable {
            angle: None,
            rate: Some(rate),
        },
        ratio,
        viscous.to_degrees(),
    )
}

/// One or two narrow resisting snags at 0-based joint `j` of `m`, each over
/// a twentieth to a tenth of the stroke, of peak `amp` [N·m].
fn snag_table(rng: &mut ChaCha8Rng, m: &Mechanism, j: usize, amp: f64) -> TorqueTable {
    let stowed = m.joints[j].stowed_deg;
    let motion = -stowed.signum();
    let at = |f: f64| stowed * (1.0 - f);
    let count = if rng.gen_bool(0.3) { 2 } else { 1 };
    let mut pts: Vec<(f64, f64)> = Vec::new();
    let mut taken: Vec<f64> = Vec::new();
    for _ in 0..count {
        let mut f = rng.gen_range(0.1..0.9);
        while taken.iter().any(|t| (t - f).abs() < 0.2) {
            f = rng.gen_range(0.1..0.9);
        }
        taken.push(f);
        let c = at(f);
        let half = 0.5 * stowed.abs() * rng.gen_range(0.05..0.1);
        let shape = rng.gen_range(0..3);
        let y = move |u: f64| match shape {
            0 => (-(2.0 * u).powi(2)).exp(),              // Gaussian
            1 => (1.0 - u.abs()).max(0.0),                // triangular
            _ => ((1.0 - u.abs()) * 3.0).clamp(0.0, 1.0), // flat-topped
        };
        let a = amp * rng.gen_range(0.6..1.0);
        for i in 0..7 {
            let u = -1.0 + 2.0 * i as f64 / 6.0;
            pts.push((c + u * half, -motion * a * y(u)));
        }
    }
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    let xs: Vec<f64> = pts.iter().map(|p| p.0).collect();
    let ys: Vec<f64> = pts.iter().map(|p| p.1).collect();
    TorqueTable {
        angle: Some(Table::new(&xs, &ys).unwrap()),
        rate: None,
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

/// How far `b` moves the pair of runs from `a` [deg RMS], noise-free.
pub fn effect_size_between(mechs: &[Mechanism], a: &[Effect], b: &[Effect]) -> f64 {
    let opts = SimOptions {
        stop_when_deployed: false,
        ..SimOptions::default()
    };
    let (mut sse, mut n) = (0.0, 0usize);
    for m in mechs {
        let (Ok(x), Ok(y)) = (
            deployment::simulate(m, a, &opts),
            deployment::simulate(m, b, &opts),
        ) else {
            return 0.0;
        };
        for j in 0..m.joint_count() {
            for (p, q) in x.phi_deg[j].iter().zip(&y.phi_deg[j]) {
                sse += (p - q).powi(2);
                n += 1;
            }
        }
    }
    (sse / n.max(1) as f64).sqrt()
}

/// One hidden torque of `form` at 1-based joint `j`, its amplitude raised
/// until it moves the runs by at least 0.3° RMS. A break-away is two
/// effects at the joint (Coulomb friction at its static level and the
/// table that takes the excess off with rate), raised until it moves the
/// runs by 0.3° from the same friction without its break-away (Coulomb at
/// the kinetic level, the same viscous part): the fall with rate must
/// show, not only the friction.
pub fn hidden_torque(seed: u64, form: Form, mechs: &[Mechanism], j: usize) -> Vec<Effect> {
    let mut amp = if form == Form::SpringDip { 0.05 } else { 0.03 };
    loop {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let table = |table| Effect {
            joint: Some(j),
            law: Law::TorqueTable(table),
        };
        if form == Form::Breakaway {
            let (t, ratio, viscous) = breakaway_table(&mut rng, amp);
            let coulomb = Effect::joint(EffectKind::CoulombFriction, j, ratio * amp);
            // The same friction without its break-away: Coulomb at the
            // kinetic level with the same viscous part.
            let kinetic = [
                Effect::joint(EffectKind::CoulombFriction, j, (ratio - 1.0) * amp),
                Effect::joint(EffectKind::ViscousDamping, j, viscous),
            ];
            let both = vec![coulomb, table(t)];
            if effect_size_between(mechs, &kinetic, &both) >= 0.3 || amp > 2.0 {
                return both;
            }
        } else {
            let e = table(draw_table(&mut rng, form, &mechs[0], j - 1, amp));
            if effect_size(mechs, &[e]) >= 0.3 || amp > 2.0 {
                return vec![e];
            }
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
            joint: None,
            law: Law::RigTilt {
                g_m_s2: 0.03,
                alpha_deg: rng.gen_range(0.0..360.0),
            },
        },
    };
    for _ in 0..12 {
        if effect_size(mechs, &[e]) >= 0.3 {
            break;
        }
        e = e.with_value(e.value() * 1.5);
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
    /// RMS of the noise the sensor added \[deg\].
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
        Family::Alone(f) => hidden_torque(seed, ALONE_FORMS[f % ALONE_FORMS.len()], &mechs, j),
        Family::BesideNamed | Family::FrictionBeside(_) => {
            let form = match family {
                Family::FrictionBeside(f) => FRICTION_FORMS[f % FRICTION_FORMS.len()],
                _ => form,
            };
            let mut t = hidden_torque(seed, form, &mechs, j);
            for _ in 0..rng.gen_range(1..=2) {
                let e = named(&mut rng, &mechs, joints);
                if !t.iter().any(|x| x.kind() == e.kind() && x.joint == e.joint) {
                    t.push(e);
                }
            }
            t
        }
        Family::TwoJoints => {
            let other = 1 + j % joints;
            let form2 = FORMS[rng.gen_range(0..FORMS.len())];
            let mut t = hidden_torque(seed, form, &mechs, j);
            t.extend(hidden_torque(seed + 1, form2, &mechs, other));
            t
        }
        Family::Null => Vec::new(),
    };
    generate(family, seed, pair, truth)
}

fn family_index(f: Family) -> u64 {
    match f {
        Family::Alone(k) if k < FORMS.len() => k as u64,
        Family::Alone(k) => 7 + k as u64,
        Family::FrictionBeside(k) => 20 + k as u64,
        Family::BesideNamed => 4,
        Family::TwoJoints => 5,
        Family::Null => 6,
    }
}

/// Every family: the six forms alone, beside named, the three friction
/// forms beside named, two joints, null.
pub fn families() -> Vec<Family> {
    let mut v: Vec<Family> = (0..ALONE_FORMS.len()).map(Family::Alone).collect();
    v.push(Family::BesideNamed);
    v.extend((0..FRICTION_FORMS.len()).map(Family::FrictionBeside));
    v.extend([Family::TwoJoints, Family::Null]);
    v
}

/// The friction form of a family (alone or beside named), if any: what the
/// tribology criteria count.
pub fn friction_form(f: Family) -> Option<Form> {
    match f {
        Family::Alone(k) => {
            Some(ALONE_FORMS[k % ALONE_FORMS.len()]).filter(|x| FRICTION_FORMS.contains(x))
        }
        Family::FrictionBeside(k) => Some(FRICTION_FORMS[k % FRICTION_FORMS.len()]),
        _ => None,
    }
}

/// The joints (1-based) that hold a per-joint effect of `effects`.
pub fn joints_of(effects: &[Effect]) -> Vec<usize> {
    let mut j: Vec<usize> = effects
        .iter()
        .filter(|e| e.kind() != EffectKind::EncoderOffset || e.value() != 0.0)
        .filter_map(|e| e.joint)
        .collect();
    j.sort();
    j.dedup();
    j
}
