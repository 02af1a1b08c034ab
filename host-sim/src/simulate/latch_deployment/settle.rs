//! Ending a physical-latch run once every latch is held for good
//! ([`Keep::Settled`](super::Keep::Settled); `docs/simulator.md`, "Held for
//! good"): the energy the chain still has cannot open any switch again, so
//! every joint's switch stays closed to the end of the run and its last
//! closing is the latch instant the full run would give.
//!
//! The criterion, at a state `y` where every joint's switch is closed and
//! every pawl is engaged:
//!
//! - `E(y) = K + V` is the ledger's stored energy (kinetic, springs with
//!   their continuation into the stop, latches). Along the run `E` can only
//!   fall: every other torque dissipates (friction, drag, the stops' and
//!   notches' damping, a spring's folding branch where it lies above its
//!   unfolding one), a pawl's drop and a stuck joint's stop are booked as
//!   lost. A run where that is not so never ends early: a rig tilt, a
//!   harness, a detent or torque table, a joint without a physical latch,
//!   a folding branch under the unfolding one (the tape springs' knee near
//!   the stop), or booked losses that fall along the run. The integration's own error moves
//!   `E` by at most the ledger's drift, which every run keeps below its
//!   tolerance `max_drift` ([`SimOptions::max_drift`], [`MAX_LEDGER_DRIFT`]
//!   by default) of the stored energy or stops with an error; so from here
//!   on `E ≤ E(y) + slack`, `slack = max_drift·|E₀| − drift(y)`.
//! - `V` is a sum of one term per joint, `V_j(φ_j)` (no rig tilt, no
//!   harness, no detent or torque table: those runs never end early). Each
//!   `V_j` has a lower bound `floor_j` over every angle, so the energy free
//!   to move any one joint is at most `F = E(y) + slack − Σ_k floor_k`.
//! - Joint `j` opens its switch only by reaching `u_j > u_s`, where
//!   `V_j ≥ floor_j + barrier_j`. If `F < barrier_j` for every joint, none
//!   can ever open: the first opening would need the energy it lacks.
//! - An engaged pawl could still break (and free its joint) if the force on
//!   its notch's wall reached its breaking torque; within the switch's
//!   travel the force's elastic part is at most its value at `u_s` and its
//!   damping part grows with the rate, which the kinetic energy `K ≤ F`
//!   bounds through the mass matrix. The run ends only if that bound stays
//!   below the breaking torque.
//!
//! `floor_j` and `barrier_j` come from the latch's laws: in the stop the
//! potential is searched on a grid, lowered by the largest step between its
//! points; between the stop and the plunger's crest (a pawl: every travel
//! beyond the stop) `V_j` rises with the travel, which is checked on a grid
//! (the joint gets no bounds, and the run does not end early, where it does
//! not); beyond the crest `V_j` is at least the spring's and the magnet's
//! energy at the crest (the plunger's is never negative), both rising.

use super::{Ledger, Sim};
use crate::simulate::ode::State;
#[cfg(doc)]
use crate::simulate::trajectory::{SimOptions, MAX_LEDGER_DRIFT};
use deploywatch_core::physics::latch_contact::{PhysicalLatch, PlungerSegment};
use deploywatch_core::physics::pawl::PawlState;
use deploywatch_core::physics::solve_spd_masked;
use deploywatch_core::Branch;

/// Points of the grid the potential's well in the stop is searched on.
const WELL_POINTS: usize = 512;

/// First depth of that grid into the stop, as travel \[rad\] (0.05°);
/// doubled until the potential falls from its deep end.
const WELL_DEPTH_RAD: f64 = 8.7e-4;

/// Doublings of [`WELL_DEPTH_RAD`] tried.
const WELL_DOUBLINGS: usize = 12;

/// Points of each grid the rise of the potential is checked on.
const RISE_POINTS: usize = 64;

/// The factor on `(M⁻¹)_jj` at the state for its largest value while every
/// joint stays within its switch's travel (under a degree from the stop:
/// the mass matrix's cosines move by less than 2 %).
const INVERSE_MASS_SAFETY: f64 = 1.5;

/// The energy bounds of one joint \[J\].
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Bounds {
    /// At most the least of the joint's potential over every angle.
    floor_j: f64,
    /// At most the least of the potential where the switch is open, less
    /// `floor_j`.
    barrier_j: f64,
}

