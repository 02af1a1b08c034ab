//! The uncertain parameters: which quantity a `--vary` names (a named effect
//! of `physics.md` section 6, or a mechanism parameter), its probability
//! law, and the map from the standard normal space to the parameter.

use super::normal;
use crate::model::effect::{Effect, EffectError, EffectKind};
use crate::model::mechanism::{Mechanism, SpringSpec};
use std::fmt;
use std::str::FromStr;

/// A mechanism parameter a `--vary` may name (the effects are the others).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MechParam {
    /// `spring_preload`: `preload_nm` of a linear spring [N·m].
    SpringPreload,
    /// `spring_stiffness`: `stiffness_nm_per_rad` of a linear spring [N·m/rad].
    SpringStiffness,
    /// `panel_mass`: `mass_kg` of the panel the joint drives \[kg\].
    PanelMass,
    /// `panel_inertia`: `inertia_kgm2` of the panel the joint drives [kg·m²].
    PanelInertia,
}

impl MechParam {
    /// Every mechanism parameter.
    pub const ALL: [MechParam; 4] = [
        MechParam::SpringPreload,
        MechParam::SpringStiffness,
        MechParam::PanelMass,
        MechParam::PanelInertia,
    ];

    /// The unit of its value.
    pub fn unit(self) -> &'static str {
        match self {
            MechParam::SpringPreload => "N·m",
            MechParam::SpringStiffness => "N·m/rad",
            MechParam::PanelMass => "kg",
            MechParam::PanelInertia => "kg·m²",
        }
    }

    /// The name in `--vary`.
    pub fn name(self) -> &'static str {
        match self {
            MechParam::SpringPreload => "spring_preload",
            MechParam::SpringStiffness => "spring_stiffness",
            MechParam::PanelMass => "panel_mass",
            MechParam::PanelInertia => "panel_inertia",
        }
    }
}

/// What a `--vary` sets.
// The effect inline (a `torque_table`'s tables too): `Copy`, as a `Vary` is.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Target {
    /// A named effect (as parsed by [`Effect::from_str`]), its value set
    /// to the draw ([`Effect::with_value`]: the joint, `rig_tilt`'s
    /// direction and the Stribeck shape kept), added to the mechanism's
    /// effects.
    Effect(Effect),
    /// A mechanism parameter of a 1-based joint, replaced by the draw.
    Mech(MechParam, usize),
}

impl Target {
    /// The target that varies the value of `e`, its other parameters
    /// (joint, `rig_tilt`'s direction, the Stribeck shape) kept.
    pub fn of_effect(e: &Effect) -> Target {
        Target::Effect(*e)
    }
}

/// A probability law of one parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Dist {
    /// `normal(mean,sd)`.
    Normal {
        /// Mean.
        mean: f64,
        /// Standard deviation (> 0).
        sd: f64,
    },
    /// `lognormal(median,sigma_ln)`: `ln x` is normal.
    LogNormal {
        /// Median (> 0).
        median: f64,
        /// Standard deviation of `ln x` (> 0).
        sigma_ln: f64,
    },
    /// `uniform(lo,hi)`.
    Uniform {
        /// Lower bound.
        lo: f64,
        /// Upper bound (> lo).
        hi: f64,
    },
    /// `truncnormal(mean,sd,lo,hi)`: a normal law kept to `[lo, hi]`.
    TruncNormal {
        /// Mean of the untruncated law.
        mean: f64,
        /// Its standard deviation (> 0).
        sd: f64,
        /// Lower bound.
        lo: f64,
        /// Upper bound (> lo).
        hi: f64,
    },
}

impl Dist {
    /// The parameter at the standard normal coordinate `u`:
    /// `x = F⁻¹(Φ(u))` (the Rosenblatt map of one variable).
    pub fn at(&self, u: f64) -> f64 {
        match *self {
            Dist::Normal { mean, sd } => mean + sd * u,
            Dist::LogNormal { median, sigma_ln } => median * (sigma_ln * u).exp(),
            Dist::Uniform { lo, hi } => lo + (hi - lo) * normal::cdf(u),
            Dist::TruncNormal { mean, sd, lo, hi } => {
                let z = normal::truncated_at((lo - mean) / sd, (hi - mean) / sd, u);
                (mean + sd * z).clamp(lo, hi)
            }
        }
    }

