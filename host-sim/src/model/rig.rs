//! The zero-g rig a deployment is tested on (`[rig]` of a mechanism file,
//! `docs/spec/formats.md`; physics in `docs/spec/physics.md` §11, this
//! project's extension): per panel a trolley on the overhead bars that
//! carries it by a wire, the air bearings' stick–slip friction, and the
//! test frames as stops with the papers' Hertz contact (seed 001 §3, §4.2).
//!
//! The chain stays the planar chain of `physics.md` §1 in the horizontal
//! plane (x out from the bus, y lateral); the rig adds one degree of
//! freedom per trolley (along its bar, x) and one per bar (the bar sliding
//! laterally on its air bearings, y), and their forces on the panels.

use crate::model::effect::{Acts, Effect, RigPart};
use deploywatch_core::Panel;

/// Standard gravity [m/s²], the default of `[rig] gravity_m_s2`.
pub const STANDARD_GRAVITY_M_S2: f64 = 9.80665;

/// The papers' Hertz contact stiffness `k` [N/mm^1.5] (seed 001 §4.2).
pub const PAPER_CONTACT_STIFFNESS: f64 = 37_000.0;

/// The papers' contact damping `c` [N·s/mm^1.25] (seed 001 §4.2).
pub const PAPER_CONTACT_DAMPING: f64 = 3.7;

/// The papers' static friction coefficient of air bearing on rail \[1\].
pub const PAPER_STATIC_MU: f64 = 0.3;

/// The papers' dynamic friction coefficient of air bearing on rail \[1\].
pub const PAPER_DYNAMIC_MU: f64 = 0.1;

/// The shortest wire a `wire_length` cause leaves \[m\]: a wire shortened
/// further would no longer hang its panel.
pub const MIN_WIRE_M: f64 = 0.05;

/// How far a stowed panel's tip may sit beyond a frame's face \[m\]
/// before the rig is refused: 1 µm, the rounding of a face written at the
/// tip's own coordinate.
pub const STOWED_CLEARANCE_M: f64 = 1e-6;

/// The outboard tip of each panel \[m\] (x out from the bus, y lateral)
/// with the joints at `phi` \[rad\]: the chain's kinematics of
/// `physics.md` §1, absolute angle `θ_i = Σ_{k ≤ i} φ_k`.
pub fn panel_tips(panels: &[Panel<f64>], phi: &[f64]) -> Vec<[f64; 2]> {
    let (mut th, mut p) = (0.0, [0.0; 2]);
    panels
        .iter()
        .zip(phi)
        .map(|(panel, &f)| {
            th += f;
            p = [
                p[0] + panel.length_m * th.cos(),
                p[1] + panel.length_m * th.sin(),
            ];
            p
        })
        .collect()
}

/// One trolley: it runs along its bar (x) and carries panel `panel` by a
/// wire from the panel's offload point.
#[derive(Clone, Debug, PartialEq)]
pub struct Trolley {
    /// The panel it carries (1-based).
    pub panel: usize,
    /// The offload point: distance from the panel's inboard hinge along
    /// the panel \[m\] (default its centre of mass).
    pub offload_m: f64,
    /// The trolley's mass \[kg\] (moves along the bar).
    pub mass_kg: f64,
    /// The bar it runs on (1-based).
    pub bar: usize,
    /// The suspension wire's length \[m\].
    pub wire_m: f64,
    /// The wire's spring [N/m] (`None`: an inextensible wire).
    pub wire_spring_n_per_m: Option<f64>,
    /// Where the trolley starts \[m\] (`None`: above the offload point of
    /// the stowed panel).
    pub start_m: Option<[f64; 2]>,
}

/// One overhead bar: it slides laterally (y) on air bearings and carries
/// its trolleys.
#[derive(Clone, Debug, PartialEq)]
pub struct Bar {
    /// The bar's own mass \[kg\] (moves laterally with its trolleys).
    pub mass_kg: f64,
}

/// A test frame as a stop: the allowed side is `normal · p ≥ at_m`.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// Its name in reports (e.g. `"lateral -y"`).
    pub name: String,
    /// Unit normal pointing into the allowed side \[1\].
    pub normal: [f64; 2],
    /// Offset of the frame's face along the normal \[m\].
    pub at_m: f64,
}

