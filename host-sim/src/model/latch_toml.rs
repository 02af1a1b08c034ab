//! Reading and writing the `[joint.latch]` table of a mechanism file
//! (`docs/spec/formats.md`, "Physical latch", this project's extension):
//! the physical latch of one joint
//! ([`deploywatch_core::physics::latch_contact`]).
//!
//! ```toml
//! [[joint]]
//! stowed_deg = -90.0
//! spring = { kind = "tape", type = "TS-1", count = 3 }
//! [joint.latch]                      # this joint's latch; absent: the ideal latch
//! model = "physical"                 # or "ideal" (no other keys)
//! switch_travel_deg = 0.05           # the switch closes this far from the stop
//! stop = { radius_mm = 40.0 }        # optional: stiffness_n_per_mm1_5 (37000), damping_ns_per_mm1_25 (3.7)
//! magnet = { force_n = 15.0, decay_mm = 0.5, reach_mm = 2.0, radius_mm = 40.0 }   # optional
//! [joint.latch.plunger]              # or inline on one line: plunger = { ... }
//! preload_n = 20.0
//! stiffness_n_per_mm = 10.0
//! radius_mm = 40.0
//! stroke_mm = 0.8
//! crest_deg = 0.6
//! entry_ramp_deg = 30.0
//! hold_ramp_deg = 50.0
//! ```
//!
//! A positive lock has a `pawl` table in place of `plunger` (`physics.md`
//! §10.5):
//!
//! ```toml
//! pawl = { preload_n = 5.0, stiffness_n_per_mm = 2.0, radius_mm = 40.0, lift_mm = 1.0, notch_deg = 0.2, cam_ramp_deg = 20.0, breaking_torque_nm = 250.0 }
//! ```
//!
//! Read on the mechanism file's one TOML tree ([`crate::model::toml_tree`]):
//! errors name the file, the line, the key path
//! (`joint[1].latch.plunger.preload_n`) and what was expected.

use std::fmt::Write as _;

use crate::model::latch::{
    LatchSpec, MagnetSpec, PlungerSpec, StopSpec, PAPER_DAMPING_NS_PER_MM1_25,
    PAPER_STIFFNESS_N_PER_MM1_5,
};
use crate::model::mechanism_error::MechanismErrorKind;
use crate::model::toml_tree::{join, Bound, Cx, Node, Res, Sp, Table};
use deploywatch_core::physics::latch_contact::Pawl;

const LATCH_KEYS: &[&str] = &[
    "model",
    "switch_travel_deg",
    "stop",
    "plunger",
    "pawl",
    "magnet",
];
const STOP_KEYS: &[&str] = &[
    "radius_mm",
    "stiffness_n_per_mm1_5",
    "damping_ns_per_mm1_25",
];
const PLUNGER_KEYS: &[&str] = &[
    "preload_n",
    "stiffness_n_per_mm",
    "radius_mm",
    "stroke_mm",
    "crest_deg",
    "entry_ramp_deg",
    "hold_ramp_deg",
];
const PAWL_KEYS: &[&str] = &[
    "preload_n",
    "stiffness_n_per_mm",
    "radius_mm",
    "lift_mm",
    "notch_deg",
    "cam_ramp_deg",
    "breaking_torque_nm",
];
const MAGNET_KEYS: &[&str] = &["force_n", "decay_mm", "reach_mm", "radius_mm"];

/// A ramp steeper than this \[deg\] would not be a ramp.
const RIGHT_ANGLE_DEG: f64 = 90.0;

