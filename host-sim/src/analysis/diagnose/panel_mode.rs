//! Flexible panels (`docs/diagnosis.md`, "Flexible panels"): a discrepancy
//! the diagnosis names by fitting it, not an effect.
//!
//! A deployed wing's panels bend: its first mode lies at a few hertz to a
//! few tens. While the wing swings, the springs' torque bends each panel
//! and each latching rings it, and the encoders, on the hinges, read that
//! as a change of the motion the rigid model cannot make (on another
//! engine's wing with its first mode at 8.2 Hz and nothing hidden, 0.38°
//! RMS): the search would bend named effects and tables to absorb it.
//!
//! So when the set found leaves the runs clearly above the noise, the
//! wing is tried with flexible panels ([`crate::model::flex`],
//! `physics.md` §12), with the empty set, each member of the set found
//! alone and the set whole (a set that absorbed the bending holds members
//! the flexible wing does not need): each at its values, the first mode
//! on a log grid of [`GRID`] frequencies from [`LOWEST_HZ`] to
//! [`HIGHEST_HZ`] (below a third of the sample rate) and at each the
//! damping ratio in [`ZETA_RANGE`] by golden section (what the runs say
//! of a flexible wing hangs on the damping: the ringing after each
//! latching drains the swinging joints, more the longer it lasts), then
//! the best start fitted with the mode and its damping (Levenberg–
//! Marquardt on `ln f`, `ln ζ` and the set's parameters). The fit of least
//! BIC names the panels when it beats the rigid set by the search's BIC
//! margin with the mode and its damping counted as two parameters, and
//! takes at least [`MIN_SHARE`] of the discrepancy the rigid set leaves
//! above the noise. Then the search runs again on the flexible wing (the
//! encoders' delay estimated again: a rigid wing's search may settle on a
//! delay that stood in for the bending), over the named effects only
//! ([`search_options`]), and its answer is the diagnosis, the mode
//! reported beside it.

use super::{
    above_noise, fitted_campaign, Engine, FitStats, FittedSet, Halt, Outcome, PanelMode,
    ParamBound, Trace, MIN_DELTA_BIC,
};
use crate::analysis::campaign_sim::CampaignSim;
use crate::analysis::diagnose::encoder_delay;
use crate::analysis::diagnose::evidence::noise_sigma_deg;
use crate::analysis::diagnose::DiagnoseOptions;
use crate::analysis::fit::{self, FitOptions};
use crate::data::campaign::Campaign;
use crate::model::flex::{PanelFlex, DEFAULT_DAMPING_RATIO};
use crate::report::progress::Progress;
use rayon::prelude::*;
use std::time::Instant;

/// Lowest first mode tried \[Hz\].
pub const LOWEST_HZ: f64 = 2.0;

/// Highest first mode tried \[Hz\] (and at most a third of the sample rate:
/// a mode the samples cannot resolve is not named).
pub const HIGHEST_HZ: f64 = 30.0;

/// Frequencies of the log grid.
pub const GRID: usize = 14;

/// Golden-section steps over `ln ζ` in [`ZETA_RANGE`] at each first mode
/// of the start grid.
const ZETA_STEPS: usize = 8;

/// The damping ratio's range in the fit \[1\].
pub const ZETA_RANGE: [f64; 2] = [0.003, 0.08];

/// Smallest finite-difference step of `ln f₁` and `ln ζ₁` in the fit: the
/// runs of a flexible wing hang on its mode closely (one run of another
/// engine's case 16 misses by 0.03° at its damping, by 0.12° at 0.8 of it).
const FD_STEP_LN: f64 = 1e-5;

/// Most searches again at a mode refitted with the set the last search
/// found.
const MODE_PASSES: usize = 2;

/// Share of the rigid set's discrepancy above the noise (`SSE − m σ̂²`)
/// that the flexible wing must take out to be named.
pub const MIN_SHARE: f64 = 0.25;

/// `campaign` with every run's mechanism given flexible panels `flex`;
/// `None` when some mechanism cannot take them (already flexible, a
/// physical latch, a truss, an enabled rig, too many panels).
pub fn flexible(campaign: &Campaign, flex: PanelFlex) -> Option<Campaign> {
    let mut c = campaign.clone();
    for r in &mut c.runs {
        let m = &mut r.mechanism;
        if m.flexible.is_some() || !m.can_be_flexible() {
            return None;
        }
        m.flexible = Some(flex);
    }
    Some(c)
}

