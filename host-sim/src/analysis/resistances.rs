//! The resistances of the margins (`docs/margin.md`): a mechanism's own
//! friction, `--friction` values, or what `identify` or `diagnose` found,
//! read from their `--json` file (`margin --from`): the friction and
//! damping per joint, and every other named effect of a diagnosis, counted
//! by [`crate::analysis::effect_margin`].
use crate::analysis::effect_margin::{self, WorstEnd};
use crate::model::effect::{Effect, EffectKind, MarginForm};
use crate::model::findings::diagnosis::FoundEffect;
use crate::model::findings::effects::FoundEffectError;
use crate::model::findings::{Diagnosis, Findings, FindingsError, Identification};
use crate::model::mechanism::Mechanism;
use std::path::Path;

/// The resistances of each joint the margins use, and where they come from.
#[derive(Clone, Debug, PartialEq)]
pub struct Resistances {
    /// Coulomb friction (EFT) per joint [N·m].
    pub coulomb_nm: Vec<f64>,
    /// Viscous damping per joint [N·m·s/rad].
    pub viscous_nms: Vec<f64>,
    /// Where the values come from, in words.
    pub source: String,
    /// What a diagnosis found that is not a named effect (`unexplained`),
    /// in words: no margin can count it.
    pub ignored: Vec<String>,
    /// Every other effect found (not `coulomb_friction` or
    /// `viscous_damping`, which are in the two lists above): each is
    /// counted by [`crate::analysis::effect_margin::counted`].
    pub others: Vec<Effect>,
    /// The mechanisms the file was found on (empty if it does not say).
    pub found_on: Vec<String>,
    /// Per effect read from a findings file, in words: the value the
    /// margins take, the worst end of its 95 % interval
    /// ([`effect_margin::worst_end`]), or its estimate and why.
    pub taken_at: Vec<String>,
    /// The wing's own losses a diagnosis could not tell from its rig-only
    /// effects ([`Diagnosis::flight_stand_ins`]): what
    /// [`Resistances::take_out_the_rig`] keeps in their place.
    pub stand_ins: Vec<WingStandIn>,
}

/// A loss of the wing's own, at the worst end of its interval, that the
/// runs could not tell from rig-only effects of the set found.
#[derive(Clone, Debug, PartialEq)]
pub struct WingStandIn {
    /// The rig-only effects it may stand in for.
    pub replaces: Vec<EffectKind>,
    /// Its effects, as the margins take them.
    pub effects: Vec<Effect>,
    /// What it is, in words: `quadratic_damping at joint 1 (…)`.
    pub words: String,
}

impl Resistances {
    /// The mechanism's own friction and damping, named `source`.
    pub fn of_mechanism(mech: &Mechanism, source: String) -> Self {
        Resistances {
            coulomb_nm: mech.joints.iter().map(|j| j.friction.coulomb_nm).collect(),
            viscous_nms: mech.joints.iter().map(|j| j.friction.viscous_nms).collect(),
            source,
            ignored: Vec::new(),
            others: Vec::new(),
            found_on: Vec::new(),
            taken_at: Vec::new(),
            stand_ins: Vec::new(),
        }
    }

    /// Adds `e` to what the margins count: friction and damping into their
    /// per-joint lists (the mechanism's own forms take their columns), any
    /// other effect into [`Resistances::others`].
    fn add(&mut self, e: Effect) {
        let column = match e.kind().margin() {
            MarginForm::Coulomb => Some(&mut self.coulomb_nm),
            MarginForm::Viscous => Some(&mut self.viscous_nms),
            MarginForm::Quadratic
            | MarginForm::Breakaway
            | MarginForm::Driving
            | MarginForm::Harness
            | MarginForm::Detent
            | MarginForm::Distributed
            | MarginForm::Tilt
            | MarginForm::Table
            | MarginForm::Sensor
            | MarginForm::LatchLine
            | MarginForm::RigLine => None,
        };
        match (column, e.joint) {
            (Some(column), Some(j)) if j >= 1 && j <= column.len() => column[j - 1] += e.value(),
            _ => self.others.push(e),
        }
    }

