//! Discovery guided by the residual torque from the data
//! ([`crate::analysis::diagnose::residual_torque`]).
//!
//! Tables are tried at the joints whose residual torque is significant
//! beside the set they would join (at every joint, in the even forms, only
//! when no joint's is), and besides the even forms of
//! [`super::discover`], in the shape the residual torque itself has
//! ([`crate::analysis::diagnose::residual_shape`]: knots placed where it bends, their
//! number by BIC), which starts the fit through the simulator. Each claim
//! is checked against the same evidence at the end: a table or a named
//! joint effect whose joint shows no significant residual torque without
//! it is dropped.

use super::candidate::Candidate;
use super::discover;
use super::outcome::{CandidateScore, FittedEffect, FittedSet, Unexplained, UnexplainedShape};
use super::policy::{Attempt, Move, Verdict};
use super::step::Step;
use super::table_form::PlacedKnots;
use super::{above_noise, labels, Engine, Proposal, Search, MAX_TABLES, NOISE_FLOOR_FACTOR};
use crate::analysis::diagnose::evidence::{analyse, CLEAR_SIGMAS};
use crate::analysis::diagnose::residual_named::{self, propose_pair};
use crate::analysis::diagnose::residual_shape::best_shape;
use crate::analysis::diagnose::residual_torque::{residual_torque, JointTorque};
use crate::data::campaign::Campaign;
use crate::model::effect::{Effect, EffectKind};

/// Without residual-torque evidence, the first table is tried at the joints
/// whose residual angle RMS is at least this share of the largest joint's
/// \[1\].
const ANGLE_EVIDENCE_SHARE: f64 = 0.5;

/// Table forms per joint that [`Move::TablePair`] pairs, best by BIC
/// first: two pairs of forms for two joints, four fits each way.
const TABLE_PAIR_FORMS: usize = 2;

impl Search<'_, '_> {
    /// Discovery: while the residual stays above the noise floor, fit torque
    /// tables at the joints whose residual torque is significant
    /// ([`Move::Table`]; the even tables at every joint for the first,
    /// [`Move::EvenTable`]), judge them like any candidate, let a named
    /// effect that explains the data replace a table
    /// ([`Move::NamedForTable`]), and after one is added let the named
    /// search go on beside it. At most [`MAX_TABLES`] tables, at different
    /// joints; then refinement and the check of every claim.
    pub(super) fn discover(&mut self) {
        for _ in 0..MAX_TABLES {
            if self.current.rms() <= self.floor() {
                break;
            }
            match self.attempt(Move::Table) {
                Attempt::NotTried => break,
                Attempt::Judged
                    if self.attempt(Move::EvenTable) != Attempt::Moved
                        && self.attempt(Move::TablePair) != Attempt::Moved =>
                {
                    break
                }
                _ => {}
            }
            if self.attempt(Move::NamedForTable) == Attempt::Moved {
                continue;
            }
            if above_noise(&self.current, self.sigma) {
                self.swaps = 0;
                self.run();
            }
        }
        self.refine_tables();
        self.check_claims();
    }

    /// [`Move::Table`]: beside the current set and in place of each of its
    /// named effects, a table at each joint without one whose residual
    /// torque beside that set is significant (the even tables at every
    /// joint when no joint's is and the set holds no table).
    pub(super) fn propose_tables(&mut self) -> Option<Proposal> {
        let moves = self.table_moves();
        self.table_tried = moves.clone();
        if moves.is_empty() {
            return None;
        }
        self.eng.say(format!(
            "discovery: the residual stays at {:.4} deg; fitting {} torque tables beside {}",
            self.current.rms(),
            moves.len(),
            labels(&self.current.candidates())
        ));
        Some(moves)
    }

