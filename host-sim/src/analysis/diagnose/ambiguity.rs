//! When the runs cannot decide (`docs/diagnosis.md`, "Ambiguity"): at each
//! joint where the set found holds named joint effects (Coulomb, viscous,
//! softening, harness), every other single and pair of them is fitted in
//! their place (and, where the set holds air drag, quadratic damping at
//! the joint in the air's place: the runs may not tell the rig's loss from
//! the hinge's, which the flight margins must keep); the sets that explain
//! the runs alike — BIC within
//! [`MIN_DELTA_BIC`] of the set found, every effect they add clear of zero
//! — form an ambiguity group. The report lists them with their fits, the
//! intervals of the set found are widened to cover them, and the test that
//! would separate them is named. Friction and a softened spring resist
//! alike over a stroke; only runs with another spring (or at another
//! temperature) tell them apart.
//!
//! The best set seen is the answer ([`Search::best_of_alternatives`]):
//! every set the stage fitted is judged against the set found by the one
//! acceptance rule ([`Search::accept`] with [`Move::Alternative`]'s
//! policy, that of a second start: a BIC better by more than
//! [`MIN_DELTA_BIC`] and a held-out RMS 5 % better; a set with fewer
//! torque tables than the set found with [`Move::NamedForTable`]'s, as
//! discovery judges a named law in a table's place: a better BIC, an RMS
//! within 5 % of the table set's and a residual not above the noise), and no effect it adds
//! a claim its joint shows no evidence of ([`Rejection::UnsupportedClaim`],
//! the rule that drops such claims at the end of discovery); the best by
//! BIC that passes becomes the set found, and the groups are formed again around
//! it. At the noise floor, where the search stops adding, a set that only
//! adds effects to the set found is not judged (the stop rule of
//! [`Search::run`]). After the drawing's tolerances take a member out
//! ([`super::tolerance`]), the sets alike are judged again at the joints
//! where it left a partner ([`Search::partners_after_tolerances`],
//! [`Move::Partner`]'s policy: the gain at least the discrepancy left).

use super::candidate::Candidate;
pub use super::outcome::Ambiguity;
use super::outcome::{FittedSet, SeparatingTest, SetAside, WithinTolerance};
use super::policy::{Move, Policy, Rejection, Verdict};
use super::step::Step;
use super::{labels, Search, MIN_DELTA_BIC};
use crate::analysis::diagnose::residual_named;
use crate::model::effect::EffectKind;

/// True when `c` is a named joint effect at `joint` (not a table).
fn named_at(c: &Candidate, joint: usize) -> bool {
    c.joint == Some(joint) && c.table.is_none() && residual_named::KINDS.contains(&c.kind)
}

/// The hinge loss that air drag on the panels may stand in for at `joint`:
/// quadratic damping (`−c φ̇|φ̇|`), the air's own law on a panel that turns
/// about a fixed hinge (`c = k L⁴/4`). A diagnosis that finds air drag
/// must say when the runs cannot tell it from this loss, which flies.
fn hinge_for_air(joint: usize) -> Candidate {
    Candidate {
        kind: EffectKind::QuadraticDamping,
        joint: Some(joint),
        table: None,
    }
}

/// True when `set` exchanges a ground-rig effect of `found`
/// ([`EffectKind::rig_only`]) for a joint effect that flies: the runs then
/// cannot tell the rig's loss from the wing's.
fn rig_for_wing(found: &[Candidate], set: &[Candidate]) -> bool {
    let drops_rig = found.iter().any(|c| c.kind.rig_only() && !set.contains(c));
    let adds_wing = set
        .iter()
        .any(|c| !c.kind.rig_only() && c.joint.is_some() && !found.contains(c));
    drops_rig && adds_wing
}

/// True when `a` and `b` hold the same candidates, in any order.
fn same_set(a: &[Candidate], b: &[Candidate]) -> bool {
    a.len() == b.len() && a.iter().all(|c| b.contains(c))
}