/// The `[joint.latch]` of one `[[joint]]`, read on the mechanism file's tree
/// by [`crate::model::mechanism_toml`] (`None`: absent or `model =
/// "ideal"`, the ideal latch), for a joint stowed at `stowed_deg`: every
/// mark where it engages (its switch, crest, entry ramp, the magnet's
/// reach) within the stroke `|stowed_deg|`, or it would engage stowed.
/// Errors name the key path (`joint[1].latch.plunger.preload_n`), the line
/// and what was expected; a key of the joint (one of `joint_keys`) in the
/// latch table is told it is written below the `[joint.latch]` line.
pub(crate) fn read(
    cx: &Cx<'_>,
    sp: &Sp,
    path: &str,
    stowed_deg: f64,
    joint_keys: &[&str],
) -> Res<Option<LatchSpec>> {
    joint_key_in_latch(cx, sp, path, joint_keys)?;
    let t = cx.table(sp, path, LATCH_KEYS)?;
    let expected = "\"physical\" or \"ideal\"";
    let Some(model) = t.get("model") else {
        return Err(cx.missing(&t, "model", expected));
    };
    match cx.string(model, &t.key("model"))? {
        "ideal" if t.entries.len() == 1 => return Ok(None),
        "ideal" => {
            // The first key beside `model`, named: an ideal latch has no
            // other.
            let (key, sp) = t
                .entries
                .iter()
                .find(|(k, _)| k != "model")
                .map_or(("model", model), |(k, sp)| (k.as_str(), sp));
            let expected =
                "no other latch key with model = \"ideal\" (the keys of a physical latch \
                            want model = \"physical\")";
            return Err(cx.invalid(sp, &t.key(key), expected));
        }
        "physical" => {}
        _ => return Err(cx.invalid(model, &t.key("model"), expected)),
    }
    let (plunger, pawl) = detent_spec(cx, &t)?;
    let spec = LatchSpec {
        switch_travel_deg: cx.req_number(&t, "switch_travel_deg", Bound::NonNegative, "deg")?,
        stop: stop_spec(cx, &t)?,
        plunger,
        pawl,
        magnet: t
            .get("magnet")
            .map(|m| magnet_spec(cx, m, &t.key("magnet")))
            .transpose()?,
    };
    spec.to_core::<f64>(1.0, 1.0, 1.0)
        .check()
        .map_err(|why| cx.invalid(sp, path, &format!("a physical latch: {why}")))?;
    within_stroke(cx, sp, path, &spec, stowed_deg)?;
    Ok(Some(spec))
}

/// A key of the joint (one of `joint_keys`: `friction`, `free_play_deg`)
/// in the latch table `sp`: written below the `[joint.latch]` line, where
/// TOML gives every key up to the next header to the latch; refused with
/// that said.
fn joint_key_in_latch(cx: &Cx<'_>, sp: &Sp, path: &str, joint_keys: &[&str]) -> Res<()> {
    let Node::Table(entries) = &sp.node else {
        return Ok(());
    };
    let misplaced = entries
        .iter()
        .find(|(k, _)| !LATCH_KEYS.contains(&k.as_str()) && joint_keys.contains(&k.as_str()));
    match misplaced {
        Some((name, v)) => Err(cx.err(
            cx.first_line(v).or_else(|| cx.line(sp)),
            MechanismErrorKind::JointKeyInLatch {
                key: join(path, name),
                name: name.clone(),
                expected: LATCH_KEYS.join(", "),
            },
        )),
        None => Ok(()),
    }
}

/// Every mark where the latch engages lies within the stroke.
fn within_stroke(cx: &Cx<'_>, sp: &Sp, path: &str, spec: &LatchSpec, stowed_deg: f64) -> Res<()> {
    use deploywatch_core::physics::latch_contact::LatchMark;
    for (mark, u) in spec.to_core::<f64>(stowed_deg, 1.0, 1.0).marks() {
        let what = match mark {
            LatchMark::Crest => "its crest (plunger crest_deg, pawl notch_deg)",
            LatchMark::EntryRamp => "its entry ramp's start (the crest plus the ramp)",
            LatchMark::MagnetReach => "its magnet's reach (reach_mm at radius_mm)",
            LatchMark::Switch => "its switch (switch_travel_deg)",
            LatchMark::Stop | LatchMark::HoldRampEnd => continue,
        };
        if !(u.to_degrees() < stowed_deg.abs()) {
            let mut expected = format!(
                "a latch that engages within the joint's stroke of {} deg (stowed_deg): {what} \
                 lies {:.2} deg from the stop, where the panel is still stowed",
                stowed_deg.abs(),
                u.to_degrees()
            );
            if let Some(hint) = crate::model::plausibility::stowed_in_radians(stowed_deg) {
                expected = format!("{expected} (stowed_deg: {hint})");
            }
            return Err(cx.invalid(sp, path, &expected));
        }
    }
    Ok(())
}

