//! `margin --from` and `reliability --from` use every effect a diagnosis
//! names, each from its 95 % interval (`docs/margin.md`, "Each effect at
//! the worst end of its interval"): for every kind of the effect
//! vocabulary (`EffectKind::EVERY`, so a kind added to it is covered here
//! without editing this file), a diagnosis JSON naming only that effect,
//! with an interval that is not symmetric about the estimate:
//!
//! - `margin --from` gives the margins of the end of the interval that
//!   lowers them: the same margins as a file giving that end as the
//!   estimate (no interval), and the lower of the two ends' (both ends are
//!   run here, so which end is worse is found, not listed; where the two
//!   ends move joints in opposite directions, as a global `rig_tilt` does,
//!   the end with the lowest margin of the wing); a kind that moves a
//!   margin moves none above the estimate's and some below;
//! - where the torque form is a hand calculation (`coulomb_friction`,
//!   `harness_stiffness`, `latch_detent`, `stribeck_friction`,
//!   `spring_softening`: the driving torque), the torque-form margin at
//!   joint 2 equals it at the end taken;
//! - `reliability --from` draws the effect from the normal law of its
//!   interval, `normal(estimate, (hi − lo) / (2 · 1.96))`; a
//!   `torque_table` (tables, not one value) is fixed in every deployment,
//!   each knot at the end of its band that resists, as `margin --from`
//!   takes it: the margin of the same draw is that of a file giving that
//!   end as the estimate, below the estimate's, below the run without the
//!   table, and the report lists it with its source
//!   ([`reliability_fixes_the_table`]).
//!
//!     cargo test -p deploywatch-sim --test margin_ends
mod common;

use common::{data, deploywatch, s, write};
use deploywatch_sim::effect::EffectKind;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// The wing a kind acts on: the rig's causes need a `[rig]`, the latch's a
/// physical latch, every other kind seed 001's T01.
fn wing_for(kind: EffectKind) -> PathBuf {
    let name = if kind.is_rig() {
        "seed001_T01_rig.toml"
    } else if EffectKind::LATCH.contains(&kind) {
        "seed001_T01_physical_latch.toml"
    } else {
        "seed001_T01.toml"
    };
    data().join("mechanisms").join(name)
}

/// The estimate of a kind and its interval `[lo, hi]`: the upper side
/// 2.5 times as wide as the lower, so either end is told from the other
/// and from the estimate.
fn estimate(kind: EffectKind) -> (f64, f64, f64) {
    let x = match kind {
        EffectKind::WireLength | EffectKind::FrameOffset => 0.005,
        EffectKind::EncoderOffset => 0.5,
        _ => 0.2,
    };
    (x, 0.8 * x, 1.5 * x)
}

/// Which end of the interval an entry gives as its value.
#[derive(Clone, Copy, Debug, PartialEq)]
enum At {
    /// The estimate with its interval.
    Interval,
    /// The estimate alone.
    Estimate,
    /// The lower end alone.
    Lo,
    /// The upper end alone.
    Hi,
}

