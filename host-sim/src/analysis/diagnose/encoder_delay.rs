//! The encoders' delay behind their latch switches (`docs/diagnosis.md`,
//! "An encoder late on its switch"): a discrepancy the diagnosis names by
//! its signature and takes out before it fits any effect.
//!
//! An encoder that reports each angle `d` late (a filter, a bus, a
//! sample-and-hold) reads `φ(t − d)` at the stamp `t`, while the latch
//! switch reads its contact at `t`. Compared with the model at the stamps,
//! the whole run looks slow by `d`: on a wing turning at 300 °/s a delay of
//! one 10 ms sample is 3° of residual, which the search would otherwise
//! bend named effects (friction, a torque table) to absorb.
//!
//! The signature is at each ideal latch (physics.md §5): the switch closes
//! at the instant `t*` the joint reaches its latched angle, somewhere in
//! `(t_{L−1}, t_L]` between the last open and the first closed sample; the
//! encoder's approach, extrapolated to its latched level, crosses it at
//! `τ = t* + d`. Each latching therefore bounds the delay:
//! `τ − t_L ≤ d < τ − t_{L−1}`, an interval one sample wide; several
//! latchings (joints × runs), closing at unrelated phases of the sample
//! clock, narrow it (set-membership estimation). The delay is named when
//! the intervals agree on a value and exclude zero.
//!
//! The extrapolation sees only the samples before the latch: a tape
//! spring's peak within a degree of the latch throws a slow joint at it
//! several milliseconds before the parabola says, which on time would read
//! as a delay. The same extrapolation on the model's own run of the
//! mechanism, read at every phase of the sample clock, shows how far it
//! can be off there; each latching's interval is widened by that.
//!
//! The runs are then compared with the model at their stamps minus the
//! delay ([`shifted`]); a sample the encoder took before the release reads
//! the stowed rest.

use crate::analysis::campaign_sim::fit_sim_options_for;
use crate::data::campaign::Campaign;
use crate::simulate::deployment;
use crate::simulate::trajectory::Trajectory;

/// Slack on each latching's interval for time-stamp jitter, in sample
/// periods: 3 σ of a jitter of 5 % of the period.
pub const JITTER_SLACK_PERIODS: f64 = 0.15;

/// Slack on each latching's interval for the sensor noise: this many σ
/// of the extrapolated level over the approach's slope at the crossing.
/// The extrapolated level's σ is σ̂ times the norm of the parabola's
/// weights there ([`Crossing::noise_gain`]), 1 at the last sample and
/// about 4 a sample beyond it; σ̂ itself is read off the runs, in whole
/// quanta of the encoder, so a generous 5 rather than 3.
pub const NOISE_SLACK_SIGMAS: f64 = 5.0;

/// An approach sample is clear of the latched level beyond this many σ̂.
pub const APPROACH_SIGMAS: f64 = 10.0;

/// Fewest latchings before a delay is named.
pub const MIN_LATCHINGS: usize = 3;

/// The latched level is the median of these samples after the switch
/// closes, from the third on (a delay of up to two samples left out).
const LEVEL_SAMPLES: usize = 30;

/// Latest sample after the switch closes still read as the approach (an
/// encoder up to this many samples late).
const MAX_LATE_SAMPLES: usize = 3;

/// A refined delay within this many sample periods of the one the search
/// ran at is taken as that one: the search is not run again. A mismatch
/// of δ leaves `φ̇ δ` in the residuals, which at 300 °/s and 10 µs is
/// already a clear share of a 0.02° noise over thousands of samples: the
/// search would take a small effect to absorb it.
pub const REFINED_ALIKE_PERIODS: f64 = 1e-4;

/// Most searches of a diagnosis with a delay: each refines the delay
/// with the set it found, and searches again where it moved.
pub const MAX_PASSES: usize = 3;

/// [`refine`] stops when its bracket is narrower than this many sample
/// periods.
const REFINE_TOLERANCE_PERIODS: f64 = 2e-5;

