//! What `deploywatch identify --json` and `deploywatch diagnose --json`
//! found, as the laws of a reliability analysis (`reliability --from`): the
//! one reader of those files here, so that it follows their format in one
//! place. A diagnosis's effects are read by the findings' own reader
//! ([`FoundEffect::to_effect`](crate::model::findings::diagnosis::FoundEffect::to_effect)),
//! so the law of each is centred on the value fitted, its other parameters
//! (joint, direction, Stribeck shape) as fitted. A torque table has no
//! one value to draw: it is a measured fixed resistance, carried as found
//! by every deployment ([`Fixed`]), each knot at the end of its band that
//! resists the deployment, as `margin --from` takes it
//! ([`resistances::at_worst_end`]).

use super::normal;
use super::params::{Dist, Fixed, Target, Vary};
use crate::analysis::fit::Z_975;
use crate::analysis::{effect_margin, resistances};
use crate::model::effect::{Effect, EffectKind, ValueRange};
use crate::model::findings::diagnosis::FoundEffect;
use crate::model::findings::{Diagnosis, Findings, FindingsError, Identification};
use crate::model::mechanism::Mechanism;

/// What a findings file gives a reliability analysis: the laws to draw
/// and the effects every deployment carries as found.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FromFindings {
    /// One law per effect found with an interval.
    pub vary: Vec<Vary>,
    /// The torque tables found, as the margins take them.
    pub fixed: Vec<Fixed>,
    /// What the file holds that is no effect (a diagnosis's
    /// `"unexplained"`), in words: in no deployment, said so by the
    /// command.
    pub left_out: Vec<String>,
    /// A diagnosis that names no effect (none found, or only
    /// `"unexplained"`): why nothing can be carried, in words. The
    /// command refuses it (`reliability --from`, exit 2).
    pub no_effect: Option<String>,
    /// The mechanisms the findings were made on (their names; empty when
    /// the file does not say): a wing other than the one analysed is the
    /// command's to say.
    pub found_on: Vec<String>,
    /// The wing's own losses the diagnosis could not tell from its
    /// rig-only effects ([`Diagnosis::flight_stand_ins`]), as laws: what
    /// [`FromFindings::take_out_the_rig`] draws in their place.
    pub stand_ins: Vec<StandInLaws>,
}

/// The laws of a loss of the wing's own that the runs could not tell from
/// rig-only effects of the set found.
#[derive(Clone, Debug, PartialEq)]
pub struct StandInLaws {
    /// The rig-only effects it may stand in for.
    pub replaces: Vec<EffectKind>,
    /// One law per effect of it.
    pub vary: Vec<Vary>,
}

impl FromFindings {
    /// What the command says of the findings applied to `mechanism`, each
    /// after `from` (how the command names the file: `--from F`,
    /// `from_`): what is left out of every deployment, and the wing they
    /// were found on when it is not this one (applied as they are). One
    /// text for the CLI's warnings and Python's `UserWarning`s.
    pub fn notes(&self, from: &str, mechanism: &str) -> Vec<String> {
        let mut out: Vec<String> = self
            .left_out
            .iter()
            .map(|w| format!("{from}: left out, not a named effect: {w}"))
            .collect();
        if !self.found_on.is_empty() && !self.found_on.iter().any(|n| n == mechanism) {
            out.push(format!(
                "{from}: found on {}, not on {mechanism}: applied as it is",
                self.found_on.join(", ")
            ));
        }
        out
    }

    /// Takes out the effects that exist only on a ground rig
    /// ([`effect_margin::rig_only`]: air drag, a tilt, the rig's rails,
    /// wires and frames): none of them flies, so the flight unit
    /// (`reliability --flight`) draws none. Draws in their place the
    /// wing's own losses the runs could not tell from them
    /// ([`FromFindings::stand_ins`]). Returns the names taken out, in the
    /// file's order, and each loss drawn in their place, in words.
    pub fn take_out_the_rig(&mut self) -> (Vec<String>, Vec<String>) {
        let names = self.rig_taken_out();
        let mut kept = Vec::new();
        for s in std::mem::take(&mut self.stand_ins) {
            if !s.replaces.iter().any(|k| names.contains(&k.to_string())) {
                continue;
            }
            let laws: Vec<String> = s.vary.iter().map(ToString::to_string).collect();
            let rig: Vec<String> = s.replaces.iter().map(ToString::to_string).collect();
            kept.push(format!(
                "{} drawn in place of {}, which the runs cannot tell it from",
                laws.join(", "),
                rig.join(", ")
            ));
            self.vary.extend(s.vary);
        }
        (names, kept)
    }

