//! Event-driven integration: Dormand–Prince 5(4) of [`crate::simulate::ode`]
//! on the tree coordinates with a PI step controller, coordinate projection
//! (positions, then velocities) after every accepted step with the
//! factorisation of the step's last stage, output samples from the dense
//! output with their positions projected, and lock events located on the
//! dense output by the chain simulator's root finder
//! ([`crate::simulate::deployment`]). Nothing is allocated per step
//! ([`super::solve`]'s work space).
//!
//! A lock event is a lockable pin's angle `α` reaching its lock angle from
//! the side it started on. At the located instant the positions are
//! projected, every lockable pin within [`CAPTURE_RAD`] of its lock angle
//! locks too (`truss-link.md`: simultaneous capture), and the velocities are
//! projected onto the new constraints in the mass-matrix metric: a perfectly
//! plastic impact. A lock that the active constraints already imply (the
//! hinge latch over a locked truss) is recorded but adds no row.

use super::kin::Model;
use super::solve::Work;
use crate::simulate::ode::locate;
use crate::simulate::ode::{self, State};
use crate::simulate::trajectory::{SimError, SimOptions, SimStats, MAX_STEPS};

/// Capture window of the simultaneous-capture rule: 0.5° \[rad\].
pub const CAPTURE_RAD: f64 = 0.5 * std::f64::consts::PI / 180.0;

/// Largest number of coordinates the integrator is instantiated for.
pub const MAX_COORDS: usize = 12;

/// A multibody run sampled at the output times.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MbTrajectory {
    /// Work done.
    pub stats: SimStats,
    /// Where the simulation stopped \[s\].
    pub end_s: f64,
    /// Mobility `n − rank C` after each lock event, starting with the
    /// initial one.
    pub mobility: Vec<usize>,
    /// Tree coordinates where the simulation stopped \[rad\].
    pub final_q: Vec<f64>,
    /// Largest constraint error after any projection [m or rad].
    pub max_constraint_error: f64,
    /// Lock instant of each pin \[s\].
    pub lock_s: Vec<Option<f64>>,
    /// Sample times \[s\].
    pub t_s: Vec<f64>,
    /// `angle_deg[p][i]`: angle `α` of pin `p` at sample `i` \[deg\] (its lock
    /// angle once locked).
    pub angle_deg: Vec<Vec<f64>>,
    /// `locked[p][i]`: pin `p` locked at sample `i`.
    pub locked: Vec<Vec<bool>>,
    /// Mechanical energy at each sample \[J\] ([`Model::energy`]).
    pub energy_j: Vec<f64>,
    /// Constraint error `max |g|` at each sample [m or rad].
    pub constraint_error: Vec<f64>,
}

/// Integrates a model from its reference pose at rest and samples it at
/// `times` (sorted, from 0). Ends when no freedom is left (with
/// `opts.stop_when_deployed`) or at the last time.
pub fn run(model: &Model, times: &[f64], opts: &SimOptions) -> Result<MbTrajectory, SimError> {
    macro_rules! dispatch {
        ($($n:literal)*) => {
            match model.n() {
                $($n => Runner::<$n>::new(model, opts).run(times),)*
                n => Err(SimError::Invalid(format!(
                    "{n} tree coordinates; 1 to {MAX_COORDS} are supported"
                ))),
            }
        };
    }
    dispatch!(1 2 3 4 5 6 7 8 9 10 11 12)
}

struct Runner<'a, const N: usize> {
    model: &'a Model,
    opts: &'a SimOptions,
    /// Pins that are constraint rows.
    active: Vec<bool>,
    /// Pins reported locked (active or implied).
    latched: Vec<bool>,
    /// Sign of `α − lock` at the start, per lockable pin.
    side: Vec<f64>,
    /// Allocation-free solves; holds the factorisation of the last
    /// evaluation.
    work: Work,
    evaluations: usize,
    out: MbTrajectory,
}

impl<'a, const N: usize> Runner<'a, N> {
    fn new(model: &'a Model, opts: &'a SimOptions) -> Self {
        let np = model.sys.pins.len();
        let side = model
            .sys
            .pins
            .iter()
            .map(|p| match p.lock_at_rad {
                Some(l) if p.offset_rad < l => -1.0,
                _ => 1.0,
            })
            .collect();
        Runner {
            model,
            opts,
            active: vec![false; np],
            latched: vec![false; np],
            side,
            work: Work::new(model),
            evaluations: 0,
            out: MbTrajectory {
                angle_deg: vec![Vec::new(); np],
                locked: vec![Vec::new(); np],
                lock_s: vec![None; np],
                ..MbTrajectory::default()
            },
        }
    }

