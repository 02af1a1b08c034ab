//! The run in progress of a physical-latch deployment: the step loop
//! (DOPRI5 steps, the first event of each step, the ledger's booking) and
//! the events applied to the state.

use super::{branch_at, Contact, Ev, Runner, Sim, MAX_EVENTS_AT_ONE_INSTANT};
use crate::simulate::latch_run::{ledger_step_factor, LatchEvent, LatchEventKind};
use crate::simulate::ode::{self, State};
use crate::simulate::trajectory::{SimError, SimOptions, Stall, MAX_STEPS};
use deploywatch_core::physics::latch_contact::{LatchMark, PlungerSegment};

impl<const N: usize> Sim<'_, N> {
    /// The joint angles of `y` \[deg\] as a sample gives them: a joint an
    /// ideal latch holds is at its stop.
    pub(super) fn angles_deg(&self, y: &State<N>) -> Vec<f64> {
        (0..N)
            .map(|j| match self.mode.latched[j] {
                true => 0.0,
                false => y.q[j].to_degrees(),
            })
            .collect()
    }
}

/// The derivative at `y` (time `t`) where the integration restarts after
/// a discontinuity (an event, a stick), the step `h` cut to a restart's
/// and the controller restarted.
fn restart<const N: usize>(
    sim: &mut Sim<'_, N>,
    y: &State<N>,
    t: f64,
    h: &mut f64,
    control: &mut ode::StepController,
) -> Result<State<N>, SimError> {
    *h = h.min(ode::RESTART_STEP_S);
    control.restart();
    sim.deriv(y).ok_or(SimError::Singular { t_s: t })
}