/// The joints where the drawing's tolerances took a named joint effect out
/// with nothing in its place (`taken`: each effect taken out and what took
/// its place) and the set `now` left holds another named effect: the
/// partner the one taken out was fitted beside. A Coulomb friction put in a
/// Stribeck friction's place is the same explanation reduced, not a
/// partner left.
fn partner_joints(taken: &[(Candidate, Option<Candidate>)], now: &[Candidate]) -> Vec<usize> {
    let mut joints: Vec<usize> = taken
        .iter()
        .filter(|(_, placed)| placed.is_none())
        .filter_map(|(c, _)| c.joint.filter(|&j| named_at(c, j)))
        .filter(|&j| now.iter().any(|c| named_at(c, j)))
        .collect();
    joints.sort_unstable();
    joints.dedup();
    joints
}

/// True when `set` exchanges what `now` holds at `joints` and nothing
/// elsewhere (it drops at least one member, each dropped and each added at
/// one of `joints`) and holds none of `apart`.
fn exchanges_at(
    now: &[Candidate],
    set: &[Candidate],
    joints: &[usize],
    apart: &[Candidate],
) -> bool {
    let at_joints = |c: &Candidate| c.joint.is_some_and(|j| joints.contains(&j));
    let mut dropped = now.iter().filter(|c| !set.contains(c)).peekable();
    dropped.peek().is_some()
        && dropped.all(at_joints)
        && set.iter().filter(|c| !now.contains(c)).all(at_joints)
        && !set.iter().any(|c| apart.contains(c))
}

/// Times an alternative may take the place of the set found (each take
/// forms the groups again, a fit of every exchange at every joint).
const MAX_TAKES: usize = 2;

impl Search<'_, '_> {
    /// The ambiguity groups of the best set seen: the groups of the current
    /// set; while a set of theirs beats it by the one acceptance rule
    /// ([`Move::Alternative`]), that set (the best by BIC that passes)
    /// becomes the current one and the groups are formed again around it
    /// (at most [`MAX_TAKES`] times).
    pub(super) fn best_of_alternatives(&mut self) -> Vec<Ambiguity> {
        let mut groups = self.ambiguities();
        for _ in 0..MAX_TAKES {
            if self.eng.halt.now() || !self.take_a_better_alternative(&groups, Move::Alternative) {
                break;
            }
            groups = self.ambiguities();
        }
        groups
    }

    /// The sets alike judged again after the drawing's tolerances took
    /// `within` out of the set found ([`super::tolerance::settle`]), as
    /// [`Search::best_of_alternatives`] judges them, with
    /// [`Move::Partner`]'s policy (what a set gains must be at least the
    /// discrepancy it leaves), but only at a joint
    /// where they took a named joint effect out and left another named
    /// effect there: that one was fitted as the partner of the one taken
    /// out (a softening beside a damping, in a Coulomb friction's place)
    /// and, left alone, may fit worse than a set alike. Judged are the sets
    /// that exchange what the set holds at such joints and nothing
    /// elsewhere, never one that holds what the tolerances set apart. A
    /// Coulomb friction put in a Stribeck friction's place is the same
    /// explanation reduced, not a partner left: its joint is not judged
    /// again (a wing off its drawing fits it worse than another law, and
    /// the tolerances already account for that). Returns the groups formed
    /// around the set the judging leaves.
    pub(super) fn partners_after_tolerances(
        &mut self,
        within: &[WithinTolerance],
    ) -> Vec<Ambiguity> {
        let mut groups = self.ambiguities();
        let apart: Vec<Candidate> = within.iter().map(|w| w.effect.candidate).collect();
        let taken: Vec<(Candidate, Option<Candidate>)> = within
            .iter()
            .map(|w| (w.effect.candidate, w.in_its_place))
            .collect();
        let joints = partner_joints(&taken, &self.current.candidates());
        if joints.is_empty() {
            return groups;
        }
        for _ in 0..MAX_TAKES {
            let now = self.current.candidates();
            let exchanges = |set: &[Candidate]| exchanges_at(&now, set, &joints, &apart);
            let judged: Vec<Ambiguity> = groups
                .iter()
                .map(|g| Ambiguity {
                    sets: g
                        .sets
                        .iter()
                        .filter(|s| exchanges(&s.candidates()))
                        .cloned()
                        .collect(),
                    ..g.clone()
                })
                .collect();
            if self.eng.halt.now() || !self.take_a_better_alternative(&judged, Move::Partner) {
                break;
            }
            groups = self.ambiguities();
        }
        groups
    }

