//! The deployment of an open chain with physical latches
//! (`docs/spec/physics.md` section 10, `docs/simulator.md` "Physical
//! latch"): the core's chain equations plus, at each joint with a
//! `[joint.latch]`, the torque of its stop, ball plunger and magnet
//! ([`deploywatch_core::physics::latch_contact`]), integrated by
//! Dormand–Prince 5(4) ([`crate::simulate::ode`]).
//!
//! A joint with a physical latch is never locked: it bounces on its stop,
//! may escape over the plunger and come back, or stop on the ramp. Joints
//! without one keep the ideal plastic latch of section 5.
//!
//! Every place where a latch's law changes form is an event, located on the
//! dense output and restarted from: each mark of the travel (stop, crest,
//! the ramps' ends, the magnet's reach, the switch) and the instant the
//! stop's raw force reaches zero (the contact lets go while still
//! compressed, the law never pulls). Between events each joint's law is
//! frozen on its segment, so the right-hand side is smooth inside a step.
//!
//! The run goes on to the last sample (a physical latch is never "done");
//! a joint's latch instant is the last closing of its switch, when the
//! switch is closed at the end. An energy ledger ([`Energy`]) is kept along
//! the run on Gauss–Legendre nodes of every step.

use crate::model::effect::Effect;
use crate::model::mechanism::Mechanism;
use crate::model::torque_table::HostChain;
use crate::simulate::ode::{locate, Dense, State};
use crate::simulate::stowed::StowedWatch;
use crate::simulate::trajectory::{Samples, SimError, SimOptions, Trajectory, MAX_SAMPLES};
use deploywatch_core::physics::latch_contact::{PhysicalLatch, PlungerSegment};
use deploywatch_core::physics::pawl::PawlState;
use deploywatch_core::physics::solve_spd_masked;
use deploywatch_core::{Branch, Mode};

mod ledger;
mod pawl;
mod runner;
mod segments;
mod settle;
mod setup;
mod stick;

use segments::{branch_at, Candidates, Contact, Ev, Segments, EVENTS_PER_JOINT};
use setup::{segment_index, Consts};

pub use setup::{check_latch_effects, latches, weakenings};

pub use crate::simulate::latch_run::{
    Energy, LatchEnd, LatchEvent, LatchEventKind, LatchOutcome, LatchRun, PawlEnd, PlungerEnd,
};

/// Most events at one instant before the run is declared stuck (Zeno).
pub const MAX_EVENTS_AT_ONE_INSTANT: usize = 50;

/// Time ahead of an event at which the new segment is read \[s\]: the state
/// is then on the far side of the mark it just reached.
const PROBE_S: f64 = 1e-9;

/// 3-point Gauss–Legendre nodes and weights on [0, 1] (exact to degree 5).
const GAUSS3: [(f64, f64); 3] = [
    (0.112_701_665_379_258_31, 5.0 / 18.0),
    (0.5, 8.0 / 18.0),
    (0.887_298_334_620_741_7, 5.0 / 18.0),
];

/// The integrator's state besides `(φ, φ̇)`.
struct Sim<'a, const N: usize> {
    chain: &'a HostChain<N>,
    latch: [Option<PhysicalLatch<f64>>; N],
    seg: [Segments; N],
    mode: Mode<N>,
    /// `sign(φ_stowed)` of the joints with an ideal latch.
    side: [f64; N],
    hyst: [Option<f64>; N],
    /// Joints held by the stick rule (`physics.md` §4a).
    stuck: [bool; N],
    /// Per joint, the sign of its rate at the step's start and the rest
    /// rate its turn event fires at ([`stick`]).
    turn: [(f64, f64); N],
    /// Per latch, its constants, computed once, not per evaluation.
    consts: [Consts; N],
    evaluations: usize,
    /// The joints' passages of their stowed angles, over the booked steps.
    watch: StowedWatch<N>,
    /// What the run knows to end once every latch is held for good
    /// ([`Keep::Settled`]; `None`: it runs to its end).
    hold: Option<settle::Hold<N>>,
}

