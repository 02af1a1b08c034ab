//! A table in place of a global stand-in: when the search ends where
//! [`super::Engine::unexplained_torque`] would fire (a global effect — rig tilt,
//! air drag — brings the residual within the noise of the angles, and
//! without it the residual torque is significant at a joint where the set
//! claims nothing), one more move is tried before the `unexplained`
//! answer: the set without that global effect, plus a torque table at that
//! joint (the even forms and the shape the residual torque has,
//! [`Search::joint_tables`]), fitted jointly, judged like any move
//! ([`Move::StandInTable`]) and refined like the other tables
//! ([`Search::refine_tables`]). The result is then judged against the set
//! with the stand-in by [`Search::accept`] with [`Move::StandIn`]'s policy:
//! kept only when it also explains the data: its BIC better than the
//! stand-in set's by more than [`super::MIN_DELTA_BIC`], its held-out RMS
//! better by [`super::policy::HELD_OUT_SHARE`], its residual not above the
//! noise and no global stand-in left ([`super::Engine::unexplained_torque`]
//! silent); its tables' intervals were judged when they were taken.

use super::discover;
use super::evidence_search::near_noise;
use super::policy::{Attempt, Move, Verdict};
use super::step::Step;
use super::{labels, Proposal, Search};

impl Search<'_, '_> {
    /// Tries a table at the joint a global stand-in hides (see the module
    /// doc); keeps the search's state when the result does not explain the
    /// data better. True when the table was kept.
    pub(super) fn replace_stand_in(&mut self) -> bool {
        // Where `unexplained_torque` fires: within the noise's bounds, with
        // a joint torque hidden by a global effect.
        if !near_noise(&self.current, self.sigma) {
            return false;
        }
        let saved = (
            self.current.clone(),
            self.current_held,
            self.seen.clone(),
            self.swaps,
        );
        match self.attempt(Move::StandInTable) {
            Attempt::NotTried => return false,
            Attempt::Moved => self.refine_tables(),
            Attempt::Judged => {}
        }
        if self.current.candidates() != saved.0.candidates() {
            let mut held = Some(self.current_held);
            let verdict = self.accept(
                (&saved.0, saved.1),
                &self.current,
                &mut held,
                &Move::StandIn.policy(),
            );
            if matches!(verdict, Verdict::Accepted(_)) {
                return true;
            }
        }
        self.eng.say(format!(
            "  the stand-in stays: {} (RMS {:.4} deg) does not explain the data better",
            labels(&self.current.candidates()),
            self.current.rms()
        ));
        (self.current, self.current_held, self.seen, self.swaps) = saved;
        false
    }

    /// [`Move::StandInTable`]: for each global effect of the set that hides a
    /// joint torque ([`super::Engine::hidden_by_globals`]), the set without
    /// it, with the tables at that joint.
    pub(super) fn propose_stand_in(&mut self) -> Option<Proposal> {
        let even = discover::table_candidates(self.eng.campaign);
        let mut moves: Vec<Step> = Vec::new();
        for (k, jt) in self.eng.hidden_by_globals(&self.current) {
            let base = self.current.without(k);
            for (c, start) in self.joint_tables(&jt, &even) {
                moves.push(Step::from(base.clone(), c, start));
            }
        }
        if moves.is_empty() {
            return None;
        }
        self.eng.say(format!(
            "stand-in: the residual stays at {:.4} deg beside a global effect; fitting {} tables in its place",
            self.current.rms(),
            moves.len()
        ));
        Some(moves)
    }
}