    /// Judges every set of `groups` but the current one (and, at the noise
    /// floor, but those that only add to it) against it, best BIC first, by
    /// [`Search::accept`] with `mv`'s policy ([`Move::Alternative`], or
    /// [`Move::Partner`] after the drawing's tolerances; with
    /// [`Move::NamedForTable`]'s for a set of fewer tables, and `mv`'s
    /// discrepancy check); takes the first that passes. Says what it did; returns
    /// whether it took one.
    fn take_a_better_alternative(&mut self, groups: &[Ambiguity], mv: Move) -> bool {
        let now = self.current.candidates();
        // The search's own stop: at the noise floor nothing is added, so a
        // set that only adds to the set found is not judged there.
        let at_floor = self.current.rms() <= self.floor();
        let mut others: Vec<&FittedSet> = groups
            .iter()
            .flat_map(|g| g.sets.iter())
            .filter(|s| {
                let set = s.candidates();
                let only_adds = at_floor && now.iter().all(|c| set.contains(c));
                !same_set(&set, &now) && !only_adds
            })
            .collect();
        others.sort_by(|a, b| a.bic().total_cmp(&b.bic()));
        others.dedup_by(|a, b| same_set(&a.candidates(), &b.candidates()));
        let Some(best) = others.first() else {
            return false;
        };
        if best.bic() - self.current.bic() >= -MIN_DELTA_BIC {
            return false;
        }
        if self.current_held.is_none() {
            self.current_held = self.eng.held_out(&self.current);
        }
        let tables = |s: &FittedSet| {
            s.members
                .iter()
                .filter(|m| m.candidate.table.is_some())
                .count()
        };
        for f in others {
            // A set with fewer tables is a named law in a table's place,
            // judged as discovery judges that exchange.
            let policy = if tables(f) < tables(&self.current) {
                Policy {
                    beyond_discrepancy: mv.policy().beyond_discrepancy,
                    ..Move::NamedForTable.policy()
                }
            } else {
                mv.policy()
            };
            let mut held = None;
            let mut verdict =
                self.accept((&self.current, self.current_held), f, &mut held, &policy);
            if matches!(verdict, Verdict::Accepted(_))
                && self.adds_unsupported_claim(&self.current, f, held.flatten())
            {
                verdict = Verdict::Rejected(Rejection::UnsupportedClaim);
            }
            let words = format!(
                "{} (RMS {:.4} deg, BIC {:+.1}, held-out RMS {})",
                labels(&f.candidates()),
                f.rms(),
                f.bic() - self.current.bic(),
                held.flatten()
                    .map_or_else(|| "n/a".to_string(), |h| format!("{h:.4} deg"))
            );
            if matches!(verdict, Verdict::Accepted(_)) {
                self.eng.say(format!(
                    "{} {words} in place of {} (RMS {:.4} deg)",
                    mv.done(),
                    labels(&now),
                    self.current.rms()
                ));
                self.current = f.clone();
                self.current_held = held.flatten();
                return true;
            }
            self.eng
                .say(format!("  alternative {words}: {verdict}; not taken"));
        }
        false
    }

    /// The ambiguity groups of the current set ([`Ambiguity`]), one per
    /// joint where another set explains the runs alike.
    pub(super) fn ambiguities(&self) -> Vec<Ambiguity> {
        let joints = self.eng.campaign.max_joints();
        (1..=joints).filter_map(|j| self.ambiguity_at(j)).collect()
    }