impl<'a, const N: usize> Sim<'a, N> {
    fn new(chain: &'a HostChain<N>, latch: [Option<PhysicalLatch<f64>>; N], y: &State<N>) -> Self {
        let mut sim = Sim {
            chain,
            latch,
            seg: [Segments {
                plunger: PlungerSegment::Clear,
                magnet: false,
                contact: Contact::Open,
                switch: false,
                pawl: PawlState::Riding,
                notch: Contact::Open,
            }; N],
            mode: Mode::default(),
            side: [1.0; N],
            hyst: [None; N],
            stuck: [false; N],
            turn: [(0.0, 0.0); N],
            consts: [Consts::default(); N],
            evaluations: 0,
            watch: StowedWatch::new(chain),
            hold: None,
        };
        for (j, jt) in chain.joints().iter().enumerate() {
            sim.side[j] = if jt.stowed_rad >= 0.0 { 1.0 } else { -1.0 };
            sim.hyst[j] = jt.spring.hysteresis_below_rad();
            sim.mode.branch[j] = branch_at(y.q[j], y.v[j]);
            if let Some(l) = &sim.latch[j] {
                let segs = [
                    PlungerSegment::Clear,
                    PlungerSegment::Entry,
                    PlungerSegment::Hold,
                ];
                let at_stop = |b| jt.spring.torque(l.side * f64::MIN_POSITIVE, b);
                sim.consts[j] = Consts {
                    marks: l.marks().map(|(_, m)| m),
                    ramp: segs.map(|g| l.ramp_rate_on(g)),
                    at_stop: [Branch::Unfold, Branch::Fold].map(at_stop),
                };
                let was = Segments::start(l, l.travel(y.q[j]));
                sim.seg[j] = classify(l, y.q[j], y.v[j], was);
            }
        }
        sim
    }

    /// The spring's torque continued into the stop: `T(0⁺)` on the
    /// stowed side while `u < 0`, minus what the chain puts there.
    fn spring_extension(&self, j: usize, phi: f64, branch: Branch) -> f64 {
        let (Some(l), Some(jt)) = (&self.latch[j], self.chain.joints().get(j)) else {
            return 0.0;
        };
        if l.travel(phi) >= 0.0 {
            return 0.0;
        }
        let soft = 1.0 - jt.effects.spring_softening;
        let at_stop = self.consts[j].at_stop[usize::from(branch == Branch::Fold)];
        soft * (at_stop - jt.spring.torque(phi, branch))
    }

    /// The latch torque of joint `j` on its frozen segments [N·m], the
    /// stop's force applied and an engaged pawl's notch force applied \[N\].
    fn latch_torque(&self, j: usize, phi: f64, phi_dot: f64) -> (f64, f64, f64) {
        self.latch_torque_on(j, &self.seg[j], phi, phi_dot)
    }

    /// [`Sim::latch_torque`] with the law frozen on `s` instead of the
    /// joint's own segments.
    fn latch_torque_on(&self, j: usize, s: &Segments, phi: f64, phi_dot: f64) -> (f64, f64, f64) {
        let Some(l) = &self.latch[j] else {
            return (0.0, 0.0, 0.0);
        };
        let u = l.travel(phi);
        let rate = self.consts[j].ramp[segment_index(s.plunger)];
        let cons = l.side * l.conservative_torque_rated(s.plunger, s.magnet, u, rate);
        let f = match s.contact {
            Contact::Pressing => l.stop_force(phi, phi_dot).raw_n,
            Contact::Open | Contact::Released => 0.0,
        };
        let f_notch = match (s.pawl, s.notch) {
            (PawlState::Engaged, Contact::Pressing) => l.notch_force(phi, phi_dot).raw_n,
            _ => 0.0,
        };
        (
            cons + l.stop_torque(f) + l.notch_torque(f_notch),
            f,
            f_notch,
        )
    }