/// Most golden-section steps of [`refine`] (0.618^60: any bracket).
const REFINE_STEPS: usize = 60;

/// Where the delay comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DelayFrom {
    /// The middle of what the latchings allow.
    Latchings,
    /// The delay at which the model found fits the runs best, within what
    /// the latchings allow ([`refine`]); where they allow zero too, named
    /// only when that fit beats the one without a delay by the search's
    /// BIC margin, counting the delay as one parameter.
    Model,
}

/// One ideal latch closing, as the encoder and the switch saw it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Latching {
    /// Run (0-based, in the campaign's order).
    pub run: usize,
    /// Joint (1-based).
    pub joint: usize,
    /// Where the encoder's approach crosses its latched level \[s\].
    pub crossing_s: f64,
    /// The same extrapolation's least and greatest error on the model's
    /// own run of the mechanism as given, over the phases of the sample
    /// clock \[s\] (`None`: the model does not latch there).
    pub model_error_s: Option<(f64, f64)>,
    /// The last sample with the switch open \[s\].
    pub open_s: f64,
    /// The first sample with the switch closed \[s\].
    pub closed_s: f64,
    /// The approach rate \[deg/s\].
    pub rate_deg_s: f64,
    /// The delay this latching allows, slack included: `[lo, hi]` \[s\].
    pub lo_s: f64,
    /// Upper end of the delay this latching allows \[s\].
    pub hi_s: f64,
}

/// The delay the latchings agree on.
#[derive(Clone, Debug, PartialEq)]
pub struct EncoderDelay {
    /// The delay taken out \[s\]: the middle of [`EncoderDelay::lo_s`] ..
    /// [`EncoderDelay::hi_s`]. Negative: the switches are late on the
    /// encoders (nothing is taken out then: the fit compares angles only).
    pub delay_s: f64,
    /// The delays every agreeing latching allows: lower end \[s\].
    pub lo_s: f64,
    /// Upper end \[s\].
    pub hi_s: f64,
    /// The latchings that agree on `[lo, hi]`.
    pub agreeing: usize,
    /// Every latching read.
    pub latchings: Vec<Latching>,
    /// The runs' sample period (the first run's median step) \[s\].
    pub period_s: f64,
    /// Where [`EncoderDelay::delay_s`] comes from.
    pub from: DelayFrom,
    /// True when no delay at all agrees with the latchings as well: zero
    /// inside `[lo, hi]`, or allowed by as many latchings elsewhere. The
    /// delay is then named only where the model fits the runs clearly
    /// better with it ([`DelayFrom::Model`]).
    pub allows_zero: bool,
}

impl EncoderDelay {
    /// The delay in sample periods.
    pub fn periods(&self) -> f64 {
        self.delay_s / self.period_s.max(f64::MIN_POSITIVE)
    }

    /// The delay `delay_s` found by the model ([`DelayFrom::Model`]).
    pub fn refined(&self, delay_s: f64) -> EncoderDelay {
        EncoderDelay {
            delay_s,
            from: DelayFrom::Model,
            ..self.clone()
        }
    }

    /// True when the angles are compared at their stamps minus the delay
    /// (the encoders are late; a late switch changes no angle).
    pub fn taken_out(&self) -> bool {
        self.delay_s > 0.0
    }
}

/// The median of `x` (`None` when empty or not finite).
fn median(mut x: Vec<f64>) -> Option<f64> {
    if x.is_empty() || x.iter().any(|v| !v.is_finite()) {
        return None;
    }
    x.sort_by(f64::total_cmp);
    Some(x[x.len() / 2])
}

/// Where an extrapolated approach reaches zero.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Crossing {
    /// The instant \[s\].
    t_s: f64,
    /// The slope there \[deg/s\], its magnitude.
    slope: f64,
    /// The norm of the weights of the samples in the value there: a noise
    /// σ on each sample gives this many σ on the value.
    noise_gain: f64,
}