/// `stop = { radius_mm = ... }` of the latch table `latch`.
fn stop_spec(cx: &Cx<'_>, latch: &Table<'_>) -> Res<StopSpec> {
    let Some(sp) = latch.get("stop") else {
        return Err(cx.missing(latch, "stop", "a table { radius_mm = ... }"));
    };
    let t = cx.table(sp, &latch.key("stop"), STOP_KEYS)?;
    let k = cx.opt_number(&t, "stiffness_n_per_mm1_5", Bound::NonNegative, "N/mm^1.5")?;
    let c = cx.opt_number(
        &t,
        "damping_ns_per_mm1_25",
        Bound::NonNegative,
        "N·s/mm^1.25",
    )?;
    Ok(StopSpec {
        radius_mm: cx.req_number(&t, "radius_mm", Bound::Positive, "mm")?,
        stiffness_n_per_mm1_5: k.unwrap_or(PAPER_STIFFNESS_N_PER_MM1_5),
        damping_ns_per_mm1_25: c.unwrap_or(PAPER_DAMPING_NS_PER_MM1_25),
    })
}

/// The latch's `plunger` or its `pawl` (exactly one of them): the plunger
/// (for a pawl, its spring on its cam) and the pawl's breaking torque.
fn detent_spec(cx: &Cx<'_>, latch: &Table<'_>) -> Res<(PlungerSpec, Option<Pawl<f64>>)> {
    match (latch.get("plunger"), latch.get("pawl")) {
        (Some(sp), None) => Ok((plunger_spec(cx, sp, &latch.key("plunger"))?, None)),
        (None, Some(sp)) => pawl_spec(cx, sp, &latch.key("pawl")).map(|(p, b)| (p, Some(b))),
        (Some(_), Some(sp)) => {
            Err(cx.invalid(sp, &latch.key("pawl"), "a plunger or a pawl, not both"))
        }
        (None, None) => Err(cx.missing(
            latch,
            "plunger",
            "a table { preload_n = ..., ... } (or a `pawl` table)",
        )),
    }
}

/// `pawl = { preload_n = ..., ... }` at `path`: the pawl's spring on its
/// cam as the core's plunger, and its breaking torque.
fn pawl_spec(cx: &Cx<'_>, sp: &Sp, path: &str) -> Res<(PlungerSpec, Pawl<f64>)> {
    let t = cx.table(sp, path, PAWL_KEYS)?;
    let n = |key: &str, range: Bound, unit: &str| cx.req_number(&t, key, range, unit);
    let cam = ramp(cx, &t, "cam_ramp_deg")?;
    let spring = PlungerSpec {
        preload_n: n("preload_n", Bound::NonNegative, "N")?,
        stiffness_n_per_mm: n("stiffness_n_per_mm", Bound::NonNegative, "N/mm")?,
        radius_mm: n("radius_mm", Bound::Positive, "mm")?,
        stroke_mm: n("lift_mm", Bound::NonNegative, "mm")?,
        crest_deg: n("notch_deg", Bound::NonNegative, "deg")?,
        entry_ramp_deg: cam,
        hold_ramp_deg: cam,
    };
    let breaking_torque_nm = n("breaking_torque_nm", Bound::Positive, "N·m")?;
    Ok((spring, Pawl { breaking_torque_nm }))
}

/// `plunger = { preload_n = ..., ... }` at `path`.
fn plunger_spec(cx: &Cx<'_>, sp: &Sp, path: &str) -> Res<PlungerSpec> {
    let t = cx.table(sp, path, PLUNGER_KEYS)?;
    let n = |key: &str, range: Bound, unit: &str| cx.req_number(&t, key, range, unit);
    Ok(PlungerSpec {
        preload_n: n("preload_n", Bound::NonNegative, "N")?,
        stiffness_n_per_mm: n("stiffness_n_per_mm", Bound::NonNegative, "N/mm")?,
        radius_mm: n("radius_mm", Bound::Positive, "mm")?,
        stroke_mm: n("stroke_mm", Bound::NonNegative, "mm")?,
        crest_deg: n("crest_deg", Bound::NonNegative, "deg")?,
        entry_ramp_deg: ramp(cx, &t, "entry_ramp_deg")?,
        hold_ramp_deg: ramp(cx, &t, "hold_ramp_deg")?,
    })
}

