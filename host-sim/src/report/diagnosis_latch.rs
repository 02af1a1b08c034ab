//! The parts of the diagnosis JSON, report and summary that runs of a
//! physical latch, sets of causes the runs cannot tell apart and a search
//! stopped early add (`docs/diagnosis.md`, "Runs of a physical
//! latch", "Ambiguity", "Long searches").

use crate::analysis::diagnose::latch_finding::{
    LatchCause, LatchDifference, LatchFinding, LatchParts, Side,
};
use crate::analysis::diagnose::latch_window::RunWindow;
use crate::analysis::diagnose::whole_run::{self, WholeRun};
use crate::analysis::diagnose::SeparatingTest;
use crate::analysis::diagnose::{FittedSet, Outcome};
use crate::analysis::latch_events::LatchEvents;
use crate::data::campaign::Campaign;
use crate::model::findings::diagnosis::{
    AmbiguityGroup, AmbiguousSet, FreeWindow, LatchEventsJson, LatchReport, WholeRunJoint,
    WholeRunJson,
};
use crate::model::findings::rounded;
use crate::report::diagnosis_outcome::{alike_words, values_words};
use crate::report::markdown::table;
use std::fmt::Write as _;

/// A window of each run (the free motion's or the one fitted), for the
/// JSON.
pub fn windows_json(c: &Campaign, ws: Option<&[RunWindow]>) -> Vec<FreeWindow> {
    let Some(ws) = ws else {
        return Vec::new();
    };
    c.runs
        .iter()
        .zip(ws)
        .map(|(cr, w)| FreeWindow {
            run: cr.name(),
            samples: w.kept,
            of: w.of,
            end_s: w.end_s.and_then(rounded),
            joint: w.joint,
        })
        .collect()
}

/// The whole-run check, for the JSON.
pub fn whole_run_json(o: &Outcome) -> Option<WholeRunJson> {
    let w = o.whole_run.as_ref()?;
    Some(WholeRunJson {
        shots: w.shots.len(),
        shot_s: rounded(w.shot_seconds()),
        joints: w
            .joints
            .iter()
            .map(|j| WholeRunJoint {
                joint: j.joint,
                free_rms_deg: rounded(j.free_rms_deg),
                after_rms_deg: j.after_rms_deg.and_then(rounded),
                after_samples: j.after_samples,
            })
            .collect(),
    })
}

fn events_json(e: &LatchEvents) -> LatchEventsJson {
    LatchEventsJson {
        first_contact_s: e.first_contact_s.and_then(rounded),
        impacts: e.impacts,
        escapes: e.escapes,
        largest_rebound_deg: rounded(e.largest_rebound_deg()),
        hold_s: e.hold_s.and_then(rounded),
        end_travel_deg: rounded(e.end_travel_deg),
    }
}

/// The latch findings, for the JSON.
pub fn latches_json(o: &Outcome) -> Vec<LatchReport> {
    o.latches
        .iter()
        .map(|f| LatchReport {
            joint: f.joint,
            measured: f.measured.iter().map(events_json).collect(),
            drawing: f
                .drawing
                .iter()
                .map(|e| e.as_ref().map(events_json))
                .collect(),
            drawing_spread: serde_json::json!({
                "impacts": f.spread.impacts,
                "escapes": f.spread.escapes,
                "runs_ending_within_crest": f.spread.held,
                "restitution": f.spread.restitution.map(|r| r.map(rounded)),
                "hold_deceleration_deg_s2": f.spread.hold_accel.map(|r| r.map(rounded)),
            }),
            restitution: f
                .restitution
                .map(|r| [rounded(r.median), rounded(r.ci95[0]), rounded(r.ci95[1])]),
            hold_deceleration_deg_s2: f
                .hold_accel
                .map(|r| [rounded(r.median), rounded(r.ci95[0]), rounded(r.ci95[1])]),
            differs: f.differs.iter().map(difference_words).collect(),
            undecided: f.undecided.iter().map(difference_words).collect(),
            cause: f.cause.map(|c| cause_words(c, f.parts)),
            plunger_weakening: f.weakening.map(|w| w.map(rounded)),
        })
        .collect()
}

