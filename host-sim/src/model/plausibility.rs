//! Values of a mechanism that are valid but unlikely: a panel mass typed in
//! grams, an inertia that no panel of that mass and length has, a stowed
//! angle or a curve spring's angles typed in radians, a spring that would
//! deploy its panels in a flash or over hours, or not at all, a rig's
//! suspension wire typed in millimetres. Each is a
//! warning
//! (the value may be right), naming the key and, when the TOML text is
//! given, its line; none stops a command.
//!
//! The estimates use no simulation: areal mass `m / L²` (the file gives no
//! panel width, so a square panel is assumed), the hinge inertia against
//! `m·L²/3` of a uniform panel, and the deployment time of a constant torque
//! releasing the spring's energy over the stroke.

use std::path::Path;

use crate::model::mechanism::{JointSpec, Mechanism, SpringSpec};

/// Lightest plausible panel [kg/m²]: a 50 µm polyimide film (1.42 g/cm³)
/// weighs 0.07 kg/m²; no self-supporting panel is lighter.
pub const MIN_AREAL_MASS_KG_M2: f64 = 0.05;

/// Heaviest plausible panel [kg/m²]: a 12.7 mm steel plate (7.85 g/cm³)
/// weighs 100 kg/m²; a mass typed in grams is a thousand times the true one.
pub const MAX_AREAL_MASS_KG_M2: f64 = 100.0;

/// Smallest plausible hinge inertia `I_c + m·com²` against `m·L²/3` (a
/// uniform panel about its hinge): 0.1, a radius of gyration of 0.18 L,
/// as if the mass sat in the fifth of the panel next to the hinge.
pub const MIN_INERTIA_RATIO: f64 = 0.1;

/// Largest plausible hinge inertia against `m·L²/3`: 3, all the mass at the
/// far edge (`m·L²`); a body within the panel's length cannot exceed it.
pub const MAX_INERTIA_RATIO: f64 = 3.0;

/// Shortest plausible deployment \[s\]: a tenth of a second, below which the
/// latch impact would break a real panel.
pub const MIN_DEPLOY_S: f64 = 0.1;

/// Longest plausible deployment \[s\]: ten minutes, beyond which the spring
/// could not overcome any real hinge's friction.
pub const MAX_DEPLOY_S: f64 = 600.0;

/// Longest plausible suspension wire of a zero-g rig's trolley \[m\]: 30 m,
/// the height of a tall high bay; a wire typed in millimetres is a
/// thousand times the true one (1.5 m typed 1500).
pub const MAX_WIRE_M: f64 = 30.0;

/// Largest tolerance in per cent that reads as a fraction typed for a
/// percentage \[%\]: 1 %. A spring's torque is known to a few per cent;
/// `0.05` typed for 5 % is 0.05 %.
pub const FRACTION_LIKE_PCT: f64 = 1.0;

/// A tolerance `pct` \[%\] given with `option` (`--spring-tolerance`) above
/// 0 and below [`FRACTION_LIKE_PCT`]: a fraction typed for a percentage, in
/// a warning.
pub fn percent_as_fraction(option: &str, pct: f64) -> Option<String> {
    (pct > 0.0 && pct < FRACTION_LIKE_PCT).then(|| {
        let meant = crate::report::text::list_4(&[pct * 100.0]);
        format!(
            "{option} {pct}: taken as {pct} %, below {FRACTION_LIKE_PCT} %: a fraction for a \
             percentage? the option takes per cent: {meant} % is `{option} {meant}`"
        )
    })
}

/// A valid but unlikely value.
#[derive(Clone, Debug, PartialEq)]
pub struct Implausible {
    /// The key path (`panel[1].mass_kg`, `joint[2].spring`), 1-based.
    pub key: String,
    /// The value's line in the TOML text, when the text was given.
    pub line: Option<usize>,
    /// What is unlikely and the likely cause, one sentence.
    pub message: String,
}

/// Relative distance of a stowed angle from a quarter turn written in
/// radians (π/2, π, 3π/2, 2π) within which it is taken for radians: 0.1 %,
/// four significant digits (1.571, 3.142); no hinge is stowed 1.571 deg
/// from its latch.
pub const RADIAN_MATCH: f64 = 1e-3;

