//! The full deployment simulator: the core's chain equations in `f64`,
//! integrated by Dormand–Prince 5(4) ([`crate::simulate::ode`]) with event location on
//! the dense output for
//! - latches: `φ_j` reaching 0 from the stowed side, located to 1e-12 s,
//!   followed by the plastic impulse of `physics.md` section 5;
//! - tape-spring branch switches: `φ_j·φ̇_j` changing sign where folding and
//!   unfolding differ (seed 001 Eq. 1).
//!
//! Between events the right-hand side is smooth, so the error control sees
//! no discontinuity; every restart re-evaluates the derivative.

use crate::model::effect::{self, Effect};
use crate::model::mechanism::{with_joints, Mechanism, MAX_CHAIN_JOINTS};
use crate::model::torque_table::HostChain;
use crate::simulate::chain_ledger::{self, Booking, ChainLedger, Power, StagePowers};
use crate::simulate::chain_sampler::Sampler;
use crate::simulate::ode::{self, locate, State};
use crate::simulate::spring_knots::{self, Knots};
use crate::simulate::stowed::StowedWatch;
pub use crate::simulate::trajectory::{
    Samples, SimError, SimOptions, SimStats, Stall, Trajectory, MAX_SAMPLES, MAX_STEPS,
};
use deploywatch_core::{Branch, Mode};

mod event_log;
mod stick;
use event_log::{EventLog, SAME_INSTANT_S};

/// A joint this close to its latch angle on the stowed side \[rad\] latches
/// with the joint whose event fired: a located event leaves the angle a
/// rounding error from 0.
pub const LATCH_REACHED_RAD: f64 = 1e-12;

/// Simulates a mechanism with extra effects (sensor effects are ignored
/// here: see [`crate::simulate::sensor`]).
pub fn simulate(
    mech: &Mechanism,
    effects: &[Effect],
    opts: &SimOptions,
) -> Result<Trajectory, SimError> {
    simulate_samples(mech, effects, opts, sample_grid(mech, opts)?)
}

/// The output grid of [`simulate`]: `opts`' (or the mechanism's) duration
/// and rate.
pub fn sample_grid(mech: &Mechanism, opts: &SimOptions) -> Result<Samples<'static>, SimError> {
    let duration = opts.duration_s.unwrap_or(mech.duration_s);
    let rate = opts.sample_hz.unwrap_or(mech.sample_hz);
    let positive = |x: f64| x > 0.0 && x.is_finite();
    if !positive(duration) || !positive(rate) {
        return Err(SimError::Invalid(format!(
            "duration ({duration} s) and sample rate ({rate} Hz) must be positive"
        )));
    }
    // The grid is generated as the run goes: a long duration costs nothing
    // when the wing latches early.
    let times = Samples::grid(duration, rate);
    if matches!(times, Samples::Grid { count, .. } if count > MAX_SAMPLES)
        && !opts.stop_when_deployed
    {
        // The whole duration would be written: refuse before the work.
        return Err(SimError::TooManySamples { t_s: duration });
    }
    Ok(times)
}

/// Simulates a mechanism and samples it at the given times (sorted, from 0):
/// the time stamps of a measured run, so that model and run compare sample by
/// sample. With `opts.stop_when_deployed` the output ends at the first time
/// at or after the last latch; otherwise it covers every time given.
pub fn simulate_at(
    mech: &Mechanism,
    effects: &[Effect],
    opts: &SimOptions,
    times: &[f64],
) -> Result<Trajectory, SimError> {
    if times.first().is_some_and(|&t| t < 0.0) || times.windows(2).any(|w| !(w[1] > w[0])) {
        return Err(SimError::Invalid(
            "sample times must start at or after 0 and increase strictly".into(),
        ));
    }
    simulate_samples(mech, effects, opts, Samples::Listed(times))
}