    /// The first of the law's numbers out of its range, said as what was
    /// expected (`sd > 0 and finite, not -1`).
    pub(crate) fn check(&self) -> Result<(), String> {
        let finite = |name: &str, v: f64| {
            (!v.is_finite()).then(|| format!("{name} a finite number, not {v}"))
        };
        let positive = |name: &str, v: f64| {
            (!(v > 0.0 && v.is_finite())).then(|| format!("{name} > 0 and finite, not {v}"))
        };
        let ordered = |lo: f64, hi: f64| {
            (!(lo < hi)).then(|| format!("lo < hi, not lo = {lo} and hi = {hi}"))
        };
        let why = match *self {
            Dist::Normal { mean, sd } => finite("mean", mean).or_else(|| positive("sd", sd)),
            Dist::LogNormal { median, sigma_ln } => {
                positive("median", median).or_else(|| positive("sigma_ln", sigma_ln))
            }
            Dist::Uniform { lo, hi } => finite("lo", lo)
                .or_else(|| finite("hi", hi))
                .or_else(|| ordered(lo, hi)),
            Dist::TruncNormal { mean, sd, lo, hi } => finite("mean", mean)
                .or_else(|| positive("sd", sd))
                .or_else(|| lo.is_nan().then(|| "lo a number, not NaN".to_string()))
                .or_else(|| hi.is_nan().then(|| "hi a number, not NaN".to_string()))
                .or_else(|| ordered(lo, hi)),
        };
        why.map_or(Ok(()), Err)
    }
}

impl fmt::Display for Dist {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Dist::Normal { mean, sd } => write!(f, "normal({mean},{sd})"),
            Dist::LogNormal { median, sigma_ln } => write!(f, "lognormal({median},{sigma_ln})"),
            Dist::Uniform { lo, hi } => write!(f, "uniform({lo},{hi})"),
            Dist::TruncNormal { mean, sd, lo, hi } => {
                write!(f, "truncnormal({mean},{sd},{lo},{hi})")
            }
        }
    }
}

/// Why a `--vary` was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum VaryError {
    /// No law after the last `:`.
    #[error("`{0}`: expected NAME[:joint=J]:DIST, DIST one of normal(mean,sd), lognormal(median,sigma_ln), uniform(lo,hi), truncnormal(mean,sd,lo,hi)")]
    Syntax(String),
    /// A law with the wrong name, count of numbers, or values.
    #[error("`{text}`: {why}")]
    Law {
        /// The whole text.
        text: String,
        /// What is wrong.
        why: String,
    },
    /// The effect part does not parse.
    #[error("`{text}`: {source}")]
    Effect {
        /// The whole text.
        text: String,
        /// The effect parser's error.
        #[source]
        source: EffectError,
    },
    /// A joint missing or not in the mechanism, or a spring that is not
    /// linear (the target's label is the caller's to say).
    #[error("{0}")]
    Mechanism(String),
}

/// One `--vary NAME[:joint=J]:DIST`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vary {
    /// What it sets.
    pub target: Target,
    /// Its law.
    pub dist: Dist,
}

/// Each parameter's [`Vary::label`], the second and later of one label
/// (an effect given two laws, whose draws add) numbered `#2`, `#3`...: the
/// keys of the JSON's parameters and of the Python package's columns, one
/// per parameter.
pub fn unique_labels(vary: &[Vary]) -> Vec<String> {
    let mut out: Vec<String> = Vec::with_capacity(vary.len());
    for v in vary {
        let label = v.label();
        let seen = vary
            .iter()
            .take(out.len())
            .filter(|w| w.label() == label)
            .count();
        out.push(if seen == 0 {
            label
        } else {
            format!("{label}#{}", seen + 1)
        });
    }
    out
}

