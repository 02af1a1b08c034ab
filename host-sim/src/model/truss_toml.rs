//! Reading the `[truss]` table of a mechanism file (`docs/spec/formats.md`,
//! "Truss", this project's extension of the mechanism format).
//!
//! ```toml
//! [truss]
//! hinges_mm = [[0.0, 0.0], [0.2, 824.0]]      # hinge j at the stowed pose
//! [[truss.point]]
//! name = "A"
//! on = "bus"                                   # "bus", "panel1".."panel4", "node"
//! at_mm = [-70.0, 299.0]
//! knee = false                                 # optional; nodes of two links
//! reference_link = "3"                         # optional; nodes of 3+ links
//! friction = { coulomb_nm = 0.065 }            # optional; every pin there
//! [[truss.link]]
//! name = "1"
//! ends = ["A", "B"]
//! mass_kg = 0.17360
//! length_mm = 139.9994
//! ```

use toml::{Table, Value};

use crate::model::mechanism::FrictionSpec;
use crate::model::truss::{Carrier, Truss, TrussError, TrussLink, TrussPoint};

const TRUSS_KEYS: &[&str] = &["hinges_mm", "point", "link"];
const POINT_KEYS: &[&str] = &["name", "on", "at_mm", "knee", "reference_link", "friction"];
const LINK_KEYS: &[&str] = &["name", "ends", "mass_kg", "length_mm"];
const FRICTION_KEYS: &[&str] = &["coulomb_nm", "viscous_nms", "coulomb_threshold_rad_s"];

fn err(key: impl Into<String>, message: impl Into<String>) -> TrussError {
    TrussError {
        key: key.into(),
        message: message.into(),
    }
}

/// The `[truss]` table of a mechanism file's text, `None` without one.
/// (The rest of the file is read by [`crate::model::mechanism_toml`].)
pub fn read(text: &str) -> Result<Option<Truss>, TrussError> {
    let root: Table = text
        .parse()
        .map_err(|e: toml::de::Error| err("truss", format!("invalid TOML: {}", e.message())))?;
    match root.get("truss") {
        None => Ok(None),
        Some(Value::Table(t)) => truss(t).map(Some),
        Some(_) => Err(err("truss", "expected a table")),
    }
}

fn known(t: &Table, key: &str, allowed: &[&str]) -> Result<(), TrussError> {
    match t.keys().find(|k| !allowed.contains(&k.as_str())) {
        Some(k) => Err(err(
            format!("{key}.{k}"),
            format!("unknown key; expected one of: {}", allowed.join(", ")),
        )),
        None => Ok(()),
    }
}

fn number(t: &Table, key: &str, name: &str) -> Result<f64, TrussError> {
    match t.get(name) {
        Some(Value::Float(x)) if x.is_finite() => Ok(*x),
        Some(Value::Integer(i)) => Ok(*i as f64),
        Some(_) => Err(err(format!("{key}.{name}"), "expected a finite number")),
        None => Err(err(format!("{key}.{name}"), "missing; expected a number")),
    }
}

fn string<'a>(t: &'a Table, key: &str, name: &str) -> Result<&'a str, TrussError> {
    match t.get(name) {
        Some(Value::String(s)) if !s.is_empty() => Ok(s),
        Some(_) => Err(err(format!("{key}.{name}"), "expected a non-empty string")),
        None => Err(err(format!("{key}.{name}"), "missing; expected a string")),
    }
}

/// A `[x, y]` pair in millimetres.
fn xy_mm(v: Option<&Value>, key: &str) -> Result<[f64; 2], TrussError> {
    let bad = || err(key, "expected [x, y] in mm (two finite numbers)");
    let a = v.and_then(Value::as_array).ok_or_else(bad)?;
    let num = |v: &Value| {
        v.as_float()
            .or(v.as_integer().map(|i| i as f64))
            .filter(|x| x.is_finite())
    };
    match a.as_slice() {
        [x, y] => Ok([num(x).ok_or_else(bad)?, num(y).ok_or_else(bad)?]),
        _ => Err(bad()),
    }
}

fn tables<'a>(t: &'a Table, key: &str, name: &str) -> Result<Vec<&'a Table>, TrussError> {
    match t.get(name) {
        None => Ok(Vec::new()),
        Some(Value::Array(a)) => a
            .iter()
            .enumerate()
            .map(|(i, v)| {
                v.as_table()
                    .ok_or_else(|| err(format!("{key}.{name}[{}]", i + 1), "expected a table"))
            })
            .collect(),
        Some(_) => Err(err(
            format!("{key}.{name}"),
            "expected an array of tables [[...]]",
        )),
    }
}

fn truss(t: &Table) -> Result<Truss, TrussError> {
    known(t, "truss", TRUSS_KEYS)?;
    let hinges = t
        .get("hinges_mm")
        .and_then(Value::as_array)
        .ok_or_else(|| {
            err(
                "truss.hinges_mm",
                "missing; expected [[x, y], ...] in mm, one per joint",
            )
        })?;
    let hinges_mm = hinges
        .iter()
        .enumerate()
        .map(|(i, v)| xy_mm(Some(v), &format!("truss.hinges_mm[{}]", i + 1)))
        .collect::<Result<_, _>>()?;
    let mut points = Vec::new();
    for (i, p) in tables(t, "truss", "point")?.into_iter().enumerate() {
        points.push(point(p, &format!("truss.point[{}]", i + 1))?);
    }
    let mut links = Vec::new();
    for (i, l) in tables(t, "truss", "link")?.into_iter().enumerate() {
        links.push(link(l, &format!("truss.link[{}]", i + 1))?);
    }
    Ok(Truss {
        hinges_mm,
        points,
        links,
    })
}