    /// [`Move::EvenTable`]: for the first table, when the tables at the
    /// evidence's joints were not kept, the even forms beside the current
    /// set that they did not hold — at the joints whose residual torque
    /// beside the current set is significant when there are any (the
    /// evidence says where; only the shape failed), at every joint when
    /// there are none. (A joint significant only beside a smaller set is
    /// not evidence beside this one: a large torque missing at one joint
    /// reaches the others through the mass matrix.)
    pub(super) fn propose_even_tables(&mut self) -> Option<Proposal> {
        let first = self
            .current
            .members
            .iter()
            .all(|m| m.candidate.table.is_none());
        let evidence: Vec<Option<usize>> = self
            .table_tried
            .iter()
            .filter(|s| s.base == self.current)
            .map(|s| s.candidate.joint)
            .collect();
        let evidence = if evidence.is_empty() {
            self.angle_joints()
        } else {
            evidence
        };
        let even: Vec<Step> = self
            .even_moves()
            .into_iter()
            .filter(|s| evidence.is_empty() || evidence.contains(&s.candidate.joint))
            .collect();
        let tried = |m: &Step| {
            self.table_tried
                .iter()
                .any(|t| t.base == m.base && t.candidate == m.candidate)
        };
        if !first || even.iter().all(tried) {
            return None;
        }
        self.eng.say(format!(
            "  no table at the evidence's joints earns its keep: even tables at joints {}",
            evidence
                .iter()
                .flatten()
                .map(|j| j.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ));
        Some(even)
    }

    /// [`Move::TablePair`]: for the first tables, when no single table
    /// was kept, two tables at two joints together: the
    /// [`TABLE_PAIR_FORMS`] best forms by BIC at each joint of the table
    /// rounds beside the current set, each fitted with each of the other
    /// joints' (its fitted single as the base, the other's screen from the
    /// start its table round gave it, [`Search::table_start`]).
    pub(super) fn propose_table_pairs(&mut self) -> Option<Proposal> {
        let start = self.current.candidates();
        if self
            .current
            .members
            .iter()
            .any(|m| m.candidate.table.is_some())
        {
            return None;
        }
        let mut singles: Vec<&CandidateScore> = self
            .rounds
            .iter()
            .filter(|r| r.start == start)
            .flat_map(|r| &r.scores)
            .filter(|s| s.candidate.table.is_some() && s.fitted.members.len() == start.len() + 1)
            .collect();
        singles.sort_by(|a, b| b.delta_bic.total_cmp(&a.delta_bic));
        let mut per_joint: Vec<&CandidateScore> = Vec::new();
        for s in singles {
            let at = per_joint
                .iter()
                .filter(|p| p.candidate.joint == s.candidate.joint)
                .count();
            if at < TABLE_PAIR_FORMS && !per_joint.iter().any(|p| p.candidate == s.candidate) {
                per_joint.push(s);
            }
        }
        let this = &*self;
        let moves: Vec<Step> = per_joint
            .iter()
            .flat_map(|a| {
                per_joint
                    .iter()
                    .filter(move |b| b.candidate.joint != a.candidate.joint)
                    .map(move |b| {
                        Step::from(a.fitted.clone(), b.candidate, this.table_start(b.candidate))
                    })
            })
            .collect();
        if moves.is_empty() {
            return None;
        }
        self.eng.say(format!(
            "  no single table earns its keep: fitting {} pairs of tables at two joints beside {}",
            moves.len(),
            labels(&start)
        ));
        Some(moves)
    }

    /// The start a table candidate was given in the last table round
    /// ([`Move::Table`], the last given to its form); `None`: its own scan.
    fn table_start(&self, cand: Candidate) -> Option<Vec<f64>> {
        let form = cand.table?;
        self.table_tried
            .iter()
            .rev()
            .filter(|s| s.candidate.table == Some(form))
            .find_map(|s| s.start.clone())
    }

    /// Where the angles say a torque is missing when the residual torque
    /// names no joint: the joints whose residual angle RMS (the largest
    /// over the runs, beside the current set) is at least
    /// [`ANGLE_EVIDENCE_SHARE`] of the largest joint's. A torque moves its
    /// own joint's angle most; the others follow through the chain.
    fn angle_joints(&self) -> Vec<Option<usize>> {
        let ev = analyse(self.eng.campaign, &self.current.effects(), self.sigma);
        let joints = ev.iter().map(|e| e.joint).max().unwrap_or(0);
        let rms = |j: usize| {
            ev.iter()
                .filter(|e| e.joint == j)
                .map(|e| e.rms_deg)
                .fold(0.0, f64::max)
        };
        let top = (1..=joints).map(rms).fold(0.0, f64::max);
        (1..=joints)
            .filter(|&j| rms(j) >= ANGLE_EVIDENCE_SHARE * top)
            .map(Some)
            .collect()
    }

    /// [`Move::NamedForTable`]: each table of the set replaced by every
    /// named candidate in turn and by the pairs of named effects at its
    /// joint ([`Search::named_pairs_for`], screened also where the two
    /// share their torque, [`super::Engine::fit_moves_sharing`]).
    pub(super) fn named_for_tables(&self) -> Vec<Step> {
        let named: Vec<Candidate> = self.outside();
        let mut moves = Vec::new();
        for (k, m) in self.current.members.iter().enumerate() {
            if m.candidate.table.is_some() {
                let reduced = self.current.without(k);
                moves.extend(named.iter().map(|&n| Step::new(reduced.clone(), n)));
                moves.extend(self.named_pairs_for(&reduced, m.candidate));
            }
        }
        moves
    }

    /// The discovery moves: beside the current set and in place of each of
    /// its named effects, a table at each joint without one whose residual
    /// torque beside that set is significant.
    fn table_moves(&self) -> Vec<Step> {
        let taken = self.table_joints();
        let named = (0..self.current.members.len())
            .filter(|&k| self.current.members[k].candidate.table.is_none());
        let bases: Vec<FittedSet> = std::iter::once(self.current.clone())
            .chain(named.map(|k| self.current.without(k)))
            .collect();
        let even = discover::table_candidates(self.eng.campaign);
        let mut moves = Vec::new();
        for base in &bases {
            let res = residual_torque(self.eng.campaign, &base.effects());
            for jt in res
                .iter()
                .filter(|j| j.significant && !taken.contains(&Some(j.joint)))
            {
                for (c, start) in self.joint_tables(jt, &even) {
                    moves.push(Step::from(base.clone(), c, start));
                }
            }
        }
        if moves.is_empty() && taken.is_empty() {
            self.eng.say("  no joint's residual torque is significant");
            return self.even_moves();
        }
        moves
    }

    /// The joints of the set's tables.
    fn table_joints(&self) -> Vec<Option<usize>> {
        self.current
            .members
            .iter()
            .filter(|m| m.candidate.table.is_some())
            .map(|m| m.candidate.joint)
            .collect()
    }

    /// The even forms at every joint without a table, beside the current
    /// set: for the first table, when the evidence finds no joint or its
    /// joints' tables do not earn their keep, although the angles say a
    /// torque is missing (one too fast for the smoother, say). A second
    /// table needs the evidence. Each claim is checked at the end.
    fn even_moves(&self) -> Vec<Step> {
        let taken = self.table_joints();
        discover::table_candidates(self.eng.campaign)
            .into_iter()
            .filter(|c| !taken.contains(&c.joint))
            .map(|c| Step::new(self.current.clone(), c))
            .collect()
    }

    /// The table candidates at one joint, each with the start of its
    /// screen: the even forms (their own scan) and the shape the residual
    /// torque has (its knot torques as the start).
    pub(super) fn joint_tables(
        &self,
        jt: &JointTorque,
        even: &[Candidate],
    ) -> Vec<(Candidate, Option<Vec<f64>>)> {
        let mine: Vec<Candidate> = even
            .iter()
            .copied()
            .filter(|c| c.joint == Some(jt.joint))
            .collect();
        let mut out: Vec<(Candidate, Option<Vec<f64>>)> = mine.iter().map(|&c| (c, None)).collect();
        let Some(form) = mine.first().and_then(|c| c.table) else {
            return out;
        };
        let motion = -f64::from(form.from_deg).signum();
        let Some(shape) = best_shape(&jt.samples, motion) else {
            return out;
        };
        let Some(placed) = PlacedKnots::form(&shape, form.from_deg, form.rate_max_deg_s) else {
            return out;
        };
        self.eng.say(format!(
            "  residual torque at joint {}: {} angle and {} rate knots (BIC {:.0} against {:.0} for none)",
            jt.joint,
            shape.angle_deg.len(),
            shape.rate_deg_s.len(),
            shape.bic,
            shape.bic_zero
        ));
        out.push((
            Candidate {
                kind: EffectKind::TorqueTable,
                joint: Some(jt.joint),
                table: Some(placed),
            },
            Some(PlacedKnots::start(&shape)),
        ));
        out
    }

    /// Drops every claim the data do not support whose loss the fit hardly
    /// notices ([`Move::DropClaim`], judged by [`Search::accept`]: the set
    /// without it within [`super::policy::CLAIM_RMS_SHARE`] of the set's RMS): a named effect whose 95 % interval
    /// contains zero (a move can leave one behind: a named effect in place
    /// of a table is not followed by the backward drop), and a table or
    /// named joint effect whose joint shows no evidence of it without it —
    /// a claim at a joint that holds nothing. The evidence of a torque is a
    /// significant residual torque at its joint; that of an encoder offset,
    /// a residual already clear at release in some run
    /// ([`offset_evidence`]: an offset reads the stowed panel off by itself
    /// before anything has moved).
    fn check_claims(&mut self) {
        loop {
            let weak: Vec<(usize, &str)> = (0..self.current.members.len())
                .filter_map(|k| self.unsupported(k).map(|why| (k, why)))
                .collect();
            let mut dropped = false;
            for (k, why) in weak {
                let gone = self.current.members[k].candidate;
                let Some(f) = self.eng.refit(self.eng.campaign, &self.current.without(k)) else {
                    continue;
                };
                // The evidence may miss a torque the fit needs: a claim goes
                // only when the fit hardly notices (the data hold nothing there).
                let verdict = self.accept(
                    (&self.current, self.current_held),
                    &f,
                    &mut None,
                    &Move::DropClaim.policy(),
                );
                if !matches!(verdict, Verdict::Accepted(_)) {
                    continue;
                }
                self.eng.say(format!(
                    "  dropped {}: {why} (RMS without it {:.4} deg)",
                    gone.words(),
                    f.rms()
                ));
                self.current_held = self.eng.held_out(&f);
                self.current = f;
                dropped = true;
                break;
            }
            if !dropped {
                return;
            }
        }
    }

    /// True when `to` adds to `from` (members not in it) a claim the data do
    /// not support that the check at the end of discovery
    /// ([`Search::check_claims`]) would drop: its joint shows no evidence
    /// of it without it, and `to` refitted without it is accepted by
    /// [`Move::DropClaim`]'s policy against `to` (held-out RMS `to_held`).
    /// A move that takes the place of the set found ([`Move::Alternative`])
    /// may not bring one in.
    pub(super) fn adds_unsupported_claim(
        &self,
        from: &FittedSet,
        to: &FittedSet,
        to_held: Option<f64>,
    ) -> bool {
        let before = from.candidates();
        (0..to.members.len()).any(|k| {
            let c = to.members[k].candidate;
            if before.contains(&c) || self.unsupported_in(to, k).is_none() {
                return false;
            }
            let Some(f) = self.eng.refit(self.eng.campaign, &to.without(k)) else {
                return false;
            };
            let verdict = self.accept((to, to_held), &f, &mut None, &Move::DropClaim.policy());
            matches!(verdict, Verdict::Accepted(_))
        })
    }

    /// Why member `k` of the current set is a claim the data do not
    /// support ([`Search::check_claims`]), or `None`.
    fn unsupported(&self, k: usize) -> Option<&'static str> {
        self.unsupported_in(&self.current, k)
    }