    /// What was found, as effects on top of `mech` (which already holds its
    /// own friction): the differences of the friction and damping lists,
    /// and every other effect.
    pub fn found_effects(&self, mech: &Mechanism) -> Vec<Effect> {
        (0..mech.joint_count())
            .flat_map(|j| {
                let own = &mech.joints[j].friction;
                [
                    Effect::joint(
                        EffectKind::CoulombFriction,
                        j + 1,
                        self.coulomb_nm[j] - own.coulomb_nm,
                    ),
                    Effect::joint(
                        EffectKind::ViscousDamping,
                        j + 1,
                        self.viscous_nms[j] - own.viscous_nms,
                    ),
                ]
            })
            .chain(self.others.iter().copied())
            .collect()
    }

    /// The margin on orbit (`--flight`): leaves out the effects that exist
    /// only on the ground rig ([`effect_margin::rig_only`]), naming them
    /// in the source, and keeps in their place the wing's own loss the
    /// diagnosis could not tell from them ([`Resistances::stand_ins`]),
    /// saying so: the runs do not show that the loss was the rig's.
    pub fn take_out_the_rig(&mut self) {
        let (rig, flies): (Vec<Effect>, Vec<Effect>) = self
            .others
            .iter()
            .partition(|e| effect_margin::rig_only(e.kind()));
        self.others = flies;
        let names: Vec<String> = rig.iter().map(|e| e.kind().to_string()).collect();
        let kept: Vec<WingStandIn> = std::mem::take(&mut self.stand_ins)
            .into_iter()
            .filter(|s| rig.iter().any(|e| s.replaces.contains(&e.kind())))
            .collect();
        let mut source = if names.is_empty() {
            format!(
                "{}; flight: the rig taken out of the nominal deployment (no rig term is in \
                 these margins either way; a joint friction given as measured on the rig stays \
                 as given, its rails lumped in: diagnose or identify the rig's runs to take them out)",
                self.source
            )
        } else {
            format!(
                "{}; flight: the rig taken out, left out as rig-only: {}",
                self.source,
                names.join(", ")
            )
        };
        for s in kept {
            let rig: Vec<String> = s.replaces.iter().map(ToString::to_string).collect();
            source.push_str(&format!(
                "; kept in place of {}, which the runs cannot tell it from: {}",
                rig.join(", "),
                s.words
            ));
            for e in s.effects {
                self.add(e);
            }
        }
        self.source = source;
    }
}

/// Why a `--from` file cannot be used.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FromError {
    /// The file cannot be read.
    #[error("cannot read: {0}")]
    Read(#[from] std::io::Error),
    /// Not the JSON of identify or diagnose.
    #[error("{0}")]
    Findings(#[from] FindingsError),
    /// A diagnosis entry that is not the effect its name says.
    #[error("{0}")]
    Found(#[from] FoundEffectError),
    /// A field missing or of the wrong kind.
    #[error("{at}: expected \"{key}\", {expected}")]
    Field {
        /// Where in the file, e.g. `joints[0]`.
        at: String,
        /// The key.
        key: &'static str,
        /// What it should hold.
        expected: &'static str,
    },
    /// A diagnosis whose answer is `unexplained` without a named effect:
    /// margins of the mechanism as given would not be what it found.
    #[error(
        "the diagnosis names no effect, its answer is {0}: margins without it would be the \
         mechanism's as given, which the runs contradict (docs/margin.md, \"From a diagnosis\")"
    )]
    Unexplained(String),
    /// An effect of an ambiguity group's set the margins would keep on
    /// orbit ([`Diagnosis::flight_stand_ins`]) that does not read.
    #[error("ambiguities at joint {joint}: {source}")]
    StandIn {
        /// The group's joint.
        joint: usize,
        /// What the effect's reader says.
        source: Box<FoundEffectError>,
    },
    /// A joint the mechanism does not have.
    #[error("{effect} at joint {joint}, but {mechanism} has joints 1 to {joints}")]
    Joint {
        /// The effect found.
        effect: EffectKind,
        /// Its joint (1-based).
        joint: usize,
        /// The mechanism's name.
        mechanism: String,
        /// Its joint count.
        joints: usize,
    },
}