/// `k` when `stowed_deg` is ±kπ/2 (k = 1..4) within [`RADIAN_MATCH`]: a
/// stowed angle typed in radians.
fn quarter_turns_in_radians(stowed_deg: f64) -> Option<i32> {
    let x = stowed_deg.abs();
    (1..=4).find(|&k| {
        let q = f64::from(k) * std::f64::consts::FRAC_PI_2;
        (x - q).abs() <= RADIAN_MATCH * q
    })
}

/// What a `stowed_deg` typed in radians reads as, when it is one
/// ([`quarter_turns_in_radians`]): the one sentence of the warning, which
/// the mechanism reader also adds to a latch that the short stroke leaves
/// no room for.
pub fn stowed_in_radians(stowed_deg: f64) -> Option<String> {
    quarter_turns_in_radians(stowed_deg).map(|k| {
        format!(
            "{} deg is {} in radians, a stroke of {:.2} deg: an angle in radians? expected degrees ({:.1})",
            stowed_deg,
            quarter_turns_text(k),
            stowed_deg.abs(),
            stowed_deg.to_degrees()
        )
    })
}

/// The deployment time of joint `j` (0-based) estimated without simulation
/// \[s\]: the spring's energy `E` over the stroke `Δφ` (its unfolding branch,
/// [`deploywatch_core::Spring::release`]) as a constant torque `E/Δφ`
/// turning the outboard panels, straight, about the joint: `t = Δφ·√(2I/E)`.
/// `None` when the spring releases no energy or the spring is invalid.
pub fn deploy_time_s(mechanism: &Mechanism, j: usize) -> Option<f64> {
    let joint = mechanism.joints.get(j)?;
    let spring = joint.spring.to_spring().ok()?;
    let stroke = joint.stowed_deg.abs().to_radians();
    let energy = spring.release(0.0, stroke);
    if !(energy > 0.0) || stroke == 0.0 {
        return None;
    }
    let mut reach = 0.0;
    let mut inertia = 0.0;
    for p in &mechanism.panels[j.min(mechanism.panels.len())..] {
        let r = reach + p.com_m;
        inertia += p.inertia_kgm2 + p.mass_kg * r * r;
        reach += p.length_m;
    }
    Some(stroke * (2.0 * inertia / energy).sqrt())
}

/// The unlikely values of `mechanism`; `text` is its TOML (for the lines).
pub fn check(mechanism: &Mechanism, text: Option<&str>) -> Vec<Implausible> {
    let doc = text.and_then(|t| toml_edit::ImDocument::parse(t).ok());
    let line_of = |table: &str, i: usize, key: &str| -> Option<usize> {
        let (doc, text) = (doc.as_ref()?, text?);
        let item = doc.get(table)?.as_array_of_tables()?.get(i)?.get(key)?;
        let start = item.span()?.start;
        Some(text[..start.min(text.len())].matches('\n').count() + 1)
    };
    let mut out = Vec::new();
    for (i, p) in mechanism.panels.iter().enumerate() {
        let mut say = |key: &str, message: String| {
            out.push(Implausible {
                key: format!("panel[{}].{key}", i + 1),
                line: line_of("panel", i, key),
                message,
            })
        };
        let l = p.length_m;
        let areal = p.mass_kg / (l * l);
        if areal > MAX_AREAL_MASS_KG_M2 {
            say("mass_kg", format!("{} kg on a {:.0} mm panel is {areal:.0} kg/m² (a square panel), heavier than a {MAX_AREAL_MASS_KG_M2} kg/m² steel plate: a mass in grams? expected kilograms", p.mass_kg, l * 1000.0));
        } else if areal < MIN_AREAL_MASS_KG_M2 {
            say("mass_kg", format!("{} kg on a {:.0} mm panel is {areal:.3} kg/m² (a square panel), lighter than a {MIN_AREAL_MASS_KG_M2} kg/m² film: a mass in tonnes, or a length in millimetres? expected kilograms and metres", p.mass_kg, l * 1000.0));
        }
        let uniform = p.mass_kg * l * l / 3.0;
        let ratio = (p.inertia_kgm2 + p.mass_kg * p.com_m * p.com_m) / uniform;
        if !(MIN_INERTIA_RATIO..=MAX_INERTIA_RATIO).contains(&ratio) {
            say("inertia_kgm2", format!("{} kg·m² about the centre of mass makes the hinge inertia {ratio:.2} times m·L²/3 = {uniform:.3} kg·m² of a uniform panel (plausible {MIN_INERTIA_RATIO} to {MAX_INERTIA_RATIO}): an inertia in other units (g·m², kg·mm²), or about another axis?", p.inertia_kgm2));
        }
    }
    for (j, joint) in mechanism.joints.iter().enumerate() {
        if let Some(message) = stowed_in_radians(joint.stowed_deg) {
            out.push(Implausible {
                key: format!("joint[{}].stowed_deg", j + 1),
                line: line_of("joint", j, "stowed_deg"),
                message,
            });
        }
    }
    for (j, joint) in mechanism.joints.iter().enumerate() {
        let say = |message: String| Implausible {
            key: format!("joint[{}].spring", j + 1),
            line: line_of("joint", j, "spring"),
            message,
        };
        out.extend(spring_units(joint).map(say));
        let Some(t) = deploy_time_s(mechanism, j) else {
            out.extend(no_energy(joint).map(say));
            continue;
        };
        if !(MIN_DEPLOY_S..=MAX_DEPLOY_S).contains(&t) {
            out.push(Implausible {
                key: format!("joint[{}].spring", j + 1),
                line: line_of("joint", j, "spring"),
                message: format!("the spring would deploy its panels in about {t:.3} s (its energy as a constant torque, no friction), outside {MIN_DEPLOY_S} s to {MAX_DEPLOY_S} s: a torque or stiffness in other units (N·mm, per degree), or a wrong hinge count?"),
            });
        }
    }
    out.extend(rig_wires(mechanism, doc.as_ref(), text));
    if doc.as_ref().is_some_and(|d| d.get("run").is_none()) {
        out.push(Implausible {
            key: "run".into(),
            line: None,
            message: format!("no [run] table: duration_s = {} s and sample_hz = {} Hz taken by default (a wing still moving then is reported not latched); expected [run] with the duration and rate of the test", mechanism.duration_s, mechanism.sample_hz),
        });
    }
    out
}

