//! Second starts for a search that ended above the noise. The greedy first step
//! can take a wrong turn (Coulomb friction for a harness at one joint, from
//! runs of one configuration where the two resist alike), and the effects added
//! beside it then fill the set with stand-ins that no later move undoes: the
//! search is run again from the baseline without that first effect
//! ([`Search::restart_without_first`]). Torques that no named effect describes,
//! at two joints, pull the stepwise search to global effects that spread over
//! every joint (a rig tilt and air drag, say); a table beside them, or in place
//! of one of them, cannot undo the other: discovery is run again from the
//! baseline, tables first ([`Search::restart_from_tables`]). Either set is kept
//! when its BIC is better by more than [`super::MIN_DELTA_BIC`] and, with two
//! or more runs, its held-out RMS beats the first set's by
//! [`super::policy::HELD_OUT_SHARE`] (the policy of every move).

use super::candidate::Candidate;
use super::policy::{Move, Verdict};
use super::{above_noise, labels, Search};

impl Search<'_, '_> {
    /// The first effect the search took (the one set of one visited first).
    fn first_step(&self) -> Option<Candidate> {
        self.seen
            .iter()
            .find(|s| s.len() == 1)
            .and_then(|s| s.first().copied())
    }

    /// When the stepwise search ended above the noise: the search again
    /// from `baseline` without its first step; the better set by BIC
    /// (by more than [`super::MIN_DELTA_BIC`]) is kept, with its rounds. Once.
    pub(super) fn restart_without_first(&mut self, baseline: &super::FittedSet) {
        if !above_noise(&self.current, self.sigma) || self.eng.halt.now() {
            return;
        }
        let Some(first) = self.first_step() else {
            return;
        };
        self.eng.say(format!(
            "restart: the search ended above the noise at {:.4} deg; again from the baseline without {}",
            self.current.rms(),
            first.words()
        ));
        let others = self.candidates.iter().copied().filter(|c| *c != first);
        let mut other = Search::new(
            self.eng,
            others.collect(),
            self.max_effects,
            self.sigma,
            baseline,
        );
        other.run();
        if self.take_if_better(other) {
            self.run();
        }
    }
}

impl<'e, 'a> Search<'e, 'a> {
    /// Discovery (unnamed torques as tables), a table in a global
    /// stand-in's place, the restart from tables, then the friction forms
    /// in place of a set that holds a table: the steps after the stepwise
    /// search, in that order.
    pub(super) fn discover_then_tables(&mut self, baseline: &super::FittedSet) {
        self.discover();
        self.replace_stand_in();
        self.restart_from_tables(baseline);
        self.try_forms_in_place_of_tables();
    }

    /// When the search with discovery still ends above the noise:
    /// discovery again from `baseline` (a table at the joints the residual
    /// torque names, then the named effects beside it, then a second
    /// table); its set is kept when it beats the current one. Once.
    pub(super) fn restart_from_tables(&mut self, baseline: &super::FittedSet) {
        if !above_noise(&self.current, self.sigma) || self.eng.halt.now() {
            return;
        }
        self.eng.say(format!(
            "restart: the search ended above the noise at {:.4} deg; discovery again from the baseline, tables first",
            self.current.rms()
        ));
        let mut other = Search::new(
            self.eng,
            self.candidates.clone(),
            self.max_effects,
            self.sigma,
            baseline,
        );
        other.discover();
        other.replace_stand_in();
        self.take_if_better(other);
    }

    /// Takes `other`'s set, rounds and state when it beats the current set
    /// by the one acceptance rule ([`Search::accept`] with
    /// [`Move::Restart`]'s policy: a BIC better by more than
    /// [`super::MIN_DELTA_BIC`] and a better prediction of the runs left out; more
    /// effects can buy a BIC, not that). Says which, and returns whether it
    /// took it.
    fn take_if_better(&mut self, mut other: Search<'e, 'a>) -> bool {
        let (a, b) = (self.current.bic(), other.current.bic());
        let mut held = Some(other.current_held);
        let verdict = self.accept(
            (&self.current, self.current_held),
            &other.current,
            &mut held,
            &Move::Restart.policy(),
        );
        if !matches!(verdict, Verdict::Accepted(_)) {
            self.eng.say(format!(
                "restart: {} (BIC {b:.1}, held-out RMS {}) does not beat {} (BIC {a:.1}, held-out RMS {}): {verdict}; kept",
                labels(&other.current.candidates()),
                held_words(other.current_held),
                labels(&self.current.candidates()),
                held_words(self.current_held)
            ));
            return false;
        }
        self.eng.say(format!(
            "restart: {} (RMS {:.4} deg, BIC {b:.1}) beats {} (BIC {a:.1}): taken",
            labels(&other.current.candidates()),
            other.current.rms(),
            labels(&self.current.candidates())
        ));
        self.rounds.append(&mut other.rounds);
        self.seen.append(&mut other.seen);
        self.current = other.current;
        self.current_held = other.current_held;
        self.tried_once = other.tried_once;
        self.swaps = other.swaps;
        self.table_tried = other.table_tried;
        true
    }
}

/// A held-out RMS in words (`n/a` with one run).
fn held_words(h: Option<f64>) -> String {
    h.map_or_else(|| "n/a".to_string(), |h| format!("{h:.4} deg"))
}
