//! The latch as built, a finding of its own (`docs/diagnosis.md`, "Runs of
//! a physical latch"): each joint's latch events in the runs against those
//! of the drawing's latch, simulated with the effects found, compared by
//! their statistics — impacts, escapes, the largest rebound that stayed in,
//! the hold, and the stop's restitution — never by their phase.

use crate::analysis::campaign_sim::CampaignSim;
use crate::analysis::latch_events::{events, travel_deg, LatchEvents};
use crate::data::campaign::Campaign;
use crate::model::effect::{Effect, EffectKind};
use crate::model::latch::LatchTolerance;
use crate::simulate::deployment::Trajectory;
use rayon::prelude::*;

/// Slack on the crest for an escape \[deg\]: about the encoder's resolution
/// (0.022°), so that noise at the crest does not count as an escape.
const ESCAPE_SLACK_DEG: f64 = 0.03;

/// Impacts slower than this [deg/s] give no restitution: at 100 Hz and
/// 0.02° of noise a rate from two samples has an error of about 3 deg/s.
const MIN_IMPACT_RATE_DEG_S: f64 = 20.0;

/// Fewest impacts for a restitution with an interval.
const MIN_RESTITUTION_IMPACTS: usize = 3;

/// A median over a joint's impacts or rebounds with its interval: the
/// stop's apparent restitution (the rate out over the rate in, from the
/// samples either side of each switch closing \[1\]), or the rebounds' hold
/// deceleration ([`crate::analysis::latch_events::Flight`], [deg/s²]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Restitution {
    /// Median over the impacts or rebounds.
    pub median: f64,
    /// 95 % interval of the median (order statistics).
    pub ci95: [f64; 2],
    /// Impacts (or rebounds) used.
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
    /// The drawing's latch itself with the effects found, run by run.
    pub drawing: Vec<Option<LatchEvents>>,
    /// The measured restitution, when enough impacts give one.
    pub restitution: Option<Restitution>,
    /// What the drawing's latch gives within its tolerances.
    pub spread: Spread,
    /// The plunger weakenings \[1\] consistent with the measured events
    /// (escapes, runs ending within the crest, hold deceleration), when the
    /// latch holds less than drawn (a magnet weakening may do the same: the
    /// runs do not tell them apart).
    pub weakening: Option<Range<f64>>,
    /// What differs from the drawing's latch (empty: the events are the
    /// drawing's, within what their statistics tell); in words by
    /// `report::diagnosis_latch`.
    pub differs: Vec<LatchDifference>,
    /// Statistics outside the drawing's spread (the one the report prints)
    /// but within what a reading gives over these runs: the escapes beyond
    /// the spread by at most [`ESCAPE_MARGIN`]. The runs
    /// cannot tell such a latch from the drawing's; the report says so
    /// instead of "as the drawing's latch gives".
    pub undecided: Vec<LatchDifference>,
    /// What the runs tell of the latch as built.
    pub cause: Option<LatchCause>,
    /// What the drawn latch holds with: the causes `cause` can name.
    pub parts: LatchParts,
    /// The measured hold deceleration, when enough rebounds that stayed in
    /// give one (median over the rebounds' parabolas, [deg/s²]; `impacts`
    /// counts the rebounds).
    pub hold_accel: Option<Restitution>,
}

/// Which way a measured statistic lies outside the drawing's spread.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// Below the spread.
    Below,
    /// Above the spread.
    Above,
}

/// One way a joint's latch events differ from the drawing's.
#[derive(Clone, Debug, PartialEq)]
pub enum LatchDifference {
    /// Escapes over the plunger beyond the drawing's spread (by more than
    /// [`ESCAPE_MARGIN`]).
    Escapes {
        /// Escapes in the runs.
        measured: usize,
        /// The drawing's spread within its tolerances.
        drawing: Range<usize>,
    },
    /// Runs ending within the crest outside the drawing's spread.
    EndsHeld {
        /// Runs that end within the crest.
        measured: usize,
        /// Runs of the campaign.
        runs: usize,
        /// The drawing's spread within its tolerances.
        drawing: Range<usize>,
    },
    /// The stop's apparent restitution outside the drawing's spread:
    /// [`Side::Below`], the stop damps more than drawn.
    Restitution {
        /// The measured median and interval \[1\].
        measured: Restitution,
        /// The drawing's spread within its tolerances \[1\].
        drawing: Range<f64>,
        /// Which way.
        side: Side,
    },
    /// The hold deceleration of the rebounds that stayed in outside the
    /// drawing's spread widened by [`ACCEL_MARGIN`]: [`Side::Below`], the
    /// latch pulls back less than drawn.
    HoldAccel {
        /// The measured median and interval [deg/s²].
        measured: Restitution,
        /// The drawing's spread within its tolerances (not widened) [deg/s²].
        drawing: Range<f64>,
        /// Which way.
        side: Side,
    },
}