    /// Why member `k` of `set` is a claim the data do not support, or
    /// `None` ([`Search::unsupported`] for any set).
    fn unsupported_in(&self, set: &FittedSet, k: usize) -> Option<&'static str> {
        let m = set.members.get(k)?;
        let c = m.candidate;
        if c.table.is_none() && m.ci95.is_some() && !m.clear_of_zero() {
            return Some("its 95 % interval contains zero");
        }
        let j = c.joint.filter(|&j| j <= self.eng.campaign.max_joints())?;
        let without = set.without(k).effects();
        if c.kind == EffectKind::EncoderOffset {
            return (!offset_evidence(self.eng.campaign, &without, j, self.sigma))
                .then_some("its joint shows no residual at release without it");
        }
        residual_torque(self.eng.campaign, &without)
            .iter()
            .any(|r| r.joint == j && !r.significant)
            .then_some("its joint shows no significant residual torque without it")
    }

    /// [`Move::Proposed`], when the stepwise search ends above the noise:
    /// the pairs of named effects at one joint that the baseline's residual
    /// torque proposes ([`propose_pair`]), fitted through the simulator in
    /// place of the current set and judged like any move. Once.
    pub(super) fn propose_proposed(&mut self) -> Option<Proposal> {
        if !self.first_time(Move::Proposed) {
            return None;
        }
        let res = residual_torque(self.eng.campaign, &[]);
        let mut moves = Vec::new();
        for p in res.iter().filter_map(propose_pair) {
            let [(a, va), (b, _)] = p.effects[..] else {
                continue;
            };
            let cand = |kind| Candidate {
                kind,
                joint: Some(p.joint),
                table: None,
            };
            if !self.candidates.contains(&cand(a)) || !self.candidates.contains(&cand(b)) {
                continue;
            }
            let base = FittedSet {
                members: vec![FittedEffect::start(cand(a), vec![va])],
                stats: None,
            };
            self.eng.say(format!(
                "  the residual torque at joint {} looks like {} and {}",
                p.joint,
                cand(a).words(),
                cand(b).words()
            ));
            moves.push(Step::new(base, cand(b)));
        }
        if moves.is_empty() {
            return None;
        }
        Some(moves)
    }
}