/// Where the parabola through three samples `(t, y)` reaches zero after
/// `t[2]` and within `reach` \[s\] of it; the line through the last two when
/// the parabola does not.
fn crossing(t: [f64; 3], y: [f64; 3], reach: f64) -> Option<Crossing> {
    let (h1, h2) = (t[1] - t[0], t[2] - t[1]);
    if !(h1 > 0.0 && h2 > 0.0) {
        return None;
    }
    // y(s) = y2 + b s + c s², s = t − t2 (Newton form about the last node).
    let d1 = (y[1] - y[0]) / h1;
    let d2 = (y[2] - y[1]) / h2;
    let c = (d2 - d1) / (h1 + h2);
    let b = d2 + c * h2;
    let inside = |s: f64| s.is_finite() && s > 0.0 && s <= reach;
    let line = -y[2] / d2;
    let parabola = if c.abs() * reach * reach < 1e-9 * y[2].abs() {
        None
    } else {
        let disc = b * b - 4.0 * c * y[2];
        (disc >= 0.0)
            .then(|| {
                let q = -0.5 * (b + b.signum() * disc.sqrt());
                [q / c, y[2] / q]
                    .into_iter()
                    .filter(|&s| inside(s))
                    .min_by(f64::total_cmp)
            })
            .flatten()
    };
    let (s, slope, weights) = match parabola {
        // Lagrange's weights of the three nodes at t2 + s.
        Some(s) => {
            let x = t[2] + s;
            let w = [
                (x - t[1]) * (x - t[2]) / ((t[0] - t[1]) * (t[0] - t[2])),
                (x - t[0]) * (x - t[2]) / ((t[1] - t[0]) * (t[1] - t[2])),
                (x - t[0]) * (x - t[1]) / ((t[2] - t[0]) * (t[2] - t[1])),
            ];
            (s, (b + 2.0 * c * s).abs(), w)
        }
        None => (line, d2.abs(), [0.0, -line / h2, 1.0 + line / h2]),
    };
    let noise_gain = weights.iter().map(|w| w * w).sum::<f64>().sqrt();
    (inside(s) && slope > 0.0 && noise_gain.is_finite()).then_some(Crossing {
        t_s: t[2] + s,
        slope,
        noise_gain,
    })
}

/// Where an approach crosses its latched level, read off samples.
struct Approach {
    /// Where the approach, extrapolated, crosses the latched level \[s\].
    crossing_s: f64,
    /// Index of the first sample with the switch closed.
    closes: usize,
    /// The approach rate \[deg/s\].
    rate_deg_s: f64,
    /// The crossing's error for a noise σ̂ = 1 deg on each sample \[s/deg\].
    noise_s_per_deg: f64,
}