/// The diagnosis entry of `kind` at joint 2 (or global), valued `at`.
fn entry(kind: EffectKind, at: At) -> Value {
    let (x, lo, hi) = estimate(kind);
    let pick = |v: [f64; 3]| match at {
        At::Interval | At::Estimate => v[0],
        At::Lo => v[1],
        At::Hi => v[2],
    };
    let joint = if kind.per_joint() {
        json!(2)
    } else {
        Value::Null
    };
    let mut e = json!({"name": kind.name(), "joint": joint, "value": pick([x, lo, hi]), "evidence": "test"});
    if kind == EffectKind::RigTilt {
        e["alpha_deg"] = json!(90.0);
    }
    if kind == EffectKind::StribeckFriction {
        e["excess_nm"] = json!(pick([0.1, 0.08, 0.15]));
        e["stribeck_rad_s"] = json!(0.05);
    }
    if kind == EffectKind::TorqueTable {
        // Joint 2 deploys from 180° to 0: each knot's band, lower and upper.
        let t = [[0.1, 0.3, 0.1], [0.08, 0.24, 0.08], [0.15, 0.45, 0.15]];
        let g = [[0.05, 0.0, -0.05], [0.04, 0.0, -0.06], [0.075, 0.0, -0.04]];
        e["angle_deg"] = json!([0.0, 90.0, 180.0]);
        e["torque_nm"] = json!(match at {
            At::Interval | At::Estimate => t[0],
            At::Lo => t[1],
            At::Hi => t[2],
        });
        e["rate_deg_s"] = json!([-100.0, 0.0, 100.0]);
        e["rate_torque_nm"] = json!(match at {
            At::Interval | At::Estimate => g[0],
            At::Lo => g[1],
            At::Hi => g[2],
        });
        if at == At::Interval {
            e["torque_ci95_nm"] = json!([t[1], t[2]]);
            e["rate_torque_ci95_nm"] = json!([g[1], g[2]]);
        }
    }
    if at == At::Interval {
        e["ci95"] = json!([lo, hi]);
        if kind == EffectKind::StribeckFriction {
            e["excess_ci95_nm"] = json!([0.08, 0.15]);
        }
    }
    e
}

/// A diagnosis file of `mech` naming `kind` alone, valued `at`.
fn diagnosis(dir: &Path, mech: &str, kind: EffectKind, at: At) -> PathBuf {
    let doc = json!({"mechanism": mech, "mechanisms": [mech], "effects": [entry(kind, at)]});
    write(
        dir,
        &format!("{}_{at:?}.json", kind.name()),
        serde_json::to_string_pretty(&doc).unwrap(),
    )
}

