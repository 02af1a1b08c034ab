//! Claims within the discrepancy (`docs/diagnosis.md`, "Claims within the
//! discrepancy"): when the set found still leaves a residual clearly above
//! the noise, something the named effects do not hold is in the runs — a
//! flexible panel's ringing, a hinge's free play, time stamps that jitter,
//! an effect outside the vocabulary. The fit then weighs a small claim no
//! longer against white noise but against that discrepancy, which is
//! smooth, correlated and as large as the claim: the BIC, which counts
//! every sample as independent, keeps what merely absorbs a share of it.
//!
//! So, above the noise, a claim stays only when it accounts for at least
//! [`DISCREPANCY_SHARE`](super::policy::DISCREPANCY_SHARE) of what the set
//! leaves unexplained: dropping it, the others refitted, must raise the
//! sum of squares by at least `SSE − m σ̂²`, the set's excess over the
//! noise (`m` residuals, noise σ̂ from the third differences). A torque
//! table's shape beyond a named law is such a claim too: the table
//! exchanged for a named torque law at its joint must lose as much, or
//! the named law takes its place. A named effect beside a table at its
//! joint is judged after the table, never dropped alone while the table
//! is there to take up its torque. A claim that does not is set aside
//! ([`Move::SetAside`], judged by the one acceptance rule,
//! [`Search::accept`]) and the report lists it with both numbers: the
//! runs cannot tell it from the discrepancy. At the noise floor nothing is
//! asked: there the residual is the noise and the BIC's count holds.

use super::ambiguity::Ambiguity;
use super::outcome::{FittedSet, SetAside};
use super::policy::{Move, Verdict};
use super::step::Step;
use super::tolerance::{self, Settled};
use super::{above_noise, labels, Search};

impl Search<'_, '_> {
    /// What the move from `current` to the smaller `to` gives up and the
    /// discrepancy `current` leaves, both as RMS over its residuals
    /// \[deg\]: `√((SSE_to − SSE)/m)` and `√((SSE − m σ̂²)/m)` (0 where
    /// negative).
    pub(super) fn discrepancy_of(&self, current: &FittedSet, to: &FittedSet) -> (f64, f64) {
        let Some(s) = current.stats else {
            return (f64::INFINITY, 0.0);
        };
        let m = s.m.max(1) as f64;
        let explained = ((to.sse() - s.sse) / m).max(0.0).sqrt();
        let discrepancy = ((s.sse - m * self.sigma * self.sigma) / m).max(0.0).sqrt();
        (explained, discrepancy)
    }

    /// Sets aside, one at a time, while the set found stays clearly above
    /// the noise, the claim whose loss the fit notices least, when that
    /// loss is within the discrepancy ([`Move::SetAside`]). A claim is a
    /// member (the set without it, the others refitted) or a table's shape
    /// beyond a named law at its joint (the set with one named effect at
    /// that joint in the table's place). Returns what it set aside.
    pub(super) fn set_aside_within_discrepancy(&mut self) -> Vec<SetAside> {
        let mut out = Vec::new();
        while !self.current.members.is_empty()
            && above_noise(&self.current, self.sigma)
            && !self.eng.halt.now()
        {
            let Some(f) = self.least_loss() else {
                break;
            };
            let verdict = self.accept(
                (&self.current, self.current_held),
                &f,
                &mut None,
                &Move::SetAside.policy(),
            );
            if !matches!(verdict, Verdict::Accepted(_)) {
                break;
            }
            let (explained_deg, discrepancy_deg) = self.discrepancy_of(&self.current, &f);
            let before = self.current.candidates();
            let after = f.candidates();
            let replaced_by: Vec<_> = after
                .iter()
                .filter(|c| !before.contains(c))
                .copied()
                .collect();
            for effect in self
                .current
                .members
                .iter()
                .filter(|m| !after.contains(&m.candidate))
            {
                self.eng.say(format!(
                    "  {} {}{} (it accounts for {explained_deg:.4} deg RMS of the {discrepancy_deg:.4} deg left; RMS without it {:.4} deg)",
                    Move::SetAside.done(),
                    effect.candidate.words(),
                    if replaced_by.is_empty() {
                        String::new()
                    } else {
                        format!(" for {}", labels(&replaced_by))
                    },
                    f.rms()
                ));
                out.push(SetAside {
                    effect: effect.clone(),
                    replaced_by: replaced_by.clone(),
                    explained_deg,
                    discrepancy_deg,
                });
            }
            self.current_held = self.eng.held_out(&f);
            self.current = f;
        }
        out
    }