/// [`simulate_at`] on any sample times.
fn simulate_samples(
    mech: &Mechanism,
    effects: &[Effect],
    opts: &SimOptions,
    times: Samples<'_>,
) -> Result<Trajectory, SimError> {
    // Latch and rig effects with nothing to act on are refused; a joint
    // with a physical latch: the latch simulator (`[joint.latch]`).
    crate::simulate::latch_deployment::check_latch_effects(mech, effects)?;
    mech.check_flexible().map_err(SimError::Invalid)?;
    if mech.has_physical_latch() {
        return crate::simulate::latch_deployment::simulate_physical(mech, effects, opts, times)
            .map(|run| run.traj);
    }
    if mech.active_rig().is_some() {
        // On the zero-g rig (`[rig]`, physics.md §11): the rig simulator.
        let list: Vec<f64> = (0..).map_while(|k| times.get(k)).collect();
        return crate::simulate::rig::simulate_rig(mech, effects, opts, &list).map(|r| r.traj);
    }
    if mech.truss.is_some() {
        // The one truss simulator (multibody), with the effects on its pins.
        return crate::simulate::truss_deployment::simulate_truss(mech, effects, opts, times)
            .map(|(traj, _)| traj);
    }
    let n = mech.joint_count();
    for e in effects {
        e.validate_joint(n)
            .map_err(|e| SimError::Invalid(e.to_string()))?;
    }
    let settle_s = opts.settle_s.unwrap_or(mech.settle_s);
    if !(settle_s >= 0.0 && settle_s.is_finite()) {
        return Err(SimError::Invalid(format!(
            "settle_s = {settle_s} s: expected a finite time ≥ 0"
        )));
    }
    let opts = SimOptions {
        settle_s: Some(settle_s),
        ..*opts
    };
    let (je, g) = effect::to_core(effects, n);
    let bad = || SimError::Invalid(format!("mechanism `{}` cannot be built", mech.name));
    let other = || {
        SimError::Invalid(format!(
            "mechanism `{}` has {n} joints; 1 to {MAX_CHAIN_JOINTS} are supported",
            mech.name
        ))
    };
    if mech.flexible.is_some() {
        // Flexible panels: the chain of 2n joints, hinges at the even ones.
        let traj = with_joints!(2 * n, M => run_chain_latching(
            &mech.flexible_chain::<M>(&je, g).ok_or_else(bad)?,
            crate::model::flex::latching::<M>(),
            times,
            &opts,
        ), else Err(other()))?;
        return Ok(traj.hinges_of_flexible());
    }
    with_joints!(n, N => run_chain(&mech.chain::<N>(&je, g).ok_or_else(bad)?, times, &opts), else Err(other()))
}

/// What the event search found in a step.
#[derive(Clone, Copy, Debug)]
enum Event {
    Latch(usize),
    Branch(usize),
    /// A stuck joint's holding torque leaves its band (`physics.md` §4a).
    Slip(usize),
    /// `|φ_j|` reaches a knot of its spring's curve on its branch
    /// ([`spring_knots`]): the step ends there, nothing else happens.
    Knot(usize),
}

impl Event {
    /// The joint (0-based).
    fn joint(self) -> usize {
        match self {
            Event::Latch(j) | Event::Branch(j) | Event::Slip(j) | Event::Knot(j) => j,
        }
    }
}

/// The integrator's discrete bookkeeping.
struct Integrator<'a, const N: usize> {
    chain: &'a HostChain<N>,
    mode: Mode<N>,
    /// `sign(φ_stowed)`: the side a latch is reached from.
    side: [f64; N],
    /// Where each joint's branch matters \[rad\] (`None`: no hysteresis).
    hyst: [Option<f64>; N],
    /// The step-size controller ([`ode::PI_CONTROL`]).
    step_control: ode::StepController,
    /// Joints held by the stick rule (`physics.md` §4a).
    stuck: [bool; N],
    /// Joints with a latch: every joint of a rigid wing; the hinges, not
    /// the flex joints, of a flexible one ([`crate::model::flex`]).
    latching: [bool; N],
    /// The piece of each joint's spring curve `|φ|` is on (its knots
    /// below and above \[rad\]), for [`Event::Knot`].
    piece: [(f64, f64); N],
    evaluations: usize,
    /// The power of the non-conservative forces at the last evaluation
    /// ([`chain_ledger::power`]).
    power: Power<N>,
    /// The power at the start of the next attempt (with its `k1`).
    power_at_start: Power<N>,
    /// The powers of the last attempt's evaluations, `[0]` at its start.
    stages: StagePowers<N>,
}