/// A fitted set's effects as JSON objects.
fn set_json(f: &FittedSet) -> Vec<serde_json::Value> {
    f.effects()
        .iter()
        .enumerate()
        .map(|(k, e)| {
            let ([lo, hi], _) = f.effect_ci(k);
            serde_json::json!({
                "name": e.kind().name(),
                "joint": e.joint,
                "value": rounded(e.value()),
                "ci95": [rounded(lo), rounded(hi)],
            })
        })
        .collect()
}

/// The ambiguity groups, for the JSON.
pub fn ambiguities_json(o: &Outcome) -> Vec<AmbiguityGroup> {
    o.ambiguities
        .iter()
        .map(|g| {
            let first = g.sets.first().map_or(0.0, FittedSet::bic);
            AmbiguityGroup {
                joint: g.joint,
                sets: g
                    .sets
                    .iter()
                    .map(|s| AmbiguousSet {
                        effects: set_json(s),
                        rms_deg: rounded(s.rms()),
                        delta_bic: rounded(s.bic() - first),
                    })
                    .collect(),
                separating_test: separating_test_words(g.separating_test, g.joint),
            }
        })
        .collect()
}

/// The summary lines `diagnose` prints for these findings.
pub fn summary_lines(o: &Outcome) -> Vec<String> {
    let mut out = Vec::new();
    if let Some(p) = &o.partial {
        out.push(format!(
            "PARTIAL: {p}; the effects are the best model found so far"
        ));
    }
    for g in &o.ambiguities {
        out.push(format!(
            "ambiguity at joint {}: {} sets explain the runs alike; {}",
            g.joint,
            g.sets.len(),
            separating_test_words(g.separating_test, g.joint)
        ));
        for s in &g.sets {
            out.push(format!("    {} (RMS {:.4} deg)", values_words(s), s.rms()));
        }
    }
    if o.fitted_whole {
        out.push(WHOLE_LINE.to_owned());
    }
    if o.fitted_to.is_some() {
        out.push(HORIZON_LINE.to_owned());
    }
    for f in &o.latches {
        out.push(latch_line(f));
    }
    out
}

/// The summary line of runs of a physical latch fitted whole.
const WHOLE_LINE: &str =
    "fitted on the whole runs: the model found closes each latch switch as often as every run does";

/// The summary line of runs of a physical latch fitted up to where the
/// model follows them.
const HORIZON_LINE: &str = "fitted up to where the model follows the runs: each run beyond its free motion, up to where a latch switch or the integration's tolerance parts the model found from it";

/// What the effects of runs of a physical latch were fitted on, in words.
fn fitted_on_words(o: &Outcome) -> &'static str {
    if o.fitted_whole {
        "The model found, simulated from the release, closes each latch switch exactly as often as every run does: it follows the runs' impact sequence, so the effects were fitted on the whole runs (the free motion, up to the first instant a joint enters its latch's reach, is given below). The latch events are also compared by their statistics with what the drawing's latch gives within its tolerances."
    } else if o.fitted_to.is_some() {
        "The model found, simulated from the release, follows each run's impact sequence beyond its free motion: its latch switches change state as the run's do (within 0.05 s) and a tenth of the integration's tolerance moves it by less than half the noise, up to the instant given below for each run. The effects were fitted on each run up to there; after it a rebound more or less, or the integration's tolerance, parts model and run, and the latch events are compared by their statistics with what the drawing's latch gives within its tolerances."
    } else {
        "The impact sequence at a physical latch (rebounds, escapes over the plunger, re-latches) is chaotic: it is not compared sample by sample. The effects were fitted on each run's free motion, up to the first instant a joint enters its latch's reach; the latch events are compared by their statistics with what the drawing's latch gives within its tolerances."
    }
}