/// A ramp angle of the plunger (or pawl) table `t`: within (0, 90) degrees.
fn ramp(cx: &Cx<'_>, t: &Table<'_>, key: &str) -> Res<f64> {
    const EXPECTED: &str = "an angle in (0, 90) [deg]";
    let x = cx.req_number(t, key, Bound::Positive, "deg")?;
    match t.get(key) {
        Some(sp) if x >= RIGHT_ANGLE_DEG => Err(cx.invalid(sp, &t.key(key), EXPECTED)),
        _ => Ok(x),
    }
}

/// `magnet = { force_n = ..., ... }` at `path`.
fn magnet_spec(cx: &Cx<'_>, sp: &Sp, path: &str) -> Res<MagnetSpec> {
    let t = cx.table(sp, path, MAGNET_KEYS)?;
    let n = |key: &str, range: Bound, unit: &str| cx.req_number(&t, key, range, unit);
    Ok(MagnetSpec {
        force_n: n("force_n", Bound::NonNegative, "N")?,
        decay_mm: n("decay_mm", Bound::Positive, "mm")?,
        reach_mm: n("reach_mm", Bound::NonNegative, "mm")?,
        radius_mm: n("radius_mm", Bound::Positive, "mm")?,
    })
}

/// The `[joint.latch]` table of `spec`, written after its `[[joint]]`
/// (what [`read`] reads back as the same spec).
pub fn write(spec: &LatchSpec) -> String {
    let (s, p) = (&spec.stop, &spec.plunger);
    let mut out = format!(
        "[joint.latch]\nmodel = \"physical\"\nswitch_travel_deg = {:?}\n",
        spec.switch_travel_deg
    );
    inline_table(
        &mut out,
        "stop",
        &[
            ("radius_mm", s.radius_mm),
            ("stiffness_n_per_mm1_5", s.stiffness_n_per_mm1_5),
            ("damping_ns_per_mm1_25", s.damping_ns_per_mm1_25),
        ],
    );
    // A pawl is the plunger's geometry under the pawl's names (lift,
    // notch, cam ramp) and its breaking torque in place of the hold ramp.
    let (key, names, last) = match &spec.pawl {
        Some(pawl) => (
            "pawl",
            ["lift_mm", "notch_deg", "cam_ramp_deg"],
            ("breaking_torque_nm", pawl.breaking_torque_nm),
        ),
        None => (
            "plunger",
            ["stroke_mm", "crest_deg", "entry_ramp_deg"],
            ("hold_ramp_deg", p.hold_ramp_deg),
        ),
    };
    inline_table(
        &mut out,
        key,
        &[
            ("preload_n", p.preload_n),
            ("stiffness_n_per_mm", p.stiffness_n_per_mm),
            ("radius_mm", p.radius_mm),
            (names[0], p.stroke_mm),
            (names[1], p.crest_deg),
            (names[2], p.entry_ramp_deg),
            last,
        ],
    );
    if let Some(m) = &spec.magnet {
        inline_table(
            &mut out,
            "magnet",
            &[
                ("force_n", m.force_n),
                ("decay_mm", m.decay_mm),
                ("reach_mm", m.reach_mm),
                ("radius_mm", m.radius_mm),
            ],
        );
    }
    out
}

/// `key = { name = value, ... }` and a newline, each value written so that
/// it reads back to the same `f64` (`{:?}`).
fn inline_table(out: &mut String, key: &str, fields: &[(&str, f64)]) {
    let body: Vec<String> = fields.iter().map(|(k, v)| format!("{k} = {v:?}")).collect();
    let _ = writeln!(out, "{key} = {{ {} }}", body.join(", "));
}