    /// The joints out of the coordinates: latched (ideal) or stuck.
    fn held(&self) -> [bool; N] {
        core::array::from_fn(|j| self.mode.latched[j] || self.stuck[j])
    }

    /// Mass matrix and right-hand side with the `held` joints' own torques
    /// left out (their latches' torques kept).
    fn system(&self, y: &State<N>, held: &[bool; N]) -> ([[f64; N]; N], [f64; N]) {
        let mode = Mode {
            latched: *held,
            branch: self.mode.branch,
        };
        let (m, mut rhs) = self.chain.equations(&y.chain(), &mode);
        for j in 0..N {
            if self.latch[j].is_some() {
                rhs[j] += self.latch_torque(j, y.q[j], y.v[j]).0
                    + self.spring_extension(j, y.q[j], self.mode.branch[j]);
            }
        }
        (m, rhs)
    }

    fn deriv(&mut self, y: &State<N>) -> Option<State<N>> {
        self.evaluations += 1;
        let held = self.held();
        let (m, rhs) = self.system(y, &held);
        let a = solve_spd_masked(&m, &rhs, &held).ok()?;
        let mut v = y.v;
        for (j, vj) in v.iter_mut().enumerate() {
            if held[j] {
                *vj = 0.0;
            }
        }
        a.iter()
            .all(|x| x.is_finite())
            .then_some(State { q: v, v: a })
    }
}

/// The segments of a latch at `(φ, φ̇)`, read a moment ahead; `was` are
/// the segments before (a compressed stop that let go stays released until
/// its force rises again; a pawl keeps its state).
fn classify(l: &PhysicalLatch<f64>, phi: f64, phi_dot: f64, was: Segments) -> Segments {
    let ahead = phi + phi_dot * PROBE_S;
    let u = l.travel(ahead);
    let raw = l.stop_force(ahead, phi_dot).raw_n;
    // A released stop presses again as soon as its law pushes, here or a
    // moment ahead (the event's root function reads it here).
    let pushes_now = was.contact == Contact::Released && l.stop_force(phi, phi_dot).raw_n > 0.0;
    let contact = if u >= 0.0 {
        Contact::Open
    } else if was.contact == Contact::Open || raw > 0.0 || pushes_now {
        Contact::Pressing
    } else {
        Contact::Released
    };
    let riding = l.pawl().is_none() || was.pawl == PawlState::Riding;
    Segments {
        plunger: if riding {
            l.plunger_segment(u)
        } else {
            PlungerSegment::Clear
        },
        magnet: l.magnet_within(u),
        contact,
        switch: l.switch_closed(ahead),
        pawl: was.pawl,
        notch: was.notch_after(l, ahead, phi_dot),
    }
}

/// Distance inside the frozen segment (> 0 while it holds), for event `ev`.
fn inside<const N: usize>(sim: &Sim<'_, N>, ev: Ev, y: &State<N>) -> f64 {
    let j = ev.joint();
    let (phi, rate) = (y.q[j], y.v[j]);
    if let Ev::Ideal(_) = ev {
        return sim.side[j] * phi;
    }
    if let Ev::Turn(_) = ev {
        return sim.turn_g(j, y);
    }
    if let Ev::Slip(_) = ev {
        return sim.slip_margin(j, y);
    }
    if let Ev::Notch(_) | Ev::Break(_) = ev {
        return sim.pawl_margin(ev, y);
    }
    if let Ev::Branch(_) = ev {
        let g = phi * rate;
        return match sim.mode.branch[j] {
            Branch::Unfold => -g,
            Branch::Fold => g + f64::MIN_POSITIVE,
        };
    }
    let Some(l) = &sim.latch[j] else {
        return 1.0;
    };
    let s = &sim.seg[j];
    let u = l.travel(phi);
    let [_, crest, entry, hold_end, reach, switch] = sim.consts[j].marks;
    match ev {
        Ev::Plunger(_) => match s.plunger {
            PlungerSegment::Entry => (u - crest).min(entry - u),
            PlungerSegment::Hold => (crest - u).min(u - hold_end),
            PlungerSegment::Clear if u > crest => u - entry,
            PlungerSegment::Clear => hold_end - u,
        },
        Ev::Magnet(_) if s.magnet => reach - u,
        Ev::Magnet(_) => u - reach,
        Ev::Switch(_) if s.switch => switch - u,
        Ev::Switch(_) => u - switch,
        _ => {
            let raw = l.stop_force(phi, rate).raw_n;
            match s.contact {
                Contact::Open => u,
                Contact::Pressing => (-u).min(raw),
                Contact::Released => (-u).min(-raw),
            }
        }
    }
}