impl Search<'_, '_> {
    /// Two named effects at one joint in place of a table there: the
    /// residual torque beside `reduced` (the set without the table) at the
    /// table's joint is regressed on each pair of named signatures
    /// ([`residual_named::fit`], no simulation); every pair with positive
    /// values is a move, the first effect starting from its regressed
    /// value. A table that stands in for two causes at one joint (a
    /// softened spring with friction, say) is replaced when the pair fits
    /// as well with fewer parameters.
    pub(super) fn named_pairs_for(&self, reduced: &FittedSet, table: Candidate) -> Vec<Step> {
        match table.joint {
            Some(joint) => self.named_pairs_at(reduced, joint),
            None => Vec::new(),
        }
    }

    /// The pairs of named joint effects at `joint` beside `reduced`
    /// ([`Search::named_pairs_for`]).
    pub(super) fn named_pairs_at(&self, reduced: &FittedSet, joint: usize) -> Vec<Step> {
        let res = residual_torque(self.eng.campaign, &reduced.effects());
        let Some(jt) = res.iter().find(|r| r.joint == joint) else {
            return Vec::new();
        };
        let samples = crate::analysis::diagnose::residual_shape::thin(&jt.samples);
        let cand = |kind| Candidate {
            kind,
            joint: Some(joint),
            table: None,
        };
        let kinds = residual_named::KINDS;
        let mut moves = Vec::new();
        for (a, &ka) in kinds.iter().enumerate() {
            for &kb in &kinds[a + 1..] {
                let (ca, cb) = (cand(ka), cand(kb));
                if !self.candidates.contains(&ca) || !self.candidates.contains(&cb) {
                    continue;
                }
                // Where the residual torque cannot separate the two (a
                // value not positive), the first starts from its value
                // alone and the screen shares the torque
                // ([`super::Engine::screen_shared`]).
                let Some((v, _)) = residual_named::fit(&samples, &[ka, kb])
                    .or_else(|| residual_named::fit(&samples, &[ka]))
                else {
                    continue;
                };
                moves.push(Step::new(
                    reduced.with(FittedEffect::start(ca, vec![v[0]])),
                    cb,
                ));
            }
        }
        moves
    }
}

