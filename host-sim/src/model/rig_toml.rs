//! Reading the `[rig]` table of a mechanism file (`docs/spec/formats.md`,
//! "Rig", this project's extension).
//!
//! ```toml
//! [rig]
//! enabled = true                 # optional; false: the flight configuration
//! static_mu = 0.3                # optional, the papers' values by default
//! dynamic_mu = 0.1
//! [[rig.bar]]
//! mass_kg = 2.0
//! [[rig.trolley]]
//! panel = 1
//! bar = 1
//! mass_kg = 0.5
//! wire_m = 1.5
//! [[rig.frame]]
//! name = "lateral -y"
//! normal = [0.0, 1.0]
//! at_m = -0.9
//! ```

use crate::model::mechanism_error::MechanismError;
use crate::model::rig::{
    Bar, Frame, Rig, RigError, Trolley, PAPER_CONTACT_DAMPING, PAPER_CONTACT_STIFFNESS,
    PAPER_DYNAMIC_MU, PAPER_STATIC_MU, STANDARD_GRAVITY_M_S2,
};
use crate::model::toml_tree::{Bound, Cx, Node, Res, Sp, Table};
use deploywatch_core::Panel;

const RIG_KEYS: &[&str] = &[
    "enabled",
    "gravity_m_s2",
    "static_mu",
    "dynamic_mu",
    "friction_load_fraction",
    "stick_speed_m_s",
    "slip_speed_m_s",
    "contact_stiffness_n_per_mm1_5",
    "contact_damping_ns_per_mm1_25",
    "bar",
    "trolley",
    "frame",
];
const BAR_KEYS: &[&str] = &["mass_kg"];
const TROLLEY_KEYS: &[&str] = &[
    "panel",
    "offload_m",
    "mass_kg",
    "bar",
    "wire_m",
    "wire_spring_n_per_m",
    "start_m",
];
const FRAME_KEYS: &[&str] = &["name", "normal", "at_m"];

/// The `[rig]` table `sp` of a mechanism file with `panels` whose joints
/// are stowed at `stowed_deg` \[deg\]; every error names its line.
pub(crate) fn read(cx: &Cx<'_>, sp: &Sp, panels: &[Panel<f64>], stowed_deg: &[f64]) -> Res<Rig> {
    let t = cx.table(sp, "rig", RIG_KEYS)?;
    let num = |key: &str, bound: Bound, unit: &str, default: f64| -> Res<f64> {
        Ok(cx.opt_number(&t, key, bound, unit)?.unwrap_or(default))
    };
    let enabled = cx.opt_bool(&t, "enabled", true)?;
    let bars = cx
        .tables(&t, "bar")?
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let bt = cx.table(b, &format!("rig.bar[{}]", i + 1), BAR_KEYS)?;
            Ok(Bar {
                mass_kg: cx.req_number(&bt, "mass_kg", Bound::NonNegative, "kg")?,
            })
        })
        .collect::<Res<Vec<_>>>()?;
    let trolleys = cx
        .tables(&t, "trolley")?
        .iter()
        .enumerate()
        .map(|(i, s)| trolley(cx, s, &format!("rig.trolley[{}]", i + 1), panels))
        .collect::<Res<Vec<_>>>()?;
    let frames = cx
        .tables(&t, "frame")?
        .iter()
        .enumerate()
        .map(|(i, s)| frame(cx, s, &format!("rig.frame[{}]", i + 1)))
        .collect::<Res<Vec<_>>>()?;
    let rig = Rig {
        enabled,
        gravity_m_s2: num(
            "gravity_m_s2",
            Bound::Positive,
            "m/s²",
            STANDARD_GRAVITY_M_S2,
        )?,
        static_mu: num("static_mu", Bound::NonNegative, "", PAPER_STATIC_MU)?,
        dynamic_mu: num("dynamic_mu", Bound::NonNegative, "", PAPER_DYNAMIC_MU)?,
        friction_load_fraction: num("friction_load_fraction", Bound::NonNegative, "", 1.0)?,
        stick_speed_m_s: num("stick_speed_m_s", Bound::Positive, "m/s", 0.01)?,
        slip_speed_m_s: num("slip_speed_m_s", Bound::Positive, "m/s", 1e-3)?,
        contact_stiffness: num(
            "contact_stiffness_n_per_mm1_5",
            Bound::NonNegative,
            "N/mm^1.5",
            PAPER_CONTACT_STIFFNESS,
        )?,
        contact_damping: num(
            "contact_damping_ns_per_mm1_25",
            Bound::NonNegative,
            "N·s/mm^1.25",
            PAPER_CONTACT_DAMPING,
        )?,
        trolleys,
        bars,
        frames,
    };
    let stowed_rad: Vec<f64> = stowed_deg.iter().map(|d| d.to_radians()).collect();
    match rig.check(panels, &stowed_rad) {
        Ok(()) => Ok(rig),
        Err(e) => Err(at_its_key(cx, sp, &t, &e)),
    }
}