/// What a joint's drawn latch holds with besides its stop: a ball
/// plunger or a pawl (whose spring the core takes as a plunger's), and a
/// magnet or none.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LatchParts {
    /// A pawl (`[joint.latch.pawl]`), not a ball plunger.
    pub pawl: bool,
    /// A magnet (`[joint.latch.magnet]`).
    pub magnet: bool,
}

impl LatchParts {
    /// The parts of joint `j`'s (0-based) drawn latch, from the first run's
    /// mechanism that has one.
    fn of(c: &Campaign, j: usize) -> LatchParts {
        c.runs
            .iter()
            .find_map(|r| r.mechanism.latch(j))
            .map(|l| LatchParts {
                pawl: l.pawl.is_some(),
                magnet: l.magnet.is_some(),
            })
            .unwrap_or_default()
    }
}

/// What the runs tell of a joint's latch as built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LatchCause {
    /// It holds less than drawn: a weaker plunger or magnet (the runs do
    /// not tell which).
    HoldsLess,
    /// It holds more than drawn: a stronger plunger or magnet, or a stop
    /// that damps more (the runs tell neither which nor by how much).
    HoldsMore,
    /// It differs from the drawing both ways over the runs.
    BothWays,
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

/// Rate ratios out/in at each closing of the switch, `t` the times \[s\],
/// `u` the travel \[deg\].
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

/// Relative margin on the ensemble's range of hold decelerations: each
/// member's median comes from a handful of rebounds itself, so 9 members
/// under-cover the spread (on the campaigns of `docs/diagnosis.md`, "Runs
/// of a physical latch", a clean campaign's interval comes close to the
/// range's edge, a weakened plunger's well below it: their figures are
/// docs/measured.md's).
pub const ACCEL_MARGIN: f64 = 0.25;

/// As-built draws of each drawing simulated beside the drawing itself: the
/// spread of a latch's statistics that its tolerances give
/// ([`LatchTolerance::default`]). Forty members in all: a count outside
/// their range by more than [`ESCAPE_MARGIN`] is one the drawing gives
/// in fewer than about one draw in forty.
pub const ENSEMBLE: usize = 39;

/// Escapes beyond the drawing's range before they are a finding: the
/// count read from measured angles at the encoder's resolution moves by
/// about one (on the 48 physical-latch campaigns of `docs/diagnosis.md`,
/// latches as built and nothing weakened, 2 of 120 joints read one
/// escape outside the range, none more: `DEPLOYWATCH_FULL=1 cargo test
/// -p deploywatch-tests --test diagnosis_physical_latch -- --nocapture`,
/// docs/measured.md).
pub const ESCAPE_MARGIN: usize = 1;

/// Members of the ensemble of each plunger weakening tried (the drawing
/// and as-built draws): enough to bound the escapes it gives.
pub const WEAKENING_MEMBERS: usize = 5;

/// Seed of the ensemble's draws (fixed: the same runs give the same report).
const ENSEMBLE_SEED: u64 = 0x1a7c4;

/// Plunger weakenings tried when a joint escapes more than its drawing's
/// spread allows \[1\].
pub const WEAKENINGS: [f64; 8] = [0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9];

/// The range over an ensemble of one count or value: `[least, most]`.
pub type Range<T> = [T; 2];

/// What the drawing's latch gives over its ensemble ([`ENSEMBLE`] as-built
/// draws and the drawing), summed over the campaign's runs.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Spread {
    /// Impacts.
    pub impacts: Range<usize>,
    /// Escapes.
    pub escapes: Range<usize>,
    /// Runs that end within the crest (held or still bouncing in).
    pub held: Range<usize>,
    /// Median restitution of each member.
    pub restitution: Option<Range<f64>>,
    /// Median hold deceleration of each member [deg/s²].
    pub hold_accel: Option<Range<f64>>,
}

/// A joint's statistics over the runs of one simulated or measured set.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Tally {
    impacts: usize,
    escapes: usize,
    held: usize,
    restitution: Option<f64>,
    accel: Option<f64>,
}