/// `margin --standard nasa-std-5017 --json` of `mech`, `--from file` if given.
fn margins(mech: &Path, from: Option<&Path>, dir: &Path) -> Value {
    let out = dir.join("m.json");
    let mut args = vec![
        "margin",
        "--quiet",
        "--mechanism",
        s(mech),
        "--standard",
        "nasa-std-5017",
        "--json",
        s(&out),
    ];
    if let Some(f) = from {
        args.extend(["--from", s(f)]);
    }
    let run = deploywatch(&args);
    assert!(
        run.status.success(),
        "margin {args:?}: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap()
}

/// Every joint's torque-form, energy-form and worst stroke margin [%]
/// (`null`, no resistance: `+∞`).
fn pcts(m: &Value) -> Vec<[f64; 3]> {
    let f = |v: &Value| v.as_f64().unwrap_or(f64::INFINITY);
    m["joints"]
        .as_array()
        .unwrap()
        .iter()
        .map(|j| {
            [
                f(&j["torque_margin_pct"]),
                f(&j["energy_margin_pct"]),
                f(&j["stroke"]["worst_margin_pct"]),
            ]
        })
        .collect()
}

/// The lowest margin of the wing [%].
fn lowest(m: &Value) -> f64 {
    pcts(m)
        .iter()
        .flatten()
        .copied()
        .fold(f64::INFINITY, f64::min)
}

/// True when `x` and `y` are the same margin [%] (to rounding).
fn close(x: f64, y: f64) -> bool {
    x == y || (x - y).abs() <= 1e-9 * x.abs().max(1.0)
}

/// Every margin of `a` against the same of `b`.
fn pairs(a: &Value, b: &Value) -> Vec<(f64, f64)> {
    pcts(a)
        .iter()
        .flatten()
        .copied()
        .zip(pcts(b).iter().flatten().copied())
        .collect()
}

/// Every margin of `a` equals `b`'s.
fn same(a: &Value, b: &Value) -> bool {
    pairs(a, b).iter().all(|(x, y)| close(*x, *y))
}

/// No margin of `a` above `b`'s.
fn no_higher(a: &Value, b: &Value) -> bool {
    pairs(a, b).iter().all(|(x, y)| *x <= *y || close(*x, *y))
}

/// The torque-form margin [%] at joint 2 by hand at the end taken (a
/// softening: the driving torque [N·m]; `hi`:
/// every kind with a hand form resists more, or drives less, when larger),
/// from the joint's driving torque `D` and friction `c0` without the
/// effect and NASA-STD-5017B's factor 3 on friction, harness and other;
/// `None` where the torque form needs the simulated deployment.
fn by_hand(kind: EffectKind, base: &Value) -> Option<f64> {
    let j = &base["joints"][1];
    let (d, c0) = (j["driving_torque_nm"].as_f64()?, j["coulomb_nm"].as_f64()?);
    let stroke = j["stowed_deg"].as_f64()?.abs().to_radians();
    let (_, _, hi) = estimate(kind);
    let pct = |d: f64, r: f64| (d / r - 1.0) * 100.0;
    match kind {
        EffectKind::CoulombFriction => Some(pct(d, 3.0 * (c0 + hi))),
        EffectKind::HarnessStiffness => Some(pct(d, 3.0 * c0 + 3.0 * hi * stroke)),
        EffectKind::LatchDetent => Some(pct(d, 3.0 * c0 + 3.0 * hi)),
        // Breakaway: the kinetic level plus the excess, each at its upper end.
        EffectKind::StribeckFriction => Some(pct(d, 3.0 * c0 + 3.0 * (hi + 0.15))),
        // Joint 2 has no friction of its own: the driving torque shows it.
        EffectKind::SpringSoftening => Some(d * (1.0 - hi)),
        _ => None,
    }
}

/// `margin --from` for one kind; `Err` says what is wrong.
fn margin_takes_the_worst_end(kind: EffectKind, dir: &Path) -> Result<(), String> {
    let mech = wing_for(kind);
    let name = match kind {
        k if k.is_rig() => "seed001-T01-rig",
        k if EffectKind::LATCH.contains(&k) => "seed001-T01-physical-latch",
        _ => "seed001-T01",
    };
    let run = |at| margins(&mech, Some(&diagnosis(dir, name, kind, at)), dir);
    let (taken, est, lo, hi) = (
        run(At::Interval),
        run(At::Estimate),
        run(At::Lo),
        run(At::Hi),
    );
    let base = margins(&mech, None, dir);
    // The end whose margins are nowhere higher; where the ends move joints
    // in opposite directions (a global rig tilt resists one joint and
    // drives another), the end with the lowest margin of the wing.
    let worse = match (no_higher(&hi, &lo), no_higher(&lo, &hi)) {
        (true, _) => &hi,
        (false, true) => &lo,
        (false, false) if lowest(&hi) <= lowest(&lo) => &hi,
        (false, false) => &lo,
    };
    if !same(&taken, worse) {
        return Err(format!(
            "the interval's margins {:?} are not those of its worse end {:?} (lo {:?}, hi {:?})",
            pcts(&taken),
            pcts(worse),
            pcts(&lo),
            pcts(&hi)
        ));
    }
    let moves = !same(&lo, &hi);
    let one_way = no_higher(&hi, &lo) || no_higher(&lo, &hi);
    let lowered = if one_way {
        !same(&taken, &est) && no_higher(&taken, &est)
    } else {
        lowest(&taken) < lowest(&est)
    };
    if moves && !lowered {
        return Err(format!(
            "the worst end does not lower the margin: {:?} vs estimate {:?}",
            pcts(&taken),
            pcts(&est)
        ));
    }
    if !no_higher(&est, &base) {
        return Err(format!(
            "an effect found raises a margin: {:?} vs {:?}",
            pcts(&est),
            pcts(&base)
        ));
    }
    if let Some(want) = by_hand(kind, &base) {
        let got = match kind {
            EffectKind::SpringSoftening => taken["joints"][1]["driving_torque_nm"]
                .as_f64()
                .unwrap_or(f64::NAN),
            _ => pcts(&taken)[1][0],
        };
        if !want.is_finite() || (got - want).abs() > 1e-6 * want.abs().max(1.0) {
            return Err(format!("torque form at joint 2: {got}, by hand {want}"));
        }
    }
    if taken["taken_at"].as_array().map_or(0, Vec::len) != 1 {
        return Err(format!("taken_at: {}", taken["taken_at"]));
    }
    Ok(())
}

/// The law `reliability --from` prints for the effect: `(mean, sd)`.
fn law(stdout: &str, kind: EffectKind) -> Option<(f64, f64)> {
    let line = stdout
        .lines()
        .find(|l| l.contains(kind.name()) && l.contains("normal("))?;
    let inside = line.split("normal(").nth(1)?.split(')').next()?;
    let mut nums = inside.split(',').map(|v| v.trim().parse::<f64>());
    Some((nums.next()?.ok()?, nums.next()?.ok()?))
}

/// `reliability --from` for one kind: its law from the interval, or a
/// refusal naming it (exit 2).
fn reliability_draws_it(kind: EffectKind, dir: &Path) -> Result<(), String> {
    if kind == EffectKind::TorqueTable {
        return reliability_fixes_the_table(dir);
    }
    let file = diagnosis(dir, "any", kind, At::Interval);
    let out = mc4(&wing_for(kind), &["--from", s(&file)])?;
    let (x, lo, hi) = estimate(kind);
    let (mean, sd) = law(&out, kind).ok_or(format!("no normal law of {kind} in:\n{out}"))?;
    let want_sd = (hi - lo) / (2.0 * 1.959_963_985);
    // The law is printed with 6 significant digits.
    if mean != x || (sd - want_sd).abs() > 1e-5 * want_sd {
        return Err(format!(
            "normal({mean},{sd}), expected normal({x},{want_sd})"
        ));
    }
    Ok(())
}

/// `deploywatch reliability MECH ARGS --fail not_latched --method mc
/// --samples 4 --quiet`: its stdout, or its stderr as the error.
fn mc4(mech: &Path, args: &[&str]) -> Result<String, String> {
    let mut all = vec!["reliability", s(mech)];
    all.extend(args);
    all.extend([
        "--fail",
        "not_latched",
        "--method",
        "mc",
        "--samples",
        "4",
        "--quiet",
    ]);
    let run = deploywatch(&all);
    if !run.status.success() {
        return Err(format!(
            "reliability {all:?}: {}",
            String::from_utf8_lossy(&run.stderr)
        ));
    }
    Ok(String::from_utf8_lossy(&run.stdout).into_owned())
}

/// `reliability` of the one-panel wing with `--from file` if given:
/// `time>0.01` and `not_latched`, so that every draw fails and the most
/// likely failure's margin is `0.01 − t_latch` \[s\] (one joint: its own
/// latch; on a chain a joint held back may let another latch earlier);
/// that margin, the JSON and stdout.
fn one_panel_reliability(from: Option<&Path>, dir: &Path) -> Result<(f64, Value, String), String> {
    let mech = data().join("mechanisms/reliability_one_panel.toml");
    let out = dir.join("r.json");
    let mut args = vec![
        "--vary",
        "spring_preload:joint=1:normal(1,0.01)",
        "--fail",
        "time>0.01",
        "--json",
        s(&out),
    ];
    if let Some(f) = from {
        args.extend(["--from", s(f)]);
    }
    let stdout = mc4(&mech, &args)?;
    let json: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let g = json["most_likely_failure"]["g"]
        .as_f64()
        .ok_or(format!("no most likely failure in {json}"))?;
    Ok((g, json, stdout))
}

/// `reliability --from` of a torque table on the one-panel wing (joint 1
/// deploys from 90° to 0, so the upper end of each band resists): fixed
/// in every deployment at its resisting end, as `margin --from` takes it.
/// The same seed draws the same points in every run, so the margins of
/// the most likely failure compare the same draw: with the interval it is
/// that of a file giving the resisting end as the estimate (the same
/// deployment, bit for bit), lower than with the estimate, lower than
/// without the table; the text and the JSON list the table with its
/// source.
fn reliability_fixes_the_table(dir: &Path) -> Result<(), String> {
    let kind = EffectKind::TorqueTable;
    let run = |at: At| {
        let mut e = entry(kind, at);
        e["joint"] = json!(1);
        let doc = json!({"mechanism": "reliability-one-panel", "effects": [e]});
        let file = write(dir, &format!("one_panel_{at:?}.json"), doc.to_string());
        one_panel_reliability(Some(&file), dir)
    };
    let (taken, est, hi) = (run(At::Interval)?, run(At::Estimate)?, run(At::Hi)?);
    let base = one_panel_reliability(None, dir)?;
    let fixed = |r: &(f64, Value, String)| r.1["fixed"].as_array().cloned().unwrap_or_default();
    if !fixed(&base).is_empty() || fixed(&taken).len() != 1 {
        return Err(format!(
            "fixed: {:?} without --from, {:?} with it",
            fixed(&base),
            fixed(&taken)
        ));
    }
    let (effect, source) = (&fixed(&taken)[0]["effect"], &fixed(&taken)[0]["source"]);
    if *effect != fixed(&hi)[0]["effect"] {
        return Err(format!(
            "the table taken {effect}, its resisting end {}",
            fixed(&hi)[0]["effect"]
        ));
    }
    let listed = effect.as_str().is_some_and(|e| {
        taken
            .2
            .lines()
            .any(|l| l.contains(e) && l.contains("fixed as found"))
    });
    if !listed || !source.as_str().is_some_and(|s| s.contains("upper end")) {
        return Err(format!("not listed with its source: {source}\n{}", taken.2));
    }
    let (g, g_est, g_hi, g_base) = (taken.0, est.0, hi.0, base.0);
    if g != g_hi || !(g < g_est && g_est < g_base) {
        return Err(format!(
            "margin of the most likely failure [s]: {g} with the interval, {g_hi} at its \
             resisting end, {g_est} at the estimate, {g_base} without the table"
        ));
    }
    Ok(())
}

/// Every kind of the vocabulary; every kind that fails is named before
/// the test fails.
#[test]
fn every_kind_counts_at_its_worst_end_and_is_drawn_from_its_interval() {
    let dir = tempfile::tempdir().unwrap();
    let mut failed = Vec::new();
    for kind in EffectKind::EVERY {
        if let Err(m) = margin_takes_the_worst_end(kind, dir.path()) {
            failed.push(format!("{kind}: margin --from: {m}"));
        }
        if let Err(m) = reliability_draws_it(kind, dir.path()) {
            failed.push(format!("{kind}: reliability --from: {m}"));
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

/// An identify JSON: each joint's friction at the upper end of its
/// interval.
#[test]
fn an_identified_friction_counts_at_the_upper_end() {
    let dir = tempfile::tempdir().unwrap();
    let mech = data().join("mechanisms/seed001_T01.toml");
    let id = json!({"method": "direct", "joints": [
        {"joint": 1, "coulomb_nm": 2.63, "ci95": [2.6, 2.7]},
        {"joint": 2, "coulomb_nm": 1.7, "ci95": null},
    ]});
    let file = write(dir.path(), "id.json", id.to_string());
    let base = margins(&mech, None, dir.path());
    let m = margins(&mech, Some(&file), dir.path());
    let c = |v: &Value, j: usize| v["joints"][j]["coulomb_nm"].as_f64().unwrap();
    assert_eq!(c(&m, 0), c(&base, 0) + 2.7, "joint 1: the upper end");
    assert_eq!(
        c(&m, 1),
        c(&base, 1) + 1.7,
        "joint 2: no interval, the estimate"
    );
    let taken = m["taken_at"].to_string();
    assert!(
        taken.contains("upper end") && taken.contains("its estimate"),
        "{taken}"
    );
}
