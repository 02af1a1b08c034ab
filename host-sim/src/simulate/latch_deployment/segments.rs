//! What a latch's law is frozen on between events (its segments), the
//! events that end them, and the spring branch a state gives: the
//! vocabulary of the physical-latch run, kept apart from the run itself.

use deploywatch_core::physics::latch_contact::{PhysicalLatch, PlungerSegment};
use deploywatch_core::physics::pawl::PawlState;
use deploywatch_core::Branch;

/// The stop's contact between events.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Contact {
    /// Off the stop (`u ≥ 0`): no force.
    Open,
    /// In the stop with the law's force `k δ^1.5 + c δ^0.25 δ̇ > 0`.
    Pressing,
    /// In the stop, but the law would pull: no force (it lets go).
    Released,
}

/// The segments a joint's latch law is frozen on between events.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Segments {
    pub(super) plunger: PlungerSegment,
    pub(super) magnet: bool,
    pub(super) contact: Contact,
    pub(super) switch: bool,
    /// A pawl's state (`Riding` for a detent): changed only by its own
    /// events (`pawl.rs`).
    pub(super) pawl: PawlState,
    /// The engaged pawl's contact with its notch's wall.
    pub(super) notch: Contact,
}

impl Segments {
    /// Before the first reading: off the stop, a pawl where `u` puts it.
    pub(super) fn start(l: &PhysicalLatch<f64>, u: f64) -> Self {
        Segments {
            plunger: PlungerSegment::Clear,
            magnet: false,
            contact: Contact::Open,
            switch: false,
            pawl: l.pawl_state_at(u),
            notch: Contact::Open,
        }
    }
}

/// What can fire in a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Ev {
    Plunger(usize),
    Magnet(usize),
    Contact(usize),
    Switch(usize),
    Ideal(usize),
    Branch(usize),
    /// The joint's rate reaches rest (`physics.md` §4a): it may stick.
    Turn(usize),
    /// A stuck joint's holding torque leaves its band: it slips.
    Slip(usize),
    /// An engaged pawl's contact with its notch's wall changes.
    Notch(usize),
    /// The torque an engaged pawl carries reaches its breaking torque.
    Break(usize),
}

impl Ev {
    /// The joint (from 0) the event belongs to.
    pub(super) fn joint(self) -> usize {
        match self {
            Ev::Plunger(j)
            | Ev::Magnet(j)
            | Ev::Contact(j)
            | Ev::Switch(j)
            | Ev::Ideal(j)
            | Ev::Branch(j)
            | Ev::Turn(j)
            | Ev::Slip(j)
            | Ev::Notch(j)
            | Ev::Break(j) => j,
        }
    }
}

/// The spring branch of seed 001 Eq. 1 from the state (`F` at rest).
pub(super) fn branch_at(phi: f64, phi_dot: f64) -> Branch {
    if phi * phi_dot < 0.0 {
        Branch::Unfold
    } else {
        Branch::Fold
    }
}

/// The most events one joint can have in a step.
pub(super) const EVENTS_PER_JOINT: usize = 8;

/// Fixed-capacity list of the events that may fire in a step.
pub(super) struct Candidates {
    pub(super) items: [Option<Ev>; EVENTS_PER_JOINT * 4],
    pub(super) len: usize,
}

impl Candidates {
    pub(super) fn push(&mut self, e: Ev) {
        if let Some(slot) = self.items.get_mut(self.len) {
            *slot = Some(e);
            self.len += 1;
        }
    }
}