impl<const N: usize> Integrator<'_, N> {
    /// The derivative at `y`, time `t`, where a step ended on a knot of
    /// joint `j`'s spring curve: its piece the one past that knot
    /// ([`Knots::past`]), every other joint's found again.
    fn next_piece(&mut self, y: &State<N>, t: f64, j: usize) -> Result<State<N>, SimError> {
        let reached = self.piece.get(j).copied();
        self.find_pieces(y);
        if let (Some(piece), Some(jt)) = (reached, self.chain.joints().get(j)) {
            let knots = Knots::of(&jt.spring, self.mode.branch[j]);
            self.piece[j] = knots.past(piece, y.q[j].abs());
        }
        self.first_stage(y, t)
    }

    /// The derivative `k1` at `y`, time `t`, where a step starts afresh
    /// (not from the last step's end), with its power kept for the ledger.
    fn first_stage(&mut self, y: &State<N>, t: f64) -> Result<State<N>, SimError> {
        let k1 = self.deriv(y).ok_or(SimError::Singular { t_s: t })?;
        self.power_at_start = self.power;
        Ok(k1)
    }

    /// Finds the piece of each joint's spring curve at `y` on its branch;
    /// a joint on a knot gets the piece it moves into: `|φ|` falls while
    /// `φ·φ̇ < 0`, and at rest on the unfolding branch (which the branch
    /// rule gives a joint its spring starts unfolding).
    fn find_pieces(&mut self, y: &State<N>) {
        for (j, jt) in self.chain.joints().iter().enumerate() {
            let g = y.q[j] * y.v[j];
            let falling = g < 0.0 || (g == 0.0 && self.mode.branch[j] == Branch::Unfold);
            let knots = Knots::of(&jt.spring, self.mode.branch[j]);
            self.piece[j] = knots.around(y.q[j].abs(), falling);
        }
    }

    /// The mode with the stuck joints held like latched ones.
    fn held(&self) -> Mode<N> {
        let mut m = self.mode;
        for j in 0..N {
            m.latched[j] |= self.stuck[j];
        }
        m
    }

    fn deriv(&mut self, y: &State<N>) -> Option<State<N>> {
        self.evaluations += 1;
        let held = self.held();
        let (a, torques) = self
            .chain
            .acceleration_with_torques(&y.chain(), &held)
            .ok()?;
        self.power = chain_ledger::power(self.chain, &held, y, &torques);
        let mut v = y.v;
        for (j, vj) in v.iter_mut().enumerate() {
            if held.latched[j] {
                *vj = 0.0;
            }
        }
        Some(State { q: v, v: a })
    }

    /// The branch rule of seed 001 Eq. 1 at a state, with the reference's
    /// convention at rest: F, unless F starts the joint unfolding.
    fn choose_branch(&mut self, y: &State<N>, j: usize) -> Branch {
        let g = y.q[j] * y.v[j];
        if g < 0.0 {
            return Branch::Unfold;
        }
        if g > 0.0 {
            return Branch::Fold;
        }
        let saved = self.mode.branch[j];
        self.mode.branch[j] = Branch::Fold;
        let acc = self.chain.acceleration(&y.chain(), &self.mode);
        self.mode.branch[j] = saved;
        match acc {
            Ok(a) if y.q[j] * a[j] < 0.0 => Branch::Unfold,
            _ => Branch::Fold,
        }
    }

    /// Event function of a candidate, positive while no event happened.
    ///
    /// Between latch events `φ_j` keeps its sign (`side`), so the branch rule
    /// `φ·φ̇ < 0` reduces to the sign of `φ̇`: a branch event is a turning
    /// point of the joint, never its passage through `φ = 0`.
    fn g(&self, ev: Event, y: &State<N>) -> f64 {
        match ev {
            Event::Latch(j) => self.side[j] * y.q[j],
            Event::Slip(j) => self.holding(j, y).map_or(-1.0, |(r, b)| b.margin(r)),
            Event::Knot(j) => spring_knots::inside(y.q[j].abs(), self.piece[j]),
            Event::Branch(j) => {
                let opening = -self.side[j] * y.v[j];
                match self.mode.branch[j] {
                    Branch::Unfold => opening,
                    Branch::Fold => {
                        if opening > 0.0 {
                            -opening
                        } else {
                            f64::MIN_POSITIVE - opening
                        }
                    }
                }
            }
        }
    }

    /// The candidates that fire by the end of a step.
    fn fired(&mut self, y0: &State<N>, y1: &State<N>) -> small_list::List<Event, 8> {
        let mut out = small_list::List::new();
        for j in 0..N {
            if self.mode.latched[j] {
                continue;
            }
            if self.stuck[j] {
                if self.g(Event::Slip(j), y1) <= 0.0 {
                    out.push(Event::Slip(j));
                }
                continue;
            }
            if self.latching[j] && self.side[j] * y0.q[j] > 0.0 && self.side[j] * y1.q[j] <= 0.0 {
                // A swing through φ = 0: a latch, or with latching off a kink
                // of the spring's preload to restart at.
                out.push(Event::Latch(j));
            }
            let knot = Event::Knot(j);
            if self.g(knot, y0) > 0.0 && self.g(knot, y1) <= 0.0 {
                out.push(knot);
            }
            if let Some(below) = self.hyst[j] {
                let want = if -self.side[j] * y1.v[j] > 0.0 {
                    Branch::Unfold
                } else {
                    Branch::Fold
                };
                if want != self.mode.branch[j] {
                    let near = y0.q[j].abs() < below || y1.q[j].abs() < below;
                    if near {
                        out.push(Event::Branch(j));
                    } else {
                        // F = U out there: switch without a restart.
                        self.mode.branch[j] = want;
                    }
                }
            }
        }
        out
    }
}