/// True when the residual of `f` is not clearly above the noise
/// ([`above_noise`]) but not down to it either (above
/// [`NOISE_FLOOR_FACTOR`] σ̂): where a global effect may stand in for a
/// joint torque.
/// Whether `effects` leave a residual at joint `joint` (1-based) already
/// clear of the noise at release in some run: the mean over the first
/// [`crate::analysis::diagnose::evidence::RELEASE_WINDOW_S`] beyond [`CLEAR_SIGMAS`] σ̂ — the evidence an
/// encoder offset leaves (`evidence::analyse`'s sensor effect).
fn offset_evidence(campaign: &Campaign, effects: &[Effect], joint: usize, sigma: f64) -> bool {
    analyse(campaign, effects, sigma)
        .iter()
        .any(|e| e.joint == joint && e.at_release_mean_deg.abs() > CLEAR_SIGMAS * sigma)
}

pub(super) fn near_noise(f: &FittedSet, sigma: f64) -> bool {
    !above_noise(f, sigma) && f.rms() > NOISE_FLOOR_FACTOR * sigma
}

impl Engine<'_> {
    /// For each global effect `k` of `f` (rig tilt, air drag): the joint
    /// whose residual torque, without that effect, is significant and
    /// largest by `χ²` among the joints where `f` claims no torque (encoder
    /// offsets aside) — the joint torque the global effect stands in for.
    pub(super) fn hidden_by_globals(&self, f: &FittedSet) -> Vec<(usize, JointTorque)> {
        let claimed: Vec<usize> = f
            .candidates()
            .iter()
            .filter(|c| c.kind != EffectKind::EncoderOffset)
            .filter_map(|c| c.joint)
            .collect();
        (0..f.members.len())
            .filter(|&k| f.members[k].candidate.joint.is_none())
            .filter_map(|k| {
                residual_torque(self.campaign, &f.without(k).effects())
                    .into_iter()
                    .filter(|j| j.significant && !claimed.contains(&j.joint))
                    .max_by(|a, b| a.chi2.total_cmp(&b.chi2))
                    .map(|j| (k, j))
            })
            .collect()
    }

    /// The `unexplained` residual of a set whose residual is not clearly
    /// above the noise ([`above_noise`]) but not down to it either (above
    /// [`NOISE_FLOOR_FACTOR`] σ̂), when a global effect of it (rig tilt,
    /// air drag) stands in for a joint torque: without it, the residual
    /// torque is significant at a joint where the set claims no torque
    /// (encoder offsets aside). The data say a torque is missing at that
    /// joint, which the global effect brought within the noise of the
    /// angles without holding it. That joint's torque is the one of the
    /// largest `χ²`.
    pub(super) fn unexplained_torque(&self, f: &FittedSet, sigma: f64) -> Option<Unexplained> {
        if !near_noise(f, sigma) {
            return None;
        }
        let (_, torque) = self
            .hidden_by_globals(f)
            .into_iter()
            .max_by(|a, b| a.1.chi2.total_cmp(&b.1.chi2))?;
        Some(Unexplained {
            rms_deg: f.rms(),
            noise_sigma_deg: sigma,
            shape: UnexplainedShape::StandIn { torque },
        })
    }
}