impl Vary {
    /// The name shown in reports, e.g. `coulomb_friction:joint=1`.
    pub fn label(&self) -> String {
        match self.target {
            Target::Effect(e) => match e.joint {
                Some(j) => format!("{}:joint={j}", e.kind()),
                None => e.kind().to_string(),
            },
            Target::Mech(p, j) => format!("{}:joint={j}", p.name()),
        }
    }

    /// The unit of its value: the effect's ([`EffectKind::unit`]; `1` for
    /// a dimensionless one) or the mechanism parameter's.
    pub fn unit(&self) -> &'static str {
        match self.target {
            Target::Effect(e) => e.kind().unit(),
            Target::Mech(p, _) => p.unit(),
        }
    }

    /// Checks the target against a mechanism.
    pub fn check(&self, mech: &Mechanism) -> Result<(), VaryError> {
        let bad = VaryError::Mechanism;
        match self.target {
            Target::Effect(e) => e
                .with_value(0.0)
                .validate_joint(mech.effect_joints())
                .map_err(|m| bad(m.to_string())),
            Target::Mech(p, j) => {
                if j == 0 || j > mech.joint_count() {
                    return Err(bad(format!(
                        "joint {j} does not exist (the mechanism has joints 1 to {})",
                        mech.joint_count()
                    )));
                }
                let linear = matches!(mech.joints[j - 1].spring, SpringSpec::Linear { .. });
                if matches!(p, MechParam::SpringPreload | MechParam::SpringStiffness) && !linear {
                    return Err(bad(format!(
                        "joint {j}'s spring is not linear (kind = \"linear\" has preload and stiffness)"
                    )));
                }
                Ok(())
            }
        }
    }

    /// Sets the value `x` into the mechanism (a mechanism parameter) or the
    /// list of effects (an effect, added).
    pub fn apply(&self, x: f64, mech: &mut Mechanism, effects: &mut Vec<Effect>) {
        match self.target {
            Target::Effect(e) => effects.push(e.with_value(x)),
            Target::Mech(p, j) => {
                let i = j - 1;
                match p {
                    MechParam::PanelMass => mech.panels[i].mass_kg = x,
                    MechParam::PanelInertia => mech.panels[i].inertia_kgm2 = x,
                    MechParam::SpringPreload | MechParam::SpringStiffness => {
                        if let SpringSpec::Linear {
                            preload_nm,
                            stiffness_nm_per_rad,
                            ..
                        } = &mut mech.joints[i].spring
                        {
                            match p {
                                MechParam::SpringPreload => *preload_nm = x,
                                _ => *stiffness_nm_per_rad = x,
                            }
                        }
                    }
                }
            }
        }
    }
}

impl fmt::Display for Vary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.label(), self.dist)
    }
}

/// The mechanism's own value that an effect `e` adds to at its joint: the
/// joint's Coulomb friction \[N·m\] or viscous damping \[N·m·s/rad\];
/// 0 for every other effect.
pub(crate) fn own_value(mech: &Mechanism, e: &Effect) -> f64 {
    let joint = e.joint.and_then(|j| mech.joints.get(j.checked_sub(1)?));
    match (e.kind(), joint) {
        (EffectKind::CoulombFriction, Some(x)) => x.friction.coulomb_nm,
        (EffectKind::ViscousDamping, Some(x)) => x.friction.viscous_nms,
        _ => 0.0,
    }
}