/// A tiny fixed-capacity list (events per step).
mod small_list {
    pub struct List<T: Copy, const C: usize> {
        items: [Option<T>; C],
        len: usize,
    }
    impl<T: Copy, const C: usize> List<T, C> {
        pub fn new() -> Self {
            List {
                items: [None; C],
                len: 0,
            }
        }
        pub fn push(&mut self, t: T) {
            if self.len < C {
                self.items[self.len] = Some(t);
                self.len += 1;
            }
        }
        pub fn iter(&self) -> impl Iterator<Item = T> + '_ {
            self.items[..self.len].iter().flatten().copied()
        }
    }
}

/// Integrates a chain from its stowed state at rest up to the last of
/// `times`, sampling it there: start at rest, then take steps (each cut at
/// its first event, latch or branch switch) until every joint latched or the
/// last sample, then close the run (`settle_s` of the deployed state, or the
/// samples left).
pub fn run_chain<const N: usize>(
    chain: &HostChain<N>,
    times: Samples<'_>,
    opts: &SimOptions,
) -> Result<Trajectory, SimError> {
    run_chain_latching(chain, [true; N], times, opts)
}

/// [`run_chain`] with only the joints of `latching` latching: the others
/// (a flexible panel's flex joints, [`crate::model::flex`]) swing free for
/// the whole run, and the run is deployed when every latching joint
/// latched. The trajectory has every joint of the chain.
pub fn run_chain_latching<const N: usize>(
    chain: &HostChain<N>,
    latching: [bool; N],
    times: Samples<'_>,
    opts: &SimOptions,
) -> Result<Trajectory, SimError> {
    let duration = times.last();
    let (mut it, mut y) = Integrator::at_rest(chain, latching);
    if opts.stall == Stall::Hold {
        it.stick_at_start(&mut y);
    }
    let unwatched: [bool; N] = core::array::from_fn(|j| !latching[j]);
    let mut ledger = ChainLedger::start(chain, &y, duration, opts);
    let mut watch = StowedWatch::new(chain);
    let mut out = Sampler::new(times, N);
    out.push_while(|tk| tk <= 0.0, |_| y, &it.mode.latched)?;

    let mut t = 0.0;
    let mut k1 = it.first_stage(&y, t)?;
    let mut h = ode::INITIAL_STEP_S.min(opts.max_step_s);
    let mut events = EventLog::<N>::new();
    let mut done = false;
    while !done && t < duration {
        h = h.min(opts.max_step_s).min(duration - t);
        if h < ode::MIN_STEP_S {
            if duration - t < ode::END_SLACK_S {
                break;
            }
            return Err(SimError::StepUnderflow { t_s: t });
        }
        let Some(att) = it.attempt(&mut out.out.stats, t, &y, &k1, &mut h, opts)? else {
            continue;
        };
        let t1 = t + h;
        let (t_end, first) = it.first_event(&y, &att, t, t1);
        // Samples up to the end of this (possibly cut) step. A sample at the
        // event instant itself is taken after the event is applied.
        let cut = first.is_some();
        let y_end = if cut { att.dense.at(t_end) } else { att.y1 };
        let powers = (t, h, &it.stages);
        let cap = match ledger.book(it.chain, powers, (t_end, &y_end), cut)? {
            Booking::Kept { cap } => cap,
            Booking::Retake { h: next } => {
                out.out.stats.retake(t_end - t);
                h = next;
                continue;
            }
        };
        let locked: [bool; N] = core::array::from_fn(|j| it.mode.latched[j] || unwatched[j]);
        watch.step(&att.dense, t, t_end, &locked);
        out.push_while(
            |tk| if cut { tk < t_end } else { tk <= t_end },
            |tk| att.dense.at(tk),
            &it.mode.latched,
        )?;
        if let Some(Event::Knot(j)) = first {
            // The curve's next piece: the torque is continuous, the step
            // size stands (only the derivative is evaluated again).
            (t, y) = (t_end, y_end);
            out.out.stats.knots += 1;
            k1 = it.next_piece(&y, t, j)?;
            continue;
        }
        let Some(ev) = first else {
            (t, y, k1) = (t1, att.y1, att.k7);
            it.power_at_start = it.stages[6];
            h = it.step_control.accept(h, att.err).min(cap);
            events.same_instant = 0;
            let creeps = opts.stall == Stall::Hold && it.slow(&y);
            let before = creeps.then(|| chain_ledger::state_energy(it.chain, &y));
            if let Some((j, before)) = before.and_then(|e| Some((it.creep_sticks(&mut y)?, e))) {
                // A joint creeping to rest sticks (`creep`): a restart.
                out.out.stats.events += 1;
                ledger.event(it.chain, before, &y, t, j + 1)?;
                it.find_pieces(&y);
                k1 = it.first_stage(&y, t)?;
                h = h.min(ode::RESTART_STEP_S);
                it.step_control.restart();
            }
            continue;
        };
        out.out.stats.events += 1;
        events.event(t, t_end);
        y = y_end;
        let before = chain_ledger::state_energy(it.chain, &y);
        done = it.apply_event(ev, &mut y, t_end, opts, &mut events, &mut out.out)?;
        ledger.event(it.chain, before, &y, t_end, ev.joint() + 1)?;
        t = t_end;
        k1 = it.first_stage(&y, t)?;
        // Restart with a modest step after a discontinuity.
        h = h.min(ode::RESTART_STEP_S);
        it.step_control.restart();
    }
    out.out.end_s = t.min(duration);
    out.out.past_stowed = watch.found();
    out.close(t, &y, &it.mode.latched, done, opts)?;
    out.out.stats.evaluations = it.evaluations;
    Ok(out.out)
}