impl Search<'_, '_> {
    /// [`Move::JointPairs`], when the stepwise search stalls with the
    /// residual clearly above the noise: at each joint where the set holds
    /// named joint effects with a torque signature, every pair of them in
    /// place of those effects ([`Search::named_pairs_at`], screened also
    /// where the two share their torque,
    /// [`super::Engine::fit_moves_sharing`]): two causes at one joint where
    /// the search settled on stand-ins. Once (counted from the first time
    /// the residual is above the noise here).
    pub(super) fn propose_joint_pairs(&mut self) -> Option<Proposal> {
        if !above_noise(&self.current, self.sigma) || !self.first_time(Move::JointPairs) {
            return None;
        }
        let named_at = |c: &Candidate, j: usize| {
            c.joint == Some(j) && c.table.is_none() && residual_named::KINDS.contains(&c.kind)
        };
        let mut joints: Vec<usize> = self
            .current
            .candidates()
            .iter()
            .filter(|c| c.table.is_none() && residual_named::KINDS.contains(&c.kind))
            .filter_map(|c| c.joint)
            .collect();
        joints.sort_unstable();
        joints.dedup();
        let mut moves = Vec::new();
        for j in joints {
            let mut base = self.current.clone();
            while let Some(k) = base.members.iter().position(|m| named_at(&m.candidate, j)) {
                base = base.without(k);
            }
            moves.extend(self.named_pairs_at(&base, j));
        }
        if moves.is_empty() {
            return None;
        }
        self.eng.say(format!(
            "  named pairs at a joint in place of its named effects: fitting {}",
            moves.len()
        ));
        Some(moves)
    }
}