impl<const N: usize> Sim<'_, N> {
    /// The events whose segment is left somewhere in the step (checked at
    /// its ends and at interior points of the dense output).
    fn candidates(&mut self, dense: &Dense<N>, y1: &State<N>) -> Candidates {
        let mut out = Candidates {
            items: [None; EVENTS_PER_JOINT * 4],
            len: 0,
        };
        let probes: [State<N>; 4] = [0.25, 0.5, 0.75, 1.0].map(|s| {
            if s == 1.0 {
                *y1
            } else {
                dense.at(dense.t0 + s * dense.h)
            }
        });
        self.arm_turns(&dense.at(dense.t0));
        for j in 0..N {
            if self.mode.latched[j] {
                continue;
            }
            if self.stuck[j] {
                out.push(Ev::Slip(j));
                continue;
            }
            let mut evs = [None; EVENTS_PER_JOINT];
            if let Some(l) = &self.latch[j] {
                let magnet = (l.magnet.force_n > 0.0).then_some(Ev::Magnet(j));
                let (plunger, notch, brk) = self.pawl_events(j);
                evs = [
                    plunger,
                    magnet,
                    Some(Ev::Contact(j)),
                    Some(Ev::Switch(j)),
                    None,
                    None,
                    notch,
                    brk,
                ];
            } else {
                evs[0] = Some(Ev::Ideal(j));
            }
            if let Some(below) = self.hyst[j] {
                let want = branch_at(y1.q[j], y1.v[j]);
                let near = probes.iter().any(|p| p.q[j].abs() < below)
                    || dense.at(dense.t0).q[j].abs() < below;
                if want != self.mode.branch[j] && !near {
                    self.mode.branch[j] = want; // F = U out there: no restart.
                } else {
                    evs[5] = Some(Ev::Branch(j));
                }
            }
            if self.turn[j].0 != 0.0 {
                evs[4] = Some(Ev::Turn(j));
            }
            for ev in evs.into_iter().flatten() {
                if matches!(ev, Ev::Slip(_)) || probes.iter().any(|p| inside(self, ev, p) <= 0.0) {
                    out.push(ev);
                }
            }
        }
        out
    }

    /// The first event of the step and its instant (`None`: none fired).
    fn first_event(&mut self, dense: &Dense<N>, y1: &State<N>) -> (f64, Option<Ev>) {
        let t1 = dense.t0 + dense.h;
        let fired = self.candidates(dense, y1);
        let mut best = (t1, None);
        for ev in fired.items.iter().take(fired.len).flatten().copied() {
            // The first change from inside (g > 0) to outside on the probes
            // brackets the root; a segment left at the very start (g = 0
            // there) is bracketed from its first inside probe.
            let mut lo: Option<f64> = None;
            let mut bracket = None;
            for s in [0.0, 0.25, 0.5, 0.75, 1.0] {
                let t = if s == 1.0 { t1 } else { dense.t0 + s * dense.h };
                let y = if s == 1.0 { *y1 } else { dense.at(t) };
                let g = inside(self, ev, &y);
                match lo {
                    Some(a) if g <= 0.0 => {
                        bracket = Some((a, t));
                        break;
                    }
                    _ if g > 0.0 => lo = Some(t),
                    _ => {}
                }
            }
            let Some((a, b)) = bracket.or_else(|| {
                // A stuck joint whose torque left its band by the step's
                // start slips there.
                // So does an ideal joint found at or past its latch angle
                // (a crossing at the instant of another event, a tape
                // branch switch at φ = 0, is not bracketed by the search).
                // So does a stop contact whose law has left its state by
                // the start (a released stop whose force is pushing again:
                // never bracketed, the joint sank into the stop with no
                // force, its elastic energy booked as negative damping).
                let g0 = inside(self, ev, &dense.at(dense.t0));
                let slips = (matches!(ev, Ev::Slip(_) | Ev::Ideal(_)) && g0 <= 0.0)
                    || (matches!(ev, Ev::Contact(_)) && g0 < 0.0);
                slips.then_some((dense.t0, dense.t0))
            }) else {
                continue;
            };
            let te = locate(|y| inside(self, ev, y), dense, a, b);
            if best.1.is_none() || te < best.0 {
                best = (te, Some(ev));
            }
        }
        best
    }
}