/// The rig (`[rig]`).
#[derive(Clone, Debug, PartialEq)]
pub struct Rig {
    /// `enabled` (default true): false is the flight configuration, the
    /// file keeps the rig's description.
    pub enabled: bool,
    /// Gravity [m/s²], which the wires offload.
    pub gravity_m_s2: f64,
    /// Static friction coefficient of the air bearings on their rails \[1\].
    pub static_mu: f64,
    /// Dynamic friction coefficient \[1\].
    pub dynamic_mu: f64,
    /// The share of the carried weight that presses the bearings on their
    /// rails \[1\] (default 1: the whole carried load; an air bearing that
    /// floats most of it takes less).
    pub friction_load_fraction: f64,
    /// The speed below which the friction rises from dynamic to static
    /// (the Stribeck speed of the law) [m/s].
    pub stick_speed_m_s: f64,
    /// The regularisation speed of the friction's sign [m/s].
    pub slip_speed_m_s: f64,
    /// Hertz contact stiffness [N/mm^1.5].
    pub contact_stiffness: f64,
    /// Contact damping [N·s/mm^1.25].
    pub contact_damping: f64,
    /// The trolleys, one per panel.
    pub trolleys: Vec<Trolley>,
    /// The bars.
    pub bars: Vec<Bar>,
    /// The frames.
    pub frames: Vec<Frame>,
}

/// What is wrong with a `[rig]` table's contents (beyond its keys' types).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum RigError {
    /// A trolley carries a panel that does not exist, or two carry one.
    #[error("rig.trolley[{index}]: panel {panel}: expected each of panels 1 to {panels} once")]
    Panel {
        /// 1-based trolley.
        index: usize,
        /// The panel given.
        panel: usize,
        /// The mechanism's panels.
        panels: usize,
    },
    /// A trolley on a bar that does not exist.
    #[error("rig.trolley[{index}]: bar {bar}: the rig has {}", crate::report::text::one_to(*bars, "bar", "bars"))]
    Bar {
        /// 1-based trolley.
        index: usize,
        /// The bar given.
        bar: usize,
        /// The rig's bars.
        bars: usize,
    },
    /// The dynamic friction exceeds the static.
    #[error("rig: dynamic_mu {dynamic} exceeds static_mu {stat}")]
    Friction {
        /// Static.
        stat: f64,
        /// Dynamic.
        dynamic: f64,
    },
    /// A frame's normal of zero length.
    #[error("rig.frame[{index}]: normal must not be zero")]
    Normal {
        /// 1-based frame.
        index: usize,
    },
    /// A trolley's offload point off its panel.
    #[error("rig.trolley[{index}]: offload_m {offload_m} m is off panel {panel}, which runs from its hinge (0 m) to its tip ({length_m} m)")]
    Offload {
        /// 1-based trolley.
        index: usize,
        /// The panel it carries (1-based).
        panel: usize,
        /// The offload point given \[m\].
        offload_m: f64,
        /// The panel's length \[m\].
        length_m: f64,
    },
    /// A share of the carried weight above the whole of it.
    #[error("rig: friction_load_fraction {fraction} is more than the whole carried weight (1)")]
    LoadFraction {
        /// The fraction given.
        fraction: f64,
    },
    /// A frame the stowed wing already crosses: the run would start inside
    /// it.
    #[error("rig.frame[{index}] \"{name}\": panel {panel}'s tip is {depth_mm:.1} mm beyond its face when stowed (the allowed side is normal · p ≥ at_m): a normal pointing out of the allowed side, or at_m of the other sign?")]
    CrossedWhenStowed {
        /// 1-based frame.
        index: usize,
        /// Its name.
        name: String,
        /// The deepest panel (1-based).
        panel: usize,
        /// How far its tip is beyond the face \[mm\].
        depth_mm: f64,
    },
}

impl Rig {
    /// Checks the rig against a mechanism's `panels` stowed at
    /// `stowed_rad` (its joints' stowed angles \[rad\], as the chain takes
    /// them): each panel carried once, by a trolley on a bar that exists, at
    /// a point on the panel; friction coefficients and load share in range;
    /// no frame crossed by a panel's tip before the run starts.
    pub fn check(&self, panels: &[Panel<f64>], stowed_rad: &[f64]) -> Result<(), RigError> {
        let mut seen = vec![false; panels.len()];
        for (i, t) in self.trolleys.iter().enumerate() {
            if t.panel == 0 || t.panel > panels.len() || seen[t.panel - 1] {
                return Err(RigError::Panel {
                    index: i + 1,
                    panel: t.panel,
                    panels: panels.len(),
                });
            }
            seen[t.panel - 1] = true;
            if t.bar == 0 || t.bar > self.bars.len() {
                return Err(RigError::Bar {
                    index: i + 1,
                    bar: t.bar,
                    bars: self.bars.len(),
                });
            }
            let length_m = panels[t.panel - 1].length_m;
            if !(0.0..=length_m).contains(&t.offload_m) {
                return Err(RigError::Offload {
                    index: i + 1,
                    panel: t.panel,
                    offload_m: t.offload_m,
                    length_m,
                });
            }
        }
        if self.dynamic_mu > self.static_mu {
            return Err(RigError::Friction {
                stat: self.static_mu,
                dynamic: self.dynamic_mu,
            });
        }
        if self.friction_load_fraction > 1.0 {
            return Err(RigError::LoadFraction {
                fraction: self.friction_load_fraction,
            });
        }
        let tips = panel_tips(panels, stowed_rad);
        for (i, f) in self.frames.iter().enumerate() {
            if f.normal[0].hypot(f.normal[1]) == 0.0 {
                return Err(RigError::Normal { index: i + 1 });
            }
            // The innermost of the deepest tips.
            let deepest = tips
                .iter()
                .map(|p| f.at_m - (f.normal[0] * p[0] + f.normal[1] * p[1]))
                .enumerate()
                .fold(None, |best: Option<(usize, f64)>, (i, d)| match best {
                    Some((_, b)) if b >= d => best,
                    _ => Some((i, d)),
                });
            if let Some((panel, depth)) = deepest.filter(|&(_, d)| d > STOWED_CLEARANCE_M) {
                return Err(RigError::CrossedWhenStowed {
                    index: i + 1,
                    name: f.name.clone(),
                    panel: panel + 1,
                    depth_mm: depth * 1e3,
                });
            }
        }
        Ok(())
    }

