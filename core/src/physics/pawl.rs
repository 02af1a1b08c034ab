//! A pawl: the positive lock of a physical latch (`docs/spec/physics.md`
//! section 10.5, this project's extension), beside the ball plunger's
//! detent of [`crate::physics::latch_contact`].
//!
//! # The cam and the drop
//! A spring-loaded pawl rides on a cam of the moving part: the latch's
//! [`Plunger`](crate::physics::latch_contact::Plunger) is then the pawl's
//! spring (`P = P0 + k_p x`) on the cam's ramp (its entry ramp, angle `α_e`,
//! lifting the pawl by `h` at the notch's edge `u_n`, the plunger's crest).
//! While the pawl rides (`u > u_n`) it resists the approach with the entry
//! ramp's conservative torque of section 10.3. At `u = u_n` the pawl drops
//! into its notch: its spring's energy `E_click = P0 h + ½ k_p h²` goes
//! into the click (the pawl's own impact, booked as lost). There is no hold
//! ramp: the notch's wall is square.
//!
//! # The notch: a stiff unilateral contact
//! From the drop on the joint is between its stop (`u = 0`) and the pawl:
//! a return beyond the notch presses the pawl against the notch's wall, a
//! Hertz contact of the stop's law at the pawl's radius `r_p`,
//!
//! ```text
//! δ_n = (u − u_n) r_p [mm],   F_n = k δ_n^1.5 + c δ_n^0.25 δ̇_n   (δ_n > 0),   applied max(F_n, 0)
//! τ_u = −F_n r_p,   V_n = k δ_n^2.5 / 2.5
//! ```
//!
//! so the joint cannot be climbed back over the pawl: the torque the pawl
//! carries is `F_n r_p`.
//!
//! # Breaking
//! When the carried torque reaches the stated breaking torque `T_b` the
//! pawl breaks: from then the joint is free of it (stop and magnet still
//! act) — a failed latch. The notch contact's elastic energy at that
//! instant is lost with it.
//!
//! Everything here is a pure function of the state, the pawl's
//! [`PawlState`] and the frozen plunger segment; it never panics.

use crate::physics::latch_contact::{Lock, Pawl};

use crate::physics::latch_contact::{PhysicalLatch, PlungerSegment, StopForce, MM_PER_M};
use crate::physics::real::Real;

/// Where a pawl is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PawlState {
    /// Not in its notch yet: clear of the cam or riding on it.
    Riding,
    /// Dropped into its notch: the joint cannot return past `u_n`.
    Engaged,
    /// Broken: the joint is free of it.
    Broken,
}

impl<T: Real> PhysicalLatch<T> {
    /// The pawl, `None` for a ball plunger's detent.
    pub fn pawl(&self) -> Option<&Pawl<T>> {
        match &self.lock {
            Lock::Pawl(p) => Some(p),
            Lock::Detent => None,
        }
    }

    /// A pawl's state at travel `u` \[rad\] at the start of a run: engaged
    /// at or inside its notch (`u ≤ u_n`), riding beyond it.
    pub fn pawl_state_at(&self, u: T) -> PawlState {
        if self.pawl().is_some() && u <= self.plunger.crest_rad {
            PawlState::Engaged
        } else {
            PawlState::Riding
        }
    }

    /// `r_p` \[mm\].
    fn pawl_radius_mm(&self) -> T {
        self.plunger.radius_m * T::of(MM_PER_M)
    }

    /// The force on the notch's wall at `(φ, φ̇)` with the pawl engaged
    /// (zero while `u ≤ u_n`, and for a detent).
    pub fn notch_force(&self, phi: T, phi_dot: T) -> StopForce<T> {
        let r = self.pawl_radius_mm();
        let mut delta = (self.travel(phi) - self.plunger.crest_rad) * r;
        if self.pawl().is_none() {
            delta = T::ZERO;
        }
        self.stop.force(delta, self.travel(phi_dot) * r)
    }

    /// The joint torque `τ_φ` [N·m] of a notch force `force_n` \[N\]: towards
    /// the stop.
    pub fn notch_torque(&self, force_n: T) -> T {
        -self.side * force_n * self.plunger.radius_m
    }

    /// The torque the pawl carries under a notch force `force_n` \[N\],
    /// `F_n r_p` [N·m].
    pub fn carried_torque(&self, force_n: T) -> T {
        force_n * self.plunger.radius_m
    }

    /// The notch contact's elastic energy `k δ_n^2.5 / 2.5` \[J\] at `φ`.
    pub(crate) fn notch_energy(&self, phi: T) -> T {
        if self.pawl().is_none() {
            return T::ZERO;
        }
        let delta = (self.travel(phi) - self.plunger.crest_rad) * self.pawl_radius_mm();
        self.stop.energy(delta)
    }

    /// The click of a pawl's drop, `P0 h + ½ k_p h²` \[J\]: its spring's
    /// energy at the notch's edge, lost.
    pub fn click_energy(&self) -> T {
        self.engagement_energy()
    }

    /// The farthest travel a pawl that carries less than its breaking
    /// torque reaches \[rad\]: the notch plus the contact's compression at
    /// `T_b` (`u_n` for a detent).
    pub fn breaking_travel_rad(&self) -> T {
        let Some(p) = self.pawl() else {
            return self.plunger.crest_rad;
        };
        let f = p.breaking_torque_nm / self.plunger.radius_m;
        let k = self.stop.stiffness_n_per_mm1_5;
        let delta_mm = T::of(libm::pow((f / k).to_f64(), 2.0 / 3.0));
        self.plunger.crest_rad + delta_mm / self.pawl_radius_mm()
    }