/// The approach of joint `j` (0-based) to its latch in the samples `t_s`,
/// `phi` with the switches `switches` (every joint's), when its switch
/// closes once for good and the approach is clear of the noise
/// `sigma_deg`: the parabola through its last three samples clear of the
/// latched level, extrapolated to it.
fn approach(
    t_s: &[f64],
    phi: &[f64],
    switches: &[Vec<bool>],
    j: usize,
    sigma_deg: f64,
) -> Option<Approach> {
    let switch = switches.get(j)?;
    let n = t_s.len().min(switch.len()).min(phi.len());
    let closes = switch.iter().take(n).position(|&s| s)?;
    if closes < 4 || switch[closes..n].iter().any(|&s| !s) {
        return None;
    }
    let level = median(
        phi.get(closes + 2..(closes + 2 + LEVEL_SAMPLES).min(n))?
            .to_vec(),
    )?;
    if n < closes + 2 + LEVEL_SAMPLES / 3 {
        return None;
    }
    let y = |i: usize| phi[i] - level;
    let clear = APPROACH_SIGMAS * sigma_deg.max(1e-6);
    let side = y(closes - 1).signum();
    if side * y(closes - 1) <= clear {
        return None;
    }
    let mut k = closes - 1;
    while k + 1 < n && k < closes + MAX_LATE_SAMPLES && side * y(k + 1) > clear {
        k += 1;
    }
    // Another latch closing over the approach changes every rate at once
    // (the plastic impulse of physics.md §5): no parabola spans it.
    let others_change = switches.iter().enumerate().any(|(o, s)| {
        o != j && (k - 3..=k + 1).any(|i| s.get(i).zip(s.get(i + 1)).is_some_and(|(a, b)| a != b))
    });
    if others_change {
        return None;
    }
    let ts = [t_s[k - 2], t_s[k - 1], t_s[k]];
    let ys = [y(k - 2), y(k - 1), y(k)];
    // The approach: every sample clear of the level and closing on it.
    if ys.iter().any(|v| side * v <= clear)
        || !(side * ys[0] > side * ys[1] && side * ys[1] > side * ys[2])
    {
        return None;
    }
    let h = t_s.get(k + 1).map_or(ts[2] - ts[1], |t1| t1 - ts[2]);
    let x = crossing(ts, ys, 1.5 * h)?;
    Some(Approach {
        crossing_s: x.t_s,
        closes,
        rate_deg_s: ((ys[2] - ys[1]) / (ts[2] - ts[1])).abs(),
        noise_s_per_deg: x.noise_gain / x.slope,
    })
}

/// The model's run of a mechanism sampled [`MODEL_PHASES`] times finer
/// than the run's period: [`model_errors`] reads it at every phase of the
/// sample clock.
struct FineModel {
    traj: Trajectory,
}

/// Phases of the sample clock at which [`model_errors`] reads the model.
const MODEL_PHASES: usize = 16;

impl FineModel {
    /// The model of run `r` of `campaign` (its mechanism as given, no
    /// effect) over the run's length at `period_s` / [`MODEL_PHASES`].
    fn of(campaign: &Campaign, r: usize, period_s: f64) -> Option<FineModel> {
        let cr = campaign.runs.get(r)?;
        let end = *cr.run.t_s.last()?;
        let step = period_s / MODEL_PHASES as f64;
        if !(step > 0.0 && end.is_finite() && end / step < 1e7) {
            return None;
        }
        let times: Vec<f64> = (0..=(end / step).ceil() as usize)
            .map(|k| k as f64 * step)
            .collect();
        let opts = fit_sim_options_for(&cr.mechanism);
        let traj = deployment::simulate_at(&cr.mechanism, &[], &opts, &times).ok()?;
        Some(FineModel { traj })
    }

    /// Every [`MODEL_PHASES`]-th sample from `phase` on.
    fn at_phase(&self, phase: usize, j: usize) -> (Vec<f64>, Vec<f64>, Vec<Vec<bool>>) {
        let pick = |v: &[f64]| {
            v.iter()
                .skip(phase)
                .step_by(MODEL_PHASES)
                .copied()
                .collect()
        };
        let t = pick(&self.traj.t_s);
        let phi = self.traj.phi_deg.get(j).map_or_else(Vec::new, |p| pick(p));
        let switches = self
            .traj
            .latched
            .iter()
            .map(|s| {
                s.iter()
                    .skip(phase)
                    .step_by(MODEL_PHASES)
                    .copied()
                    .collect()
            })
            .collect();
        (t, phi, switches)
    }
}

