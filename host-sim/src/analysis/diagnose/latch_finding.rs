//! The latch as built, a finding of its own (`docs/diagnosis.md`, "Runs of
//! a physical latch"): each joint's latch events in the runs against those
//! of the drawing's latch, simulated with the effects found, compared by
//! their statistics — impacts, escapes, the largest rebound that stayed in,
//! the hold, and the stop's restitution — never by their phase.

use crate::analysis::campaign_sim::CampaignSim;
use crate::analysis::latch_events::{events, travel_deg, LatchEvents};
use crate::data::campaign::Campaign;
use crate::model::effect::Effect;

/// Slack on the crest for an escape [deg]: about the encoder's resolution
/// (0.022°), so that noise at the crest does not count as an escape.
const ESCAPE_SLACK_DEG: f64 = 0.03;

/// Impacts slower than this [deg/s] give no restitution: at 100 Hz and
/// 0.02° of noise a rate from two samples has an error of about 3 deg/s.
const MIN_IMPACT_RATE_DEG_S: f64 = 20.0;

/// Fewest impacts for a restitution with an interval.
const MIN_RESTITUTION_IMPACTS: usize = 3;

/// A restitution differs from the drawing's when its interval excludes the
/// drawing's value and they differ by more than this share [1].
const RESTITUTION_SHARE: f64 = 0.1;

/// The stop's apparent restitution over a joint's impacts: the rate out
/// over the rate in, from the samples either side of each switch closing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Restitution {
    /// Median over the impacts [1].
    pub median: f64,
    /// 95 % interval of the median (order statistics) [1].
    pub ci95: [f64; 2],
    /// Impacts used.
    pub impacts: usize,
}

/// One joint's latch: its events run by run, measured and as the drawing
/// predicts them, and what differs.
#[derive(Clone, Debug, PartialEq)]
pub struct LatchFinding {
    /// Joint, from 1.
    pub joint: usize,
    /// The measured events, run by run.
    pub measured: Vec<LatchEvents>,
    /// The drawing's latch with the effects found, run by run (`None`
    /// where the simulation failed).
    pub drawing: Vec<Option<LatchEvents>>,
    /// The measured restitution, when enough impacts give one.
    pub restitution: Option<Restitution>,
    /// The drawing's, likewise.
    pub drawing_restitution: Option<Restitution>,
    /// What differs from the drawing's latch, one phrase each (empty: the
    /// events are the drawing's, within what their statistics tell).
    pub differs: Vec<String>,
    /// What the runs tell of the latch as built, in words.
    pub cause: Option<String>,
}

/// The median of `x` and its 95 % interval from order statistics (ranks
/// `n/2 ∓ 1.96 √n / 2`).
fn median_ci(mut x: Vec<f64>) -> Option<Restitution> {
    if x.len() < MIN_RESTITUTION_IMPACTS {
        return None;
    }
    x.sort_by(f64::total_cmp);
    let n = x.len();
    let h = 0.98 * (n as f64).sqrt();
    let lo = ((n as f64 / 2.0 - h).floor().max(0.0)) as usize;
    let hi = ((n as f64 / 2.0 + h).ceil() as usize).min(n - 1);
    Some(Restitution {
        median: x[n / 2],
        ci95: [x[lo], x[hi]],
        impacts: n,
    })
}

/// Rate ratios out/in at each closing of the switch, `t` the times [s],
/// `u` the travel [deg].
fn ratios(t: &[f64], u: &[f64], switch: &[bool]) -> Vec<f64> {
    let n = t.len().min(u.len()).min(switch.len());
    let mut out = Vec::new();
    for i in 2..n.saturating_sub(1) {
        if !switch[i] || switch[i - 1] || switch[i + 1] {
            continue;
        }
        let v_in = (u[i - 2] - u[i - 1]) / (t[i - 1] - t[i - 2]);
        let v_out = (u[i + 1] - u[i]) / (t[i + 1] - t[i]);
        if v_in > MIN_IMPACT_RATE_DEG_S && v_out > 0.0 {
            out.push(v_out / v_in);
        }
    }
    out
}

/// One joint's series of one run: times, travel [deg], switch.
type Series<'a> = (&'a [f64], Vec<f64>, &'a [bool]);