    /// Potential energy of the latch's conservative parts at `φ` \[J\] with
    /// the plunger on segment `seg` and a pawl in `pawl` (ignored for a
    /// detent): the plunger or the riding pawl's spring, the engaged pawl's
    /// notch contact, magnet and stop.
    pub fn potential_energy_on(&self, seg: PlungerSegment, pawl: PawlState, phi: T) -> T {
        let u = self.travel(phi);
        let riding = self.pawl().is_none() || pawl == PawlState::Riding;
        let spring = if riding {
            self.plunger_energy_at(self.depression_on(seg, u).0)
        } else {
            T::ZERO
        };
        let notch = if pawl == PawlState::Engaged {
            self.notch_energy(phi)
        } else {
            T::ZERO
        };
        spring + notch + self.magnet_energy(u) + self.stop_energy(phi)
    }

    /// The latch's whole joint torque `τ_φ(φ, φ̇)` [N·m] with a pawl in
    /// state `pawl`: stop, magnet, the riding pawl's cam or the engaged
    /// pawl's notch (each contact clamped at zero force); for a detent
    /// [`PhysicalLatch::torque`].
    pub fn torque_with(&self, pawl: PawlState, phi: T, phi_dot: T) -> T {
        if self.pawl().is_none() || pawl == PawlState::Riding {
            return self.torque(phi, phi_dot);
        }
        let u = self.travel(phi);
        let magnet = self.magnet_force_on(self.magnet_within(u), u) * self.magnet.radius_m;
        let stop = self.stop_torque(self.stop_force(phi, phi_dot).applied_n());
        let notch = match pawl {
            PawlState::Engaged => self.notch_torque(self.notch_force(phi, phi_dot).applied_n()),
            _ => T::ZERO,
        };
        -self.side * magnet + stop + notch
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::latch_contact::{HertzStop, Magnet, Plunger};

    fn pawl(side: f64) -> PhysicalLatch<f64> {
        PhysicalLatch {
            side,
            stop: HertzStop {
                stiffness_n_per_mm1_5: 37_000.0,
                damping_ns_per_mm1_25: 3.7,
                radius_m: 0.04,
            },
            plunger: Plunger {
                preload_n: 5.0,
                stiffness_n_per_mm: 2.0,
                radius_m: 0.04,
                stroke_mm: 1.0,
                crest_rad: 0.2f64.to_radians(),
                entry_ramp_rad: 20f64.to_radians(),
                hold_ramp_rad: 20f64.to_radians(),
            },
            magnet: Magnet {
                force_n: 0.0,
                decay_mm: 1.0,
                reach_mm: 0.0,
                radius_m: 0.04,
            },
            switch_travel_rad: 0.05f64.to_radians(),
            lock: Lock::Pawl(Pawl {
                breaking_torque_nm: 200.0,
            }),
        }
    }

    #[test]
    fn the_cam_resists_the_pawl_drops_and_the_notch_pushes_back_in() {
        for side in [1.0, -1.0] {
            let l = pawl(side);
            assert_eq!(l.check(), Ok(()));
            let c = l.plunger.crest_rad;
            // Riding on the cam: resists the approach (τ_u > 0).
            let on_cam = c + 0.5 * l.entry_width_rad();
            assert!(side * l.torque_with(PawlState::Riding, side * on_cam, 0.0) > 0.0);
            // No hold ramp: past the notch's edge the cam is clear.
            assert_eq!(l.plunger_segment(0.5 * c), PlungerSegment::Clear);
            // Engaged, a return beyond the notch is pushed back (τ_u < 0).
            let beyond = side * (c + 1e-4);
            assert!(side * l.torque_with(PawlState::Engaged, beyond, 0.0) < 0.0);
            assert_eq!(l.torque_with(PawlState::Broken, beyond, 0.0), 0.0);
            // The click is the cam's energy at its edge.
            let at_edge = l.potential_energy_on(PlungerSegment::Entry, PawlState::Riding, side * c);
            assert!((at_edge - l.click_energy()).abs() < 1e-15);
            assert!((l.click_energy() - (5.0 + 1.0) / 1000.0).abs() < 1e-15);
        }
    }

    #[test]
    fn notch_torque_is_minus_the_gradient_of_its_energy() {
        let l = pawl(-1.0);
        let c = l.plunger.crest_rad;
        for k in 1..40 {
            let u = c + k as f64 * 2e-5;
            let phi = -u;
            let e = 1e-9;
            let grad = (l.notch_energy(phi + e) - l.notch_energy(phi - e)) / (2.0 * e);
            let tau = l.notch_torque(l.notch_force(phi, 0.0).elastic_n);
            assert!(
                (tau + grad).abs() < 1e-5 * (1.0 + tau.abs()),
                "{u}: {tau} vs {grad}"
            );
        }
    }

    #[test]
    fn at_the_breaking_travel_the_pawl_carries_its_breaking_torque() {
        let l = pawl(1.0);
        let u = l.breaking_travel_rad();
        let t = l.carried_torque(l.notch_force(u, 0.0).elastic_n);
        assert!((t - 200.0).abs() < 1e-9 * 200.0, "{t}");
        assert_eq!(l.holding_torque(), 200.0);
        let mut bad = l;
        bad.lock = Lock::Pawl(Pawl {
            breaking_torque_nm: 0.0,
        });
        assert!(bad.check().is_err());
        for x in [f64::NAN, -1.0, 0.0, 1.0, f64::INFINITY] {
            let _ = bad.torque_with(PawlState::Engaged, x, x);
            let _ = bad.potential_energy_on(PlungerSegment::Entry, PawlState::Engaged, x);
            let _ = bad.breaking_travel_rad();
        }
    }
}
