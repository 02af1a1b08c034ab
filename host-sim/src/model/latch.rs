//! A joint's physical latch as written in the mechanism file's
//! `[joint.latch]` table (`docs/spec/formats.md`, "Physical latch", this
//! project's extension), in the file's units, and its conversion to the
//! core's [`PhysicalLatch`] ([`deploywatch_core::physics::latch_contact`]).
//! Read and written by [`crate::model::latch_toml`].

use deploywatch_core::physics::latch_contact::{HertzStop, Magnet, PhysicalLatch, Plunger};
use deploywatch_core::physics::latch_contact::{Lock, Pawl};
use deploywatch_core::Real;

/// The papers' contact stiffness `k` [N/mm^1.5] (seed 000 §4.2, seed 001
/// §4.2): the default of `stop.stiffness_n_per_mm1_5`.
pub const PAPER_STIFFNESS_N_PER_MM1_5: f64 = 37_000.0;

/// The papers' contact damping `c` [N·s/mm^1.25] (seed 000 §4.2, seed 001
/// §4.2): the default of `stop.damping_ns_per_mm1_25`.
pub const PAPER_DAMPING_NS_PER_MM1_25: f64 = 3.7;

/// The stop as written: Hertz contact at a radius.
#[derive(Clone, Debug, PartialEq)]
pub struct StopSpec {
    /// `radius_mm`: contact distance from the hinge axis \[mm\].
    pub radius_mm: f64,
    /// `stiffness_n_per_mm1_5` [N/mm^1.5].
    pub stiffness_n_per_mm1_5: f64,
    /// `damping_ns_per_mm1_25` [N·s/mm^1.25].
    pub damping_ns_per_mm1_25: f64,
}

/// The ball plunger as written.
#[derive(Clone, Debug, PartialEq)]
pub struct PlungerSpec {
    /// `preload_n` \[N\].
    pub preload_n: f64,
    /// `stiffness_n_per_mm` [N/mm].
    pub stiffness_n_per_mm: f64,
    /// `radius_mm` \[mm\].
    pub radius_mm: f64,
    /// `stroke_mm`: ball depression at the crest \[mm\].
    pub stroke_mm: f64,
    /// `crest_deg`: travel from the stop of the crest \[deg\].
    pub crest_deg: f64,
    /// `entry_ramp_deg` \[deg\].
    pub entry_ramp_deg: f64,
    /// `hold_ramp_deg` \[deg\].
    pub hold_ramp_deg: f64,
}

/// The magnet as written.
#[derive(Clone, Debug, PartialEq)]
pub struct MagnetSpec {
    /// `force_n`: attraction at contact \[N\].
    pub force_n: f64,
    /// `decay_mm` \[mm\].
    pub decay_mm: f64,
    /// `reach_mm` \[mm\].
    pub reach_mm: f64,
    /// `radius_mm` \[mm\].
    pub radius_mm: f64,
}

/// A joint's physical latch as written in `[joint.latch]`.
#[derive(Clone, Debug, PartialEq)]
pub struct LatchSpec {
    /// `switch_travel_deg` \[deg\].
    pub switch_travel_deg: f64,
    /// `stop`.
    pub stop: StopSpec,
    /// `plunger`; with a pawl, the pawl's spring on its cam as the core
    /// takes it (`pawl.preload_n`, `stiffness_n_per_mm`, `radius_mm`; the
    /// stroke is `lift_mm`, the crest `notch_deg`, the entry ramp
    /// `cam_ramp_deg`; the hold ramp, unused, the cam's angle).
    pub plunger: PlungerSpec,
    /// `magnet`, `None` without one.
    pub magnet: Option<MagnetSpec>,
    /// `pawl.breaking_torque_nm` [N·m] of a latch written with a `pawl`
    /// table (a positive lock, `physics.md` §10.5); `None`: a ball plunger.
    pub pawl: Option<Pawl<f64>>,
}

/// Millimetres per metre.
const MM_PER_M: f64 = 1000.0;

impl LatchSpec {
    /// How far back from the stop the joint may go and still be held [deg
    /// of travel], for a joint stowed at `stowed_deg`: the plunger's crest,
    /// or for a pawl its notch plus the contact's give under its breaking
    /// torque (beyond that the pawl has broken; `physics.md` §10.5).
    pub fn hold_limit_deg(&self, stowed_deg: f64) -> f64 {
        match self.pawl {
            Some(_) => self
                .to_core::<f64>(stowed_deg, 1.0, 1.0)
                .breaking_travel_rad()
                .to_degrees(),
            None => self.plunger.crest_deg,
        }
    }