/// Where run `run` was fitted to when it was fitted up to where the model
/// follows it, in words.
fn fitted_to_words(run: &str, w: &RunWindow) -> String {
    match (w.end_s, w.joint) {
        (Some(t), Some(j)) => format!(
            "- {run}: fitted to {t:.2} s ({} of {} samples), where the model parts from it at joint {j}",
            w.kept, w.of
        ),
        _ => format!("- {run}: fitted whole (the model follows it to its end)"),
    }
}

fn latch_line(f: &LatchFinding) -> String {
    let esc: usize = f.measured.iter().map(|e| e.escapes).sum();
    let imp: usize = f.measured.iter().map(|e| e.impacts).sum();
    let mut s = format!(
        "latch at joint {}: {imp} impact(s), {esc} escape(s) over {} run(s)",
        f.joint,
        f.measured.len()
    );
    if f.differs.is_empty() && !f.undecided.is_empty() {
        let _ = write!(s, "; {}", undecided_words(f));
    } else if f.differs.is_empty() {
        s += "; as the drawing's latch gives within its tolerances";
    } else {
        let _ = write!(s, "; differs from the drawing: {}", differences_words(f));
    }
    if let Some(w) = f.weakening {
        let _ = write!(s, "; {}", weakening_words(w));
    }
    s
}

/// The whole-run check in the report: the stretches after the free
/// windows shot from the measured state, and each joint's residual there
/// beside its free window's.
fn report_whole_run(md: &mut String, w: &WholeRun) {
    if w.shots.is_empty() {
        let _ = writeln!(
            md,
            "Over the whole runs: after the free windows no stretch of {} samples or more is clear of a latch's contact transient (a joint within its latch's reach whose switch has not been closed for {:.1} s): the motion after the first contact is not compared with the model.\n",
            whole_run::MIN_SHOT_SAMPLES,
            whole_run::HELD_S
        );
        return;
    }
    let _ = writeln!(
        md,
        "Over the whole runs: after each free window, {} stretches ({:.1} s) where no joint is in a latch's contact were simulated from the measured state at their start (each at most {:.1} s, its start's angles and rates fitted). Residual RMS per joint, over the free windows and over those stretches where the joint swings clear of its latch (noise floor {:.4} deg):\n",
        w.shots.len(),
        w.shot_seconds(),
        whole_run::SHOT_S,
        w.noise_sigma_deg
    );
    let rows: Vec<Vec<String>> = w
        .joints
        .iter()
        .map(|j| {
            vec![
                j.joint.to_string(),
                format!("{:.4}", j.free_rms_deg),
                j.after_rms_deg
                    .map_or_else(|| "too few samples".to_string(), |r| format!("{r:.4}")),
                j.after_samples.to_string(),
            ]
        })
        .collect();
    md.push_str(&table(
        &[
            "joint",
            "free window [deg]",
            "after the first contact [deg]",
            "samples after",
        ],
        &rows,
    ));
    let _ = writeln!(md);
    shots_table(md, w);
    match w.missed() {
        Some(m) => {
            let _ = writeln!(
                md,
                "**The model found does not follow joint {} after the first contact** ({:.4} deg RMS, more than {} times the noise floor). Either something acts there that the free windows do not show, or the latches as built move the wing otherwise than the drawing's between contacts (a rattle or an escape the shots start beside); these runs do not tell which, and the diagnosis names no cause for it. Runs with the latches held (or of ideal latches) would.\n",
                m.joint,
                m.after_rms_deg.unwrap_or(0.0),
                whole_run::AFTER_CONTACT_FACTOR
            );
        }
        None => {
            let _ = writeln!(
                md,
                "The model found holds after the first contact too (every joint within {} times the noise floor).\n",
                whole_run::AFTER_CONTACT_FACTOR
            );
        }
    }
}