fn widen<T: PartialOrd + Copy>(r: Option<Range<T>>, x: T) -> Range<T> {
    match r {
        None => [x, x],
        Some([a, b]) => [if x < a { x } else { a }, if x > b { x } else { b }],
    }
}

/// The campaign's runs simulated on `members` as-built draws of their
/// mechanisms (member 0 the drawing itself) with `effects`: `[member][run]`.
fn ensemble(c: &Campaign, effects: &[Effect], members: usize) -> Vec<Vec<Option<Trajectory>>> {
    use rand::{Rng, SeedableRng};
    (0..members)
        .into_par_iter()
        .map(|k| {
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(ENSEMBLE_SEED + k as u64);
            let mut uniform = || rng.gen::<f64>();
            let tol = LatchTolerance::default();
            let mut built = c.clone();
            for r in built.runs.iter_mut() {
                if k > 0 {
                    r.mechanism = r.mechanism.as_built(&tol, &mut uniform);
                }
            }
            (0..built.runs.len())
                .map(|i| built.simulate_with(i, effects, &latch_options()).ok())
                .collect()
        })
        .collect()
}

/// The settings of the ensemble's runs: the simulator's default accuracy
/// (rtol 1e-8) over the whole runs, the energy ledger booked but not
/// enforced. Not the fit's 1e-7 ([`crate::analysis::campaign_sim::FIT_RTOL`]):
/// the free motion it fits converges there, but a latch that rattles does
/// not, and its events are what the ensemble counts (a plunger escaped
/// over 6 times at 1e-6 and 1e-7, 8 to 10 at 1e-8 to 1e-10: `cargo run
/// --release -p deploywatch-sim --example latch_tolerance`).
fn latch_options() -> crate::simulate::deployment::SimOptions {
    crate::simulate::deployment::SimOptions {
        stop_when_deployed: false,
        max_drift: f64::INFINITY,
        ..Default::default()
    }
}

/// One joint's series of one run: times, travel \[deg\], switch.
type Series<'a> = (&'a [f64], Vec<f64>, &'a [bool]);

/// The tally of joint `j` over the runs `runs` of `c`, from `series(i)`.
fn tally<'a>(
    c: &Campaign,
    j: usize,
    series: impl Fn(usize) -> Option<(&'a [f64], &'a [f64], &'a [bool])>,
) -> Option<(Tally, Vec<LatchEvents>)> {
    let mut t = Tally::default();
    let mut all = Vec::new();
    let mut ratios_all = Vec::new();
    let mut accels = Vec::new();
    for (i, cr) in c.runs.iter().enumerate() {
        let (Some(latch), Some(spec)) = (cr.mechanism.latch(j), cr.mechanism.joints.get(j)) else {
            continue;
        };
        let (ts, phi, sw) = series(i)?;
        let s: Series = (
            ts,
            phi.iter()
                .map(|&p| travel_deg(spec.stowed_deg, p))
                .collect(),
            sw,
        );
        // The crest, or a pawl's notch and give: beyond it the joint is out.
        let crest = latch.hold_limit_deg(spec.stowed_deg);
        let e = events(s.0, &s.1, s.2, crest, ESCAPE_SLACK_DEG);
        ratios_all.extend(ratios(s.0, &s.1, s.2));
        accels.extend(e.flights.iter().map(|f| f.accel_deg_s2));
        t.impacts += e.impacts;
        t.escapes += e.escapes;
        t.held += usize::from(e.first_contact_s.is_some() && e.end_travel_deg <= crest);
        all.push(e);
    }
    t.restitution = median_ci(ratios_all).map(|r| r.median);
    t.accel = median_ci(accels).map(|r| r.median);
    Some((t, all))
}