/// The least and the greatest error of [`approach`]'s crossing on the
/// model's own run (noise-free) at joint `j` (0-based), over the phases of
/// the sample clock: where it puts the crossing minus the instant the
/// model latched \[s\]. The extrapolation cannot see what the last
/// sample's interval holds: on a tape spring, the peak of its unfolding
/// curve within a degree of the latch throws a slow joint at it
/// milliseconds early, by how much depending on where the last sample
/// falls (`docs/diagnosis.md`, "An encoder late on its switch"). `None`
/// when the model does not latch there once for good.
fn model_errors(model: &FineModel, j: usize, sigma_deg: f64) -> Option<(f64, f64)> {
    let latched_s = (*model.traj.latch_s.get(j)?)?;
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for phase in 0..MODEL_PHASES {
        let (t, phi, switches) = model.at_phase(phase, j);
        if let Some(a) = approach(&t, &phi, &switches, j, sigma_deg) {
            let e = a.crossing_s - latched_s;
            if e.is_finite() {
                (lo, hi) = (lo.min(e), hi.max(e));
            }
        }
    }
    (lo <= hi).then_some((lo, hi))
}

/// The latching of joint `j` (0-based) in run `r` of `campaign`, when its
/// latch is ideal, closes once for good and the encoder's approach to it
/// is clear of the noise `sigma_deg`. `model` is the model's run
/// ([`FineModel`]): the crossing's error there, over every phase of the
/// sample clock ([`model_errors`]), widens the delay the latching allows.
fn latching(
    campaign: &Campaign,
    r: usize,
    j: usize,
    sigma_deg: f64,
    model: Option<&FineModel>,
) -> Option<Latching> {
    let a = readable(campaign, r, j, sigma_deg)?;
    let run = &campaign.runs.get(r)?.run;
    let model_error_s = model.and_then(|m| model_errors(m, j, sigma_deg));
    // The crossing read is `t* + d + e`, the error `e` within what the
    // model shows (zero included): `d = crossing − t* − e`.
    let (e_lo, e_hi) = model_error_s.map_or((0.0, 0.0), |(lo, hi)| (lo.min(0.0), hi.max(0.0)));
    let (open_s, closed_s) = (run.t_s[a.closes - 1], run.t_s[a.closes]);
    let slack = NOISE_SLACK_SIGMAS * sigma_deg * a.noise_s_per_deg
        + JITTER_SLACK_PERIODS * (closed_s - open_s);
    Some(Latching {
        run: r,
        joint: j + 1,
        crossing_s: a.crossing_s,
        model_error_s,
        open_s,
        closed_s,
        rate_deg_s: a.rate_deg_s,
        lo_s: a.crossing_s - closed_s - e_hi - slack,
        hi_s: a.crossing_s - open_s - e_lo + slack,
    })
}

/// The encoder's approach to the latch of joint `j` (0-based) in run `r`
/// of `campaign`, when its latch is ideal, closes once for good and the
/// approach is clear of the noise `sigma_deg` ([`approach`]).
fn readable(campaign: &Campaign, r: usize, j: usize, sigma_deg: f64) -> Option<Approach> {
    let cr = campaign.runs.get(r)?;
    let (run, mech) = (&cr.run, &cr.mechanism);
    if mech.latch(j).is_some() || mech.truss.is_some() {
        return None;
    }
    approach(&run.t_s, run.phi_deg.get(j)?, &run.latch, j, sigma_deg)
}

/// The run's median sample step \[s\].
fn period_s(campaign: &Campaign) -> Option<f64> {
    let t = &campaign.runs.first()?.run.t_s;
    median(t.windows(2).map(|w| w[1] - w[0]).collect())
}