    /// `f` without the members `drop` selects (the others' values kept).
    fn reduced_by(f: &FittedSet, drop: impl Fn(&Candidate) -> bool) -> FittedSet {
        let mut r = f.clone();
        while let Some(k) = r.members.iter().position(|m| drop(&m.candidate)) {
            r = r.without(k);
        }
        r
    }

    /// The moves that exchange what the set holds at `joint` (its named
    /// effects and table) for each single and pair of named joint effects
    /// there, beside the rest of the set and, when the set holds a global
    /// effect (rig tilt, air drag), beside the rest without it too (a
    /// global effect may stand in for a joint torque).
    fn exchanges_at(&self, joint: usize) -> Vec<Step> {
        let at = |c: &Candidate| c.joint == Some(joint) && c.kind != EffectKind::EncoderOffset;
        let rest = Self::reduced_by(&self.current, at);
        let mut bases = vec![rest.clone()];
        if rest.members.iter().any(|m| m.candidate.joint.is_none()) {
            bases.push(Self::reduced_by(&rest, |c| c.joint.is_none()));
        }
        let mut moves = Vec::new();
        for base in bases {
            moves.extend(
                residual_named::KINDS
                    .iter()
                    .map(|&kind| Candidate {
                        kind,
                        joint: Some(joint),
                        table: None,
                    })
                    .filter(|c| self.candidates.contains(c))
                    .map(|c| Step::new(base.clone(), c)),
            );
            moves.extend(self.named_pairs_at(&base, joint));
        }
        // An alternative exchanges the joint's effects: a set that keeps
        // them all (and adds one more, near zero) is the same explanation.
        let now = self.current.candidates();
        let here: Vec<Candidate> = now.iter().copied().filter(at).collect();
        moves.retain(|step| {
            let mut s = step.base.candidates();
            s.push(step.candidate);
            !same_set(&s, &now) && (here.is_empty() || !here.iter().all(|h| s.contains(h)))
        });
        moves
    }

    /// When the set holds air drag: the set with quadratic damping at
    /// `joint` in the air drag's place, the rest kept (the effects at the
    /// joint too: the rig's loss exchanged for the wing's, nothing else),
    /// fitted from the damping the air drag gives a panel that turns about
    /// that hinge (`c = k R⁴/4`, `R` the panels' length from the hinge
    /// out, of the first run's mechanism) and the kind's scan. Fitted
    /// apart from the exchanges of [`Search::exchanges_at`], whose screen
    /// keeps the sets that add little to the air drag and would leave this
    /// one out.
    fn hinge_in_place_of_air(&self, joint: usize) -> Option<FittedSet> {
        let air = |c: &Candidate| c.kind == EffectKind::AirDrag;
        let k = self
            .current
            .members
            .iter()
            .find(|m| air(&m.candidate))?
            .params
            .first()
            .copied()?;
        let hinge = hinge_for_air(joint);
        if self.current.contains(&hinge) {
            return None;
        }
        let base = Self::reduced_by(&self.current, air);
        let c = self.eng.campaign;
        let reach: f64 = c
            .runs
            .first()?
            .mechanism
            .panels
            .iter()
            .skip(joint - 1)
            .map(|p| p.length_m)
            .sum();
        let starts = std::iter::once(vec![k * reach.powi(4) / 4.0]).chain(hinge.scan());
        let points = starts.map(|s| base.params().into_iter().chain(s).collect());
        let p = self.eng.best_point(c, &base, hinge, points)?;
        self.eng.fit(c, &p.candidates(), &p.params())
    }

    /// A fitted alternative without the members whose interval holds zero
    /// (refitted once), when that still fits alike.
    fn trimmed(&self, f: FittedSet, best: f64) -> FittedSet {
        let keep: Vec<usize> = (0..f.members.len())
            .filter(|&k| f.members[k].clear_of_zero())
            .collect();
        if keep.len() == f.members.len() || keep.is_empty() {
            return f;
        }
        let mut r = f.clone();
        for k in (0..f.members.len()).rev().filter(|k| !keep.contains(k)) {
            r = r.without(k);
        }
        match self.eng.refit(self.eng.campaign, &r) {
            Some(t) if t.bic() - best < MIN_DELTA_BIC => t,
            _ => f,
        }
    }