    /// The set found settled against the drawing's tolerances
    /// ([`tolerance::settle`]), and the claims within the discrepancy judged
    /// again when that took a member out: what the tolerances made (an
    /// encoder offset a spring's tolerance moves, say) may have carried the
    /// set to the noise, and without it the rest stands above the noise
    /// again, where a table's shape beyond a named law is weighed against
    /// that discrepancy. Then the partner a taken-out effect leaves at its
    /// joint is judged against the sets alike there
    /// ([`Search::partners_after_tolerances`]), and a set that takes its
    /// place is settled against the tolerances in turn. `ambiguities` and
    /// `set_aside` are the search's: the sets alike are formed again
    /// around the set settled, and the claims set aside extended.
    pub(super) fn settle(
        &mut self,
        ambiguities: &mut Vec<Ambiguity>,
        set_aside: &mut Vec<SetAside>,
    ) -> Settled {
        let settled = tolerance::settle(self.eng, self.current.clone());
        if settled.within.is_empty() || self.eng.halt.now() {
            return settled;
        }
        self.current_held = self.eng.held_out(&settled.set);
        self.current = settled.set.clone();
        let more = self.set_aside_within_discrepancy();
        let before = self.current.candidates();
        if !self.eng.halt.now() {
            *ambiguities = self.partners_after_tolerances(&settled.within);
        }
        let exchanged = self.current.candidates() != before;
        if more.is_empty() && !exchanged {
            return settled;
        }
        set_aside.extend(more);
        let again = tolerance::settle(self.eng, self.current.clone());
        let mut within = settled.within;
        within.extend(again.within);
        Settled { within, ..again }
    }

    /// Of the smaller and simpler sets (each member dropped, each table
    /// exchanged for each named torque law at its joint), fitted, the one
    /// with the least SSE. A named effect at a joint that also has a table
    /// is not dropped alone: the table would take up its torque whatever
    /// it is, so the table is judged first (dropped, or exchanged).
    fn least_loss(&self) -> Option<FittedSet> {
        let c = self.eng.campaign;
        let tabled = |joint: Option<usize>| {
            self.current
                .members
                .iter()
                .any(|m| m.candidate.table.is_some() && m.candidate.joint == joint)
        };
        let droppable: Vec<usize> = (0..self.current.members.len())
            .filter(|&k| {
                let m = &self.current.members[k].candidate;
                m.table.is_some() || m.joint.is_none() || !tabled(m.joint)
            })
            .collect();
        let drops = droppable.into_iter().filter_map(|k| {
            let without = self.current.without(k);
            if without.members.is_empty() {
                Some(self.eng.baseline())
            } else {
                self.eng.refit(c, &without)
            }
        });
        let named = self.outside();
        let mut steps = Vec::new();
        for (k, m) in self.current.members.iter().enumerate() {
            if m.candidate.table.is_none() {
                continue;
            }
            let reduced = self.current.without(k);
            steps.extend(
                named
                    .iter()
                    .filter(|n| {
                        n.joint == m.candidate.joint && n.table.is_none() && !n.kind.is_sensor()
                    })
                    .map(|&n| Step::new(reduced.clone(), n)),
            );
        }
        let exchanges = self
            .eng
            .fit_moves(c, &steps)
            .into_iter()
            .filter_map(|(_, f, _)| f);
        drops
            .chain(exchanges)
            .filter(|f| f.stats.is_some())
            .min_by(|a, b| a.sse().total_cmp(&b.sse()))
    }
}