/// The delay of the campaign's encoders behind their latch switches, from
/// every ideal latch that closes once for good, against the noise σ̂
/// `sigma_deg`, each widened by the extrapolation's error on the model's
/// run of the mechanism as given ([`model_errors`]); `None` when fewer than [`MIN_LATCHINGS`] latchings are
/// read or when they do not agree (more than one in five outside the best
/// value). Where zero delay agrees with them as well as any,
/// [`EncoderDelay::allows_zero`] says so.
pub fn estimate(campaign: &Campaign, sigma_deg: f64) -> Option<EncoderDelay> {
    if !sigma_deg.is_finite() {
        return None;
    }
    let period = period_s(campaign)?;
    // The model is simulated only for a run with a latching to read: none
    // on a truss wing or a wing of physical latches.
    let models: Vec<Option<FineModel>> = (0..campaign.runs.len())
        .map(|r| {
            (0..campaign.runs[r].run.joints())
                .any(|j| readable(campaign, r, j, sigma_deg).is_some())
                .then(|| FineModel::of(campaign, r, period))
                .flatten()
        })
        .collect();
    let latchings: Vec<Latching> = (0..campaign.runs.len())
        .flat_map(|r| (0..campaign.runs[r].run.joints()).map(move |j| (r, j)))
        .filter_map(|(r, j)| latching(campaign, r, j, sigma_deg, models[r].as_ref()))
        .filter(|l| l.lo_s.is_finite() && l.hi_s.is_finite() && l.lo_s <= l.hi_s)
        .collect();
    if latchings.len() < MIN_LATCHINGS {
        return None;
    }
    let count = |d: f64| {
        latchings
            .iter()
            .filter(|l| l.lo_s <= d && d <= l.hi_s)
            .count()
    };
    let mut ends: Vec<f64> = latchings.iter().flat_map(|l| [l.lo_s, l.hi_s]).collect();
    ends.sort_by(f64::total_cmp);
    // The value most latchings allow: the widest run of gaps between ends
    // with the highest count.
    let (mut best, mut lo, mut hi) = (0usize, 0.0, 0.0);
    for w in ends.windows(2) {
        let c = count(0.5 * (w[0] + w[1]));
        if c > best {
            (best, lo, hi) = (c, w[0], w[1]);
        } else if c == best && w[0] <= hi {
            hi = w[1];
        }
    }
    let need = latchings.len() - latchings.len() / 5;
    if best < need {
        return None;
    }
    Some(EncoderDelay {
        allows_zero: count(0.0) >= need || (lo <= 0.0 && 0.0 <= hi),
        delay_s: 0.5 * (lo + hi),
        lo_s: lo,
        hi_s: hi,
        agreeing: best,
        latchings,
        period_s: period,
        from: DelayFrom::Latchings,
    })
}

/// The campaign compared with the model at its stamps minus `delay_s`:
/// each sample's time is `t − d`; a sample the encoder took before the
/// release (`t ≤ d`) reads the stowed rest and is placed just after
/// `t = 0` (1 ns apart, the times strictly increasing), where the model
/// has not moved. A delay ≤ 0 leaves the campaign as it is.
pub fn shifted(campaign: &Campaign, delay_s: f64) -> Campaign {
    let mut out = campaign.clone();
    if !(delay_s > 0.0) {
        return out;
    }
    for cr in &mut out.runs {
        for (i, t) in cr.run.t_s.iter_mut().enumerate() {
            *t = (*t - delay_s).max(i as f64 * 1e-9);
        }
    }
    out
}

/// The delay in `[lo, hi]` \[s\] where `sse` (the model's SSE with the
/// angles compared at their stamps minus the delay) is least, by golden
/// section down to [`REFINE_TOLERANCE_PERIODS`] of `period_s`; `None` values (a failed fit) count as worst. The middle when
/// every value fails.
pub fn refine(lo: f64, hi: f64, period_s: f64, sse: impl Fn(f64) -> Option<f64>) -> f64 {
    let f = |d: f64| sse(d).filter(|v| v.is_finite()).unwrap_or(f64::INFINITY);
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let (mut a, mut b) = (lo, hi);
    let (mut x1, mut x2) = (b - r * (b - a), a + r * (b - a));
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..REFINE_STEPS {
        if b - a < REFINE_TOLERANCE_PERIODS * period_s {
            break;
        }
        if f1 <= f2 {
            (b, x2, f2) = (x2, x1, f1);
            x1 = b - r * (b - a);
            f1 = f(x1);
        } else {
            (a, x1, f1) = (x1, x2, f2);
            x2 = a + r * (b - a);
            f2 = f(x2);
        }
    }
    match (f1.is_finite(), f2.is_finite()) {
        (false, false) => 0.5 * (lo + hi),
        _ if f1 <= f2 => x1,
        _ => x2,
    }
}

