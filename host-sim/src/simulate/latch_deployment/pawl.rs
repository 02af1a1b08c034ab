//! A pawl in the physical-latch simulator (`docs/spec/physics.md` §10.5,
//! [`deploywatch_core::physics::pawl`]): the drop into the notch at the
//! cam's edge (the click's energy booked as lost), the stiff unilateral
//! contact with the notch's wall (onset, release and separation located
//! like the stop's), and the break when the torque the pawl carries
//! reaches its breaking torque (the contact's elastic energy booked as
//! lost; the joint is then free of the pawl).

use super::{classify, Contact, Ev, Runner, Segments, Sim, PROBE_S};
use crate::simulate::latch_run::LatchEventKind;
use crate::simulate::ode::State;
use deploywatch_core::physics::latch_contact::PhysicalLatch;
use deploywatch_core::physics::pawl::PawlState;

impl Segments {
    /// The notch contact of latch `l` at `phi` (read a moment ahead) with
    /// rate `phi_dot`, from these segments before: open unless the pawl is
    /// engaged and the joint is beyond the notch; a compressed contact that
    /// let go stays released until its force rises again.
    pub(super) fn notch_after(&self, l: &PhysicalLatch<f64>, phi: f64, phi_dot: f64) -> Contact {
        if l.pawl().is_none() || self.pawl != PawlState::Engaged {
            return Contact::Open;
        }
        if l.travel(phi) <= l.plunger.crest_rad {
            return Contact::Open;
        }
        let raw = l.notch_force(phi, phi_dot).raw_n;
        if self.notch == Contact::Open || raw > 0.0 {
            Contact::Pressing
        } else {
            Contact::Released
        }
    }
}

impl<const N: usize> Sim<'_, N> {
    /// Joint `j`'s latch events besides the stop, magnet and switch: the
    /// plunger's (a detent, or a pawl riding its cam), or an engaged pawl's
    /// notch contact and, while it presses, its break.
    pub(super) fn pawl_events(&self, j: usize) -> (Option<Ev>, Option<Ev>, Option<Ev>) {
        let Some(l) = &self.latch[j] else {
            return (None, None, None);
        };
        let s = &self.seg[j];
        match (l.pawl(), s.pawl) {
            (None, _) | (Some(_), PawlState::Riding) => (Some(Ev::Plunger(j)), None, None),
            (Some(_), PawlState::Engaged) => {
                let brk = (s.notch == Contact::Pressing).then_some(Ev::Break(j));
                (None, Some(Ev::Notch(j)), brk)
            }
            (Some(_), PawlState::Broken) => (None, None, None),
        }
    }

    /// How far inside its frozen segment an engaged pawl is (> 0 while it
    /// holds), for `Ev::Notch` (the contact's onset, release, separation)
    /// or `Ev::Break` (the breaking torque less the torque carried).
    pub(super) fn pawl_margin(&self, ev: Ev, y: &State<N>) -> f64 {
        let j = ev.joint();
        let Some((l, p)) = self.latch[j].as_ref().and_then(|l| Some((l, *l.pawl()?))) else {
            return 1.0;
        };
        let (phi, rate) = (y.q[j], y.v[j]);
        let beyond = l.travel(phi) - l.plunger.crest_rad;
        let raw = l.notch_force(phi, rate).raw_n;
        if let Ev::Break(_) = ev {
            return p.breaking_torque_nm - l.carried_torque(raw);
        }
        match self.seg[j].notch {
            Contact::Open => -beyond,
            Contact::Pressing => beyond.min(raw),
            Contact::Released => beyond.min(-raw),
        }
    }

    /// Joint `j`'s latch potential \[J\] on its segments, a pawl in `pawl`.
    fn latch_potential(&self, j: usize, pawl: PawlState, phi: f64) -> f64 {
        self.latch[j].map_or(0.0, |l| {
            l.potential_energy_on(self.seg[j].plunger, pawl, phi)
        })
    }
}

impl<const N: usize> Sim<'_, N> {
    /// Joint `j`'s latch segments classified again at `y` (the one rule
    /// after every latch event): its latch and the segments before and
    /// after, or `None` for a joint without a physical latch.
    pub(super) fn reclassify(
        &mut self,
        j: usize,
        y: &State<N>,
    ) -> Option<(PhysicalLatch<f64>, Segments, Segments)> {
        let l = self.latch[j]?;
        let before = self.seg[j];
        let after = classify(&l, y.q[j], y.v[j], before);
        self.seg[j] = after;
        Some((l, before, after))
    }
}

impl Runner<'_> {
    /// A pawl riding its cam reaches the notch's edge moving in (`ev` the
    /// plunger's event): it drops, the cam's energy goes into the click.
    /// `None`: not a pawl's drop.
    pub(super) fn pawl_drop<const N: usize>(
        &mut self,
        sim: &mut Sim<'_, N>,
        ev: Ev,
        j: usize,
        y: &State<N>,
    ) -> Option<LatchEventKind> {
        let l = sim.latch[j].filter(|l| l.pawl().is_some())?;
        let before = sim.seg[j];
        let ahead = l.travel(y.q[j] + y.v[j] * PROBE_S);
        let drops = matches!(ev, Ev::Plunger(_))
            && before.pawl == PawlState::Riding
            && ahead <= l.plunger.crest_rad;
        if !drops {
            return None;
        }
        self.pawl_to(sim, j, y, PawlState::Riding, PawlState::Engaged);
        Some(LatchEventKind::PawlDrop)
    }

    /// An engaged pawl's event at joint `j`: its notch contact changes, or
    /// (`breaks`) it breaks (the contact's elastic energy lost with it; the
    /// joint free of it).
    pub(super) fn pawl_event<const N: usize>(
        &mut self,
        sim: &mut Sim<'_, N>,
        j: usize,
        y: &State<N>,
        breaks: bool,
    ) -> LatchEventKind {
        if sim.latch[j].is_some() && breaks {
            self.pawl_to(sim, j, y, PawlState::Engaged, PawlState::Broken);
            return LatchEventKind::PawlBreak;
        }
        sim.reclassify(j, y);
        LatchEventKind::Notch
    }

    /// Joint `j`'s pawl goes from `from` to `to` (a drop or a break): its
    /// segments reclassified with the notch contact open, and the latch
    /// potential it took booked as lost \[J\] (the click; the contact's
    /// elastic energy at a break).
    fn pawl_to<const N: usize>(
        &mut self,
        sim: &mut Sim<'_, N>,
        j: usize,
        y: &State<N>,
        from: PawlState,
        to: PawlState,
    ) {
        let Some(l) = sim.latch[j] else {
            return;
        };
        let v_before = sim.latch_potential(j, from, y.q[j]);
        let was = Segments {
            pawl: to,
            notch: Contact::Open,
            ..sim.seg[j]
        };
        sim.seg[j] = classify(&l, y.q[j], y.v[j], was);
        let v_after = sim.latch_potential(j, to, y.q[j]);
        let e = &mut self.ledger.energy;
        e.impact_j += v_before - v_after;
        e.pawl_j += v_before - v_after;
    }
}