/// Checks a deployment's effects once the drawn values are in: at each
/// joint, each kind's total — the mechanism's own value (its Coulomb
/// friction and viscous damping, which an effect of that name adds to)
/// plus every effect of the kind there — must stay in the values the kind
/// allows ([`EffectKind::allowed`]): a law's tail may not make friction
/// drive its joint or a softening reverse its spring, which `--effect`
/// refuses too. A value outside is an error naming it, never a silent
/// deployment of another physics. A panel's mass and inertia drawn are
/// held above 0 (no chain has another); a linear spring's preload and
/// stiffness are deployed as drawn, below 0 too: the law `T0 + k |φ|`
/// holds there (a spring whose torque vanishes short of the latch), and a
/// normal law's tail, which subset simulation and importance sampling
/// explore, is a failure of the wing, not of the analysis.
pub fn check_drawn(mech: &Mechanism, effects: &[Effect]) -> Result<(), String> {
    let outside = |p: MechParam, j: usize, x: f64, expected: &str| {
        format!(
            "{} at joint {j} would be {x} {}: expected {expected} (as the mechanism file); a law \
             that reaches there wants truncnormal(mean,sd,lo,hi) kept inside",
            p.name(),
            p.unit()
        )
    };
    for (i, panel) in mech.panels.iter().enumerate() {
        if !(panel.mass_kg > 0.0 && panel.mass_kg.is_finite()) {
            return Err(outside(MechParam::PanelMass, i + 1, panel.mass_kg, "> 0"));
        }
        if !(panel.inertia_kgm2 > 0.0 && panel.inertia_kgm2.is_finite()) {
            return Err(outside(
                MechParam::PanelInertia,
                i + 1,
                panel.inertia_kgm2,
                "> 0",
            ));
        }
    }
    for (i, e) in effects.iter().enumerate() {
        let same = |f: &&Effect| f.kind() == e.kind() && f.joint == e.joint;
        if effects[..i].iter().any(|f| same(&f)) {
            continue;
        }
        let own = own_value(mech, e);
        let total = own + effects.iter().filter(same).map(Effect::value).sum::<f64>();
        let range = e.kind().allowed();
        if !range.contains(total) {
            let at = e
                .joint
                .map(|j| format!(" at joint {j}"))
                .unwrap_or_default();
            return Err(format!(
                "{}{at} would be {total} {} ({own} in the mechanism plus the effects drawn or \
                 fixed): expected {}; a law that reaches there wants truncnormal(mean,sd,lo,hi) \
                 kept inside",
                e.kind(),
                e.kind().unit(),
                range.describe()
            ));
        }
    }
    Ok(())
}

/// An effect every deployment carries as it was found, not drawn: a
/// diagnosis's `torque_table` (`reliability --from`), a measured fixed
/// resistance with no one value to draw (`docs/reliability.md` §2).
#[derive(Clone, Debug, PartialEq)]
pub struct Fixed {
    /// The effect, added to every deployment next to the drawn ones.
    pub effect: Effect,
    /// Where it comes from and which values were taken, in words (e.g.
    /// `diagnose effects[0]: each knot at the upper end of its 95 % band
    /// ...`).
    pub source: String,
}

fn parse_dist(text: &str, law: &str) -> Result<Dist, VaryError> {
    let bad = |why: String| VaryError::Law {
        text: text.to_string(),
        why,
    };
    let (name, rest) = law
        .split_once('(')
        .ok_or_else(|| VaryError::Syntax(text.to_string()))?;
    let args = rest
        .strip_suffix(')')
        .ok_or_else(|| bad(format!("`{law}`: expected a closing parenthesis")))?;
    let nums: Vec<f64> = args
        .split(',')
        .map(|a| a.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| bad(format!("`{law}`: expected numbers separated by commas")))?;
    let want = |n: usize| {
        if nums.len() == n {
            Ok(())
        } else {
            Err(bad(format!("`{law}`: {name} takes {n} numbers")))
        }
    };
    let dist = match name.trim() {
        "normal" => {
            want(2)?;
            Dist::Normal {
                mean: nums[0],
                sd: nums[1],
            }
        }
        "lognormal" => {
            want(2)?;
            Dist::LogNormal {
                median: nums[0],
                sigma_ln: nums[1],
            }
        }
        "uniform" => {
            want(2)?;
            Dist::Uniform {
                lo: nums[0],
                hi: nums[1],
            }
        }
        "truncnormal" => {
            want(4)?;
            Dist::TruncNormal {
                mean: nums[0],
                sd: nums[1],
                lo: nums[2],
                hi: nums[3],
            }
        }
        other => {
            return Err(bad(format!(
                "unknown law `{other}`: expected normal, lognormal, uniform or truncnormal"
            )))
        }
    };
    dist.check()
        .map_err(|w| bad(format!("`{law}`: expected {w}")))?;
    Ok(dist)
}