    /// The core's latch, in `f64` for the simulator or `f32` for the
    /// on-board monitor, for a joint stowed at `stowed_deg`, with the
    /// plunger's preload and rate scaled by `plunger_scale` and the magnet's
    /// force by `magnet_scale` (`1 − weakening`).
    pub fn to_core<T: Real>(
        &self,
        stowed_deg: f64,
        plunger_scale: f64,
        magnet_scale: f64,
    ) -> PhysicalLatch<T> {
        let (s, p) = (&self.stop, &self.plunger);
        let mm = |x: f64| T::of(x / MM_PER_M);
        let rad = |deg: f64| T::of(deg.to_radians());
        let magnet = match &self.magnet {
            Some(m) => Magnet {
                force_n: T::of(m.force_n * magnet_scale),
                decay_mm: T::of(m.decay_mm),
                reach_mm: T::of(m.reach_mm),
                radius_m: mm(m.radius_mm),
            },
            None => Magnet {
                force_n: T::ZERO,
                decay_mm: T::ONE,
                reach_mm: T::ZERO,
                radius_m: mm(s.radius_mm),
            },
        };
        PhysicalLatch {
            side: if stowed_deg >= 0.0 { T::ONE } else { -T::ONE },
            stop: HertzStop {
                stiffness_n_per_mm1_5: T::of(s.stiffness_n_per_mm1_5),
                damping_ns_per_mm1_25: T::of(s.damping_ns_per_mm1_25),
                radius_m: mm(s.radius_mm),
            },
            plunger: Plunger {
                preload_n: T::of(p.preload_n * plunger_scale),
                stiffness_n_per_mm: T::of(p.stiffness_n_per_mm * plunger_scale),
                radius_m: mm(p.radius_mm),
                stroke_mm: T::of(p.stroke_mm),
                crest_rad: rad(p.crest_deg),
                entry_ramp_rad: rad(p.entry_ramp_deg),
                hold_ramp_rad: rad(p.hold_ramp_deg),
            },
            magnet,
            switch_travel_rad: rad(self.switch_travel_deg),
            lock: match self.pawl {
                Some(p) => Lock::Pawl(Pawl {
                    breaking_torque_nm: T::of(p.breaking_torque_nm),
                }),
                None => Lock::Detent,
            },
        }
    }
}

/// How far a physical latch as built may differ from its drawing: the
/// tolerances of a real ball plunger, magnet and stop, each a half-width of a
/// uniform spread around the drawing's value.
///
/// [`LatchTolerance::default`] holds the figures of a commercial M8 ball
/// plunger and a small NdFeB magnet as bought (a vendor's preload and rate
/// ±20 %, a magnet's pull ±30 % with grade and gap, the stop's damping ±30 %)
/// and a crest machined to ±0.1°: deploywatch's own figures, the ones the
/// physical-latch campaigns of `docs/diagnosis.md` draw from. A pawl's
/// spring takes the plunger's spreads, its notch the crest's, and its
/// breaking torque ±15 % (the scatter of a machined part's strength,
/// deploywatch's own figure).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LatchTolerance {
    /// Relative spread of the plunger's preload \[1\].
    pub plunger_preload: f64,
    /// Relative spread of the plunger's rate \[1\].
    pub plunger_stiffness: f64,
    /// Relative spread of the magnet's force at contact \[1\].
    pub magnet_force: f64,
    /// Relative spread of the stop's contact damping \[1\].
    pub stop_damping: f64,
    /// Absolute spread of the crest's position \[deg\].
    pub crest_deg: f64,
    /// Relative spread of a pawl's breaking torque \[1\].
    pub breaking_torque: f64,
}

impl Default for LatchTolerance {
    fn default() -> Self {
        LatchTolerance {
            plunger_preload: 0.2,
            plunger_stiffness: 0.2,
            magnet_force: 0.3,
            stop_damping: 0.3,
            crest_deg: 0.1,
            breaking_torque: 0.15,
        }
    }
}