/// What an identify or diagnose JSON found.
struct Found {
    /// Which command wrote it.
    command: &'static str,
    /// The named effects.
    effects: Vec<Effect>,
    /// What is not a named effect, in words (not in the margins).
    ignored: Vec<String>,
    /// The mechanisms it was found on.
    found_on: Vec<String>,
    /// Per effect, the value taken, in words.
    taken_at: Vec<String>,
    /// What the source line adds (a diagnosis that found nothing).
    note: Option<String>,
    /// The wing's losses that may stand in for rig-only effects.
    stand_ins: Vec<WingStandIn>,
}

/// Reads `--from`: an identify JSON (`"method"` and `"joints"`) or a
/// diagnose JSON (`"effects"`) ([`Findings`]), for a mechanism of `mech`
/// (whose own friction the found values add to, as the effects do in
/// `physics.md` 6).
pub fn read_found(path: &Path, mech: &Mechanism) -> Result<Resistances, FromError> {
    let found = match Findings::from_json_str(&std::fs::read_to_string(path)?)? {
        Findings::Identify(id) => identify_effects(&id)?,
        Findings::Diagnosis(d) => diagnose_effects(&d, mech)?,
    };
    let source = match &found.note {
        Some(note) => format!("{} ({}): {note}", found.command, path.display()),
        None => format!(
            "{} ({}) + the mechanism's friction",
            found.command,
            path.display()
        ),
    };
    let mut r = resistances_with(mech, found.effects, source)?;
    for s in &found.stand_ins {
        for e in &s.effects {
            valid_joint(e, mech)?;
        }
    }
    r.stand_ins = found.stand_ins;
    r.ignored = found.ignored;
    r.found_on = found.found_on;
    r.taken_at = found.taken_at;
    Ok(r)
}

/// The resistances of `mech` (its own friction) with `effects` added:
/// friction and damping into their per-joint lists, every other effect
/// into [`Resistances::others`].
pub fn resistances_with(
    mech: &Mechanism,
    effects: Vec<Effect>,
    source: String,
) -> Result<Resistances, FromError> {
    let mut r = Resistances::of_mechanism(mech, source);
    for e in effects {
        valid_joint(&e, mech)?;
        r.add(e);
    }
    Ok(r)
}

/// `e` if its joint is one of `mech`'s.
fn valid_joint(e: &Effect, mech: &Mechanism) -> Result<(), FromError> {
    let n = mech.joint_count();
    e.validate_joint(n).map_err(|_| FromError::Joint {
        effect: e.kind(),
        joint: e.joint.unwrap_or(0),
        mechanism: mech.name.clone(),
        joints: n,
    })
}

/// `x` if it is a finite number ≥ 0.
fn nonneg(x: Option<f64>, key: &'static str, at: &str) -> Result<f64, FromError> {
    x.filter(|x| x.is_finite() && *x >= 0.0)
        .ok_or_else(|| FromError::Field {
            at: at.to_string(),
            key,
            expected: "a number ≥ 0",
        })
}

/// `joint` if it is a joint number (from 1).
fn joint_of(joint: Option<usize>, at: &str) -> Result<usize, FromError> {
    joint.filter(|j| *j >= 1).ok_or_else(|| FromError::Field {
        at: at.to_string(),
        key: "joint",
        expected: "a joint number from 1",
    })
}