/// The whole-run check's shots: per shot, each joint's residual RMS where
/// it is clear of its latch.
fn shots_table(md: &mut String, w: &WholeRun) {
    let shots: Vec<Vec<String>> = w
        .shots
        .iter()
        .map(|s| {
            let mut row = vec![
                format!("{}", s.run + 1),
                format!("{:.2}", s.start_s),
                format!("{:.2}", s.length_s),
            ];
            row.extend(
                s.rms_deg
                    .iter()
                    .map(|r| r.map_or_else(|| "in its latch".to_string(), |r| format!("{r:.4}"))),
            );
            row
        })
        .collect();
    let joints: Vec<String> = (1..=w.joints.len())
        .map(|j| format!("joint {j} [deg]"))
        .collect();
    let mut head = vec!["run", "start [s]", "length [s]"];
    head.extend(joints.iter().map(String::as_str));
    let _ = writeln!(
        md,
        "The shots, each joint's residual RMS where it is clear of its latch:\n"
    );
    md.push_str(&table(&head, &shots));
    let _ = writeln!(md);
}

/// The report's sections for these findings: a search stopped early, the
/// free window, each latch as built, the ambiguity groups.
pub fn report(md: &mut String, c: &Campaign, o: &Outcome) {
    if let Some(p) = &o.partial {
        let _ = writeln!(
            md,
            "**Partial result: {p}.** The effects below are the best model found so far, not the end of the search.\n"
        );
    }
    if let Some(ws) = &o.free_window {
        let _ = writeln!(md, "## Runs of a physical latch\n");
        let _ = writeln!(md, "{}\n", fitted_on_words(o));
        for (cr, w) in c.runs.iter().zip(ws) {
            let _ = match (w.end_s, w.joint) {
                (Some(t), Some(j)) => writeln!(
                    md,
                    "- {}: free motion {} {t:.2} s ({} of {} samples), where joint {j} enters its latch's reach",
                    cr.name(),
                    if o.fitted_whole || o.fitted_to.is_some() { "to" } else { "fitted to" },
                    w.kept,
                    w.of
                ),
                _ => writeln!(md, "- {}: no joint reaches its latch; fitted whole", cr.name()),
            };
        }
        for (cr, w) in c.runs.iter().zip(o.fitted_to.iter().flatten()) {
            let _ = writeln!(md, "{}", fitted_to_words(&cr.name(), w));
        }
        let _ = writeln!(md);
        if let Some(w) = &o.whole_run {
            report_whole_run(md, w);
        }
        for f in &o.latches {
            report_latch(md, c, f);
        }
    }
    report_ambiguity(md, o);
}

/// The plunger weakenings consistent with the measured events, in words.
fn weakening_words([lo, hi]: [f64; 2]) -> String {
    let tried = &crate::analysis::diagnose::latch_finding::WEAKENINGS;
    let (first, last) = (tried[0], tried[tried.len() - 1]);
    if lo <= first && hi >= last {
        format!("the runs do not determine how much: every plunger weakening tried ({first:.1} to {last:.1}) gives the measured events")
    } else {
        format!("a plunger weakening of {lo:.1} .. {hi:.1} (of {first:.1} to {last:.1} in steps of 0.1 tried) gives the measured events (escapes, runs ending within the crest, hold deceleration)")
    }
}