/// The search's settings on the flexible wing: `opts` without the
/// discovery of torque tables. Each model run of a flexible wing costs 10
/// to 30 times a rigid one's (its panels ring at several times the first
/// mode while the hinges swing), and a table's many parameters take the
/// most runs: discovery there, every table form screened and refined on
/// the flexible wing, took a campaign of another engine from a minute to
/// more than an hour (`docs/measured.md`, "campaigns of another engine").
/// What the named effects leave on the flexible wing is reported
/// `unexplained`.
pub fn search_options(opts: &DiagnoseOptions) -> DiagnoseOptions {
    DiagnoseOptions {
        discover: false,
        ..opts.clone()
    }
}

/// The campaign as the report compares it: with the mode named, every
/// mechanism flexible at it.
pub fn apply(campaign: &Campaign, mode: Option<&PanelMode>) -> Campaign {
    match mode.and_then(|m| flexible(campaign, m.flex)) {
        Some(c) => c,
        None => campaign.clone(),
    }
}

/// The flex at `hz` with the assumed damping.
fn at(hz: f64) -> PanelFlex {
    PanelFlex {
        first_mode_hz: hz,
        damping_ratio: DEFAULT_DAMPING_RATIO,
    }
}

/// Tries flexible panels on `campaign` after `first`, the rigid wing's
/// diagnosis (module doc); `search` runs the diagnosis on a campaign.
/// Returns the diagnosis to keep: `first`, or the search's on the
/// flexible wing with [`Outcome::panel_mode`] set.
pub(super) fn consider(
    campaign: &Campaign,
    first: Outcome,
    (opts, t0): (&DiagnoseOptions, Instant),
    progress: Progress,
    search: impl Fn(&Campaign, &DiagnoseOptions) -> Outcome,
) -> Outcome {
    let sigma = noise_sigma_deg(campaign);
    if first.partial.is_some() || !above_noise(&first.extended, sigma) {
        return first;
    }
    let Some(rigid) = first.extended.stats else {
        return first;
    };
    let sample_hz = campaign
        .runs
        .iter()
        .map(|r| r.mechanism.sample_hz)
        .fold(f64::INFINITY, f64::min);
    let highest = HIGHEST_HZ.min(sample_hz / 3.0);
    if flexible(campaign, at(highest)).is_none() || !(highest > LOWEST_HZ) {
        return first;
    }
    let compared = fitted_campaign(&encoder_delay::apply(
        campaign,
        first.encoder_delay.as_ref(),
    ));
    let eng = Engine {
        campaign: &compared,
        progress,
        sims: std::sync::atomic::AtomicUsize::new(0),
        halt: Halt::new(opts, t0),
        trace: Trace::default(),
    };
    let m = rigid.m.max(1) as f64;
    let Some((flex, refit)) = best_flexible(&eng, &compared, &first.extended, highest) else {
        return first;
    };
    let sims = eng.sims.load(std::sync::atomic::Ordering::Relaxed);
    if !named(&first.extended, &refit, sigma) || !resolved(flex, highest) {
        progress(&format!(
            "flexible panels tried: a first mode at {:.2} Hz, {:.1} % damped, takes the runs from {:.4} to {:.4} deg RMS with {}: not named{}",
            flex.first_mode_hz,
            100.0 * flex.damping_ratio,
            (rigid.sse / m).sqrt(),
            refit.rms(),
            super::labels(&refit.candidates()),
            if resolved(flex, highest) {
                ""
            } else {
                " (the mode runs to an end of its range)"
            }
        ));
        let mut out = first;
        out.simulations += sims;
        return out;
    }
    let mode = PanelMode {
        flex,
        rigid_rms_deg: (rigid.sse / m).sqrt(),
        flexible_rms_deg: refit.rms(),
    };
    progress(&format!("{}: searching again with them", mode.words()));
    let Some(flex_campaign) = flexible(campaign, mode.flex) else {
        return first;
    };
    let opts = search_options(opts);
    let out = search(&flex_campaign, &opts);
    let (mode, mut out) = refined(
        &eng,
        campaign,
        (mode, out),
        (&opts, highest),
        progress,
        &search,
    );
    out.simulations += eng.sims.load(std::sync::atomic::Ordering::Relaxed) + first.simulations;
    out.panel_mode = Some(mode);
    out
}