/// The EFTs of an identify JSON, and the mechanisms of its runs.
fn identify_effects(id: &Identification) -> Result<Found, FromError> {
    let (mut effects, mut taken_at) = (Vec::new(), Vec::new());
    for (i, j) in id.joints.iter().enumerate() {
        let at = format!("joints[{i}]");
        let joint = joint_of(Some(j.joint), &at)?;
        let estimate = nonneg(Some(j.coulomb_nm), "coulomb_nm", &at)?;
        let kind = EffectKind::CoulombFriction;
        let ci = j.ci95.map(|[lo, hi]| [Some(lo), Some(hi)]);
        let (value, words) = end_of(kind, estimate, ci);
        taken_at.push(format!("{kind} at joint {joint}: {words}"));
        effects.push(Effect::joint(kind, joint, value));
    }
    let found_on = id.found_on();
    // A response surface whose design missed the friction that explains
    // the runs: its EFTs are taken as written, and the source says so.
    let note = id
        .rsm
        .as_ref()
        .and_then(|r| r.beyond_design.as_ref())
        .map(|b| {
            let nm: Vec<String> = b.coulomb_nm.iter().map(|c| format!("{c:.4}")).collect();
            format!(
                "+ the mechanism's friction; these are the response surface's EFTs, which leave \
                 residuals above the noise, where least squares explains the runs at {} N·m \
                 (rsm.beyond_design): identify again with --method direct or that --center",
                nm.join(", ")
            )
        });
    Ok(Found {
        command: "identify",
        effects,
        ignored: Vec::new(),
        found_on,
        taken_at,
        note,
        stand_ins: Vec::new(),
    })
}

/// The named effects of a diagnose JSON (read by the one reader of its
/// entries, [`FoundEffect::to_effect`](crate::model::findings::diagnosis::FoundEffect::to_effect)), what is not a named effect (in
/// words), and the mechanisms it was found on.
///
/// A diagnosis that found nothing (the mechanisms as given explain the
/// runs) gives the mechanism's own margins, said so in `taken_at`; one
/// whose only answer is `unexplained` is refused ([`FromError::Unexplained`]).
fn diagnose_effects(d: &Diagnosis, mech: &Mechanism) -> Result<Found, FromError> {
    let (mut effects, mut ignored, mut taken_at) = (Vec::new(), Vec::new(), Vec::new());
    let mut note = None;
    match d.answer_without_effect() {
        Some(answer) if d.effects.is_empty() => {
            note = Some(format!("{answer}: the margins of the mechanism as given"));
        }
        Some(answer) => return Err(FromError::Unexplained(answer)),
        None => {}
    }
    for (i, e) in d.effects.iter().enumerate() {
        let worst = e
            .name
            .parse::<EffectKind>()
            .ok()
            .map(|k| at_worst_end(e, k, mech));
        let entry = worst.as_ref().map_or(e, |w| &w.0);
        match entry.to_effect(i)? {
            Some(effect) => {
                let joint = effect
                    .joint
                    .map_or(String::new(), |j| format!(" at joint {j}"));
                let words = worst.map(|w| w.1).unwrap_or_default();
                taken_at.push(format!("{}{joint}: {words}", effect.kind()));
                effects.push(effect);
            }
            None => ignored.push(e.joint.map_or(e.no_effect_words(), |j| {
                format!("{} at joint {j}", e.no_effect_words())
            })),
        }
    }
    Ok(Found {
        command: "diagnose",
        effects,
        ignored,
        found_on: d.found_on(),
        taken_at,
        note,
        stand_ins: wing_stand_ins(d, mech)?,
    })
}