/// The latch findings of a campaign, joint by joint for every joint with a
/// physical latch in some run: the measured events against the spread the
/// drawing's latch gives with `effects` (the effects found) over
/// [`ENSEMBLE`] as-built draws, each simulated over the whole runs; where a
/// joint escapes more than that spread allows, the plunger weakenings that
/// give its escapes.
pub fn latch_findings(c: &Campaign, effects: &[Effect]) -> Vec<LatchFinding> {
    let sims = ensemble(c, effects, ENSEMBLE + 1);
    (0..c.max_joints())
        .filter_map(|j| {
            if !c.runs.iter().any(|r| r.mechanism.latch(j).is_some()) {
                return None;
            }
            let run = |i: usize| -> Option<(&[f64], &[f64], &[bool])> {
                let r = &c.runs[i].run;
                Some((&r.t_s, r.phi_deg.get(j)?, r.latch.get(j)?))
            };
            let (meas, measured) = tally(c, j, run)?;
            let mut spread: Option<(Range<usize>, Range<usize>, Range<usize>)> = None;
            let mut rest: Option<Range<f64>> = None;
            let (mut acc, mut acc_members): (Option<Range<f64>>, usize) = (None, 0);
            let mut drawing = Vec::new();
            for (k, member) in sims.iter().enumerate() {
                let sim = |i: usize| -> Option<(&[f64], &[f64], &[bool])> {
                    let t = member.get(i)?.as_ref()?;
                    Some((&t.t_s, t.phi_deg.get(j)?, t.latched.get(j)?))
                };
                let Some((t, evs)) = tally(c, j, sim) else {
                    continue;
                };
                if k == 0 {
                    drawing = evs.into_iter().map(Some).collect();
                }
                spread = Some(match spread {
                    None => ([t.impacts; 2], [t.escapes; 2], [t.held; 2]),
                    Some((a, b, h)) => (
                        widen(Some(a), t.impacts),
                        widen(Some(b), t.escapes),
                        widen(Some(h), t.held),
                    ),
                });
                if let Some(r) = t.restitution {
                    rest = Some(widen(rest, r));
                }
                if let Some(a) = t.accel {
                    acc = Some(widen(acc, a));
                    acc_members += 1;
                }
            }
            let (impacts, escapes, held) = spread?;
            let mut f = LatchFinding {
                joint: j + 1,
                measured,
                drawing,
                restitution: None,
                spread: Spread {
                    impacts,
                    escapes,
                    held,
                    restitution: rest,
                    // A spread of a few members' medians is no spread.
                    hold_accel: acc.filter(|_| 2 * acc_members > ENSEMBLE),
                },
                hold_accel: None,
                differs: Vec::new(),
                undecided: Vec::new(),
                cause: None,
                parts: LatchParts::of(c, j),
                weakening: None,
            };
            f.restitution = measured_restitution(c, j);
            f.hold_accel = median_ci(
                f.measured
                    .iter()
                    .flat_map(|e| e.flights.iter().map(|x| x.accel_deg_s2))
                    .collect(),
            );
            compare(&mut f, &meas);
            if f.cause == Some(LatchCause::HoldsLess) {
                f.weakening = weakening_range(c, effects, j, &meas, f.hold_accel);
            }
            Some(f)
        })
        .collect()
}

/// The measured restitution of joint `j` with its interval.
fn measured_restitution(c: &Campaign, j: usize) -> Option<Restitution> {
    let mut r = Vec::new();
    for cr in &c.runs {
        let (Some(_), Some(spec)) = (cr.mechanism.latch(j), cr.mechanism.joints.get(j)) else {
            continue;
        };
        let u: Vec<f64> = cr.run.phi_deg[j]
            .iter()
            .map(|&p| travel_deg(spec.stowed_deg, p))
            .collect();
        r.extend(ratios(&cr.run.t_s, &u, &cr.run.latch[j]));
    }
    median_ci(r)
}

/// The plunger weakenings of [`WEAKENINGS`] whose simulated runs at joint
/// `j` (0-based; [`WEAKENING_MEMBERS`] members each) are consistent with
/// the measured `m`: their range of escapes and of runs ending within the
/// crest includes the measured count, and, when the rebounds give a hold
/// deceleration `accel`, their range of it (widened by [`ACCEL_MARGIN`])
/// meets its interval. `[least, most]`, `None` when none is.
fn weakening_range(
    c: &Campaign,
    effects: &[Effect],
    j: usize,
    m: &Tally,
    accel: Option<Restitution>,
) -> Option<Range<f64>> {
    let consistent: Vec<f64> = WEAKENINGS
        .par_iter()
        .filter(|&&w| {
            let mut with = effects.to_vec();
            with.push(Effect::joint(EffectKind::PlungerWeakening, j + 1, w));
            let sims = ensemble(c, &with, WEAKENING_MEMBERS);
            let (mut esc, mut held, mut acc) = (None, None, None);
            for member in &sims {
                let sim = |i: usize| -> Option<(&[f64], &[f64], &[bool])> {
                    let t = member.get(i)?.as_ref()?;
                    Some((&t.t_s, t.phi_deg.get(j)?, t.latched.get(j)?))
                };
                if let Some((t, _)) = tally(c, j, sim) {
                    esc = Some(widen(esc, t.escapes));
                    held = Some(widen(held, t.held));
                    if let Some(a) = t.accel {
                        acc = Some(widen(acc, a));
                    }
                }
            }
            let within =
                |x: usize, r: Option<Range<usize>>| r.is_some_and(|[a, b]| a <= x && x <= b);
            let accel_ok = match (accel, acc) {
                (Some(a), Some([lo, hi])) => {
                    a.ci95[1] >= lo * (1.0 - ACCEL_MARGIN) && a.ci95[0] <= hi * (1.0 + ACCEL_MARGIN)
                }
                _ => true,
            };
            within(m.escapes, esc) && within(m.held, held) && accel_ok
        })
        .copied()
        .collect();
    Some([*consistent.first()?, *consistent.last()?])
}

