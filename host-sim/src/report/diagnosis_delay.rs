//! The encoders' delay behind their latch switches in the diagnosis
//! report and JSON (`docs/diagnosis.md`, "An encoder late on its switch").

use crate::analysis::diagnose::encoder_delay::{self, EncoderDelay};
use crate::analysis::diagnose::Outcome;
use crate::data::campaign::Campaign;
use crate::model::findings::diagnosis::{EncoderDelayJson, LatchingJson};
use crate::report::markdown::table;
use std::fmt::Write as _;

/// A value for the JSON: `None` when not finite.
fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

/// The delay in the JSON (`None`: no delay named).
pub fn json(c: &Campaign, o: &Outcome) -> Option<EncoderDelayJson> {
    let d = o.encoder_delay.as_ref()?;
    Some(EncoderDelayJson {
        delay_s: finite(d.delay_s),
        lo_s: finite(d.lo_s),
        hi_s: finite(d.hi_s),
        period_s: finite(d.period_s),
        taken_out: d.taken_out(),
        agreeing: d.agreeing,
        latchings: d
            .latchings
            .iter()
            .map(|l| LatchingJson {
                run: c.runs.get(l.run).map(|r| r.name()).unwrap_or_default(),
                joint: l.joint,
                crossing_s: finite(l.crossing_s),
                model_error_s: l
                    .model_error_s
                    .filter(|(a, b)| a.is_finite() && b.is_finite())
                    .map(|(a, b)| [a, b]),
                open_s: finite(l.open_s),
                closed_s: finite(l.closed_s),
                rate_deg_s: finite(l.rate_deg_s),
            })
            .collect(),
    })
}

/// The summary's line (none without a delay).
pub fn summary_line(o: &Outcome) -> Option<String> {
    o.encoder_delay
        .as_ref()
        .map(|d| format!("discrepancy (not an effect): {}", encoder_delay::words(d)))
}

/// The report's section (none without a delay).
pub fn report(md: &mut String, c: &Campaign, o: &Outcome) {
    let Some(d) = &o.encoder_delay else { return };
    let _ = writeln!(md, "## An encoder late on its switch\n");
    let _ = writeln!(
        md,
        "A discrepancy named by its signature, not an effect: {}. Each ideal latch's switch closes between its last open and first closed sample; the encoder's approach, extrapolated to its latched level, crosses it later by the delay. The same extrapolation on the model's own run, read at every phase of the sample clock, shows how far it can be off there (a tape spring's peak near the latch throws a slow joint at it early); each latching's interval is widened by that. Each latching below bounds the delay to about one sample ({:.0} % of the period allowed for time-stamp jitter, {:.0} σ of the extrapolated angle over the approach's slope for the noise); together they give {:.1} to {:.1} ms.\n",
        encoder_delay::words(d),
        100.0 * encoder_delay::JITTER_SLACK_PERIODS,
        encoder_delay::NOISE_SLACK_SIGMAS,
        d.lo_s * 1e3,
        d.hi_s * 1e3
    );
    md.push_str(&latchings_table(c, d));
    let _ = writeln!(md);
}

/// One row per latching: where its encoder crosses, its switch's samples
/// and the delay it allows.
fn latchings_table(c: &Campaign, d: &EncoderDelay) -> String {
    let rows: Vec<Vec<String>> = d
        .latchings
        .iter()
        .map(|l| {
            vec![
                c.runs.get(l.run).map(|r| r.name()).unwrap_or_default(),
                l.joint.to_string(),
                format!("{:.4}", l.crossing_s),
                l.model_error_s.map_or("–".into(), |(a, b)| {
                    format!("{:+.1} .. {:+.1}", a * 1e3, b * 1e3)
                }),
                format!("{:.4} .. {:.4}", l.open_s, l.closed_s),
                format!("{:.0}", l.rate_deg_s),
                format!("{:.1} .. {:.1}", l.lo_s * 1e3, l.hi_s * 1e3),
                if l.lo_s <= d.delay_s && d.delay_s <= l.hi_s {
                    "yes".into()
                } else {
                    "no".into()
                },
            ]
        })
        .collect();
    table(
        &[
            "run",
            "joint",
            "encoder crosses [s]",
            "extrapolation's error on the model [ms]",
            "switch closes between [s]",
            "rate [deg/s]",
            "delay allowed [ms]",
            "agrees",
        ],
        &rows,
    )
}
