//! A table in place of a global stand-in: when the search ends where
//! [`super::Engine::unexplained_torque`] would fire (a global effect — rig tilt,
//! air drag — brings the residual within the noise of the angles, and
//! without it the residual torque is significant at a joint where the set
//! claims nothing), one more move is tried before the `unexplained`
//! answer: the set without that global effect, plus a torque table at that
//! joint (the even forms and the shape the residual torque has,
//! [`Search::joint_tables`]), fitted jointly, judged like any move and
//! refined like the other tables ([`Search::refine_tables`]). It is kept
//! only when it also explains the data: its BIC better than the stand-in
//! set's by more than [`MIN_DELTA_BIC`], its held-out RMS better by
//! [`HELD_OUT_SHARE`], its residual not above the noise and no global
//! stand-in left ([`super::Engine::unexplained_torque`] silent).

use super::candidate::Candidate;
use super::discover;
use super::evidence_search::near_noise;
use super::outcome::FittedSet;
use super::{above_noise, labels, Search, HELD_OUT_SHARE, MIN_DELTA_BIC};

impl Search<'_, '_> {
    /// Tries a table at the joint a global stand-in hides (see the module
    /// doc); keeps the search's state when the result does not explain the
    /// data better. True when the table was kept.
    pub(super) fn replace_stand_in(&mut self, sigma: f64) -> bool {
        // Where `unexplained_torque` fires: within the noise's bounds, with
        // a joint torque hidden by a global effect.
        if !near_noise(&self.current, sigma) {
            return false;
        }
        let moves = self.stand_in_moves();
        if moves.is_empty() {
            return false;
        }
        let saved = (
            self.current.clone(),
            self.current_held,
            self.seen.clone(),
            self.swaps,
        );
        let what = format!(
            "a table in place of a global stand-in in {}",
            labels(&saved.0.set)
        );
        self.eng.say(format!(
            "stand-in: the residual stays at {:.4} deg beside a global effect; fitting {} tables in its place",
            self.current.rms(),
            moves.len()
        ));
        if self.step(&moves, what, "a table in place of a global stand-in:") {
            self.refine_tables();
        }
        let gain = saved.0.bic() - self.current.bic();
        let held_better = match (self.current_held, saved.1) {
            (Some(h), Some(c)) => h < HELD_OUT_SHARE * c,
            _ => true,
        };
        if self.current.set != saved.0.set
            && gain > MIN_DELTA_BIC
            && held_better
            && !above_noise(&self.current, sigma)
            && self.eng.unexplained_torque(&self.current, sigma).is_none()
        {
            return true;
        }
        self.eng.say(format!(
            "  the stand-in stays: {} (RMS {:.4} deg) does not explain the data better",
            labels(&self.current.set),
            self.current.rms()
        ));
        (self.current, self.current_held, self.seen, self.swaps) = saved;
        false
    }

    /// For each global effect of the set that hides a joint torque
    /// ([`super::Engine::hidden_by_globals`]): the set without it, with the
    /// tables at that joint.
    fn stand_in_moves(&self) -> Vec<(FittedSet, Candidate)> {
        let even = discover::table_candidates(self.eng.campaign);
        let mut moves = Vec::new();
        for (k, jt) in self.eng.hidden_by_globals(&self.current) {
            let base = self.current.without(k);
            for c in self.joint_tables(&jt, &even) {
                moves.push((base.clone(), c));
            }
        }
        moves
    }
}