impl<'a, const N: usize> Integrator<'a, N> {
    /// The integrator at the stowed state at rest, each joint on the branch
    /// the rule gives there.
    fn at_rest(chain: &'a HostChain<N>, latching: [bool; N]) -> (Self, State<N>) {
        let mut it = Integrator {
            chain,
            mode: Mode::default(),
            side: [0.0; N],
            hyst: [None; N],
            step_control: ode::StepController::new(ode::PI_CONTROL),
            stuck: [false; N],
            latching,
            piece: [(f64::NEG_INFINITY, f64::INFINITY); N],
            evaluations: 0,
            power: Power::ZERO,
            power_at_start: Power::ZERO,
            stages: [Power::ZERO; 7],
        };
        let mut y = State::<N>::ZERO;
        for (j, jt) in chain.joints().iter().enumerate() {
            y.q[j] = jt.stowed_rad;
            it.side[j] = if jt.stowed_rad >= 0.0 { 1.0 } else { -1.0 };
            it.hyst[j] = jt.spring.hysteresis_below_rad();
        }
        for j in 0..N {
            it.mode.branch[j] = it.choose_branch(&y, j);
        }
        it.find_pieces(&y);
        (it, y)
    }

    /// One Dormand–Prince step of `h` from `(t, y)`: the accepted attempt,
    /// or `None` with `h` shrunk after a rejection.
    fn attempt(
        &mut self,
        stats: &mut SimStats,
        t: f64,
        y: &State<N>,
        k1: &State<N>,
        h: &mut f64,
        opts: &SimOptions,
    ) -> Result<Option<ode::Attempt<N>>, SimError> {
        // The powers of the evaluations, in order, beside the derivatives:
        // `[0]` is the start's, kept since `k1` was evaluated.
        let mut stages = [Power::ZERO; 7];
        stages[0] = self.power_at_start;
        let mut next = 1;
        let mut f = |_t: f64, s: &State<N>| {
            let k = self.deriv(s);
            if let Some(p) = stages.get_mut(next) {
                *p = self.power;
            }
            next += 1;
            k
        };
        let step = ode::step(&mut f, t, y, k1, *h, opts.rtol, opts.atol);
        self.stages = stages;
        let Some(att) = step else {
            // The trial state left the domain (e.g. NaN): shrink.
            *h *= ode::FAILED_STEP_SHRINK;
            stats.rejected += 1;
            return Ok(None);
        };
        if att.err > 1.0 {
            *h = self.step_control.reject(*h, att.err);
            stats.rejected += 1;
            return Ok(None);
        }
        stats.steps += 1;
        if stats.steps + stats.rejected > MAX_STEPS {
            return Err(SimError::TooManySteps { t_s: t });
        }
        Ok(Some(att))
    }