/// The ledger's running sums (kept by `ledger.rs`).
#[derive(Clone, Copy, Debug, Default)]
struct Ledger {
    energy: Energy,
    /// Total at the start \[J\].
    start_j: f64,
    /// The drift at the last closing, `total − start` \[J\].
    now_j: f64,
    /// The run's duration \[s\] ([`step_budget`](super::latch_run::step_budget)).
    duration_s: f64,
    /// The run's tolerance, relative to the stored energy
    /// ([`SimOptions::max_drift`]).
    max_drift: f64,
}

/// Samples of the run.
struct Out<'t> {
    times: Samples<'t>,
    k: usize,
    traj: Trajectory,
}

impl Out<'_> {
    fn push_while<const N: usize>(
        &mut self,
        sim: &Sim<'_, N>,
        inside_step: impl Fn(f64) -> bool,
        state: impl Fn(f64) -> State<N>,
    ) -> Result<(), SimError> {
        while let Some(tk) = self.times.get(self.k).filter(|&tk| inside_step(tk)) {
            if self.traj.t_s.len() >= MAX_SAMPLES {
                return Err(SimError::TooManySamples { t_s: tk });
            }
            let y = state(tk);
            self.traj.t_s.push(tk);
            for j in 0..N {
                let ideal = sim.mode.latched[j];
                let (q, v) = if ideal { (0.0, 0.0) } else { (y.q[j], y.v[j]) };
                let closed = ideal || sim.latch[j].as_ref().is_some_and(|l| l.switch_closed(q));
                self.traj.phi_deg[j].push(q.to_degrees());
                self.traj.rate_deg_s[j].push(v.to_degrees());
                self.traj.latched[j].push(closed);
            }
            self.k += 1;
        }
        Ok(())
    }
}

/// Simulates a mechanism with at least one physical latch (an open chain:
/// truss wings are refused) at the given sample times.
pub fn simulate_physical(
    mech: &Mechanism,
    effects: &[Effect],
    opts: &SimOptions,
    times: Samples<'_>,
) -> Result<LatchRun, SimError> {
    simulate_with(mech, effects, opts, times, Keep::Ledger)
}

/// What a run keeps besides its trajectory and events.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Keep {
    /// The energy ledger ([`Energy`]), on Gauss–Legendre nodes of every step.
    Ledger,
    /// Nothing more: a verdict's run (`reliability`), whose trajectory and
    /// events are the same bits; its [`LatchRun::energy`] is all zero. The
    /// ledger is kept and checked all the same: every run stops with
    /// [`SimError::EnergyDrift`] when it does not close.
    Trajectory,
    /// [`Keep::Trajectory`] with the steps sized by the ledger as well as
    /// by DOPRI5's error ([`crate::simulate::latch_run::ledger_step_factor`]): the reliability's
    /// verdict runs. Fewer steps are taken again for the ledger; the step
    /// sequence differs from [`Keep::Ledger`]'s, so the bits do; the
    /// verdicts on a fixed sample are compared by
    /// `examples/physical_verdicts.rs` and `tests/physical_verdicts.rs`.
    Verdict,
    /// [`Keep::Ledger`], the run ended as soon as every latch is held for
    /// good: every switch closed and the chain's energy (its ledger's drift
    /// allowed for) below what could open any of them again or break a
    /// pawl (`settle.rs`, `docs/simulator.md` "Held for good"). The steps
    /// up to that instant are [`Keep::Ledger`]'s, bit for bit, and no
    /// switch changes after it, so every joint's latch instant, and every
    /// margin of the reliability's criteria, is the full run's; the
    /// trajectory ends there ([`LatchRun::settled_s`]). A run where some
    /// latch is never held for good is [`Keep::Ledger`]'s to its end.
    Settled,
}