/// Fills `differs`, `undecided` and `cause`: escapes, runs ending held, or a
/// restitution outside what the drawing's spread gives.
fn compare(f: &mut LatchFinding, m: &Tally) {
    let sp = f.spread.clone();
    let outside = |x: usize, r: Range<usize>| x < r[0] || x > r[1];
    // Escapes read from measured angles: beyond the range of the
    // ensemble's forty draws by more than a reading's margin.
    let far = |x: usize, r: Range<usize>| x > r[1] + ESCAPE_MARGIN || x + ESCAPE_MARGIN < r[0];
    let runs = f.measured.len();
    let (mut weaker, mut stronger) = (false, false);
    if outside(m.escapes, sp.escapes) {
        let d = LatchDifference::Escapes {
            measured: m.escapes,
            drawing: sp.escapes,
        };
        if far(m.escapes, sp.escapes) {
            f.differs.push(d);
            weaker |= m.escapes > sp.escapes[1];
            stronger |= m.escapes < sp.escapes[0];
        } else {
            f.undecided.push(d);
        }
    }
    if outside(m.held, sp.held) {
        f.differs.push(LatchDifference::EndsHeld {
            measured: m.held,
            runs,
            drawing: sp.held,
        });
        weaker |= m.held < sp.held[0];
        stronger |= m.held > sp.held[1];
    }
    if let (Some(r), Some([lo, hi])) = (f.restitution, sp.restitution) {
        if r.ci95[1] < lo || r.ci95[0] > hi {
            f.differs.push(LatchDifference::Restitution {
                measured: r,
                drawing: [lo, hi],
                side: if r.ci95[1] < lo {
                    Side::Below
                } else {
                    Side::Above
                },
            });
        }
    }
    if let (Some(a), Some([lo, hi])) = (f.hold_accel, sp.hold_accel) {
        // The rebounds' deceleration: what holds the joint against the
        // stop (plunger on its hold ramp, magnet, spring) per inertia.
        let (lo_w, hi_w) = (lo * (1.0 - ACCEL_MARGIN), hi * (1.0 + ACCEL_MARGIN));
        if a.ci95[1] < lo_w || a.ci95[0] > hi_w {
            let less = a.ci95[1] < lo_w;
            f.differs.push(LatchDifference::HoldAccel {
                measured: a,
                drawing: [lo, hi],
                side: if less { Side::Below } else { Side::Above },
            });
            weaker |= less;
            stronger |= !less;
        }
    }
    f.cause = match (weaker, stronger) {
        (true, false) => Some(LatchCause::HoldsLess),
        (false, true) => Some(LatchCause::HoldsMore),
        (true, true) => Some(LatchCause::BothWays),
        (false, false) => None,
    };
}

/// A finding at joint 1 of `runs` runs with `escapes` measured escapes and
/// `held` runs ending within the crest, compared with `spread` (no
/// restitution or hold deceleration measured): the comparison alone, for
/// the report's tests.
#[cfg(test)]
pub fn compare_for_test(runs: usize, spread: Spread, escapes: usize, held: usize) -> LatchFinding {
    let mut f = LatchFinding {
        joint: 1,
        measured: vec![LatchEvents::default(); runs],
        drawing: Vec::new(),
        restitution: None,
        spread,
        weakening: None,
        differs: Vec::new(),
        undecided: Vec::new(),
        cause: None,
        parts: LatchParts::default(),
        hold_accel: None,
    };
    let m = Tally {
        escapes,
        held,
        ..Tally::default()
    };
    compare(&mut f, &m);
    f
}
