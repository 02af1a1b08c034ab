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

use crate::model::mechanism::FrictionSpec;
use crate::model::mechanism_error::MechanismErrorKind;
use crate::model::toml_tree::{Bound, Cx, Node, Res, Sp, Table};
use crate::model::truss::{Carrier, Truss, TrussLink, TrussPoint};

const TRUSS_KEYS: &[&str] = &["hinges_mm", "point", "link"];
const POINT_KEYS: &[&str] = &["name", "on", "at_mm", "knee", "reference_link", "friction"];
const LINK_KEYS: &[&str] = &["name", "ends", "mass_kg", "length_mm"];
const FRICTION_KEYS: &[&str] = &["coulomb_nm", "viscous_nms", "coulomb_threshold_rad_s"];

/// The `[truss]` table `sp` of a mechanism file with `panels` panels,
/// read and checked ([`Truss::check`]); every error names its line.
pub(crate) fn read(cx: &Cx<'_>, sp: &Sp, panels: usize) -> Res<Truss> {
    let t = cx.table(sp, "truss", TRUSS_KEYS)?;
    let expected = "[[x, y], ...] in mm, one per joint";
    let hinges = match t.get("hinges_mm") {
        Some(h) => h,
        None => return Err(cx.missing(&t, "hinges_mm", expected)),
    };
    let Node::Array(items) = &hinges.node else {
        return Err(cx.wrong_type(hinges, &t.key("hinges_mm"), expected));
    };
    let hinges_mm = items
        .iter()
        .enumerate()
        .map(|(i, v)| xy_mm(cx, v, &format!("truss.hinges_mm[{}]", i + 1)))
        .collect::<Res<_>>()?;
    let points = cx
        .tables(&t, "point")?
        .iter()
        .enumerate()
        .map(|(i, p)| point(cx, p, &format!("truss.point[{}]", i + 1)))
        .collect::<Res<_>>()?;
    let links = cx
        .tables(&t, "link")?
        .iter()
        .enumerate()
        .map(|(i, l)| link(cx, l, &format!("truss.link[{}]", i + 1)))
        .collect::<Res<_>>()?;
    let truss = Truss {
        hinges_mm,
        points,
        links,
    };
    truss.check(panels).map_err(|source| {
        let line = cx.line(sp.at_path(&source.key)).or_else(|| cx.line(sp));
        cx.err(line, MechanismErrorKind::Truss { source })
    })?;
    Ok(truss)
}

/// A `[x, y]` pair in millimetres.
fn xy_mm(cx: &Cx<'_>, sp: &Sp, key: &str) -> Res<[f64; 2]> {
    let (x, y) = cx.pair(sp, key, "[x, y] in mm")?;
    Ok([x, y])
}

/// A required non-empty string.
fn name<'s>(cx: &Cx<'_>, t: &Table<'s>, key: &str) -> Res<&'s str> {
    let Some(sp) = t.get(key) else {
        return Err(cx.missing(t, key, "a non-empty string"));
    };
    match cx.string(sp, &t.key(key))? {
        "" => Err(cx.invalid(sp, &t.key(key), "a non-empty string")),
        s => Ok(s),
    }
}

fn point(cx: &Cx<'_>, sp: &Sp, key: &str) -> Res<TrussPoint> {
    let t = cx.table(sp, key, POINT_KEYS)?;
    let on = match name(cx, &t, "on")? {
        "bus" => Carrier::Bus,
        "node" => Carrier::Node,
        s => match s
            .strip_prefix("panel")
            .and_then(|n| n.parse::<usize>().ok())
        {
            Some(n) => Carrier::Panel(n),
            None => {
                let sp = t.get("on").unwrap_or(sp);
                let expected = "\"bus\", \"node\" or \"panel1\"..\"panel4\"";
                return Err(cx.invalid(sp, &t.key("on"), expected));
            }
        },
    };
    let knee = cx.opt_bool(&t, "knee", false)?;
    let reference_link = match t.get("reference_link") {
        None => None,
        Some(_) => Some(name(cx, &t, "reference_link")?.to_string()),
    };
    let at_mm = match t.get("at_mm") {
        Some(a) => xy_mm(cx, a, &t.key("at_mm"))?,
        None => return Err(cx.missing(&t, "at_mm", "[x, y] in mm")),
    };
    let friction = match t.get("friction") {
        Some(f) => friction(cx, f, &t.key("friction"))?,
        None => FrictionSpec::default(),
    };
    Ok(TrussPoint {
        name: name(cx, &t, "name")?.to_string(),
        on,
        at_mm,
        knee,
        reference_link,
        friction,
    })
}

/// `friction = { coulomb_nm = ..., ... }`: every value ≥ 0, the rest of
/// [`FrictionSpec::default`].
fn friction(cx: &Cx<'_>, sp: &Sp, key: &str) -> Res<FrictionSpec> {
    let t = cx.table(sp, key, FRICTION_KEYS)?;
    let mut f = FrictionSpec::default();
    let nonneg = Bound::NonNegative;
    if let Some(x) = cx.opt_number(&t, "coulomb_nm", nonneg, "N·m")? {
        f.coulomb_nm = x;
    }
    if let Some(x) = cx.opt_number(&t, "viscous_nms", nonneg, "N·m·s/rad")? {
        f.viscous_nms = x;
    }
    if let Some(x) = cx.opt_number(&t, "coulomb_threshold_rad_s", nonneg, "rad/s")? {
        f.coulomb_threshold_rad_s = x;
    }
    Ok(f)
}

fn link(cx: &Cx<'_>, sp: &Sp, key: &str) -> Res<TrussLink> {
    let t = cx.table(sp, key, LINK_KEYS)?;
    let expected = "two different point names [\"A\", \"B\"]";
    let ends = match t.get("ends") {
        None => return Err(cx.missing(&t, "ends", expected)),
        Some(e) => match &e.node {
            Node::Array(items) => match items.as_slice() {
                [Sp {
                    node: Node::Str(a), ..
                }, Sp {
                    node: Node::Str(b), ..
                }] if a != b => [a.clone(), b.clone()],
                _ => return Err(cx.invalid(e, &t.key("ends"), expected)),
            },
            _ => return Err(cx.wrong_type(e, &t.key("ends"), expected)),
        },
    };
    Ok(TrussLink {
        name: name(cx, &t, "name")?.to_string(),
        ends,
        mass_kg: cx.req_number(&t, "mass_kg", Bound::Positive, "kg")?,
        length_mm: cx.req_number(&t, "length_mm", Bound::Positive, "mm")?,
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
