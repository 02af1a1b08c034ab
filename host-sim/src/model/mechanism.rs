//! A mechanism as the host sees it: what a mechanism TOML file
//! (`docs/spec/formats.md`) describes, sized at run time (1 to 8 joints),
//! and its conversion into the core's fixed-size [`Chain`].
//!
//! Reading and validating the TOML lives in [`crate::model::mechanism_toml`].

pub use crate::model::friction_spec::FrictionSpec;
use crate::model::torque_table::{HostChain, HostJointEffects};
use deploywatch_core::{Chain, Curve, Friction, GlobalEffects, Joint, Panel, Real, Spring};
use deploywatch_core::{CurveError, Fold, Interp, TapePoints};

/// Most joints a mechanism, and so a run, may have: the most the on-board
/// monitor's frames carry ([`deploywatch_core::telemetry::config::MAX_JOINTS`],
/// checked below to be the same), so that every mechanism simulated can be
/// monitored (a firmware is built for one joint count of them).
pub const MAX_CHAIN_JOINTS: usize = 8;

const _: () = assert!(deploywatch_core::telemetry::config::MAX_JOINTS == MAX_CHAIN_JOINTS);

/// Calls `$body` with `const $n: usize` set to `$joints` (1 to
/// [`MAX_CHAIN_JOINTS`]), `$other` for any other count: the one dispatch from a
/// run-time joint count to the core's const-generic `Chain<T, N>`,
/// `Monitor<N>`, ...
///
/// ```ignore
/// with_joints!(mech.joint_count(), N => run::<N>(mech), else Err(too_many()))
/// ```
macro_rules! with_joints {
    ($joints:expr, $n:ident => $body:expr, else $other:expr) => {
        $crate::model::mechanism::with_joints!(@arms $joints; $n; $body; $other; 1 2 3 4 5 6 7 8)
    };
    (@arms $joints:expr; $n:ident; $body:expr; $other:expr; $($k:literal)*) => {
        match $joints {
            $($k => {
                const $n: usize = $k;
                $body
            })*
            _ => $other,
        }
    };
}
pub(crate) use with_joints;

// `with_joints!` has one arm per joint count up to `MAX_CHAIN_JOINTS`.
const _: () = assert!(MAX_CHAIN_JOINTS == 8);

/// One hinge spring as written in the file.
#[derive(Clone, Debug, PartialEq)]
pub enum SpringSpec {
    /// `kind = "linear"`: `T = T0 + k|φ|` per hinge.
    Linear {
        /// `preload_nm` [N·m].
        preload_nm: f64,
        /// `stiffness_nm_per_rad` [N·m/rad].
        stiffness_nm_per_rad: f64,
        /// `count` of identical hinges.
        count: u32,
    },
    /// `kind = "tape"`: a tape-spring hinge of a type in `[tape."NAME"]`.
    Tape {
        /// The type's name, e.g. `"TS-1"`.
        type_name: String,
        /// The type's points (seed 001 Table 1).
        points: TapePoints<f64>,
        /// `count` of identical hinges.
        count: u32,
    },
    /// `kind = "curve"`: branches given point by point.
    Curve {
        /// `unfold = [[deg, N·m], ...]`.
        unfold: Vec<(f64, f64)>,
        /// `fold = [[deg, N·m], ...]`, `None` for no hysteresis.
        fold: Option<Vec<(f64, f64)>>,
        /// `interp`, Akima by default.
        interp: Interp,
        /// `count` of identical hinges.
        count: u32,
    },
}

impl SpringSpec {
    /// The core spring this describes, in the float type `T` (`f64` for the
    /// simulator, `f32` for the on-board monitor): every number of the file
    /// converted by [`Real::of`] (rounded to nearest), then checked by the
    /// core ([`Spring::tape`], [`Curve::new`]).
    pub fn to_spring<T: Real>(&self) -> Result<Spring<T>, CurveError> {
        let count = |c: u32| T::of(f64::from(c));
        let pair = |p: (f64, f64)| (T::of(p.0), T::of(p.1));
        let points = |ps: &[(f64, f64)]| ps.iter().map(|&p| pair(p)).collect::<Vec<_>>();
        Ok(match self {
            SpringSpec::Linear {
                preload_nm,
                stiffness_nm_per_rad,
                count: c,
            } => Spring::Linear {
                preload_nm: T::of(*preload_nm),
                stiffness_nm_per_rad: T::of(*stiffness_nm_per_rad),
                count: count(*c),
            },
            SpringSpec::Tape {
                points: p,
                count: c,
                ..
            } => {
                let p = TapePoints {
                    a: pair(p.a),
                    b: pair(p.b),
                    d: pair(p.d),
                    m_90: T::of(p.m_90),
                    c_180: T::of(p.c_180),
                };
                Spring::tape(&p, count(*c))?
            }
            SpringSpec::Curve {
                unfold,
                fold,
                interp,
                count: c,
            } => Spring::Curve {
                unfold: Curve::new(&points(unfold), *interp)?,
                fold: match fold {
                    None => Fold::SameAsUnfold,
                    Some(f) => Fold::Curve(Curve::new(&points(f), *interp)?),
                },
                count: count(*c),
            },
        })
    }
}