impl FromStr for Vary {
    type Err = VaryError;
    /// Parses `NAME[:joint=J][:alpha_deg=A]:DIST`; the effect part goes
    /// through the `--effect` parser ([`Effect::from_str`]).
    fn from_str(s: &str) -> Result<Self, VaryError> {
        let (head, law) = s
            .rsplit_once(':')
            .filter(|(_, l)| l.contains('('))
            .ok_or_else(|| VaryError::Syntax(s.to_string()))?;
        let dist = parse_dist(s, law)?;
        let name = head.split(':').next().unwrap_or("").trim();
        let target = if let Some(p) = MechParam::ALL.iter().copied().find(|p| p.name() == name) {
            let joint = head
                .split(':')
                .skip(1)
                .find_map(|kv| kv.trim().strip_prefix("joint="))
                .and_then(|j| j.trim().parse::<usize>().ok())
                .filter(|&j| j >= 1)
                .ok_or_else(|| {
                    VaryError::Mechanism(format!("`{s}`: {} needs joint=J (from 1)", p.name()))
                })?;
            Target::Mech(p, joint)
        } else {
            let effect: Effect =
                format!("{head}:value=0")
                    .parse()
                    .map_err(|source| VaryError::Effect {
                        text: s.to_string(),
                        source,
                    })?;
            if effect.kind() == EffectKind::TorqueTable {
                return Err(VaryError::Mechanism(format!(
                    "`{s}`: torque_table has tables, not one value to vary"
                )));
            }
            Target::of_effect(&effect)
        };
        Ok(Vary { target, dist })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_effect_given_two_laws_has_two_keys() {
        let v = |t: &str| t.parse::<Vary>().unwrap();
        let vary = [
            v("coulomb_friction:joint=1:normal(1,0.1)"),
            v("viscous_damping:joint=1:normal(1,0.1)"),
            v("coulomb_friction:joint=1:normal(1,0.1)"),
            v("coulomb_friction:joint=1:uniform(0,1)"),
        ];
        assert_eq!(
            unique_labels(&vary),
            [
                "coulomb_friction:joint=1",
                "viscous_damping:joint=1",
                "coulomb_friction:joint=1#2",
                "coulomb_friction:joint=1#3",
            ]
        );
    }

    #[test]
    fn parses_effects_and_mechanism_parameters() {
        let v: Vary = "coulomb_friction:joint=2:normal(1.5,0.1)".parse().unwrap();
        assert_eq!(v.label(), "coulomb_friction:joint=2");
        assert_eq!(v.dist, Dist::Normal { mean: 1.5, sd: 0.1 });
        let v: Vary = "panel_mass:joint=1:truncnormal(3.5,0.2,3,4)"
            .parse()
            .unwrap();
        assert_eq!(v.target, Target::Mech(MechParam::PanelMass, 1));
        let v: Vary = "air_drag:lognormal(0.1,0.3)".parse().unwrap();
        assert_eq!(v.to_string(), "air_drag:lognormal(0.1,0.3)");
        for bad in [
            "coulomb_friction:joint=1",
            "coulomb_friction:joint=1:normal(1)",
            "coulomb_friction:joint=1:normal(1,-1)",
            "coulomb_friction:joint=1:gauss(1,1)",
            "friction:joint=1:normal(1,1)",
            "spring_preload:uniform(1,2)",
        ] {
            assert!(bad.parse::<Vary>().is_err(), "{bad}");
        }
    }

    #[test]
    fn the_laws_map_the_normal_space() {
        let n = Dist::Normal { mean: 2.0, sd: 0.5 };
        assert_eq!(n.at(1.0), 2.5);
        let u = Dist::Uniform { lo: 1.0, hi: 3.0 };
        assert!((u.at(0.0) - 2.0).abs() < 1e-15);
        let t = Dist::TruncNormal {
            mean: 0.0,
            sd: 1.0,
            lo: -1.0,
            hi: 1.0,
        };
        assert!(t.at(8.0) <= 1.0 && t.at(-8.0) >= -1.0 && t.at(0.0).abs() < 1e-12);
        let l = Dist::LogNormal {
            median: 2.0,
            sigma_ln: 0.1,
        };
        assert_eq!(l.at(0.0), 2.0);
    }
}