/// The diagnosis's [`Diagnosis::flight_stand_ins`], each effect at the
/// worst end of its interval, as the margins take what was found.
fn wing_stand_ins(d: &Diagnosis, mech: &Mechanism) -> Result<Vec<WingStandIn>, FromError> {
    let mut out = Vec::new();
    for s in d.flight_stand_ins() {
        let (mut effects, mut words) = (Vec::new(), Vec::new());
        for f in &s.effects {
            let Ok(kind) = f.name.parse::<EffectKind>() else {
                continue;
            };
            let (worst, taken) = at_worst_end(f, kind, mech);
            let read = worst.to_effect(0).map_err(|source| FromError::StandIn {
                joint: s.joint,
                source: Box::new(source),
            })?;
            if let Some(e) = read {
                let joint = e.joint.map_or(String::new(), |j| format!(" at joint {j}"));
                words.push(format!("{kind}{joint} ({taken})"));
                effects.push(e);
            }
        }
        if !effects.is_empty() {
            out.push(WingStandIn {
                replaces: s.replaces,
                effects,
                words: words.join(", "),
            });
        }
    }
    Ok(out)
}

/// The value of an effect of `kind` estimated at `estimate` that the
/// margins take, at the end of its 95 % interval `ci` that
/// [`effect_margin::worst_end`] names (never on the estimate's kinder
/// side), and what was taken in words.
fn end_of(kind: EffectKind, estimate: f64, ci: Option<[Option<f64>; 2]>) -> (f64, String) {
    let unit = kind.unit();
    let Some([Some(lo), Some(hi)]) = ci else {
        return (
            estimate,
            format!("{estimate} {unit}, its estimate (no 95 % interval in the file)"),
        );
    };
    let (value, end) = match effect_margin::worst_end(kind) {
        WorstEnd::Upper => (hi.max(estimate), "the upper end"),
        WorstEnd::LargerMagnitude if hi.abs() >= lo.abs() => {
            (hi, "the end of the larger magnitude")
        }
        WorstEnd::LargerMagnitude => (lo, "the end of the larger magnitude"),
        WorstEnd::Resisting => (estimate, "its estimate"),
        WorstEnd::Estimate(why) => {
            return (estimate, format!("{estimate} {unit}, its estimate ({why})"));
        }
    };
    (
        value,
        format!("{value} {unit}, {end} of its 95 % interval [{lo}, {hi}] (estimate {estimate})"),
    )
}

/// A diagnosis entry of `kind` with its value (a Stribeck law's excess
/// too) at the worst end of its 95 % interval ([`end_of`]), or for a
/// table each knot's torque at the end of its band that resists joint's
/// deployment on `mech` more; and what was taken, in words. The margins
/// take it so, and `reliability --from` a table
/// ([`crate::analysis::reliability::identified`]).
pub fn at_worst_end(f: &FoundEffect, kind: EffectKind, mech: &Mechanism) -> (FoundEffect, String) {
    let mut w = f.clone();
    if kind != EffectKind::TorqueTable {
        let (value, words) = end_of(kind, f.value.unwrap_or(f64::NAN), f.ci95);
        w.value = f.value.map(|_| value);
        if kind == EffectKind::StribeckFriction {
            if let (Some(x), Some([Some(_), Some(hi)])) = (f.excess_nm, f.excess_ci95_nm) {
                w.excess_nm = Some(hi.max(x));
            }
        }
        return (w, words);
    }
    // A joint deploying towards positive angles (stowed below 0) is
    // resisted by a negative torque: the lower end of each band.
    let towards_positive = f
        .joint
        .and_then(|j| mech.joints.get(j.wrapping_sub(1)))
        .is_some_and(|jt| jt.stowed_deg < 0.0);
    let side = usize::from(!towards_positive);
    let mut banded = false;
    for (knots, band) in [
        (&mut w.torque_nm, &f.torque_ci95_nm),
        (&mut w.rate_torque_nm, &f.rate_torque_ci95_nm),
    ] {
        if let (Some(k), Some(b)) = (knots.as_mut(), band) {
            for (y, end) in k.iter_mut().zip(&b[side]) {
                if end.is_some() {
                    *y = *end;
                    banded = true;
                }
            }
        }
    }
    let words = if banded {
        format!(
            "each knot at the {} end of its 95 % band (the end that resists the deployment)",
            if towards_positive { "lower" } else { "upper" }
        )
    } else {
        "its estimate (no 95 % band in the file)".to_string()
    };
    (w, words)
}