fn report_latch(md: &mut String, c: &Campaign, f: &LatchFinding) {
    let _ = writeln!(md, "### Latch at joint {}\n", f.joint);
    for (cr, e) in c.runs.iter().zip(&f.measured) {
        let _ = writeln!(md, "- {}: {}", cr.name(), events_words(e));
    }
    let sp = &f.spread;
    let _ = writeln!(
        md,
        "- the drawing's latch within its tolerances, with the effects found: {}..{} impacts, {}..{} escapes, ends within the crest in {}..{} run(s){}{}",
        sp.impacts[0],
        sp.impacts[1],
        sp.escapes[0],
        sp.escapes[1],
        sp.held[0],
        sp.held[1],
        sp.restitution
            .map(|[a, b]| format!(", apparent restitution {a:.2}..{b:.2}"))
            .unwrap_or_default(),
        sp.hold_accel
            .map(|[a, b]| format!(
                ", rebounds that stayed in decelerating at {a:.0}..{b:.0} deg/s²"
            ))
            .unwrap_or_default()
    );
    if let Some(r) = f.restitution {
        let _ = writeln!(
            md,
            "- measured apparent restitution {:.2} (95 % CI {:.2} .. {:.2}, {} impacts)",
            r.median, r.ci95[0], r.ci95[1], r.impacts
        );
    }
    if let Some(a) = f.hold_accel {
        let _ = writeln!(
            md,
            "- measured deceleration of the rebounds that stayed in {:.0} deg/s² (95 % CI {:.0} .. {:.0}, {} rebounds of {} samples or more)",
            a.median, a.ci95[0], a.ci95[1], a.impacts, crate::analysis::latch_events::MIN_FLIGHT_SAMPLES
        );
    }
    if f.differs.is_empty() && !f.undecided.is_empty() {
        let _ = writeln!(md, "\n{}.\n", capitalised(&undecided_words(f)));
        return;
    }
    if f.differs.is_empty() {
        let _ = writeln!(
            md,
            "\nThe events are what the drawing's latch gives within its tolerances: no finding.\n"
        );
        return;
    }
    let _ = writeln!(
        md,
        "\n**The latch as built differs from its drawing:** {}.",
        differences_words(f)
    );
    if let Some(cause) = f.cause {
        let _ = writeln!(md, "{}.", cause_words(cause, f.parts));
    }
    if let Some(w) = f.weakening {
        let _ = writeln!(md, "{}.", weakening_words(w));
    }
    let _ = writeln!(md);
}

fn report_ambiguity(md: &mut String, o: &Outcome) {
    if o.ambiguities.is_empty() {
        return;
    }
    let _ = writeln!(md, "## Ambiguity: the runs cannot decide\n");
    for g in &o.ambiguities {
        let _ = writeln!(
            md,
            "At joint {} these sets explain the runs alike ({}); the intervals above are widened to cover them. {}.\n",
            g.joint,
            alike_words(g),
            capitalised(&separating_test_words(g.separating_test, g.joint))
        );
        let first = g.sets.first().map_or(0.0, FittedSet::bic);
        md.push_str(&table(
            &["set", "RMS [deg]", "ΔBIC"],
            g.sets.iter().map(|s| {
                vec![
                    values_words(s),
                    format!("{:.4}", s.rms()),
                    format!("{:+.1}", s.bic() - first),
                ]
            }),
        ));
        let _ = writeln!(md);
    }
}

/// What differs from the drawing's latch, one phrase per difference joined
/// by `; `.
pub fn differences_words(f: &LatchFinding) -> String {
    f.differs
        .iter()
        .map(difference_words)
        .collect::<Vec<_>>()
        .join("; ")
}

/// Statistics outside the printed spread that the runs cannot decide, in
/// words (without the final full stop).
fn undecided_words(f: &LatchFinding) -> String {
    let runs = f.measured.len();
    format!(
        "outside the drawing's spread but within a reading's margin over {runs} run(s): {}; these runs cannot tell this latch from the drawing's within its tolerances (more runs of the wing would)",
        f.undecided
            .iter()
            .map(difference_words)
            .collect::<Vec<_>>()
            .join("; ")
    )
}

/// `s` with its first letter in upper case.
fn capitalised(s: &str) -> String {
    let mut c = s.chars();
    c.next()
        .map(|first| first.to_uppercase().chain(c).collect())
        .unwrap_or_default()
}