/// [`simulate_physical`], keeping what `keep` says.
pub fn simulate_with(
    mech: &Mechanism,
    effects: &[Effect],
    opts: &SimOptions,
    times: Samples<'_>,
    keep: Keep,
) -> Result<LatchRun, SimError> {
    if mech.truss.is_some() {
        return Err(SimError::Invalid(format!(
            "mechanism `{}`: physical latches are simulated on open chains only, not on truss wings",
            mech.name
        )));
    }
    check_latch_effects(mech, effects)?;
    let n = mech.joint_count();
    let (je, g) = crate::model::effect::to_core(effects, n);
    let bad = || SimError::Invalid(format!("mechanism `{}` cannot be built", mech.name));
    crate::model::mechanism::with_joints!(n, N => {
        let chain = mech.chain::<N>(&je, g).ok_or_else(bad)?;
        let y0 = State {
            q: core::array::from_fn(|j| chain.joints()[j].stowed_rad),
            v: [0.0; N],
        };
        run_keeping(&chain, latches::<N>(mech, effects), y0, Begin::default(), times, opts, keep)
    }, else Err(bad()))
}

/// Where a run of [`simulate_physical_from`] starts: every joint's angle
/// and rate, and which joints of an ideal latch are held at it.
#[derive(Clone, Debug, PartialEq)]
pub struct StartState {
    /// Joint angles \[rad\], one per joint.
    pub q_rad: Vec<f64>,
    /// Joint rates \[rad/s\], one per joint.
    pub v_rad_s: Vec<f64>,
    /// Joints of an ideal latch held latched from the start (their angle
    /// and rate are taken as 0).
    pub held: Vec<bool>,
    /// The spring branch each joint starts on (`None`: the branch its rate
    /// gives). A spring with hysteresis (a tape spring's fold) keeps its
    /// branch over a small loop, which a state alone does not tell.
    pub branch: Vec<Option<Branch>>,
}

/// [`simulate_physical`] from `start` at `t = 0` instead of the stowed
/// rest: a shot of the diagnosis's whole-run check from a measured state
/// (`analysis::diagnose::whole_run`). `times` count from that start.
pub fn simulate_physical_from(
    mech: &Mechanism,
    effects: &[Effect],
    opts: &SimOptions,
    start: &StartState,
    times: Samples<'_>,
) -> Result<LatchRun, SimError> {
    check_latch_effects(mech, effects)?;
    let n = mech.joint_count();
    if [
        start.q_rad.len(),
        start.v_rad_s.len(),
        start.held.len(),
        start.branch.len(),
    ] != [n; 4]
    {
        return Err(SimError::Invalid(format!(
            "mechanism `{}`: a start state needs {n} angles, rates, held flags and branches",
            mech.name
        )));
    }
    let (je, g) = crate::model::effect::to_core(effects, n);
    let bad = || SimError::Invalid(format!("mechanism `{}` cannot be built", mech.name));
    crate::model::mechanism::with_joints!(n, N => {
        let chain = mech.chain::<N>(&je, g).ok_or_else(bad)?;
        let begin = Begin {
            held: core::array::from_fn(|j| start.held[j]),
            branch: core::array::from_fn(|j| start.branch[j]),
        };
        let held = begin.held;
        let y0 = State {
            q: core::array::from_fn(|j| if held[j] { 0.0 } else { start.q_rad[j] }),
            v: core::array::from_fn(|j| if held[j] { 0.0 } else { start.v_rad_s[j] }),
        };
        run_keeping(&chain, latches::<N>(mech, effects), y0, begin, times, opts, Keep::Trajectory)
    }, else Err(bad()))
}