impl Runner<'_> {
    /// Each joint's latch instant: the ideal latch's, or the last closing of a
    /// physical latch's switch when it is closed at the end.
    pub(super) fn latch_instants<const N: usize>(&self, sim: &Sim<'_, N>) -> Vec<Option<f64>> {
        let (events, traj) = (&self.events, &self.out.traj);
        (0..N)
            .map(|j| {
                // A run ended held for good has every switch closed to
                // the end (`settle.rs`), sampled there or not.
                let closed_at_end =
                    self.settled_s.is_some() || traj.latched[j].last().copied().unwrap_or(false);
                let mine = events.iter().filter(|e| e.joint == j + 1);
                if sim.latch[j].is_none() {
                    return mine
                        .filter(|e| e.kind == LatchEventKind::IdealLatch)
                        .map(|e| e.t_s)
                        .next();
                }
                let last_close = mine
                    .rev()
                    .find(|e| {
                        e.kind == LatchEventKind::Mark(LatchMark::Switch) && e.rate_rad_s < 0.0
                    })
                    .map(|e| e.t_s);
                if closed_at_end {
                    last_close.or(Some(0.0))
                } else {
                    None
                }
            })
            .collect()
    }

    /// Steps from `y` at 0 to `duration`; returns when and in which state
    /// it stopped.
    pub(super) fn integrate<const N: usize>(
        &mut self,
        sim: &mut Sim<'_, N>,
        mut y: State<N>,
        duration: f64,
        opts: &SimOptions,
    ) -> Result<(f64, State<N>), SimError> {
        let mut t = 0.0;
        let mut k1 = sim.deriv(&y).ok_or(SimError::Singular { t_s: t })?;
        let mut h = ode::INITIAL_STEP_S.min(opts.max_step_s);
        let mut control = ode::StepController::new(ode::ELEMENTARY_CONTROL);
        while t < duration {
            h = h.min(opts.max_step_s).min(duration - t);
            if h < ode::MIN_STEP_S {
                if duration - t < ode::END_SLACK_S {
                    break;
                }
                return Err(SimError::StepUnderflow { t_s: t });
            }
            let stats = &mut self.out.traj.stats;
            let mut f = |_t: f64, s: &State<N>| sim.deriv(s);
            let Some(att) = ode::step(&mut f, t, &y, &k1, h, opts.rtol, opts.atol) else {
                h *= ode::FAILED_STEP_SHRINK;
                stats.rejected += 1;
                continue;
            };
            if att.err > 1.0 {
                h = control.reject(h, att.err);
                stats.rejected += 1;
                continue;
            }
            stats.steps += 1;
            if stats.steps + stats.rejected > MAX_STEPS {
                return Err(SimError::TooManySteps { t_s: t });
            }
            let (t_end, first) = sim.first_event(&att.dense, &att.y1);
            let cut = first.is_some();
            let y_end = if cut { att.dense.at(t_end) } else { att.y1 };
            let (booked, ratio) = self.book(sim, &att.dense, t_end, &y_end)?;
            let ledger_h = (t_end - t) * ledger_step_factor(ratio);
            if !booked {
                h = self.out.traj.stats.retake(t_end - t);
                if self.size_by_ledger {
                    h = ledger_h;
                }
                continue;
            }
            self.out.push_while(
                sim,
                |tk| if cut { tk < t_end } else { tk <= t_end },
                |tk| att.dense.at(tk),
            )?;
            let Some(ev) = first else {
                let next = control
                    .accept(h, att.err)
                    .min(self.ledger_cap(ledger_h, ratio));
                (t, y, k1, h) = (t_end, att.y1, att.k7, next);
                self.same_instant = 0;
                if opts.stall == Stall::Hold && self.creep(sim, &mut y, t)? {
                    k1 = restart(sim, &y, t, &mut h, &mut control)?;
                }
                if sim.settled(&self.ledger, &y) {
                    self.settled_s = Some(t);
                    break;
                }
                continue;
            };
            y = y_end;
            self.event(sim, ev, &mut y, t, t_end)?;
            t = t_end;
            if sim.settled(&self.ledger, &y) {
                self.settled_s = Some(t);
                break;
            }
            k1 = restart(sim, &y, t, &mut h, &mut control)?;
        }
        self.out.push_while(sim, |tk| tk <= t + 1e-9, |_| y)?;
        Ok((t.min(duration), y))
    }

    /// The event `ev` at `t_end` (the step began at `t`): applied to `y`,
    /// the ledger closed over it and checked; events at one instant in a
    /// row counted.
    fn event<const N: usize>(
        &mut self,
        sim: &mut Sim<'_, N>,
        ev: Ev,
        y: &mut State<N>,
        t: f64,
        t_end: f64,
    ) -> Result<(), SimError> {
        self.same_instant = if t_end - t < 1e-12 {
            self.same_instant + 1
        } else {
            0
        };
        self.apply(sim, ev, y, t_end)?;
        sim.close_ledger(&mut self.ledger, y);
        if let Some(e) = self.events.last() {
            self.ledger
                .check(t_end, e.joint, || format!("its event {:?}", e.kind))?;
        }
        Ok(())
    }

    /// The most the step after an uncut step booked with `ratio` may be
    /// \[s\]: `ledger_h` with [`Keep::Verdict`](super::Keep::Verdict), unless the step was
    /// booked over its budget (one under `LEDGER_MIN_STEP_S`: its drift is
    /// the rounding's); a step cut short by an event caps nothing.
    fn ledger_cap(&self, ledger_h: f64, ratio: f64) -> f64 {
        match self.size_by_ledger && ratio <= 1.0 {
            true => ledger_h,
            false => f64::INFINITY,
        }
    }

    /// Applies event `ev` at `t` to the state `y` there.
    fn apply<const N: usize>(
        &mut self,
        sim: &mut Sim<'_, N>,
        ev: Ev,
        y: &mut State<N>,
        t: f64,
    ) -> Result<(), SimError> {
        self.out.traj.stats.events += 1;
        let j = ev.joint();
        if self.same_instant > MAX_EVENTS_AT_ONE_INSTANT {
            return Err(SimError::Sliding {
                joint: j + 1,
                t_s: t,
            });
        }
        let kind = match ev {
            Ev::Ideal(_) => {
                self.ideal_latch(sim, y, t, j)?;
                LatchEventKind::IdealLatch
            }
            Ev::Branch(_) => {
                sim.mode.branch[j] = branch_at(y.q[j], y.v[j]);
                // A branch event at a turning point is a turn too.
                match self.turn_at_rest(sim, j, y) {
                    Some(kind) => kind,
                    None => LatchEventKind::Branch,
                }
            }
            Ev::Turn(_) => self.turn(sim, j, y),
            Ev::Slip(_) => {
                sim.slip(j, y);
                LatchEventKind::Slip
            }
            Ev::Notch(_) | Ev::Break(_) => self.pawl_event(sim, j, y, matches!(ev, Ev::Break(_))),
            _ => self.cross(sim, ev, j, y),
        };
        // Every other latch read again from the state: an event of one kind
        // can coincide with a mark of another (a branch switch at the stop).
        for k in (0..N).filter(|&k| k != j || matches!(ev, Ev::Branch(_))) {
            sim.reclassify(k, y);
        }
        self.log(sim, j, kind, y, t);
        Ok(())
    }

    /// Logs an event of `kind` at joint `j` (0-based) at `t`, state `y`.
    pub(super) fn log<const N: usize>(
        &mut self,
        sim: &Sim<'_, N>,
        j: usize,
        kind: LatchEventKind,
        y: &State<N>,
        t: f64,
    ) {
        let (u, du) = match &sim.latch[j] {
            Some(l) => (l.travel(y.q[j]), l.travel(y.v[j])),
            None => (sim.side[j] * y.q[j], sim.side[j] * y.v[j]),
        };
        self.events.push(LatchEvent {
            t_s: t,
            joint: j + 1,
            kind,
            travel_rad: u,
            rate_rad_s: du,
            evaluations: sim.evaluations,
        });
    }

    /// A latch segment left: the new segments, and what to log.
    fn cross<const N: usize>(
        &mut self,
        sim: &mut Sim<'_, N>,
        ev: Ev,
        j: usize,
        y: &State<N>,
    ) -> LatchEventKind {
        if let Some(kind) = self.pawl_drop(sim, ev, j, y) {
            return kind;
        }
        let Some((l, before, after)) = sim.reclassify(j, y) else {
            return LatchEventKind::Branch;
        };
        let mark = |m| LatchEventKind::Mark(m);
        match ev {
            Ev::Plunger(_)
                if before.plunger == PlungerSegment::Entry
                    && after.plunger == PlungerSegment::Hold =>
            {
                mark(LatchMark::Crest)
            }
            Ev::Plunger(_)
                if before.plunger == PlungerSegment::Hold
                    && after.plunger == PlungerSegment::Entry =>
            {
                mark(LatchMark::Crest)
            }
            Ev::Plunger(_) if l.travel(y.q[j]) > l.plunger.crest_rad => mark(LatchMark::EntryRamp),
            Ev::Plunger(_) => mark(LatchMark::HoldRampEnd),
            Ev::Magnet(_) => mark(LatchMark::MagnetReach),
            Ev::Switch(_) => mark(LatchMark::Switch),
            _ => match (before.contact, after.contact) {
                (_, Contact::Open) | (Contact::Open, _) => mark(LatchMark::Stop),
                (_, Contact::Released) => LatchEventKind::Release,
                _ => LatchEventKind::Press,
            },
        }
    }
}