/// The mode refitted with the set the search found on the flexible wing
/// (the start's set may have held what the bending was bent into), at
/// most [`MODE_PASSES`] times: where it fits better by the BIC margin, the
/// search runs again there (`search` with `opts`, modes up to `highest`
/// \[Hz\]). The mode and the last search's outcome.
fn refined(
    eng: &Engine<'_>,
    campaign: &Campaign,
    (mut mode, mut out): (PanelMode, Outcome),
    (opts, highest): (&DiagnoseOptions, f64),
    progress: Progress,
    search: &impl Fn(&Campaign, &DiagnoseOptions) -> Outcome,
) -> (PanelMode, Outcome) {
    for _ in 0..MODE_PASSES {
        let mut p = vec![mode.flex.first_mode_hz.ln(), mode.flex.damping_ratio.ln()];
        p.extend(out.extended.params());
        let cands = out.extended.candidates();
        let base = fitted_campaign(&encoder_delay::apply(campaign, out.encoder_delay.as_ref()));
        let Some((again, refit)) = fit_from(eng, &base, &cands, &p, highest) else {
            break;
        };
        if !(refit.bic() + MIN_DELTA_BIC < out.extended.bic())
            || out.partial.is_some()
            || !resolved(again, highest)
        {
            break;
        }
        mode.flex = again;
        progress(&format!(
            "the set found fits best with the first mode at {:.2} Hz, damping ratio {:.1} %: searching again there",
            again.first_mode_hz,
            100.0 * again.damping_ratio
        ));
        let Some(c) = flexible(campaign, again) else {
            break;
        };
        let before = out.simulations;
        out = search(&c, opts);
        out.simulations += before;
    }
    (mode, out)
}

/// Share of the first mode's range at each end \[1\] (on `ln f`) where a
/// fitted mode is not resolved.
const EDGE_SHARE: f64 = 0.01;

/// True when `flex`'s first mode lies inside its range `[LOWEST_HZ,
/// highest]` \[Hz\], off each end by more than [`EDGE_SHARE`] of it on a log
/// scale: a fit that runs to an end has no optimum the runs resolve (at
/// the top, a wing barely flexible and damped at the range's most; on
/// another engine's campaign with its first mode at 4.5 Hz, the mode
/// refitted with the set found ran to 30 Hz and 8 %), and is neither
/// named nor searched at.
fn resolved(flex: PanelFlex, highest: f64) -> bool {
    let (lo, hi) = (LOWEST_HZ.ln(), highest.ln());
    let edge = EDGE_SHARE * (hi - lo);
    let f = flex.first_mode_hz.ln();
    f > lo + edge && f < hi - edge
}

/// True when `flexible`, a set fitted on the flexible wing, names the
/// panels against `rigid`, the set found on the rigid one: better by the
/// search's BIC margin with the mode and its damping counted as two
/// parameters, and [`MIN_SHARE`] of the rigid set's excess over the noise
/// `sigma` \[deg\] taken out.
fn named(rigid: &FittedSet, flexible: &FittedSet, sigma: f64) -> bool {
    let (Some(r), Some(f)) = (rigid.stats, flexible.stats) else {
        return false;
    };
    let m = r.m.max(1) as f64;
    let excess = r.sse - m * sigma * sigma;
    f.sse > 0.0
        && flexible.bic() + 2.0 * m.ln() + MIN_DELTA_BIC < rigid.bic()
        && r.sse - f.sse >= MIN_SHARE * excess
}

/// The flexible wing that fits `compared` best and its set: the empty set,
/// each member of `found` alone and `found` whole, each started from its
/// values in `found` at the best point of a grid of first modes
/// ([`GRID`] on a log scale in `[LOWEST_HZ, highest]`, at each the damping
/// ratio in [`ZETA_RANGE`] by golden section), then fitted with the mode and its damping
/// (Levenberg–Marquardt on `ln f`, `ln ζ` and the set's parameters); the
/// one of least BIC, with its flex.
fn best_flexible(
    eng: &Engine<'_>,
    compared: &Campaign,
    found: &FittedSet,
    highest: f64,
) -> Option<(PanelFlex, FittedSet)> {
    let mut sets = vec![FittedSet {
        members: Vec::new(),
        stats: None,
    }];
    if found.members.len() > 1 {
        for k in 0..found.members.len() {
            sets.push(FittedSet {
                members: vec![found.members[k].clone()],
                stats: None,
            });
        }
    }
    if found.members.len() == 1 {
        sets.push(found.clone());
    }
    sets.par_iter()
        .filter_map(|set| fit_flexible(eng, compared, set, highest))
        .collect::<Vec<_>>()
        .into_iter()
        .min_by(|a, b| a.1.bic().total_cmp(&b.1.bic()))
}

