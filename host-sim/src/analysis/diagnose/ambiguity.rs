//! When the runs cannot decide (`docs/diagnosis.md`, "Ambiguity"): at each
//! joint where the set found holds named joint effects (Coulomb, viscous,
//! softening, harness), every other single and pair of them is fitted in
//! their place; the sets that explain the runs alike — BIC within
//! [`MIN_DELTA_BIC`] of the set found, every effect they add clear of zero
//! — form an ambiguity group. The report lists them with their fits, the
//! intervals of the set found are widened to cover them, and the test that
//! would separate them is named. Friction and a softened spring resist
//! alike over a stroke; only runs with another spring (or at another
//! temperature) tell them apart.

use super::candidate::Candidate;
use super::outcome::FittedSet;
use super::{labels, new_members_clear, Search, MIN_DELTA_BIC};
use crate::analysis::residual_named;

/// Sets of causes that explain the runs alike at one joint.
#[derive(Clone, Debug, PartialEq)]
pub struct Ambiguity {
    /// The joint (1-based) whose named effects the sets exchange.
    pub joint: usize,
    /// The set found, then each alternative, fitted (BIC within
    /// [`MIN_DELTA_BIC`] of the set found).
    pub sets: Vec<FittedSet>,
    /// The test that would separate them, in words.
    pub separating_test: String,
}

/// True when `c` is a named joint effect at `joint` (not a table).
fn named_at(c: &Candidate, joint: usize) -> bool {
    c.joint == Some(joint) && c.table.is_none() && residual_named::KINDS.contains(&c.kind)
}

/// True when `a` and `b` hold the same candidates, in any order.
fn same_set(a: &[Candidate], b: &[Candidate]) -> bool {
    a.len() == b.len() && a.iter().all(|c| b.contains(c))
}

impl Search<'_, '_> {
    /// The ambiguity groups of the current set ([`Ambiguity`]).
    pub(super) fn ambiguities(&self) -> Vec<Ambiguity> {
        let mut joints: Vec<usize> = self
            .current
            .set
            .iter()
            .filter_map(|c| c.joint.filter(|&j| named_at(c, j)))
            .collect();
        joints.dedup();
        joints.sort_unstable();
        joints.dedup();
        joints
            .into_iter()
            .filter_map(|j| self.ambiguity_at(j))
            .collect()
    }

    /// The ambiguity group at `joint`, when there is one.
    fn ambiguity_at(&self, joint: usize) -> Option<Ambiguity> {
        let mut reduced = self.current.clone();
        while let Some(k) = reduced.set.iter().position(|c| named_at(c, joint)) {
            reduced = reduced.without(k);
        }
        let mut moves: Vec<(FittedSet, Candidate)> = residual_named::KINDS
            .iter()
            .map(|&kind| Candidate {
                kind,
                joint: Some(joint),
                table: None,
            })
            .filter(|c| self.candidates.contains(c))
            .map(|c| (reduced.clone(), c))
            .collect();
        moves.extend(self.named_pairs_at(&reduced, joint));
        // An alternative exchanges the joint's effects: a set that keeps
        // them all (and adds one more, near zero) is the same explanation.
        let here: Vec<Candidate> = self
            .current
            .set
            .iter()
            .copied()
            .filter(|c| named_at(c, joint))
            .collect();
        moves.retain(|(base, c)| {
            let mut s = base.set.clone();
            s.push(*c);
            !same_set(&s, &self.current.set) && !here.iter().all(|h| s.contains(h))
        });
        if moves.is_empty() {
            return None;
        }
        self.eng.say(format!(
            "ambiguity: fitting {} other sets of named effects at joint {joint}",
            moves.len()
        ));
        let best = self.current.bic();
        let mut alike: Vec<FittedSet> = self
            .eng
            .fit_moves_sharing(self.eng.campaign, &moves)
            .into_iter()
            .filter(|(_, _, screened_out)| !screened_out)
            .filter_map(|(_, f, _)| f)
            .filter(|f| f.bic() - best < MIN_DELTA_BIC && new_members_clear(f, &reduced))
            .collect();
        if alike.is_empty() {
            return None;
        }
        alike.sort_by(|a, b| a.bic().total_cmp(&b.bic()));
        for f in &alike {
            self.eng.say(format!(
                "  explains the runs alike: {} (RMS {:.4} deg, BIC {:+.1})",
                labels(&f.set),
                f.rms(),
                f.bic() - best
            ));
        }
        let one_config = {
            let names: Vec<&str> = self
                .eng
                .campaign
                .runs
                .iter()
                .map(|r| r.mechanism.name.as_str())
                .collect();
            names.windows(2).all(|w| w[0] == w[1])
        };
        let separating_test = if one_config {
            format!(
                "the runs are of one configuration: runs with another spring at joint {joint} (softening scales with the spring's torque, friction and a harness do not), or at another temperature, would separate them"
            )
        } else {
            format!(
                "runs that move joint {joint} over another range of angle and rate (another spring or stowed angle at that joint), or at another temperature, would separate them"
            )
        };
        let mut sets = vec![self.current.clone()];
        sets.extend(alike);
        Some(Ambiguity {
            joint,
            sets,
            separating_test,
        })
    }
}

/// The set found with the interval of each named effect at an ambiguous
/// joint widened to cover its fits in every set of the group (and zero
/// when a set of the group does without it).
pub fn widened(found: &FittedSet, groups: &[Ambiguity]) -> FittedSet {
    let mut out = found.clone();
    let mut off = 0;
    for c in &found.set {
        let n = c.params();
        for g in groups.iter().filter(|g| c.joint == Some(g.joint) && n == 1) {
            let Some(ci) = out.ci95.get_mut(off) else {
                continue;
            };
            for s in &g.sets {
                match s.set.iter().position(|x| x == c) {
                    Some(k) => {
                        if let Some((p, band)) = s.effect_params(k) {
                            ci[0] = ci[0].min(p[0]).min(band[0][0]);
                            ci[1] = ci[1].max(p[0]).max(band[0][1]);
                        }
                    }
                    None => {
                        ci[0] = ci[0].min(0.0);
                        ci[1] = ci[1].max(0.0);
                    }
                }
            }
        }
        off += n;
    }
    out
}