/// One difference from the drawing's latch in words.
pub fn difference_words(d: &LatchDifference) -> String {
    match d {
        LatchDifference::Escapes { measured, drawing } => format!(
            "{measured} escape(s) over the plunger in the runs, {}..{} with the drawing's latch within its tolerances",
            drawing[0], drawing[1]
        ),
        LatchDifference::EndsHeld {
            measured,
            runs,
            drawing,
        } => format!(
            "ends within the crest in {measured} of {runs} run(s), {}..{} with the drawing's latch within its tolerances",
            drawing[0], drawing[1]
        ),
        LatchDifference::Restitution {
            measured: r,
            drawing: [lo, hi],
            side,
        } => format!(
            "the stop's apparent restitution {:.2} (95 % CI {:.2} .. {:.2}, {} impacts), {lo:.2}..{hi:.2} with the drawing's stop within its tolerances: it damps {} than drawn",
            r.median,
            r.ci95[0],
            r.ci95[1],
            r.impacts,
            match side {
                Side::Below => "more",
                Side::Above => "less",
            }
        ),
        LatchDifference::HoldAccel {
            measured: a,
            drawing: [lo, hi],
            side,
        } => format!(
            "the rebounds that stayed in decelerate at {:.0} deg/s² (95 % CI {:.0} .. {:.0}, {} rebounds), {lo:.0}..{hi:.0} with the drawing's latch within its tolerances: it pulls back {} than drawn",
            a.median,
            a.ci95[0],
            a.ci95[1],
            a.impacts,
            match side {
                Side::Below => "less",
                Side::Above => "more",
            }
        ),
    }
}

/// What the runs tell of the latch as built, in words (without the final
/// full stop): the causes the drawn latch's parts can have.
pub fn cause_words(c: LatchCause, parts: LatchParts) -> String {
    let magnet = if parts.magnet { " or magnet" } else { "" };
    match (c, parts.pawl) {
        (LatchCause::HoldsLess, false) if parts.magnet => "the latch holds less than drawn: a weaker plunger or magnet (plunger_weakening or magnet_weakening at this joint; the runs do not tell which)".into(),
        (LatchCause::HoldsLess, false) => "the latch holds less than drawn: a weaker plunger (plunger_weakening at this joint)".into(),
        (LatchCause::HoldsLess, true) => format!(
            "the latch holds less than drawn: a weaker pawl spring (plunger_weakening at this joint){}, or a pawl that gives way below its drawn breaking torque (the runs do not tell which)",
            if parts.magnet { ", a weaker magnet (magnet_weakening)" } else { "" }
        ),
        (LatchCause::HoldsMore, pawl) => format!(
            "the latch holds more than drawn: a stronger {}{magnet}, or a stop that damps more (these runs do not tell which, nor by how much)",
            if pawl { "pawl spring" } else { "plunger" }
        ),
        (LatchCause::BothWays, _) => "the latch differs from the drawing both ways over the runs".into(),
    }
}

/// The test that would separate the sets of an ambiguity group at `joint`,
/// in words (without the final full stop).
pub fn separating_test_words(t: SeparatingTest, joint: usize) -> String {
    match t {
        SeparatingTest::AnotherSpring => format!(
            "the runs are of one configuration: runs with another spring at joint {joint} (softening scales with the spring's torque, friction and a harness do not), or at another temperature, would separate them"
        ),
        SeparatingTest::AnotherRange => format!(
            "runs that move joint {joint} over another range of angle and rate (another spring or stowed angle at that joint), or at another temperature, would separate them"
        ),
        SeparatingTest::WithoutTheRig => format!(
            "a set puts a loss of the wing's own at joint {joint} in place of the rig's (air drag, a tilt): runs without it (in vacuum, the rig levelled) would separate them; until then the flight margins keep the wing's loss"
        ),
    }
}