    /// The ambiguity group at `joint`, when there is one.
    fn ambiguity_at(&self, joint: usize) -> Option<Ambiguity> {
        let moves = self.exchanges_at(joint);
        if moves.is_empty() || self.eng.halt.now() {
            return None;
        }
        self.eng.say(format!(
            "ambiguity: at joint {joint}, fitting {} other sets of named effects",
            moves.len()
        ));
        let best = self.current.bic();
        let fits: Vec<FittedSet> = self
            .eng
            .fit_moves_sharing(self.eng.campaign, &moves)
            .into_iter()
            .filter(|(_, _, screened_out)| !screened_out)
            .filter_map(|(_, f, _)| f)
            .chain(self.hinge_in_place_of_air(joint))
            .filter(|f| f.bic() - best < MIN_DELTA_BIC)
            .collect();
        let mut alike: Vec<FittedSet> = Vec::new();
        for f in fits {
            let f = self.trimmed(f, best);
            let clear = f
                .members
                .iter()
                .filter(|m| m.candidate.table.is_none())
                .all(|m| m.clear_of_zero());
            let set = f.candidates();
            let named_here = set
                .iter()
                .any(|c| named_at(c, joint) || *c == hinge_for_air(joint));
            if clear
                && named_here
                && !same_set(&set, &self.current.candidates())
                && !alike.iter().any(|a| same_set(&a.candidates(), &set))
            {
                alike.push(f);
            }
        }
        if alike.is_empty() {
            return None;
        }
        alike.sort_by(|a, b| a.bic().total_cmp(&b.bic()));
        for f in &alike {
            self.eng.say(format!(
                "  explains the runs alike: {} (RMS {:.4} deg, BIC {:+.1})",
                labels(&f.candidates()),
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
        let now = self.current.candidates();
        let separating_test = if alike.iter().any(|f| rig_for_wing(&now, &f.candidates())) {
            SeparatingTest::WithoutTheRig
        } else if one_config {
            SeparatingTest::AnotherSpring
        } else {
            SeparatingTest::AnotherRange
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
    for m in out.members.iter_mut() {
        let c = m.candidate;
        if m.params.len() != 1 {
            continue;
        }
        for g in groups.iter().filter(|g| c.joint == Some(g.joint)) {
            let Some(ci) = m.ci95.as_mut().and_then(|v| v.first_mut()) else {
                continue;
            };
            for s in &g.sets {
                match s.members.iter().position(|x| x.candidate == c) {
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
    }
    out
}

/// The groups as the report lists them beside `answer`: without the sets
/// that keep every member of the answer and add to it. Such a set is not
/// another explanation of what the answer explains but a claim made on top
/// of it that was not taken. Fitting better by more than
/// [`MIN_DELTA_BIC`], it was refused by the acceptance rule (its gain not
/// held out, within the discrepancy left, at a joint that shows no evidence
/// of it), or re-fits what the drawing's tolerances or the discrepancy
/// took out of the answer; fitting alike, what it adds explains nothing
/// the runs show (a harness of 0.0002 N·m/rad beside a clean wing's
/// answer): the same explanation, as at a joint where the answer holds
/// effects ([`Search::ambiguities`] leaves such sets out there). Listed,
/// it would read as a set the runs cannot tell from the answer. A group
/// left with the answer alone is dropped. The answer's intervals are
/// widened over the sets listed ([`widened`]).
pub(super) fn listed(groups: Vec<Ambiguity>, answer: &FittedSet) -> Vec<Ambiguity> {
    let holds = answer.candidates();
    groups
        .into_iter()
        .filter_map(|mut g| {
            let mut k = 0;
            g.sets.retain(|s| {
                k += 1;
                let adds = holds.iter().all(|c| s.contains(c)) && s.members.len() > holds.len();
                k == 1 || !adds
            });
            (g.sets.len() > 1).then_some(g)
        })
        .collect()
}

impl Search<'_, '_> {
    /// Once the search is done: the sets that explain the runs alike
    /// ([`Search::ambiguities`]) and the claims set aside within the discrepancy
    /// ([`super::discrepancy`]; the sets alike are listed again when some were),
    /// after a fit on the whole runs (`whole`) the negligible members
    /// dropped ([`super::whole_fit`]).
    pub(super) fn alternatives_and_set_aside(
        &mut self,
        whole: bool,
    ) -> (Vec<Ambiguity>, Vec<SetAside>) {
        if whole {
            self.drop_negligible();
        }
        let mut ambiguities = if self.eng.halt.now() {
            Vec::new()
        } else {
            self.best_of_alternatives()
        };
        let set_aside = self.set_aside_within_discrepancy();
        if !set_aside.is_empty() && !self.eng.halt.now() {
            ambiguities = self.ambiguities();
        }
        (ambiguities, set_aside)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(kind: EffectKind, joint: usize) -> Candidate {
        Candidate {
            kind,
            joint: Some(joint),
            table: None,
        }
    }

    fn rig_tilt() -> Candidate {
        Candidate {
            kind: EffectKind::RigTilt,
            joint: None,
            table: None,
        }
    }

    #[test]
    fn a_partner_is_left_only_where_a_named_effect_was_taken_out_beside_it() {
        use EffectKind::{
            CoulombFriction, EncoderOffset, SpringSoftening, StribeckFriction, ViscousDamping,
        };
        let now = [at(SpringSoftening, 1), at(ViscousDamping, 3)];
        // A damping taken out beside the softening at joint 1: joint 1.
        assert_eq!(
            partner_joints(&[(at(ViscousDamping, 1), None)], &now),
            vec![1]
        );
        // A Stribeck friction reduced to Coulomb friction in its place.
        let reduced = (at(StribeckFriction, 1), Some(at(CoulombFriction, 1)));
        assert!(partner_joints(&[reduced], &now).is_empty());
        // A global effect, an encoder offset, a joint left with nothing named.
        assert!(partner_joints(&[(rig_tilt(), None)], &now).is_empty());
        assert!(partner_joints(&[(at(EncoderOffset, 1), None)], &now).is_empty());
        assert!(partner_joints(&[(at(ViscousDamping, 2), None)], &now).is_empty());
        // Two taken out at one joint name it once.
        let two = [
            (at(ViscousDamping, 1), None),
            (at(CoulombFriction, 1), None),
        ];
        assert_eq!(partner_joints(&two, &now), vec![1]);
    }

    #[test]
    fn an_exchange_stays_at_its_joints_and_never_brings_back_what_was_set_apart() {
        use EffectKind::{
            CoulombFriction, EncoderOffset, HarnessStiffness, SpringSoftening, ViscousDamping,
        };
        let now = [at(SpringSoftening, 1), at(EncoderOffset, 4)];
        let apart = [at(ViscousDamping, 1)];
        let joints = [1];
        let ok = |set: &[Candidate]| exchanges_at(&now, set, &joints, &apart);
        assert!(ok(&[at(CoulombFriction, 1), at(EncoderOffset, 4)]));
        assert!(ok(&[
            at(CoulombFriction, 1),
            at(HarnessStiffness, 1),
            at(EncoderOffset, 4)
        ]));
        // Keeps every member: adds, exchanges nothing.
        assert!(!ok(&[
            at(SpringSoftening, 1),
            at(EncoderOffset, 4),
            at(CoulombFriction, 2)
        ]));
        assert!(!ok(&now));
        // Holds what the tolerances set apart.
        assert!(!ok(&[at(ViscousDamping, 1), at(EncoderOffset, 4)]));
        // Drops or adds at another joint.
        assert!(!ok(&[at(CoulombFriction, 1)]));
        assert!(!ok(&[
            at(CoulombFriction, 1),
            at(EncoderOffset, 4),
            at(CoulombFriction, 2)
        ]));
        assert!(!ok(&[
            at(CoulombFriction, 1),
            at(EncoderOffset, 4),
            rig_tilt()
        ]));
    }
}
