//! A generator of random valid wings: 2–8 panels; linear, tape
//! and curve (Akima) springs; ideal, plunger + magnet and pawl latches mixed
//! in one wing; with and without a `[rig]`; friction and named effects
//! (Coulomb friction, viscous damping at a joint; air drag) drawn. It writes the
//! mechanism TOML text (`docs/spec/formats.md`), so a test loads it as a
//! user's file and the parser is exercised too. The wing is a function of
//! its seed only: a failing seed reproduces the wing.

use crate::SplitMix;
use deploywatch_sim::effect::{Effect, EffectKind};

/// What [`wing_toml`] drew besides the text.
#[derive(Clone, Debug, PartialEq)]
pub struct Wing {
    /// The mechanism TOML text.
    pub toml: String,
    /// Joint count (2–8).
    pub joints: usize,
    /// Joints (1-based) with a physical latch.
    pub physical: Vec<usize>,
    /// True when an enabled `[rig]` was written.
    pub rig: bool,
    /// Named effects to simulate the wing with (`--effect`), none on most
    /// wings.
    pub effects: Vec<Effect>,
}

fn uniform(r: &mut SplitMix, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * r.next_f64()
}

fn pick(r: &mut SplitMix, n: usize) -> usize {
    // n ≤ 8: the product is below n and the cast exact.
    ((r.next_f64() * n as f64) as usize).min(n - 1)
}

/// The `spring = {...}` of one joint.
fn spring(r: &mut SplitMix) -> String {
    match pick(r, 3) {
        0 => format!(
            "{{ kind = \"linear\", preload_nm = {:.4}, stiffness_nm_per_rad = {:.4}, count = {} }}",
            uniform(r, 0.8, 2.0),
            uniform(r, 0.1, 0.8),
            1 + pick(r, 3)
        ),
        1 => format!(
            "{{ kind = \"tape\", type = \"TS-{}\", count = {} }}",
            1 + pick(r, 3),
            2 + pick(r, 2)
        ),
        _ => {
            let (a, b, c) = (
                uniform(r, 0.8, 1.5),
                uniform(r, 1.5, 2.5),
                uniform(r, 2.5, 3.5),
            );
            format!(
                "{{ kind = \"curve\", unfold = [[0.0, {a:.4}], [60.0, {b:.4}], [120.0, {c:.4}], [180.0, {c:.4}]], interp = \"akima\", count = 1 }}"
            )
        }
    }
}

/// A physical latch table: a plunger (with or without a magnet) or a pawl.
fn latch(r: &mut SplitMix) -> String {
    let head = "[joint.latch]\nmodel = \"physical\"\n";
    if r.next_f64() < 0.5 {
        let magnet = if r.next_f64() < 0.5 {
            "magnet = { force_n = 15.0, decay_mm = 0.5, reach_mm = 2.0, radius_mm = 40.0 }\n"
        } else {
            ""
        };
        format!(
            "{head}switch_travel_deg = 0.05\nstop = {{ radius_mm = 40.0 }}\n\
             plunger = {{ preload_n = {:.2}, stiffness_n_per_mm = 10.0, radius_mm = 40.0, stroke_mm = 0.8, \
             crest_deg = 0.6, entry_ramp_deg = 30.0, hold_ramp_deg = 50.0 }}\n{magnet}",
            uniform(r, 15.0, 30.0)
        )
    } else {
        format!(
            "{head}switch_travel_deg = 0.35\nstop = {{ radius_mm = 40.0 }}\n\
             pawl = {{ preload_n = 5.0, stiffness_n_per_mm = 2.0, radius_mm = 40.0, lift_mm = 1.0, \
             notch_deg = 0.3, cam_ramp_deg = 20.0, breaking_torque_nm = {:.1} }}\n",
            uniform(r, 800.0, 1500.0)
        )
    }
}

const TAPES: &str = "[tape.\"TS-1\"]\na = [1.10, 69.39]\nb = [1.10, 1.50]\nd = [0.52, 37.0]\nm_90 = 1.20\nc_180 = 2.32\n\n\
[tape.\"TS-2\"]\na = [1.26, 58.20]\nb = [1.28, 0.86]\nd = [0.65, 26.0]\nm_90 = 0.80\nc_180 = 1.46\n\n\
[tape.\"TS-3\"]\na = [1.08, 33.43]\nb = [1.15, 0.46]\nd = [0.29, 11.07]\nm_90 = 0.385\nc_180 = 0.74\n";

/// The share of physical latches among the joints the tests draw
/// (`tests/random_wings.rs` and the census of
/// `tests/examples/stowed_census.rs`).
pub const PHYSICAL_SHARE: f64 = 0.25;

/// A random valid wing from `seed`; `physical_share` of its joints (drawn)
/// get a physical latch, the others the ideal latch.
pub fn wing_toml(seed: u64, physical_share: f64) -> Wing {
    let mut r = SplitMix(seed);
    let joints = 2 + pick(&mut r, 7);
    let mut t = format!("name = \"random-{seed}\"\n\n");
    for _ in 0..joints {
        let mass = uniform(&mut r, 0.5, 4.0);
        let len = uniform(&mut r, 0.3, 1.0);
        t += &format!(
            "[[panel]]\nlength_m = {len:.4}\nmass_kg = {mass:.4}\ncom_m = {:.4}\ninertia_kgm2 = {:.5}\n\n",
            len / 2.0,
            mass * len * len / 12.0
        );
    }
    let mut physical = Vec::new();
    for j in 1..=joints {
        let stowed = match j {
            1 => -90.0,
            _ if j % 2 == 0 => 180.0,
            _ => -180.0,
        };
        t += &format!(
            "[[joint]]\nstowed_deg = {stowed:.1}\nspring = {}\n",
            spring(&mut r)
        );
        if r.next_f64() < 0.7 {
            t += &format!(
                "friction = {{ coulomb_nm = {:.3} }}\n",
                uniform(&mut r, 0.0, 0.3)
            );
        }
        if r.next_f64() < physical_share {
            t += &latch(&mut r);
            physical.push(j);
        }
        t += "\n";
    }
    t += TAPES;
    let rig = r.next_f64() < 0.3;
    if rig {
        t += "\n[rig]\n[[rig.bar]]\nmass_kg = 2.0\n[[rig.trolley]]\npanel = 1\nbar = 1\nmass_kg = 0.3\nwire_m = 1.5\n";
    }
    t += "\n[run]\nduration_s = 8.0\nsample_hz = 100.0\n";
    let effects = effects(&mut r, joints);
    Wing {
        toml: t,
        joints,
        physical,
        rig,
        effects,
    }
}

/// Named effects drawn for a wing of `joints` joints: none on half the
/// wings; otherwise Coulomb friction \[N·m\] or viscous damping
/// \[N·m·s/rad\] at a drawn joint, or air drag \[kg/m²\].
fn effects(r: &mut SplitMix, joints: usize) -> Vec<Effect> {
    if r.next_f64() < 0.5 {
        return Vec::new();
    }
    let joint = 1 + pick(r, joints);
    vec![match pick(r, 3) {
        0 => Effect::joint(EffectKind::CoulombFriction, joint, uniform(r, 0.05, 0.5)),
        1 => Effect::joint(EffectKind::ViscousDamping, joint, uniform(r, 0.05, 1.0)),
        _ => Effect::global(EffectKind::AirDrag, uniform(r, 0.05, 0.5)),
    }]
}