/// [`shifted`] by what a diagnosis took out (`None`: the campaign as it is).
pub fn apply(campaign: &Campaign, delay: Option<&EncoderDelay>) -> Campaign {
    match delay {
        Some(d) if d.taken_out() => shifted(campaign, d.delay_s),
        _ => campaign.clone(),
    }
}

/// The delay in words, for the progress and the report.
pub fn words(d: &EncoderDelay) -> String {
    let ms = |s: f64| s * 1e3;
    if d.taken_out() {
        format!(
            "the encoders read {:.2} ms ({:.2} samples) behind their latch switches ({} of {} latchings allow {:.1} to {:.1} ms{}): the angles are compared with the model at their stamps minus {:.2} ms",
            ms(d.delay_s),
            d.periods(),
            d.agreeing,
            d.latchings.len(),
            ms(d.lo_s),
            ms(d.hi_s),
            match d.from {
                DelayFrom::Latchings => "; their middle taken",
                DelayFrom::Model => "; the model found fits best there",
            },
            ms(d.delay_s)
        )
    } else {
        format!(
            "the latch switches close {:.1} ms ({:.2} samples; {:.1} to {:.1} ms) after the encoders reach their latched angles, by {} of {} latchings: the angles are compared at their stamps (the fit reads no switch)",
            ms(-d.delay_s),
            -d.periods(),
            ms(-d.hi_s),
            ms(-d.lo_s),
            d.agreeing,
            d.latchings.len()
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three samples of `y = 0.01 − 4 (t − 0.5)²` cross zero at 0.45, the
    /// first root beyond the last node, exactly; the noise gain is the norm
    /// of Lagrange's weights there.
    #[test]
    fn the_crossing_of_a_parabola_is_exact_and_its_noise_gain_grows_with_the_reach() {
        let f = |t: f64| 0.01 - (t - 0.5) * (t - 0.5) * 4.0;
        let t = [0.0, 0.1, 0.2];
        let y = [f(t[0]), f(t[1]), f(t[2])];
        // Roots at 0.45 and 0.55; the first after 0.2 within reach.
        let x = crossing(t, y, 0.3).expect("a crossing");
        assert!((x.t_s - 0.45).abs() < 1e-12, "{x:?}");
        assert!((x.slope - 0.4).abs() < 1e-9, "{x:?}");
        // Extrapolating 2.5 steps beyond the last node: the weights are
        // those of the Lagrange basis at x = 4.5 (nodes 0, 1, 2).
        let (l0, l1, l2): (f64, f64, f64) = (3.5 * 2.5 / 2.0, -4.5 * 2.5, 4.5 * 3.5 / 2.0);
        let gain = (l0 * l0 + l1 * l1 + l2 * l2).sqrt();
        assert!((x.noise_gain - gain).abs() < 1e-9, "{x:?} against {gain}");
        // The parabola out of reach: the line through the last two (0.325).
        let line = crossing(t, y, 0.2).expect("the line's crossing");
        assert!((line.t_s - 0.325).abs() < 1e-12, "{line:?}");
        // Both out of reach: none.
        assert!(crossing(t, y, 0.1).is_none());
    }

    #[test]
    fn a_straight_approach_crosses_where_its_line_does_with_the_line_weights() {
        let t = [0.0, 0.01, 0.02];
        let y = [3.0, 2.0, 1.0];
        let x = crossing(t, y, 0.015).expect("a crossing");
        assert!((x.t_s - 0.03).abs() < 1e-12, "{x:?}");
        assert!((x.slope - 100.0).abs() < 1e-9, "{x:?}");
        // One step beyond: weights 0, −1, 2.
        assert!((x.noise_gain - 5f64.sqrt()).abs() < 1e-9, "{x:?}");
    }
}