/// The rig's suspension wires longer than [`MAX_WIRE_M`]: lengths typed in
/// millimetres (`doc` and `text`, the TOML, for the lines).
fn rig_wires(
    mechanism: &Mechanism,
    doc: Option<&toml_edit::ImDocument<&str>>,
    text: Option<&str>,
) -> Vec<Implausible> {
    let Some(rig) = &mechanism.rig else {
        return Vec::new();
    };
    let line_of = |i: usize| -> Option<usize> {
        let (doc, text) = (doc?, text?);
        let trolleys = doc.get("rig")?.get("trolley")?.as_array_of_tables()?;
        let start = trolleys.get(i)?.get("wire_m")?.span()?.start;
        Some(text[..start.min(text.len())].matches('\n').count() + 1)
    };
    (rig.trolleys.iter().enumerate())
        .filter(|(_, t)| t.wire_m > MAX_WIRE_M)
        .map(|(i, t)| Implausible {
            key: format!("rig.trolley[{}].wire_m", i + 1),
            line: line_of(i),
            message: format!("a suspension wire of {} m ({:.1} km), longer than the {MAX_WIRE_M} m of a tall high bay: a length in millimetres? expected metres ({} m)", t.wire_m, t.wire_m / 1000.0, t.wire_m / 1000.0),
        })
        .collect()
}

/// [`check`] of a mechanism read from `path` (its text read again for the
/// lines), as `path:line: key: message` lines for the CLI's warnings.
pub fn warnings(mechanism: &Mechanism, path: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).ok();
    warnings_in(mechanism, text.as_deref(), &path.display().to_string())
}

/// [`check`] of a mechanism whose TOML `text` came from `file`, as
/// `file:line: key: message` lines (what [`warnings`] gives for a path).
pub fn warnings_in(mechanism: &Mechanism, text: Option<&str>, file: &str) -> Vec<String> {
    check(mechanism, text)
        .into_iter()
        .map(|w| match w.line {
            Some(l) => format!("{file}:{l}: `{}`: {}", w.key, w.message),
            None => format!("{file}: `{}`: {}", w.key, w.message),
        })
        .collect()
}

/// Largest angle \[deg\] of a curve spring's points taken for radians: one
/// turn in radians, 2π within [`RADIAN_MATCH`].
pub const CURVE_RADIANS_MAX: f64 = std::f64::consts::TAU * (1.0 + RADIAN_MATCH);