    fn deriv(&mut self, y: &State<N>) -> Option<State<N>> {
        self.evaluations += 1;
        let mut out = State {
            q: y.v,
            v: [0.0; N],
        };
        self.work
            .acceleration(self.model, &y.q, &y.v, &self.active, &mut out.v)?;
        Some(out)
    }

    /// Event function of pin `p`: positive until it reaches its lock angle.
    fn g(&self, p: usize, y: &State<N>) -> f64 {
        let lock = self.model.sys.pins[p].lock_at_rad.unwrap_or(0.0);
        self.side[p] * (self.model.pin_angle_at(&y.q, p) - lock)
    }

    fn lockable(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.latched.len())
            .filter(|&p| !self.latched[p] && self.model.sys.pins[p].lock_at_rad.is_some())
    }

    fn record_error(&mut self, err: f64) {
        self.out.max_constraint_error = self.out.max_constraint_error.max(err);
    }

    /// Projects positions then velocities with the active rows,
    /// refactoring (after an event).
    fn project(&mut self, y: &mut State<N>, t: f64) -> Result<(), SimError> {
        let err = self
            .work
            .project_position(self.model, &mut y.q, &self.active)
            .ok_or(SimError::Singular { t_s: t })?;
        self.record_error(err);
        self.work
            .project_velocity_factored(&mut y.v)
            .ok_or(SimError::Singular { t_s: t })
    }

    /// Projects positions then velocities with the metric `M` of the
    /// step's last stage (at its end point): positions by a simplified
    /// Gauss–Newton (Jacobian of the last projection frozen), velocities
    /// onto the rows rebuilt at the projected positions. No new
    /// factorisation of `M`.
    fn project_factored(&mut self, y: &mut State<N>, t: f64) -> Result<(), SimError> {
        let err = self
            .work
            .project_position_factored(self.model, &mut y.q, &self.active)
            .ok_or(SimError::Singular { t_s: t })?;
        self.record_error(err);
        self.work.refresh_rows(self.model, &y.q, &self.active);
        self.work
            .project_velocity_factored(&mut y.v)
            .ok_or(SimError::Singular { t_s: t })
    }

    fn push(&mut self, t: f64, y: &State<N>) {
        self.out.t_s.push(t);
        let energy = self.work.energy(self.model, &y.q, &y.v);
        self.out.energy_j.push(energy);
        let err = self.work.residual_at_kin(self.model, &self.active);
        self.out.constraint_error.push(err);
        for p in 0..self.latched.len() {
            let alpha = match (self.latched[p], self.model.sys.pins[p].lock_at_rad) {
                (true, Some(l)) => l,
                _ => self.model.pin_angle(&self.work.kin, p).0,
            };
            self.out.angle_deg[p].push(alpha.to_degrees());
            self.out.locked[p].push(self.latched[p]);
        }
    }

    /// Applies a lock event at `t`: captures every pin within
    /// [`CAPTURE_RAD`], then the plastic impact. Returns the mobility left.
    fn lock(&mut self, t: f64, y: &mut State<N>) -> Result<usize, SimError> {
        self.project(y, t)?;
        let mut caught: Vec<(f64, usize)> = Vec::new();
        for p in self.lockable() {
            let d = self.g(p, y);
            if d <= CAPTURE_RAD {
                caught.push((d, p));
            }
        }
        caught.sort_by(|a, b| a.0.total_cmp(&b.0));
        for &(_, p) in &caught {
            if self.model.lock_is_independent(&y.q, &self.active, p) {
                self.active[p] = true;
            }
            self.latched[p] = true;
            self.out.lock_s[p] = Some(t);
        }
        self.project(y, t)?;
        let m = self.model.mobility(&y.q, &self.active);
        self.out.mobility.push(m);
        Ok(m)
    }

    /// Holds every pin that starts at its lock angle from the start (a
    /// hold-down: the lock-up mode of `truss-link.md`); the mobility at the
    /// start.
    fn hold_downs(&mut self, y: &State<N>) -> usize {
        for (p, pin) in self.model.sys.pins.iter().enumerate() {
            if pin.lock_at_rad == Some(pin.offset_rad) {
                self.active[p] = true;
                self.latched[p] = true;
                self.out.lock_s[p] = Some(0.0);
            }
        }
        let m0 = self.model.mobility(&y.q, &self.active);
        self.out.mobility.push(m0);
        m0
    }

    /// The first lock instant within the step `[t, t1]`, located on its
    /// dense output (`None`: no lock, or latching off).
    fn first_lock(&self, att: &ode::Attempt<N>, t: f64, t1: f64) -> Option<f64> {
        let mut first: Option<f64> = None;
        if self.opts.latching {
            for p in self.lockable() {
                if self.g(p, &att.y1) <= 0.0 {
                    let te = locate(|s| self.g(p, s), &att.dense, t, t1);
                    first = Some(first.map_or(te, |f: f64| f.min(te)));
                }
            }
        }
        first
    }

    /// Writes the output samples from `times[k]` up to `t_end` (inclusive
    /// when the step ends without a lock): the interpolant with its
    /// positions projected (frozen Gauss–Newton, no new rows); the velocity
    /// is the interpolant's, consistent to the step's accuracy. Returns the
    /// next sample's index.
    fn sample_step(
        &mut self,
        dense: &ode::Dense<N>,
        times: &[f64],
        mut k: usize,
        t_end: f64,
        through_end: bool,
    ) -> Result<usize, SimError> {
        while k < times.len() && (times[k] < t_end || (through_end && times[k] <= t_end)) {
            let mut s = dense.at(times[k]);
            let err = self
                .work
                .project_position_factored(self.model, &mut s.q, &self.active)
                .ok_or(SimError::Singular { t_s: times[k] })?;
            self.record_error(err);
            self.push(times[k], &s);
            k += 1;
        }
        Ok(k)
    }

    fn run(mut self, times: &[f64]) -> Result<MbTrajectory, SimError> {
        let duration = times.last().copied().unwrap_or(0.0);
        let mut y = State::<N>::ZERO;
        let m0 = self.hold_downs(&y);
        let mut k = 0usize;
        while k < times.len() && times[k] <= 0.0 {
            self.push(times[k], &y);
            k += 1;
        }
        let mut t = 0.0;
        let mut k1 = self.deriv(&y).ok_or(SimError::Singular { t_s: t })?;
        let mut h = ode::INITIAL_STEP_S.min(self.opts.max_step_s);
        let mut done = m0 == 0;
        let mut ctl = ode::StepController::new(ode::PI_CONTROL);
        while !done && t < duration {
            h = h.min(self.opts.max_step_s).min(duration - t);
            if h < ode::MIN_STEP_S {
                if duration - t < ode::END_SLACK_S {
                    break;
                }
                return Err(SimError::StepUnderflow { t_s: t });
            }
            let (rtol, atol) = (self.opts.rtol, self.opts.atol);
            let mut f = |_t: f64, s: &State<N>| self.deriv(s);
            let Some(att) = ode::step(&mut f, t, &y, &k1, h, rtol, atol) else {
                h *= ode::FAILED_STEP_SHRINK;
                self.out.stats.rejected += 1;
                continue;
            };
            if att.err > 1.0 {
                h = ctl.reject(h, att.err);
                self.out.stats.rejected += 1;
                continue;
            }
            // From here to the projection of the end point the work space
            // holds the factorisation at `att.y1` (the last stage, FSAL).
            self.out.stats.steps += 1;
            if self.out.stats.steps + self.out.stats.rejected > MAX_STEPS {
                return Err(SimError::TooManySteps { t_s: t });
            }
            let t1 = t + h;
            let first = self.first_lock(&att, t, t1);
            let t_end = first.unwrap_or(t1);
            k = self.sample_step(&att.dense, times, k, t_end, first.is_none())?;
            if first.is_some() {
                let mut ye = att.dense.at(t_end);
                self.out.stats.events += 1;
                done = self.lock(t_end, &mut ye)? == 0 && self.opts.stop_when_deployed;
                h = h.min(ode::RESTART_STEP_S);
                ctl.restart();
                t = t_end;
                y = ye;
                k1 = self.deriv(&y).ok_or(SimError::Singular { t_s: t })?;
            } else {
                // The last stage's derivative at the unprojected end point
                // starts the next step (FSAL): the projection moves the
                // state by about the local error, which changes `f` by as
                // little.
                let mut ye = att.y1;
                self.project_factored(&mut ye, t_end)?;
                h = ctl.accept(h, att.err);
                t = t_end;
                y = ye;
                k1 = att.k7;
            }
        }
        self.out.end_s = t.min(duration);
        self.out.final_q = y.q.to_vec();
        // Close the run: the first sample at or after the end.
        if k < times.len() {
            self.push(times[k], &y);
        }
        self.out.stats.evaluations = self.evaluations;
        Ok(self.out)
    }
}