/// `set` fitted on `compared` with flexible panels (see [`best_flexible`]).
fn fit_flexible(
    eng: &Engine<'_>,
    compared: &Campaign,
    set: &FittedSet,
    highest: f64,
) -> Option<(PanelFlex, FittedSet)> {
    let (cands, p0) = (set.candidates(), set.params());
    let sse = |p: &[f64]| -> f64 {
        residuals_at(eng, compared, &cands, p)
            .map_or(f64::INFINITY, |r| r.iter().map(|x| x * x).sum())
    };
    let (a, b) = (LOWEST_HZ.ln(), highest.ln());
    let (za, zb) = (ZETA_RANGE[0].ln(), ZETA_RANGE[1].ln());
    let mut start: Option<(f64, Vec<f64>)> = None;
    for i in 0..GRID {
        let lf = a + (b - a) * i as f64 / (GRID - 1) as f64;
        let at_zeta = |lz: f64| {
            let mut p = vec![lf, lz];
            p.extend_from_slice(&p0);
            (sse(&p), p)
        };
        let best = golden(za, zb, ZETA_STEPS, |lz| at_zeta(lz).0);
        let (s, p) = at_zeta(best);
        if start.as_ref().is_none_or(|(b, _)| s < *b) {
            start = Some((s, p));
        }
    }
    let (_, p) = start?;
    fit_from(eng, compared, &cands, &p, highest)
}

/// The set `cands` fitted on `compared` with flexible panels from `p`
/// (`ln f₁`, `ln ζ₁`, then the set's parameters): the mode found and the
/// set with its statistics.
fn fit_from(
    eng: &Engine<'_>,
    compared: &Campaign,
    cands: &[super::Candidate],
    p: &[f64],
    highest: f64,
) -> Option<(PanelFlex, FittedSet)> {
    let residuals = |p: &[f64]| residuals_at(eng, compared, cands, p);
    let (a, b) = (LOWEST_HZ.ln(), highest.ln());
    let bounds: Vec<ParamBound> = cands.iter().flat_map(|c| c.bounds()).collect();
    let mut lower = vec![a, ZETA_RANGE[0].ln()];
    let mut upper = vec![b, ZETA_RANGE[1].ln()];
    let mut min_step = vec![FD_STEP_LN, FD_STEP_LN];
    lower.extend(bounds.iter().map(|x| x.lower));
    upper.extend(bounds.iter().map(|x| x.upper));
    min_step.extend(bounds.iter().map(|x| x.min_step));
    let opts = FitOptions {
        lower,
        upper,
        min_step,
        patience: super::FIT_PATIENCE,
    };
    let model = fit::InSeries {
        model: &residuals,
        lengths: compared.series_lengths(),
    };
    let r = fit::least_squares(&model, p, &opts).ok()?;
    let flex = PanelFlex {
        first_mode_hz: r.params[0].exp(),
        damping_ratio: r.params[1].exp(),
    };
    let stats = FitStats {
        sse: r.sse,
        m: r.residuals,
        evaluations: r.evaluations,
    };
    let fitted = FittedSet::from_flat(cands, &r.params[2..], Some(&r.ci95[2..]), Some(stats));
    Some((flex, fitted))
}

/// The residuals of `cands` on `compared` made flexible, at `p` (`ln f₁`,
/// `ln ζ₁`, then the set's parameters).
fn residuals_at(
    eng: &Engine<'_>,
    compared: &Campaign,
    cands: &[super::Candidate],
    p: &[f64],
) -> Option<Vec<f64>> {
    let flex = PanelFlex {
        first_mode_hz: p[0].exp(),
        damping_ratio: p[1].exp(),
    };
    eng.residuals(&flexible(compared, flex)?, cands, &p[2..])
}

/// The minimiser of `f` in `[lo, hi]` by `steps` steps of golden section.
fn golden(mut lo: f64, mut hi: f64, steps: usize, f: impl Fn(f64) -> f64) -> f64 {
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut x1, mut x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..steps {
        if f1 <= f2 {
            hi = x2;
            (x2, f2) = (x1, f1);
            x1 = hi - g * (hi - lo);
            f1 = f(x1);
        } else {
            lo = x1;
            (x1, f1) = (x2, f2);
            x2 = lo + g * (hi - lo);
            f2 = f(x2);
        }
    }
    if f1 <= f2 {
        x1
    } else {
        x2
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mode_at_an_end_of_its_range_is_not_resolved() {
        let at = |hz: f64| PanelFlex {
            first_mode_hz: hz,
            damping_ratio: 0.02,
        };
        assert!(resolved(at(4.5), HIGHEST_HZ));
        assert!(!resolved(at(HIGHEST_HZ), HIGHEST_HZ));
        assert!(!resolved(at(LOWEST_HZ), HIGHEST_HZ));
        // The range's top is the sample rate's third where that is lower.
        assert!(!resolved(at(16.6), 100.0 / 6.0));
        assert!(resolved(at(16.0), 100.0 / 6.0));
    }
}