/// A joint's latch events in one run, in words: `touched at 1.84 s, 26 impacts, 6 escapes, largest
/// rebound that stayed in 0.35°, held from 8.63 s`.
pub fn events_words(e: &LatchEvents) -> String {
    let Some(t0) = e.first_contact_s else {
        return format!(
            "never closed its switch ({:.2}° from the stop at the end)",
            e.end_travel_deg
        );
    };
    let hold = match e.hold_s {
        Some(t) => format!("held from {t:.2} s"),
        None => format!(
            "not held at the end ({:.2}° from the stop)",
            e.end_travel_deg
        ),
    };
    format!(
        "first impact at {t0:.2} s, {} impact(s), {} escape(s), largest rebound that stayed in {:.2}°, {hold}",
        e.impacts,
        e.escapes,
        e.largest_rebound_deg()
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::diagnose::latch_finding::{compare_for_test, Spread};

    /// A finding of `escapes` measured escapes over two runs, each ending
    /// held, against a drawing whose spread is `drawing` escapes and both
    /// runs held.
    fn finding(escapes: usize, drawing: [usize; 2]) -> LatchFinding {
        let spread = Spread {
            impacts: [20, 30],
            escapes: drawing,
            held: [2, 2],
            restitution: None,
            hold_accel: None,
        };
        compare_for_test(2, spread, escapes, 2)
    }

    #[test]
    fn escapes_outside_the_printed_spread_are_never_as_the_drawing() {
        // One escape beyond the most of the drawing's spread: a reading's
        // margin, neither a finding nor the drawing.
        let f = finding(18, [11, 17]);
        assert!(f.differs.is_empty(), "{:?}", f.differs);
        assert_eq!(f.undecided.len(), 1);
        let line = latch_line(&f);
        assert!(!line.contains("as the drawing"), "{line}");
        assert!(line.contains("cannot tell"), "{line}");
        let mut md = String::new();
        let c = Campaign::default();
        report_latch(&mut md, &c, &f);
        assert!(!md.contains("what the drawing's latch gives"), "{md}");
    }

    #[test]
    fn escapes_beyond_the_spread_name_a_latch_that_holds_less() {
        // A new user's 50 % plunger: 23 escapes against 11–17 printed.
        let f = finding(23, [11, 17]);
        assert_eq!(f.cause, Some(LatchCause::HoldsLess));
        assert!(f.undecided.is_empty());
        assert!(latch_line(&f).contains("differs from the drawing"));
    }

    /// The causes named are those the drawn latch's parts can have: no
    /// magnet where it has none, the pawl (and its breaking) on a pawl.
    #[test]
    fn the_cause_names_only_the_parts_the_latch_has() {
        let less = LatchCause::HoldsLess;
        let parts = |pawl, magnet| LatchParts { pawl, magnet };
        let plunger = cause_words(less, parts(false, false));
        assert!(plunger.contains("plunger_weakening") && !plunger.contains("magnet"));
        let both = cause_words(less, parts(false, true));
        assert!(
            both.contains("plunger_weakening or magnet_weakening"),
            "{both}"
        );
        let pawl = cause_words(less, parts(true, false));
        assert!(
            pawl.contains("pawl spring")
                && pawl.contains("breaking torque")
                && !pawl.contains("magnet"),
            "{pawl}"
        );
        let more = cause_words(LatchCause::HoldsMore, parts(true, false));
        assert!(
            more.contains("stronger pawl spring,") && !more.contains("magnet"),
            "{more}"
        );
    }

    #[test]
    fn fewer_escapes_than_the_spread_name_a_latch_that_holds_more() {
        assert!(finding(10, [11, 17]).cause.is_none());
        assert_eq!(finding(9, [11, 17]).cause, Some(LatchCause::HoldsMore));
    }

    #[test]
    fn escapes_within_the_spread_are_as_the_drawing() {
        let f = finding(14, [11, 17]);
        assert!(f.differs.is_empty() && f.undecided.is_empty());
        assert!(latch_line(&f).contains("as the drawing's latch gives"));
    }
}