fn point(t: &Table, key: &str) -> Result<TrussPoint, TrussError> {
    known(t, key, POINT_KEYS)?;
    let on = match string(t, key, "on")? {
        "bus" => Carrier::Bus,
        "node" => Carrier::Node,
        s => match s
            .strip_prefix("panel")
            .and_then(|n| n.parse::<usize>().ok())
        {
            Some(n) => Carrier::Panel(n),
            None => {
                return Err(err(
                    format!("{key}.on"),
                    format!("\"{s}\"; expected \"bus\", \"node\" or \"panel1\"..\"panel4\""),
                ))
            }
        },
    };
    let knee = match t.get("knee") {
        None => false,
        Some(Value::Boolean(b)) => *b,
        Some(_) => return Err(err(format!("{key}.knee"), "expected true or false")),
    };
    let reference_link = match t.get("reference_link") {
        None => None,
        Some(_) => Some(string(t, key, "reference_link")?.to_string()),
    };
    Ok(TrussPoint {
        name: string(t, key, "name")?.to_string(),
        on,
        at_mm: xy_mm(t.get("at_mm"), &format!("{key}.at_mm"))?,
        knee,
        reference_link,
        friction: friction(t.get("friction"), &format!("{key}.friction"))?,
    })
}

fn friction(v: Option<&Value>, key: &str) -> Result<FrictionSpec, TrussError> {
    let mut f = FrictionSpec::default();
    let Some(v) = v else { return Ok(f) };
    let t = v
        .as_table()
        .ok_or_else(|| err(key, "expected an inline table { coulomb_nm = ... }"))?;
    known(t, key, FRICTION_KEYS)?;
    let nonneg = |name: &str, d: f64| -> Result<f64, TrussError> {
        match t.get(name) {
            None => Ok(d),
            Some(_) => {
                let x = number(t, key, name)?;
                if x < 0.0 {
                    return Err(err(format!("{key}.{name}"), "expected a number ≥ 0"));
                }
                Ok(x)
            }
        }
    };
    f.coulomb_nm = nonneg("coulomb_nm", 0.0)?;
    f.viscous_nms = nonneg("viscous_nms", 0.0)?;
    f.coulomb_threshold_rad_s = nonneg("coulomb_threshold_rad_s", f.coulomb_threshold_rad_s)?;
    Ok(f)
}

fn link(t: &Table, key: &str) -> Result<TrussLink, TrussError> {
    known(t, key, LINK_KEYS)?;
    let ends = match t.get("ends").and_then(Value::as_array).map(Vec::as_slice) {
        Some([Value::String(a), Value::String(b)]) if a != b => [a.clone(), b.clone()],
        _ => {
            return Err(err(
                format!("{key}.ends"),
                "expected two different point names [\"A\", \"B\"]",
            ))
        }
    };
    let mass_kg = number(t, key, "mass_kg")?;
    let length_mm = number(t, key, "length_mm")?;
    if !(mass_kg > 0.0) || !(length_mm > 0.0) {
        return Err(err(
            key.to_string(),
            "expected mass_kg > 0 and length_mm > 0",
        ));
    }
    Ok(TrussLink {
        name: string(t, key, "name")?.to_string(),
        ends,
        mass_kg,
        length_mm,
    })
}

/// Writes a truss as the `[truss]` table, every number in Rust's shortest
/// round-trip form, so that [`read`] gives it back equal.
pub fn write(t: &Truss, out: &mut String) {
    use std::fmt::Write as _;
    let xy = |p: [f64; 2]| format!("[{:?}, {:?}]", p[0], p[1]);
    let hinges: Vec<String> = t.hinges_mm.iter().map(|&h| xy(h)).collect();
    let _ = writeln!(out, "\n[truss]\nhinges_mm = [{}]", hinges.join(", "));
    for p in &t.points {
        let on = match p.on {
            Carrier::Bus => "bus".to_string(),
            Carrier::Node => "node".to_string(),
            Carrier::Panel(i) => format!("panel{i}"),
        };
        let _ = write!(
            out,
            "\n[[truss.point]]\nname = {:?}\non = {on:?}\nat_mm = {}\n",
            p.name,
            xy(p.at_mm)
        );
        if p.knee {
            let _ = writeln!(out, "knee = true");
        }
        if let Some(r) = &p.reference_link {
            let _ = writeln!(out, "reference_link = {r:?}");
        }
        if p.friction != FrictionSpec::default() {
            let f = &p.friction;
            let _ = writeln!(
                out,
                "friction = {{ coulomb_nm = {:?}, viscous_nms = {:?}, coulomb_threshold_rad_s = {:?} }}",
                f.coulomb_nm, f.viscous_nms, f.coulomb_threshold_rad_s
            );
        }
    }
    for l in &t.links {
        let _ = write!(
            out,
            "\n[[truss.link]]\nname = {:?}\nends = [{:?}, {:?}]\nmass_kg = {:?}\nlength_mm = {:?}\n",
            l.name, l.ends[0], l.ends[1], l.mass_kg, l.length_mm
        );
    }
}