    /// The friction coefficient at slip speed `v` [m/s], signed like `v`:
    /// `μ(v) = [μ_d + (μ_s − μ_d) exp(−(v/v_s)²)] tanh(v/v_ε)` (the
    /// papers' friction law, seed 001 Eq. 4, on a rail).
    pub fn mu(&self, v: f64) -> f64 {
        let stribeck = (-(v / self.stick_speed_m_s).powi(2)).exp();
        (self.dynamic_mu + (self.static_mu - self.dynamic_mu) * stribeck)
            * (v / self.slip_speed_m_s).tanh()
    }

    /// The rail's friction force \[N\] on a carriage carrying `load_n` \[N\]
    /// slipping at `v` [m/s], signed like `v`: `f N μ(v)`, `f` the
    /// [`Rig::friction_load_fraction`].
    pub fn rail_force(&self, load_n: f64, v: f64) -> f64 {
        self.friction_load_fraction * load_n * self.mu(v)
    }

    /// The wire's effective pendulum length \[m\]: its length plus the
    /// spring's static stretch under the carried weight.
    pub fn pendulum_m(&self, t: &Trolley, carried_kg: f64) -> f64 {
        t.wire_m
            + t.wire_spring_n_per_m
                .map_or(0.0, |k| carried_kg * self.gravity_m_s2 / k)
    }

    /// The rig with the rig causes among `effects` applied
    /// (`physics.md` §11.7; every other effect is left to the chain):
    /// `rig_friction` `Δμ` adds to the dynamic coefficient of every rail
    /// and `Δμ · μ_s/μ_d` (the drawing's ratio; the papers' 3 when the
    /// drawing has no friction) to the static one; `wire_length` `ΔL` adds
    /// to every wire (never below [`MIN_WIRE_M`]); `frame_offset` `Δd`
    /// moves every frame's face along its normal toward the panels
    /// (`a ← a + Δd |n|`: positive leaves less clearance).
    pub fn with_effects(&self, effects: &[Effect]) -> Rig {
        let mut r = self.clone();
        let ratio = if self.dynamic_mu > 0.0 {
            self.static_mu / self.dynamic_mu
        } else {
            PAPER_STATIC_MU / PAPER_DYNAMIC_MU
        };
        for e in effects {
            // Only the rig's causes ([`Acts::Rig`]): the chain's, the
            // sensor's and the physical latch's act elsewhere.
            let Acts::Rig(part) = e.kind().acts() else {
                continue;
            };
            let v = e.value();
            match part {
                RigPart::RailFriction => {
                    r.dynamic_mu = (r.dynamic_mu + v).max(0.0);
                    r.static_mu = (r.static_mu + ratio * v).max(r.dynamic_mu);
                }
                RigPart::WireLength => {
                    for t in &mut r.trolleys {
                        t.wire_m = (t.wire_m + v).max(MIN_WIRE_M);
                    }
                }
                RigPart::FrameOffset => {
                    for f in &mut r.frames {
                        f.at_m += v * f.normal[0].hypot(f.normal[1]);
                    }
                }
            }
        }
        r
    }

    /// The same rig on frictionless rails (`μ_s = μ_d = 0`): the rig whose
    /// friction an equivalent friction torque at the hinges lumps
    /// (`docs/margin.md`, "The margin in flight").
    pub fn frictionless(&self) -> Rig {
        Rig {
            static_mu: 0.0,
            dynamic_mu: 0.0,
            ..self.clone()
        }
    }
}