    /// The first event of a step from `t` to `t1` and its instant (`t1`
    /// and `None` when nothing fired).
    fn first_event(
        &mut self,
        y: &State<N>,
        att: &ode::Attempt<N>,
        t: f64,
        t1: f64,
    ) -> (f64, Option<Event>) {
        let fired = self.fired(y, &att.y1);
        let mut t_end = t1;
        let mut first: Option<Event> = None;
        for ev in fired.iter() {
            let te = locate(|s| self.g(ev, s), &att.dense, t, t1);
            // A latch wins a tie: at φ = 0 the joint latches, whatever its
            // rate does there.
            let earlier = match ev {
                Event::Latch(_) => te <= t_end,
                Event::Branch(_) | Event::Slip(_) | Event::Knot(_) => te < t_end - SAME_INSTANT_S,
            };
            if first.is_none() || earlier {
                t_end = te;
                first = Some(ev);
            }
        }
        (t_end, first)
    }

    /// Applies an event at `t_e` to the state `ye` there; true when every
    /// joint is now latched.
    fn apply_event(
        &mut self,
        ev: Event,
        ye: &mut State<N>,
        t_e: f64,
        opts: &SimOptions,
        events: &mut EventLog<N>,
        out: &mut Trajectory,
    ) -> Result<bool, SimError> {
        match ev {
            Event::Latch(_) if opts.latching => {
                let done = self.latch(ye, t_e, out)?;
                self.find_pieces(ye);
                return Ok(done);
            }
            Event::Latch(j) => {
                // Latching off: restart on the other side of the kink.
                self.side[j] = -self.side[j];
                self.mode.branch[j] = self.choose_branch(ye, j);
            }
            Event::Branch(j) => {
                self.mode.branch[j] = self.choose_branch(ye, j);
                if !self.try_stick(j, ye) {
                    events.branch(j, t_e)?;
                }
            }
            Event::Slip(j) => {
                let dir = self
                    .holding(j, ye)
                    .map_or(1.0, |(r, b)| b.slip_direction(r));
                self.stuck[j] = false;
                self.mode.branch[j] = deploywatch_core::Branch::select(ye.q[j], dir);
            }
            // The next piece of the spring's curve (found below).
            Event::Knot(_) => {}
        }
        self.find_pieces(ye);
        Ok(false)
    }

    /// A latch at `t_e`: every free joint at (or numerically past) the latch
    /// angle latches in the same plastic impulse (`physics.md` section 5).
    /// True when every joint is now latched.
    fn latch(
        &mut self,
        ye: &mut State<N>,
        t_e: f64,
        out: &mut Trajectory,
    ) -> Result<bool, SimError> {
        let mut after = self.mode.latched;
        for j in 0..N {
            if self.latching[j] && !after[j] && self.side[j] * ye.q[j] <= LATCH_REACHED_RAD {
                after[j] = true;
            }
        }
        ye.v = self
            .chain
            .latch_impulse(&ye.chain(), &after)
            .map_err(|_| SimError::Singular { t_s: t_e })?;
        for j in 0..N {
            if after[j] && !self.mode.latched[j] {
                out.latch_s[j] = Some(t_e);
                ye.q[j] = 0.0;
                ye.v[j] = 0.0;
            }
        }
        self.mode.latched = after;
        for j in 0..N {
            if self.stuck[j] && !after[j] && ye.v[j] != 0.0 {
                // Friction's torque is bounded: it takes no part in an
                // impulse, so a stuck joint moves off at the rate the
                // latch's impulse gives it (as in the physical-latch
                // simulator's ideal latch).
                self.stuck[j] = false;
                self.mode.branch[j] = self.choose_branch(ye, j);
            }
        }
        Ok((0..N).all(|j| self.mode.latched[j] || !self.latching[j]))
    }
}