/// The error of [`Rig::check`] at the line of the key it is about (the
/// `[rig]` table's when the key is absent), expecting what the check says.
fn at_its_key(cx: &Cx<'_>, sp: &Sp, t: &Table<'_>, e: &RigError) -> MechanismError {
    let item = |name: &str, index: usize, key: &str| {
        let s = cx.tables(t, name).ok()?.get(index - 1)?;
        let Node::Table(entries) = &s.node else {
            return None;
        };
        let found = entries.iter().find(|(k, _)| k == key).map(|(_, v)| v);
        Some((found.unwrap_or(s), format!("rig.{name}[{index}].{key}")))
    };
    let key = |k: &str| t.get(k).map(|s| (s, format!("rig.{k}")));
    let at = match e {
        RigError::Panel { index, .. } => item("trolley", *index, "panel"),
        RigError::Bar { index, .. } => item("trolley", *index, "bar"),
        RigError::Offload { index, .. } => item("trolley", *index, "offload_m"),
        RigError::Friction { .. } => key("dynamic_mu").or_else(|| key("static_mu")),
        RigError::LoadFraction { .. } => key("friction_load_fraction"),
        RigError::Normal { index } => item("frame", *index, "normal"),
        RigError::CrossedWhenStowed { index, .. } => item("frame", *index, "at_m"),
    };
    let (s, k) = at.unwrap_or((sp, "rig".to_string()));
    cx.invalid(s, &k, &format!("a consistent rig ({e})"))
}

/// A required integer ≥ 1.
fn index(cx: &Cx<'_>, t: &Table<'_>, key: &str) -> Res<usize> {
    let expected = "an integer ≥ 1";
    match t.get(key) {
        None => Err(cx.missing(t, key, expected)),
        Some(sp) => match sp.node {
            Node::Int(i) if i >= 1 => Ok(i as usize),
            _ => Err(cx.invalid(sp, &t.key(key), expected)),
        },
    }
}

fn trolley(cx: &Cx<'_>, sp: &Sp, path: &str, panels: &[Panel<f64>]) -> Res<Trolley> {
    let t = cx.table(sp, path, TROLLEY_KEYS)?;
    let panel = index(cx, &t, "panel")?;
    let com = panels.get(panel - 1).map_or(0.0, |p| p.com_m);
    Ok(Trolley {
        panel,
        offload_m: cx
            .opt_number(&t, "offload_m", Bound::Finite, "m")?
            .unwrap_or(com),
        mass_kg: cx.req_number(&t, "mass_kg", Bound::NonNegative, "kg")?,
        bar: index(cx, &t, "bar")?,
        wire_m: cx.req_number(&t, "wire_m", Bound::Positive, "m")?,
        wire_spring_n_per_m: cx.opt_number(&t, "wire_spring_n_per_m", Bound::Positive, "N/m")?,
        start_m: t
            .get("start_m")
            .map(|s| {
                cx.pair(s, &t.key("start_m"), "[x, y] in m")
                    .map(|(x, y)| [x, y])
            })
            .transpose()?,
    })
}

fn frame(cx: &Cx<'_>, sp: &Sp, path: &str) -> Res<Frame> {
    let t = cx.table(sp, path, FRAME_KEYS)?;
    let name = match t.get("name") {
        Some(s) => cx.string(s, &t.key("name"))?.to_string(),
        None => path.to_string(),
    };
    let (nx, ny) = match t.get("normal") {
        Some(s) => cx.pair(s, &t.key("normal"), "[x, y]")?,
        None => return Err(cx.missing(&t, "normal", "[x, y], into the allowed side")),
    };
    let len = nx.hypot(ny);
    if len == 0.0 {
        let s = t.get("normal").unwrap_or(sp);
        return Err(cx.invalid(s, &t.key("normal"), "a non-zero [x, y]"));
    }
    Ok(Frame {
        name,
        normal: [nx / len, ny / len],
        at_m: cx.req_number(&t, "at_m", Bound::Finite, "m")?,
    })
}

/// Appends `[rig]` as [`read`] takes it (every key written, so that a
/// written mechanism reads back to the same rig).
pub(crate) fn write(r: &Rig, out: &mut String) {
    use crate::model::toml_tree::{num, toml_str};
    use std::fmt::Write as _;
    let _ = write!(
        out,
        "\n[rig]\nenabled = {}\ngravity_m_s2 = {}\nstatic_mu = {}\ndynamic_mu = {}\n\
         friction_load_fraction = {}\nstick_speed_m_s = {}\nslip_speed_m_s = {}\n\
         contact_stiffness_n_per_mm1_5 = {}\ncontact_damping_ns_per_mm1_25 = {}\n",
        r.enabled,
        num(r.gravity_m_s2),
        num(r.static_mu),
        num(r.dynamic_mu),
        num(r.friction_load_fraction),
        num(r.stick_speed_m_s),
        num(r.slip_speed_m_s),
        num(r.contact_stiffness),
        num(r.contact_damping)
    );
    for b in &r.bars {
        let _ = write!(out, "\n[[rig.bar]]\nmass_kg = {}\n", num(b.mass_kg));
    }
    for t in &r.trolleys {
        let _ = write!(
            out,
            "\n[[rig.trolley]]\npanel = {}\nbar = {}\nmass_kg = {}\nwire_m = {}\noffload_m = {}\n",
            t.panel,
            t.bar,
            num(t.mass_kg),
            num(t.wire_m),
            num(t.offload_m)
        );
        if let Some(k) = t.wire_spring_n_per_m {
            let _ = writeln!(out, "wire_spring_n_per_m = {}", num(k));
        }
        if let Some([x, y]) = t.start_m {
            let _ = writeln!(out, "start_m = [{}, {}]", num(x), num(y));
        }
    }
    for f in &r.frames {
        let _ = write!(
            out,
            "\n[[rig.frame]]\nname = {}\nnormal = [{}, {}]\nat_m = {}\n",
            toml_str(&f.name),
            num(f.normal[0]),
            num(f.normal[1]),
            num(f.at_m)
        );
    }
}