    /// [`FromFindings::take_out_the_rig`] for the flight unit, and what it
    /// did in words, each after `from` (how the command names the file)
    /// and naming the option `flag` (`--flight`, `flight=True`): one text
    /// for the CLI's warnings and Python's `UserWarning`s.
    pub fn take_out_the_rig_said(&mut self, from: &str, flag: &str) -> Vec<String> {
        let (rig, kept) = self.take_out_the_rig();
        let left = rig.into_iter().map(|name| {
            format!("{from}: left out of the flight unit ({flag}), on the ground rig only: {name}")
        });
        let drawn = kept
            .into_iter()
            .map(|k| format!("{from}: in the flight unit ({flag}): {k}"));
        left.chain(drawn).collect()
    }

    /// The rig-only laws and fixed effects taken out; their names.
    fn rig_taken_out(&mut self) -> Vec<String> {
        let mut names = Vec::new();
        self.vary.retain(|v| match v.target {
            Target::Effect(e) if effect_margin::rig_only(e.kind()) => {
                names.push(e.kind().to_string());
                false
            }
            _ => true,
        });
        self.fixed.retain(|f| {
            let rig = effect_margin::rig_only(f.effect.kind());
            if rig {
                names.push(f.effect.kind().to_string());
            }
            !rig
        });
        names
    }
}

/// The laws and fixed effects of an identify or a diagnose JSON
/// ([`from_identification`], [`from_diagnosis`]) for a deployment of
/// `mech` (a table's resisting end depends on the way its joint deploys).
pub fn from_findings_json(text: &str, mech: &Mechanism) -> Result<FromFindings, String> {
    let expected = "expected the JSON of `deploywatch identify` (with \"method\" and \"joints\") \
                    or of `deploywatch diagnose` (with \"effects\")";
    match Findings::from_json_str(text) {
        Ok(Findings::Identify(id)) => Ok(FromFindings {
            vary: from_identification(&id, mech)?,
            found_on: id.found_on(),
            ..FromFindings::default()
        }),
        Ok(Findings::Diagnosis(d)) => Ok(FromFindings {
            found_on: d.found_on(),
            ..from_diagnosis(&d, mech)?
        }),
        Err(FindingsError::Unknown) => Err(expected.into()),
        Err(e) => Err(e.to_string()),
    }
}

/// The identified Coulomb frictions of an identify JSON as normal laws:
/// `"joints": [{"joint": J, "coulomb_nm": T, "ci95": [lo, hi]}, ...]`
/// gives `coulomb_friction:joint=J:normal(T, (hi − lo)/(2·1.96))` (added to
/// the mechanism's own friction, as the identified effects are), kept
/// where the joint's friction is ≥ 0 ([`kept_in_range`]).
pub fn from_identification(id: &Identification, mech: &Mechanism) -> Result<Vec<Vary>, String> {
    let mut out = Vec::new();
    for (i, j) in id.joints.iter().enumerate() {
        let at = |key: &str| format!("joints[{i}]: expected \"{key}\"");
        if j.joint < 1 {
            return Err(at("joint") + ", a joint number from 1");
        }
        let t = j.coulomb_nm;
        let Some([lo, hi]) = j.ci95 else {
            return Err(at("ci95") + ", [lo, hi] in N·m");
        };
        if !(hi > lo) {
            return Err(format!(
                "joints[{i}] (joint {}): \"ci95\" [{lo}, {hi}] has no width, so its friction \
                 cannot be drawn: identify it again (a joint fixed at the bound 0 is given \
                 [0, t·sd]), or give its law with --vary",
                j.joint
            ));
        }
        let sd = (hi - lo) / (2.0 * Z_975);
        let dist = Dist::Normal { mean: t, sd };
        dist.check().map_err(|w| {
            format!("joints[{i}]: normal({t},{sd}) from the interval: expected {w}")
        })?;
        let effect = Effect::joint(EffectKind::CoulombFriction, j.joint, t);
        out.push(Vary {
            target: Target::of_effect(&effect),
            dist: kept_in_range(dist, &effect, mech),
        });
    }
    Ok(out)
}