impl LatchSpec {
    /// This latch as built: each toleranced figure moved by `u[k]` times
    /// its spread, `u[k]` in [−1, 1] (preload, rate, magnet force, stop
    /// damping, crest; a `u` outside is clamped to it).
    pub fn as_built(&self, tol: &LatchTolerance, u: [f64; 5]) -> LatchSpec {
        let u = u.map(|x| x.clamp(-1.0, 1.0));
        let mut b = self.clone();
        b.plunger.preload_n *= 1.0 + tol.plunger_preload * u[0];
        b.plunger.stiffness_n_per_mm *= 1.0 + tol.plunger_stiffness * u[1];
        if let Some(m) = b.magnet.as_mut() {
            m.force_n *= 1.0 + tol.magnet_force * u[2];
        }
        b.stop.damping_ns_per_mm1_25 *= 1.0 + tol.stop_damping * u[3];
        b.plunger.crest_deg = (b.plunger.crest_deg + tol.crest_deg * u[4]).max(0.0);
        b
    }

    /// This latch as built from draws of `uniform` (each in [0, 1), mapped
    /// to [−1, 1]): five for [`LatchSpec::as_built`], and a sixth for a
    /// pawl's breaking torque (a ball plunger draws five, as before).
    pub fn draw_as_built(
        &self,
        tol: &LatchTolerance,
        uniform: &mut dyn FnMut() -> f64,
    ) -> LatchSpec {
        let u: [f64; 5] = core::array::from_fn(|_| 2.0 * uniform() - 1.0);
        let mut b = self.as_built(tol, u);
        if let Some(p) = b.pawl.as_mut() {
            let v = (2.0 * uniform() - 1.0).clamp(-1.0, 1.0);
            p.breaking_torque_nm *= 1.0 + tol.breaking_torque * v;
        }
        b
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn drawing() -> LatchSpec {
        LatchSpec {
            switch_travel_deg: 0.05,
            stop: StopSpec {
                radius_mm: 40.0,
                stiffness_n_per_mm1_5: PAPER_STIFFNESS_N_PER_MM1_5,
                damping_ns_per_mm1_25: PAPER_DAMPING_NS_PER_MM1_25,
            },
            plunger: PlungerSpec {
                preload_n: 20.0,
                stiffness_n_per_mm: 10.0,
                radius_mm: 40.0,
                stroke_mm: 0.8,
                crest_deg: 0.6,
                entry_ramp_deg: 30.0,
                hold_ramp_deg: 50.0,
            },
            magnet: Some(MagnetSpec {
                force_n: 15.0,
                decay_mm: 0.5,
                reach_mm: 2.0,
                radius_mm: 40.0,
            }),
            pawl: None,
        }
    }

    #[test]
    fn as_built_moves_each_figure_by_its_tolerance_at_the_ends() {
        let d = drawing();
        let t = LatchTolerance::default();
        let hi = d.as_built(&t, [1.0; 5]);
        assert!((hi.plunger.preload_n - 24.0).abs() < 1e-12);
        assert!((hi.plunger.stiffness_n_per_mm - 12.0).abs() < 1e-12);
        assert!((hi.magnet.as_ref().map_or(0.0, |m| m.force_n) - 19.5).abs() < 1e-12);
        assert!((hi.stop.damping_ns_per_mm1_25 - 3.7 * 1.3).abs() < 1e-12);
        assert!((hi.plunger.crest_deg - 0.7).abs() < 1e-12);
        let lo = d.as_built(&t, [-5.0; 5]);
        assert!((lo.plunger.preload_n - 16.0).abs() < 1e-12);
        assert!((lo.plunger.crest_deg - 0.5).abs() < 1e-12);
        assert_eq!(d.as_built(&t, [0.0; 5]), d);
        // What is not toleranced stays as drawn.
        assert_eq!(hi.stop.stiffness_n_per_mm1_5, d.stop.stiffness_n_per_mm1_5);
        assert_eq!(hi.switch_travel_deg, d.switch_travel_deg);
    }

    #[test]
    fn a_pawl_draws_a_sixth_figure_for_its_breaking_torque_a_plunger_five() {
        let t = LatchTolerance::default();
        let mut n = 0;
        let mut one = || {
            n += 1;
            1.0 - 1e-12
        };
        let d = drawing();
        let _ = d.draw_as_built(&t, &mut one);
        assert_eq!(n, 5);
        let mut p = drawing();
        p.pawl = Some(Pawl {
            breaking_torque_nm: 200.0,
        });
        let mut n = 0;
        let mut one = || {
            n += 1;
            1.0 - 1e-12
        };
        let b = p.draw_as_built(&t, &mut one);
        assert_eq!(n, 6);
        let bt = b.pawl.map_or(0.0, |p| p.breaking_torque_nm);
        assert!((bt - 230.0).abs() < 1e-6, "{bt}");
    }
}