/// A curve spring whose points end below [`CURVE_RADIANS_MAX`] on a stroke
/// more than twice as long: its angles typed in radians.
fn spring_units(joint: &JointSpec) -> Option<String> {
    let SpringSpec::Curve { unfold, .. } = &joint.spring else {
        return None;
    };
    let widest = unfold.iter().map(|p| p.0.abs()).fold(0.0, f64::max);
    let stroke = joint.stowed_deg.abs();
    (widest <= CURVE_RADIANS_MAX && stroke > 2.0 * widest).then(|| format!("the curve's points end at {widest} deg on a stroke of {stroke} deg, and the spring holds its last torque beyond them: angles in radians? expected degrees ({:.1} deg)", widest.to_degrees()))
}

/// A spring that gives no energy over its joint's stroke (of zero torque:
/// the file refuses a negative one): the joint cannot deploy on it.
fn no_energy(joint: &JointSpec) -> Option<String> {
    let spring = joint.spring.to_spring::<f64>().ok()?;
    let stroke = joint.stowed_deg.abs();
    let energy = spring.release(0.0, stroke.to_radians());
    (energy.is_nan() || energy <= 0.0).then(|| format!("the spring gives {energy:.3} J over the {stroke} deg stroke: the joint cannot deploy on it, and its margins are undefined (0/0); a spring of zero torque?"))
}