impl SpringSpec {
    /// The same spring with its torque times `scale` at every angle (the
    /// preload and stiffness of a linear spring, every moment of a tape
    /// spring's points, every torque of a curve): the spring as built at
    /// a tolerance's edge.
    pub fn scaled(&self, scale: f64) -> SpringSpec {
        let mut out = self.clone();
        match &mut out {
            SpringSpec::Linear {
                preload_nm,
                stiffness_nm_per_rad,
                ..
            } => {
                *preload_nm *= scale;
                *stiffness_nm_per_rad *= scale;
            }
            SpringSpec::Tape { points, .. } => {
                for p in [&mut points.a, &mut points.b, &mut points.d] {
                    p.1 *= scale;
                }
                points.m_90 *= scale;
                points.c_180 *= scale;
            }
            SpringSpec::Curve { unfold, fold, .. } => {
                for p in unfold.iter_mut().chain(fold.iter_mut().flatten()) {
                    p.1 *= scale;
                }
            }
        }
        out
    }
}

/// One joint as written in the file.
#[derive(Clone, Debug, PartialEq)]
pub struct JointSpec {
    /// `stowed_deg`: the initial angle \[deg\]; the latch angle is 0.
    pub stowed_deg: f64,
    /// The hinge spring(s).
    pub spring: SpringSpec,
    /// The joint's friction.
    pub friction: FrictionSpec,
    /// `free_play_deg`: the hinge's drawn free-play, a half band \[deg\]
    /// (0: none declared; this project's extension, `docs/spec/formats.md`).
    /// Not simulated: the diagnosis reads an encoder offset within it as the
    /// play held to one side by the spring
    /// ([`crate::analysis::diagnose::free_play`]).
    pub free_play_deg: f64,
    /// `spring_tolerance_pct`: the declared half band of the spring's
    /// torque at every angle, in percent of the drawn torque (0: none
    /// declared; this project's extension, `docs/spec/formats.md`). Not
    /// simulated: the diagnosis carries it into its intervals
    /// ([`crate::analysis::diagnose::tolerance`]).
    pub spring_tolerance_pct: f64,
}

/// The declared tolerance of one panel's mass properties: half bands of
/// `mass_kg` and `inertia_kgm2` in percent of their drawn values (0: none
/// declared; this project's extension, `docs/spec/formats.md`). Not
/// simulated: the diagnosis carries them into its intervals
/// ([`crate::analysis::diagnose::tolerance`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MassTolerance {
    /// `mass_tolerance_pct` \[%\].
    pub mass_pct: f64,
    /// `inertia_tolerance_pct` \[%\].
    pub inertia_pct: f64,
}

impl MassTolerance {
    /// True when neither tolerance is declared.
    pub fn is_none(&self) -> bool {
        self.mass_pct == 0.0 && self.inertia_pct == 0.0
    }
}

/// A mechanism: panels, joints and the run settings.
#[derive(Clone, Debug, PartialEq)]
pub struct Mechanism {
    /// `name`, which runs refer to in their `mechanism` metadata.
    pub name: String,
    /// `description`, free text.
    pub description: String,
    /// `[[panel]]` tables, bus outwards.
    pub panels: Vec<Panel<f64>>,
    /// Each panel's declared mass-property tolerance, in the order of
    /// `panels` ([`Mechanism::mass_tolerance`] reads it; a panel beyond the
    /// list has none).
    pub mass_tolerances: Vec<MassTolerance>,
    /// `[[joint]]` tables; joint j drives panel j.
    pub joints: Vec<JointSpec>,
    /// `[run] duration_s`: simulate until every joint latched or this time \[s\].
    pub duration_s: f64,
    /// `[run] sample_hz` \[Hz\].
    pub sample_hz: f64,
    /// `[run] settle_s`: how long a run goes on recording after the first
    /// sample at or after the last latch \[s\] (`formats.md`).
    pub settle_s: f64,
    /// `[truss]`: links on the panels (`None`: the open chain).
    pub truss: Option<crate::model::truss::Truss>,
    /// `[joint.latch]` of each joint (`None`, or an empty list: the ideal
    /// latch of `physics.md` section 5; [`crate::model::latch`]).
    pub latches: Vec<Option<crate::model::latch::LatchSpec>>,
    /// `[rig]`: the zero-g rig the panels are tested on (`None`: no rig;
    /// [`crate::model::rig`], this project's extension).
    pub rig: Option<crate::model::rig::Rig>,
    /// `[flexible_panels]`: every panel two halves on a flex hinge
    /// (`None`: rigid panels; [`crate::model::flex`], this project's
    /// extension).
    pub flexible: Option<crate::model::flex::PanelFlex>,
}

impl Mechanism {
    /// Number of joints (= panels).
    pub fn joint_count(&self) -> usize {
        self.joints.len()
    }