/// What a run knows of its joints' bounds.
#[derive(Clone, Copy, Debug)]
pub(super) struct Hold<const N: usize> {
    /// Per joint: not computed yet (`None`), or computed (`Some(None)`: the
    /// joint's potential is not of the shape the bounds need).
    bounds: [Option<Option<Bounds>>; N],
    /// False once the run is found not passive (or never was).
    passive: bool,
    /// The ledger's booked losses at the last check \[J\].
    lost_j: f64,
}

impl<const N: usize> Hold<N> {
    /// Nothing known yet; `passive` as the chain's effects say.
    pub(super) fn new(passive: bool) -> Self {
        Hold {
            bounds: [None; N],
            passive,
            lost_j: 0.0,
        }
    }
}

impl<const N: usize> Sim<'_, N> {
    /// True when every torque outside the ledger's potential dissipates:
    /// every joint has a physical latch, no rig tilt, harness, detent or
    /// torque table acts, and no spring's folding branch lies under its
    /// unfolding one where it applies (a tape spring's knee: a small loop
    /// there would be given energy; checked on a grid).
    pub(super) fn passive(&self) -> bool {
        let global = self.chain.global();
        let joints = self.chain.joints().iter().zip(&self.latch);
        global.tilt_m_s2 == 0.0
            && joints.into_iter().all(|(jt, l)| {
                let e = &jt.effects;
                let folds_above = jt.spring.hysteresis_below_rad().is_none_or(|below| {
                    (1..=RISE_POINTS).all(|i| {
                        let phi = below * i as f64 / RISE_POINTS as f64;
                        jt.spring.magnitude(phi, Branch::Fold)
                            >= jt.spring.magnitude(phi, Branch::Unfold)
                    })
                });
                l.is_some()
                    && e.harness_nm_per_rad == 0.0
                    && e.detent_nm == 0.0
                    && e.table.angle.is_none()
                    && e.table.rate.is_none()
                    && folds_above
            })
    }

    /// Joint `j`'s share of the ledger's potential at `φ` \[J\] with its
    /// pawl (if any) engaged: the spring (continued into the stop) and the
    /// latch.
    fn joint_potential(&self, j: usize, l: &PhysicalLatch<f64>, phi: f64) -> f64 {
        let Some(jt) = self.chain.joints().get(j) else {
            return 0.0;
        };
        let soft = 1.0 - jt.effects.spring_softening;
        let u = l.travel(phi);
        let spring = if u < 0.0 {
            let t0 = jt
                .spring
                .torque(l.side * f64::MIN_POSITIVE, Branch::Unfold)
                .abs();
            soft * t0 * u
        } else {
            soft * jt.spring.release(0.0, phi.abs())
        };
        let latch = match l.pawl() {
            Some(_) => l.potential_energy_on(PlungerSegment::Clear, PawlState::Engaged, phi),
            None => l.potential_energy(phi),
        };
        spring + latch
    }

    /// The spring's and the magnet's energy at travel `u ≥ 0` \[J\].
    fn spring_and_magnet(&self, j: usize, l: &PhysicalLatch<f64>, u: f64) -> f64 {
        let Some(jt) = self.chain.joints().get(j) else {
            return 0.0;
        };
        let soft = 1.0 - jt.effects.spring_softening;
        soft * jt.spring.release(0.0, u.abs()) + l.magnet_energy(u)
    }

    /// Joint `j`'s bounds (`None`: its potential has not the shape they
    /// need).
    fn bounds(&self, j: usize) -> Option<Bounds> {
        let l = self.latch.get(j)?.as_ref()?;
        let jt = self.chain.joints().get(j)?;
        let at = |u: f64| self.joint_potential(j, l, l.side * u);
        // The well in the stop: its least value on a grid ending at the
        // stop, the grid deep enough that the potential falls from its end.
        let mut depth = WELL_DEPTH_RAD;
        let mut well = None;
        for _ in 0..WELL_DOUBLINGS {
            let h = depth / (WELL_POINTS - 1) as f64;
            let v: Vec<f64> = (0..WELL_POINTS)
                .map(|i| at(-depth + i as f64 * h))
                .collect();
            if v.len() > 1 && v[0] > v[1] {
                let least = v.iter().copied().fold(f64::INFINITY, f64::min);
                let step = v
                    .windows(2)
                    .map(|w| (w[1] - w[0]).abs())
                    .fold(0.0, f64::max);
                well = Some(least - step);
                break;
            }
            depth *= 2.0;
        }
        let well = well?;
        // Beyond the stop the potential rises up to the crest (a pawl: up
        // to the stowed angle, the notch's wall past its notch).
        let stowed = l.travel(jt.stowed_rad).abs();
        let crest = l.plunger.crest_rad;
        let rise_end = if l.pawl().is_some() { stowed } else { crest };
        let rises = |f: &dyn Fn(f64) -> f64, a: f64, b: f64| {
            let v: Vec<f64> = (0..RISE_POINTS)
                .map(|i| f(a + (b - a) * i as f64 / (RISE_POINTS - 1) as f64))
                .collect();
            v.windows(2).all(|w| w[1] >= w[0])
        };
        if !rises(&at, 0.0, rise_end) {
            return None;
        }
        // Beyond the crest (a detent): the spring's and magnet's energy,
        // rising, bound the potential from below.
        let beyond = match l.pawl() {
            Some(_) => f64::INFINITY,
            None => {
                let sm = |u: f64| self.spring_and_magnet(j, l, u);
                if !rises(&sm, crest, stowed.max(crest)) {
                    return None;
                }
                sm(crest)
            }
        };
        let floor_j = well.min(beyond);
        let switch = l.switch_travel_rad;
        let open = if switch < rise_end {
            at(switch)
        } else {
            beyond
        };
        Some(Bounds {
            floor_j,
            barrier_j: open.min(beyond) - floor_j,
        })
    }

    /// [`Sim::held_for_good`] on the run's own [`Hold`] (false without
    /// one: the run goes on to its end).
    pub(super) fn settled(&mut self, ledger: &Ledger, y: &State<N>) -> bool {
        let Some(mut hold) = self.hold else {
            return false;
        };
        let done = self.held_for_good(&mut hold, ledger, y);
        self.hold = Some(hold);
        done
    }

    /// True when every latch is held for good at `y` (module doc), the
    /// ledger closed at `y`. Computes the joints' bounds the first time
    /// every switch is closed and every pawl engaged.
    fn held_for_good(&self, hold: &mut Hold<N>, ledger: &Ledger, y: &State<N>) -> bool {
        let e = &ledger.energy;
        let lost = e.friction_j + e.contact_j + e.impact_j;
        if lost < hold.lost_j {
            hold.passive = false; // a loss booked negative: not passive
        }
        hold.lost_j = lost;
        if !hold.passive {
            return false;
        }
        for j in 0..N {
            let Some(l) = &self.latch[j] else {
                return false;
            };
            if !l.switch_closed(y.q[j]) {
                return false;
            }
            if l.pawl().is_some() && self.seg[j].pawl != PawlState::Engaged {
                return false;
            }
        }
        let mut floors = 0.0;
        let mut least_barrier = f64::INFINITY;
        for j in 0..N {
            let b = match hold.bounds[j] {
                Some(b) => b,
                None => {
                    let b = self.bounds(j);
                    hold.bounds[j] = Some(b);
                    b
                }
            };
            let Some(b) = b else {
                return false;
            };
            floors += b.floor_j;
            least_barrier = least_barrier.min(b.barrier_j);
        }
        let slack = (ledger.max_drift * e.stored_j.abs() - ledger.now_j).max(0.0);
        let free = e.kinetic_j + e.spring_j + e.latch_j + slack - floors;
        free < least_barrier && self.pawls_hold(free.max(0.0), y)
    }

    /// True when no engaged pawl can reach its breaking torque with at most
    /// `free` \[J\] of kinetic energy while its switch stays closed.
    fn pawls_hold(&self, free: f64, y: &State<N>) -> bool {
        let m = self.chain.mass_matrix(&y.q);
        for (j, l) in self.latch.iter().enumerate() {
            let Some((l, p)) = l.as_ref().and_then(|l| Some((l, *l.pawl()?))) else {
                continue;
            };
            let mut unit = [0.0; N];
            unit[j] = 1.0;
            let Ok(col) = solve_spd_masked(&m, &unit, &[false; N]) else {
                return false;
            };
            // K ≥ φ̇_j² / (2 (M⁻¹)_jj): the joint's largest rate.
            let rate = (2.0 * free * col[j].max(0.0) * INVERSE_MASS_SAFETY).sqrt();
            let phi = l.side * l.switch_travel_rad;
            let force = l.notch_force(phi, l.side * rate).raw_n.max(0.0);
            let holds = l.carried_torque(force) < p.breaking_torque_nm;
            if !holds {
                return false;
            }
        }
        true
    }
}