/// The named effects of a diagnosis as normal laws: each effect's value
/// centred on the value fitted with the standard deviation of its 95 %
/// interval, `(hi − lo)/(2·1.96)`, every other parameter as fitted; each
/// `torque_table` fixed, each knot at the end of its 95 % band that
/// resists its joint's deployment on `mech` (its estimate without a
/// band), as `margin --from` takes it. An entry that is no named effect
/// (`"unexplained"`) is left out and named in [`FromFindings::left_out`];
/// an effect without an interval, or of a name this version does not know,
/// is refused, naming it. A diagnosis that names no effect (none found,
/// or only `"unexplained"`) gives nothing to draw and says why in
/// [`FromFindings::no_effect`]: there is nothing to carry, and a run of
/// the mechanism as given would not be what it found.
pub fn from_diagnosis(d: &Diagnosis, mech: &Mechanism) -> Result<FromFindings, String> {
    let mut out = FromFindings {
        no_effect: names_no_effect(d),
        ..FromFindings::default()
    };
    for (i, f) in d.effects.iter().enumerate() {
        let at = format!("effects[{i}] ({})", f.name);
        if f.name.parse() == Ok(EffectKind::TorqueTable) {
            let (worst, words) = resistances::at_worst_end(f, EffectKind::TorqueTable, mech);
            if let Some(effect) = worst.to_effect(i).map_err(|e| e.to_string())? {
                let source = format!("diagnose {at}: {words}");
                out.fixed.push(Fixed { effect, source });
            }
            continue;
        }
        match law_of(f, i, &at, mech)? {
            Some(v) => out.vary.push(v),
            None => out.left_out.push(f.no_effect_words()),
        }
    }
    for s in d.flight_stand_ins() {
        let at = format!("ambiguities at joint {}", s.joint);
        let mut vary = Vec::new();
        for f in s.effects.iter().filter(|f| f.name != "torque_table") {
            vary.extend(law_of(f, 0, &format!("{at} ({})", f.name), mech)?);
        }
        if !vary.is_empty() {
            out.stand_ins.push(StandInLaws {
                replaces: s.replaces,
                vary,
            });
        }
    }
    Ok(out)
}

/// The normal law of the effect `f` (entry `i`, named `at` in errors) from
/// its 95 % interval, kept where its effect is allowed; `None` for an entry
/// that is no effect (`"unexplained"`).
fn law_of(f: &FoundEffect, i: usize, at: &str, mech: &Mechanism) -> Result<Option<Vary>, String> {
    let Some(e) = f.to_effect(i).map_err(|e| e.to_string())? else {
        return Ok(None);
    };
    let Some([Some(lo), Some(hi)]) = f.ci95 else {
        return Err(format!(
            "{at}: expected \"ci95\", [lo, hi] in {}",
            e.kind().unit()
        ));
    };
    let sd = (hi - lo) / (2.0 * Z_975);
    let dist = Dist::Normal {
        mean: e.value(),
        sd,
    };
    dist.check().map_err(|w| {
        format!(
            "{at}: normal({},{sd}) from the interval: expected {w}",
            e.value()
        )
    })?;
    Ok(Some(Vary {
        target: Target::of_effect(&e),
        dist: kept_in_range(dist, &e, mech),
    }))
}

/// A law's share beyond the values its effect allows above which the law is
/// kept inside them \[1\]: far below any probability of failure the
/// analysis resolves, so a normal law a few dozen deviations from the edge
/// is drawn as it is, to the bit.
pub const LAW_TAIL_KEPT: f64 = 1e-12;

/// The normal law of a finding, as a truncated normal kept where the total
/// of its effect at its joint (the mechanism's own friction or damping plus
/// the draw, [`super::params::check_drawn`]) is allowed, when more than
/// [`LAW_TAIL_KEPT`] of it falls outside: an interval that reaches below
/// zero friction is no licence to draw friction that drives the joint.
fn kept_in_range(dist: Dist, e: &Effect, mech: &Mechanism) -> Dist {
    let Dist::Normal { mean, sd } = dist else {
        return dist;
    };
    let own = super::params::own_value(mech, e);
    let (lo, hi) = match e.kind().allowed() {
        // `0 − own`: +0 where the mechanism has none (printed `0`, not `-0`).
        ValueRange::NonNegative => (0.0 - own, f64::INFINITY),
        ValueRange::Fraction => (0.0, 1.0),
        ValueRange::BelowOne | ValueRange::Finite => return dist,
    };
    let outside = normal::cdf((lo - mean) / sd) + normal::cdf((mean - hi) / sd);
    if outside > LAW_TAIL_KEPT {
        Dist::TruncNormal { mean, sd, lo, hi }
    } else {
        dist
    }
}

/// Why a diagnosis cannot be carried into a model when it names no effect
/// of the vocabulary ([`Diagnosis::answer_without_effect`]), in words.
fn names_no_effect(d: &Diagnosis) -> Option<String> {
    d.answer_without_effect().map(|answer| {
        format!(
            "the diagnosis names no effect to carry into the model: its answer is {answer}; \
             without these findings the mechanism is taken as given (docs/reliability.md, \
             \"From a diagnosis\")"
        )
    })
}
