//! The parts of the diagnosis JSON, report and summary that runs of a
//! physical latch, sets of causes the runs cannot tell apart and a search
//! stopped early add (`docs/diagnosis.md`, "Runs of a physical
//! latch", "Ambiguity", "Long searches").

use crate::analysis::diagnose::latch_finding::{events_words, LatchFinding};
use crate::analysis::diagnose::{FittedSet, Outcome};
use crate::analysis::latch_events::LatchEvents;
use crate::data::campaign::Campaign;
use crate::model::findings::diagnosis::{
    AmbiguityGroup, AmbiguousSet, FreeWindow, LatchEventsJson, LatchReport,
};
use crate::model::findings::rounded;
use crate::report::markdown::table;
use std::fmt::Write as _;

/// The free window of each run, for the JSON.
pub fn windows_json(c: &Campaign, o: &Outcome) -> Vec<FreeWindow> {
    let Some(ws) = &o.free_window else {
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
            differs: f.differs.clone(),
            cause: f.cause.clone(),
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
                separating_test: g.separating_test.clone(),
            }
        })
        .collect()
}

/// A set in words with values: `coulomb_friction at joint 2 = 0.4991`.
fn set_words(f: &FittedSet) -> String {
    let e = f.effects();
    if e.is_empty() {
        return "nothing".into();
    }
    e.iter()
        .map(|e| match e.joint {
            Some(j) => format!("{} at joint {j} = {:.4}", e.kind(), e.value()),
            None => format!("{} = {:.4}", e.kind(), e.value()),
        })
        .collect::<Vec<_>>()
        .join(", ")
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
            g.separating_test
        ));
        for s in &g.sets {
            out.push(format!("    {} (RMS {:.4} deg)", set_words(s), s.rms()));
        }
    }
    for f in &o.latches {
        out.push(latch_line(f));
    }
    out
}

fn latch_line(f: &LatchFinding) -> String {
    let esc: usize = f.measured.iter().map(|e| e.escapes).sum();
    let imp: usize = f.measured.iter().map(|e| e.impacts).sum();
    let mut s = format!(
        "latch at joint {}: {imp} impact(s), {esc} escape(s) over {} run(s)",
        f.joint,
        f.measured.len()
    );
    if f.differs.is_empty() {
        s += "; as the drawing's latch gives within its tolerances";
    } else {
        let _ = write!(s, "; differs from the drawing: {}", f.differs.join("; "));
    }
    if let Some(w) = f.weakening {
        let _ = write!(s, "; {}", weakening_words(w));
    }
    s
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
        let _ = writeln!(
            md,
            "The impact sequence at a physical latch (rebounds, escapes over the plunger, re-latches) is chaotic: it is not compared sample by sample. The effects were fitted on each run's free motion, up to the first instant a joint enters its latch's reach; the latch events are compared by their statistics with what the drawing's latch gives within its tolerances.\n"
        );
        for (cr, w) in c.runs.iter().zip(ws) {
            let _ = match (w.end_s, w.joint) {
                (Some(t), Some(j)) => writeln!(
                    md,
                    "- {}: free motion fitted to {t:.2} s ({} of {} samples), where joint {j} enters its latch's reach",
                    cr.name(),
                    w.kept,
                    w.of
                ),
                _ => writeln!(md, "- {}: no joint reaches its latch; fitted whole", cr.name()),
            };
        }
        let _ = writeln!(md);
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
        f.differs.join("; ")
    );
    if let Some(cause) = &f.cause {
        let _ = writeln!(md, "{cause}.");
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
            "At joint {} these sets explain the runs alike (BIC within 10 of the set found); the intervals above are widened to cover them. {}.\n",
            g.joint, g.separating_test
        );
        let first = g.sets.first().map_or(0.0, FittedSet::bic);
        md.push_str(&table(
            &["set", "RMS [deg]", "ΔBIC"],
            g.sets.iter().map(|s| {
                vec![
                    set_words(s),
                    format!("{:.4}", s.rms()),
                    format!("{:+.1}", s.bic() - first),
                ]
            }),
        ));
        let _ = writeln!(md);
    }
}
