//! The resistances of the margins (`docs/margin.md`): a mechanism's own
//! friction, `--friction` values, or what `identify` or `diagnose` found,
//! read from their `--json` file (`margin --from`): the friction and
//! damping per joint, and every other named effect of a diagnosis, counted
//! by [`crate::analysis::effect_margin`].
use crate::analysis::effect_margin;
use crate::model::effect::{Effect, EffectKind};
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
    /// in the source.
    pub fn take_out_the_rig(&mut self) {
        let (rig, flies): (Vec<Effect>, Vec<Effect>) = self
            .others
            .iter()
            .partition(|e| effect_margin::rig_only(e.kind));
        self.others = flies;
        let names: Vec<String> = rig.iter().map(|e| e.kind.to_string()).collect();
        self.source = if names.is_empty() {
            format!("{}; flight: the rig taken out", self.source)
        } else {
            format!(
                "{}; flight: the rig taken out, left out as rig-only: {}",
                self.source,
                names.join(", ")
            )
        };
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
}

/// Reads `--from`: an identify JSON (`"method"` and `"joints"`) or a
/// diagnose JSON (`"effects"`) ([`Findings`]), for a mechanism of `mech`
/// (whose own friction the found values add to, as the effects do in
/// `physics.md` 6).
pub fn read_found(path: &Path, mech: &Mechanism) -> Result<Resistances, FromError> {
    let found = match Findings::from_json_str(&std::fs::read_to_string(path)?)? {
        Findings::Identify(id) => identify_effects(&id)?,
        Findings::Diagnosis(d) => diagnose_effects(&d)?,
    };
    let source = format!(
        "{} ({}) + the mechanism's friction",
        found.command,
        path.display()
    );
    let mut r = resistances_with(mech, found.effects, source)?;
    r.ignored = found.ignored;
    r.found_on = found.found_on;
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
    let n = mech.joint_count();
    let mut r = Resistances::of_mechanism(mech, source);
    for e in effects {
        if e.validate_joint(n).is_err() {
            return Err(FromError::Joint {
                effect: e.kind,
                joint: e.joint.unwrap_or(0),
                mechanism: mech.name.clone(),
                joints: n,
            });
        }
        match (e.kind, e.joint) {
            (EffectKind::CoulombFriction, Some(j)) => r.coulomb_nm[j - 1] += e.value,
            (EffectKind::ViscousDamping, Some(j)) => r.viscous_nms[j - 1] += e.value,
            _ => r.others.push(e),
        }
    }
    Ok(r)
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
    let mut effects = Vec::new();
    for (i, j) in id.joints.iter().enumerate() {
        let at = format!("joints[{i}]");
        let joint = joint_of(Some(j.joint), &at)?;
        let value = nonneg(Some(j.coulomb_nm), "coulomb_nm", &at)?;
        effects.push(Effect::joint(EffectKind::CoulombFriction, joint, value));
    }
    let mut found_on: Vec<String> = id.after.runs.iter().map(|r| r.mechanism.clone()).collect();
    found_on.dedup();
    Ok(Found {
        command: "identify",
        effects,
        ignored: Vec::new(),
        found_on,
    })
}

/// The named effects of a diagnose JSON (read by the one reader of its
/// entries, [`FoundEffect::to_effect`](crate::model::findings::diagnosis::FoundEffect::to_effect)), what is not a named effect (in
/// words), and the mechanisms it was found on.
fn diagnose_effects(d: &Diagnosis) -> Result<Found, FromError> {
    let (mut effects, mut ignored) = (Vec::new(), Vec::new());
    for (i, e) in d.effects.iter().enumerate() {
        match e.to_effect(i)? {
            Some(effect) => effects.push(effect),
            None => ignored.push(
                e.joint
                    .map_or(e.name.clone(), |j| format!("{} at joint {j}", e.name)),
            ),
        }
    }
    Ok(Found {
        command: "diagnose",
        effects,
        ignored,
        found_on: d.found_on(),
    })
}