/// The latch findings of a campaign, joint by joint for every joint with a
/// physical latch in some run: the measured events against the drawing's
/// latch simulated over each whole run with `effects` (the effects found).
pub fn latch_findings(c: &Campaign, effects: &[Effect]) -> Vec<LatchFinding> {
    let sims: Vec<_> = (0..c.runs.len())
        .map(|i| c.simulate(i, effects).ok())
        .collect();
    let joints = c.max_joints();
    (0..joints)
        .filter_map(|j| {
            let runs: Vec<usize> = (0..c.runs.len())
                .filter(|&i| c.runs[i].mechanism.latch(j).is_some())
                .collect();
            if runs.is_empty() {
                return None;
            }
            let mut f = LatchFinding {
                joint: j + 1,
                measured: Vec::new(),
                drawing: Vec::new(),
                restitution: None,
                drawing_restitution: None,
                differs: Vec::new(),
                cause: None,
            };
            let (mut r_meas, mut r_draw) = (Vec::new(), Vec::new());
            for &i in &runs {
                let cr = &c.runs[i];
                let (Some(latch), Some(spec)) = (cr.mechanism.latch(j), cr.mechanism.joints.get(j))
                else {
                    continue;
                };
                let crest = latch.plunger.crest_deg;
                let stowed = spec.stowed_deg;
                let tr = |phi: &[f64]| phi.iter().map(|&p| travel_deg(stowed, p)).collect();
                let meas: Series = (&cr.run.t_s, tr(&cr.run.phi_deg[j]), &cr.run.latch[j]);
                f.measured
                    .push(events(meas.0, &meas.1, meas.2, crest, ESCAPE_SLACK_DEG));
                r_meas.extend(ratios(meas.0, &meas.1, meas.2));
                let drawn = sims[i].as_ref().map(|tj| {
                    let s: Series = (&tj.t_s, tr(&tj.phi_deg[j]), &tj.latched[j]);
                    r_draw.extend(ratios(s.0, &s.1, s.2));
                    events(s.0, &s.1, s.2, crest, ESCAPE_SLACK_DEG)
                });
                f.drawing.push(drawn);
            }
            f.restitution = median_ci(r_meas);
            f.drawing_restitution = median_ci(r_draw);
            compare(&mut f);
            Some(f)
        })
        .collect()
}

/// Fills `differs` and `cause`: escapes where the drawing holds (or the
/// reverse), a hold at the end that the drawing does not give (or the
/// reverse), and a restitution whose interval excludes the drawing's.
fn compare(f: &mut LatchFinding) {
    let touched = |e: &LatchEvents| e.first_contact_s.is_some();
    let meas_touch = f.measured.iter().filter(|e| touched(e)).count();
    let drawn: Vec<&LatchEvents> = f.drawing.iter().flatten().collect();
    let draw_touch = drawn.iter().filter(|e| touched(e)).count();
    if meas_touch == 0 && draw_touch == 0 {
        return;
    }
    let esc_m: usize = f.measured.iter().map(|e| e.escapes).sum();
    let esc_d: usize = drawn.iter().map(|e| e.escapes).sum();
    let held_m = f.measured.iter().filter(|e| e.hold_s.is_some()).count();
    let held_d = drawn.iter().filter(|e| e.hold_s.is_some()).count();
    let mut weaker = false;
    let mut stronger = false;
    if (esc_m > 0) != (esc_d > 0) && meas_touch > 0 && draw_touch > 0 {
        f.differs.push(format!(
            "{esc_m} escape(s) over the plunger in the runs, {esc_d} with the drawing's latch"
        ));
        weaker |= esc_m > esc_d;
        stronger |= esc_m < esc_d;
    }
    if held_m != held_d {
        f.differs.push(format!(
            "held at the end of {held_m} of {} run(s), {held_d} with the drawing's latch",
            f.measured.len()
        ));
        weaker |= held_m < held_d && meas_touch >= draw_touch;
        stronger |= held_m > held_d && draw_touch >= meas_touch;
    }
    if let (Some(m), Some(d)) = (f.restitution, f.drawing_restitution) {
        let outside = d.median < m.ci95[0] || d.median > m.ci95[1];
        if outside && (m.median - d.median).abs() > RESTITUTION_SHARE * d.median.abs() {
            f.differs.push(format!(
                "the stop's restitution {:.2} (95 % CI {:.2} .. {:.2}, {} impacts), {:.2} with the drawing's stop: it damps {} than drawn",
                m.median,
                m.ci95[0],
                m.ci95[1],
                m.impacts,
                d.median,
                if m.median < d.median { "more" } else { "less" }
            ));
        }
    }
    f.cause = match (weaker, stronger) {
        (true, false) => Some(
            "the latch holds less than drawn: a weaker plunger or magnet (plunger_weakening or magnet_weakening at this joint; these runs do not determine which, nor by how much: the escapes are a chaotic sequence)".into(),
        ),
        (false, true) => Some(
            "the latch holds more than drawn: a stronger plunger or magnet, or a stop that damps more (these runs do not determine which, nor by how much)".into(),
        ),
        (true, true) => Some("the latch differs from the drawing in both directions over the runs: within the spread a chaotic impact sequence gives".into()),
        (false, false) => None,
    };
}

/// The events in words: `touched at 1.84 s, 26 impacts, 6 escapes, largest
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
