//! The effect syntax of `deploywatch simulate --effect` and of findings:
//! `NAME[:joint=J]:value=V[:KEY=X]…`, read and written.

use std::fmt;
use std::str::FromStr;

use super::error::EffectError;
use super::kind::EffectKind;
use super::{Effect, Law};
use crate::model::torque_table::{self, TablePoints};

impl FromStr for EffectKind {
    type Err = EffectError;
    fn from_str(s: &str) -> Result<Self, EffectError> {
        EffectKind::EVERY
            .iter()
            .copied()
            .find(|k| k.name() == s)
            .ok_or_else(|| EffectError::UnknownName {
                name: s.to_string(),
            })
    }
}

impl fmt::Display for Effect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.kind())?;
        if let Some(j) = self.joint {
            write!(f, ":joint={j}")?;
        }
        write!(f, ":value={}", self.value())?;
        for (key, xs) in self.law.keys() {
            write!(f, ":{}={}", key.name(), torque_table::list(&xs))?;
        }
        Ok(())
    }
}

impl FromStr for Effect {
    type Err = EffectError;
    /// Parses `NAME[:joint=J]:value=V[:alpha_deg=A]` (the `--effect` syntax).
    fn from_str(s: &str) -> Result<Self, EffectError> {
        let mut parts = s.split(':');
        let kind: EffectKind = parts.next().unwrap_or("").trim().parse()?;
        let mut joint = None;
        let mut value = None;
        let mut alpha_deg = 0.0;
        let (mut excess_nm, mut stribeck_rad_s) = (None, None);
        let mut points = TablePoints::default();
        let table_error = |source| EffectError::Table {
            text: s.to_string(),
            source,
        };
        let mut seen: Vec<&str> = Vec::new();
        for p in parts {
            let (k, v) = p.split_once('=').ok_or_else(|| EffectError::NotKeyValue {
                part: p.to_string(),
                text: s.to_string(),
            })?;
            if seen.contains(&k.trim()) {
                return Err(EffectError::RepeatedKey {
                    key: k.trim().to_string(),
                    text: s.to_string(),
                });
            }
            seen.push(k.trim());
            let bad = |expected| EffectError::BadNumber {
                key: k.to_string(),
                value: v.to_string(),
                text: s.to_string(),
                expected,
            };
            let num = |v: &str| v.trim().parse::<f64>().map_err(|_| bad("a number"));
            match k.trim() {
                "joint" => {
                    joint = Some(
                        v.trim()
                            .parse::<usize>()
                            .map_err(|_| bad("a joint number from 1"))?,
                    )
                }
                "value" => value = Some(num(v)?),
                "alpha_deg" => alpha_deg = num(v)?,
                "excess_nm" if kind == EffectKind::StribeckFriction => {
                    excess_nm = Some(Some(num(v)?).filter(|x| *x >= 0.0).ok_or(bad("≥ 0"))?)
                }
                "stribeck_rad_s" if kind == EffectKind::StribeckFriction => {
                    stribeck_rad_s = Some(Some(num(v)?).filter(|x| *x > 0.0).ok_or(bad("> 0"))?)
                }
                other if points.take(other, v).map_err(table_error)? => {}
                other => {
                    return Err(EffectError::UnknownKey {
                        key: other.to_string(),
                        text: s.to_string(),
                    })
                }
            }
        }
        if kind == EffectKind::TorqueTable {
            let table = points.build().map_err(table_error)?;
            return Ok(Effect {
                joint,
                law: Law::TorqueTable(table),
            });
        }
        if !points.is_empty() {
            return Err(EffectError::TableOnNamedEffect {
                text: s.to_string(),
            });
        }
        let value = value.ok_or_else(|| EffectError::MissingValue {
            text: s.to_string(),
        })?;
        let (excess_nm, rate_rad_s) = stribeck_keys(kind, excess_nm, stribeck_rad_s, s)?;
        let law = Law::of_syntax(kind, value, alpha_deg, excess_nm, rate_rad_s);
        Ok(Effect { joint, law })
    }
}

/// `stribeck_friction`'s `excess_nm` and `stribeck_rad_s` (both required
/// there; `(0, 0)` for any other effect).
fn stribeck_keys(
    kind: EffectKind,
    excess_nm: Option<f64>,
    stribeck_rad_s: Option<f64>,
    text: &str,
) -> Result<(f64, f64), EffectError> {
    match (excess_nm, stribeck_rad_s) {
        (Some(e), Some(w)) => Ok((e, w)),
        _ if kind == EffectKind::StribeckFriction => Err(EffectError::StribeckShapeMissing {
            text: text.to_string(),
        }),
        _ => Ok((0.0, 0.0)),
    }
}