/// Integrates a chain with the given latches from `y0` at `t = 0` to the
/// last of `times`, sampling it there.
pub fn run_from<const N: usize>(
    chain: &HostChain<N>,
    latch: [Option<PhysicalLatch<f64>>; N],
    y0: State<N>,
    times: Samples<'_>,
    opts: &SimOptions,
) -> Result<LatchRun, SimError> {
    run_keeping(
        chain,
        latch,
        y0,
        Begin::default(),
        times,
        opts,
        Keep::Ledger,
    )
}

/// What a run knows of its start besides `(φ, φ̇)` ([`StartState`]): the
/// joints of an ideal latch held from the start and the springs' branches
/// (the stowed rest's by default: nothing held, each branch its rate's).
#[derive(Clone, Copy, Debug)]
struct Begin<const N: usize> {
    held: [bool; N],
    branch: [Option<Branch>; N],
}

impl<const N: usize> Default for Begin<N> {
    fn default() -> Self {
        Begin {
            held: [false; N],
            branch: [None; N],
        }
    }
}

/// [`run_from`], keeping what `keep` says, from `begin`.
fn run_keeping<const N: usize>(
    chain: &HostChain<N>,
    latch: [Option<PhysicalLatch<f64>>; N],
    y0: State<N>,
    begin: Begin<N>,
    times: Samples<'_>,
    opts: &SimOptions,
    keep: Keep,
) -> Result<LatchRun, SimError> {
    let mut sim = Sim::new(chain, latch, &y0);
    sim.mode.latched = begin.held;
    for (j, b) in begin.branch.iter().enumerate() {
        if let Some(b) = b {
            sim.mode.branch[j] = *b;
        }
    }
    if keep == Keep::Settled {
        sim.hold = Some(settle::Hold::new(sim.passive()));
    }
    let mut run = Runner {
        out: Out {
            times,
            k: 0,
            traj: Trajectory::with_joints(N),
        },
        events: Vec::new(),
        ledger: Ledger::default(),
        same_instant: 0,
        size_by_ledger: keep == Keep::Verdict,
        settled_s: None,
    };
    let (k, s, l) = sim.energies(&y0);
    run.ledger.start_j = k + s + l;
    run.ledger.duration_s = times.last();
    run.ledger.max_drift = opts.max_drift;
    run.ledger.energy.stored_j = k + s + l;
    sim.close_ledger(&mut run.ledger, &y0);
    sim.stick_at_rest(&y0);
    run.out.push_while(&sim, |tk| tk <= 0.0, |_| y0)?;
    let (t_end, y_end) = run.integrate(&mut sim, y0, times.last(), opts)?;
    run.out.traj.end_s = t_end;
    let end_phi_deg = sim.angles_deg(&y_end);
    run.out.traj.stats.evaluations = sim.evaluations;
    run.out.traj.latch_s = run.latch_instants(&sim);
    run.out.traj.past_stowed = sim.watch.found();
    Ok(LatchRun {
        traj: run.out.traj,
        events: run.events,
        end_phi_deg,
        settled_s: run.settled_s,
        energy: match keep {
            Keep::Ledger | Keep::Settled => run.ledger.energy,
            Keep::Trajectory | Keep::Verdict => Energy::default(),
        },
    })
}

/// The run in progress.
struct Runner<'t> {
    out: Out<'t>,
    events: Vec<LatchEvent>,
    ledger: Ledger,
    same_instant: usize,
    /// Steps sized by the ledger too ([`Keep::Verdict`]).
    size_by_ledger: bool,
    /// Where the run ended because every latch is held for good \[s\]
    /// ([`Keep::Settled`]).
    settled_s: Option<f64>,
}