    /// The physical latch of joint `j` (0-based), `None` for the ideal one.
    pub fn latch(&self, j: usize) -> Option<&crate::model::latch::LatchSpec> {
        self.latches.get(j).and_then(Option::as_ref)
    }

    /// The rig, when the file has one and it is enabled.
    pub fn active_rig(&self) -> Option<&crate::model::rig::Rig> {
        self.rig.as_ref().filter(|r| r.enabled)
    }

    /// The same mechanism as it flies: the rig taken out (`--flight`).
    pub fn flight(&self) -> Mechanism {
        Mechanism {
            rig: None,
            ..self.clone()
        }
    }

    /// The declared mass-property tolerance of panel `i` (0-based); none
    /// for a panel the list does not reach.
    pub fn mass_tolerance(&self, i: usize) -> MassTolerance {
        self.mass_tolerances.get(i).copied().unwrap_or_default()
    }

    /// True when some joint has a physical latch.
    pub fn has_physical_latch(&self) -> bool {
        self.latches.iter().any(Option::is_some)
    }

    /// Joints an effect or an identification may name: the hinges `1..=n`,
    /// then, on a wing with a truss, one per friction node
    /// ([`crate::model::truss::Truss::friction_nodes`]): 3 for the seed 000
    /// truss wing (joint 3 = the pins at F).
    pub fn effect_joints(&self) -> usize {
        self.joint_count() + self.truss.as_ref().map_or(0, |t| t.friction_nodes().len())
    }

    /// A joint for people: `joint 2`, or `joint 3 (truss node F)` for a
    /// friction node of a truss.
    pub fn joint_label(&self, joint: usize) -> String {
        let n = self.joint_count();
        match &self.truss {
            Some(t) if joint > n => match t.friction_nodes().get(joint - n - 1) {
                Some(&i) => format!("joint {joint} (truss node {})", t.points[i].name),
                None => format!("joint {joint}"),
            },
            _ => format!("joint {joint}"),
        }
    }

    /// The core chain with `N = self.joint_count()` joints and the given
    /// per-joint and global effects (`effects.len()` must be `N`).
    ///
    /// Returns `None` if `N` does not match; the panel and spring data were
    /// validated when the file was read.
    pub fn chain<const N: usize>(
        &self,
        effects: &[HostJointEffects],
        global: GlobalEffects<f64>,
    ) -> Option<HostChain<N>> {
        if self.joints.len() != N || self.panels.len() != N || effects.len() != N {
            return None;
        }
        let panels: [Panel<f64>; N] = core::array::from_fn(|i| self.panels[i]);
        let mut joints = [Joint {
            stowed_rad: 0.0,
            spring: Spring::None,
            friction: Friction::default(),
            effects: HostJointEffects::default(),
        }; N];
        for (i, j) in self.joints.iter().enumerate() {
            joints[i] = Joint {
                stowed_rad: j.stowed_deg.to_radians(),
                spring: j.spring.to_spring().ok()?,
                friction: j.friction.to_friction(),
                effects: effects[i],
            };
        }
        Chain::new(panels, joints, global).ok()
    }
}

impl Mechanism {
    /// This mechanism with every physical latch as built: five draws of
    /// `uniform` (each in [0, 1)) per physical latch, joint by joint, mapped
    /// to [−1, 1] for [`crate::model::latch::LatchSpec::as_built`], and a
    /// sixth for a pawl's breaking torque
    /// ([`crate::model::latch::LatchSpec::draw_as_built`]). Ideal latches
    /// draw nothing.
    pub fn as_built(
        &self,
        tol: &crate::model::latch::LatchTolerance,
        uniform: &mut dyn FnMut() -> f64,
    ) -> Self {
        let mut m = self.clone();
        for latch in m.latches.iter_mut().flatten() {
            *latch = latch.draw_as_built(tol, uniform);
        }
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mechanism_as_built_draws_only_its_physical_latches() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/mechanisms");
        let t = crate::model::latch::LatchTolerance::default();
        let mut state = 0.0_f64;
        let mut draws = 0;
        let mut uniform = || {
            draws += 1;
            state = (state + 0.618_033_988_75) % 1.0;
            state
        };
        let ideal = Mechanism::load(&root.join("seed001_T01.toml"));
        let ideal = ideal.expect("bundled mechanism");
        assert_eq!(ideal.as_built(&t, &mut uniform), ideal);
        let drawn = Mechanism::load(&root.join("seed001_T01_physical_latch.toml"))
            .expect("bundled mechanism");
        let built = drawn.as_built(&t, &mut uniform);
        assert_eq!(draws, 15);
        for j in 0..3 {
            let (d, b) = (
                drawn.latch(j).expect("drawn"),
                built.latch(j).expect("built"),
            );
            assert_ne!(d, b, "joint {} unchanged", j + 1);
            let r = b.plunger.preload_n / d.plunger.preload_n;
            assert!((0.8..=1.2).contains(&r), "preload ratio {r}");
        }
    }
}