/// `k` quarter turns as a multiple of π in words: `π/2`, `π`, `3π/2`, `2π`.
fn quarter_turns_text(k: i32) -> String {
    match (k % 2, k / 2) {
        (1, 0) => "π/2".into(),
        (1, n) => format!("{}π/2", 2 * n + 1),
        (_, 1) => "π".into(),
        (_, n) => format!("{n}π"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn t01_text() -> String {
        let p =
            PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../data/mechanisms/seed001_T01.toml");
        std::fs::read_to_string(p).unwrap()
    }

    #[test]
    fn the_t01_springs_deploy_in_seconds_and_nothing_is_unlikely() {
        let text = t01_text();
        let m = Mechanism::from_toml_str(&text, "t01").unwrap();
        assert_eq!(check(&m, Some(&text)), Vec::new());
        // The bundled run latches its joints within 1 to 4 s.
        for j in 0..3 {
            let t = deploy_time_s(&m, j).unwrap();
            assert!((0.2..20.0).contains(&t), "joint {}: {t} s", j + 1);
        }
    }

    #[test]
    fn a_file_without_a_run_table_is_told_the_defaults() {
        let text = t01_text();
        let start = text.find("[run]").expect("T01 has a [run] table");
        let end = text[start..].find("\n\n").map_or(text.len(), |e| start + e);
        let without = format!("{}{}", &text[..start], &text[end..]);
        let m = Mechanism::from_toml_str(&without, "t01").unwrap();
        let found = check(&m, Some(&without));
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!(found[0].key, "run");
        assert!(
            found[0].message.contains("6 s") && found[0].message.contains("100 Hz"),
            "{}",
            found[0].message
        );
    }

    #[test]
    fn a_stowed_angle_in_radians_names_the_key_and_its_line() {
        let text = t01_text().replacen("stowed_deg = 180.0", "stowed_deg = 3.1416", 1);
        let m = Mechanism::from_toml_str(&text, "t01").unwrap();
        let found = check(&m, Some(&text));
        let w: Vec<_> = found
            .iter()
            .filter(|w| w.key == "joint[2].stowed_deg")
            .collect();
        assert_eq!(w.len(), 1, "{found:?}");
        let line = text.lines().position(|l| l.contains("3.1416")).unwrap() + 1;
        assert_eq!(w[0].line, Some(line));
        assert!(
            w[0].message.contains("radians")
                && w[0].message.contains("180.0")
                && w[0].message.contains("3.1416 deg is π in radians"),
            "{}",
            w[0].message
        );
        let named: Vec<String> = (1..=4).map(quarter_turns_text).collect();
        assert_eq!(named, ["π/2", "π", "3π/2", "2π"]);
    }

    #[test]
    fn a_mass_in_grams_names_the_key_and_its_line() {
        let text = t01_text().replacen("mass_kg = 3.5", "mass_kg = 3500.0", 1);
        let line = 1 + text.lines().position(|l| l.contains("3500.0")).unwrap();
        let m = Mechanism::from_toml_str(&text, "t01").unwrap();
        let w = check(&m, Some(&text));
        assert_eq!(w.len(), 1, "{w:?}");
        assert_eq!(
            (w[0].key.as_str(), w[0].line),
            ("panel[1].mass_kg", Some(line))
        );
        assert!(w[0].message.contains("grams"), "{}", w[0].message);
    }

    #[test]
    fn a_tolerance_below_one_per_cent_reads_as_a_fraction() {
        let w = percent_as_fraction("--spring-tolerance", 0.05).expect("0.05 %");
        assert!(
            w.contains("0.05 %") && w.contains("fraction") && w.contains("`--spring-tolerance 5`"),
            "{w}"
        );
        assert_eq!(percent_as_fraction("--spring-tolerance", 0.0), None);
        assert_eq!(percent_as_fraction("--spring-tolerance", 5.0), None);
    }

    #[test]
    fn a_rig_wire_in_millimetres_names_the_trolley_and_its_line() {
        let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("../data/mechanisms/seed001_T01_rig.toml");
        let text = std::fs::read_to_string(p).unwrap();
        let m = Mechanism::from_toml_str(&text, "rig").unwrap();
        assert_eq!(check(&m, Some(&text)), Vec::new());
        let text = text.replacen("wire_m = 1.5", "wire_m = 1500", 1);
        let line = 1 + text.lines().position(|l| l.contains("1500")).unwrap();
        let m = Mechanism::from_toml_str(&text, "rig").unwrap();
        let w = check(&m, Some(&text));
        assert_eq!(w.len(), 1, "{w:?}");
        assert_eq!(
            (w[0].key.as_str(), w[0].line),
            ("rig.trolley[1].wire_m", Some(line))
        );
        assert!(w[0].message.contains("millimetres"), "{}", w[0].message);
    }

    /// One 1 m panel of 2 kg stowed at 90 deg on `spring` (a TOML inline
    /// table).
    fn one_panel(spring: &str) -> String {
        format!("name = \"one\"\n[[panel]]\nlength_m = 1.0\nmass_kg = 2.0\ncom_m = 0.5\ninertia_kgm2 = 0.17\n[[joint]]\nstowed_deg = 90.0\nspring = {spring}\n[run]\nduration_s = 6.0\n")
    }

    /// The warnings about `joint[1].spring` of [`one_panel`] on `spring`.
    fn spring_warnings(spring: &str) -> Vec<Implausible> {
        let text = one_panel(spring);
        let m = Mechanism::from_toml_str(&text, "one").unwrap();
        let line = 1 + text.lines().position(|l| l.starts_with("spring")).unwrap();
        let w: Vec<_> = check(&m, Some(&text))
            .into_iter()
            .filter(|w| w.key == "joint[1].spring")
            .collect();
        assert!(w.iter().all(|w| w.line == Some(line)), "{w:?}");
        w
    }

    #[test]
    fn a_curve_spring_in_radians_names_its_line_and_the_same_in_degrees_does_not() {
        let rad = spring_warnings(
            "{ kind = \"curve\", unfold = [[0.0, 1.5], [0.7854, 1.2], [1.5708, 1.0]], count = 1 }",
        );
        assert_eq!(rad.len(), 1, "{rad:?}");
        assert!(
            rad[0].message.contains("radians") && rad[0].message.contains("90.0 deg"),
            "{}",
            rad[0].message
        );
        let deg = spring_warnings(
            "{ kind = \"curve\", unfold = [[0.0, 1.5], [45.0, 1.2], [90.0, 1.0]], count = 1 }",
        );
        assert_eq!(deg, Vec::new());
    }

    #[test]
    fn a_spring_that_gives_no_energy_is_told_it_cannot_deploy() {
        for spring in [
            "{ kind = \"linear\", preload_nm = 0.0, stiffness_nm_per_rad = 0.0, count = 1 }",
            "{ kind = \"curve\", unfold = [[0.0, 0.0], [90.0, 0.0]], count = 1 }",
        ] {
            let w = spring_warnings(spring);
            assert_eq!(w.len(), 1, "{spring}: {w:?}");
            assert!(w[0].message.contains("cannot deploy"), "{}", w[0].message);
        }
        assert_eq!(
            spring_warnings(
                "{ kind = \"linear\", preload_nm = 0.5, stiffness_nm_per_rad = 0.0, count = 1 }"
            ),
            Vec::new()
        );
    }
}
