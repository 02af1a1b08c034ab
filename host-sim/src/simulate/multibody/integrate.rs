//! Event-driven integration: Dormand–Prince 5(4) of [`crate::simulate::ode`]
//! on the tree coordinates, coordinate projection (positions, then
//! velocities) after every accepted step, and lock events located on the
//! dense output by the chain simulator's root finder
//! ([`crate::simulate::deployment`]).
//!
//! A lock event is a lockable pin's angle `α` reaching its lock angle from
//! the side it started on. At the located instant the positions are
//! projected, every lockable pin within [`CAPTURE_RAD`] of its lock angle
//! locks too (`truss-link.md`: simultaneous capture), and the velocities are
//! projected onto the new constraints in the mass-matrix metric: a perfectly
//! plastic impact. A lock that the active constraints already imply (the
//! hinge latch over a locked truss) is recorded but adds no row.

use super::kin::Model;
use crate::simulate::deployment::{locate, SimError, SimOptions, SimStats, MAX_STEPS};
use crate::simulate::ode::{self, State};

/// Capture window of the simultaneous-capture rule: 0.5° [rad].
pub const CAPTURE_RAD: f64 = 0.5 * std::f64::consts::PI / 180.0;

/// Largest number of coordinates the integrator is instantiated for.
pub const MAX_COORDS: usize = 12;

/// A multibody run sampled at the output times.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MbTrajectory {
    /// Work done.
    pub stats: SimStats,
    /// Where the simulation stopped [s].
    pub end_s: f64,
    /// Mobility `n − rank C` after each lock event, starting with the
    /// initial one.
    pub mobility: Vec<usize>,
    /// Tree coordinates where the simulation stopped [rad].
    pub final_q: Vec<f64>,
    /// Largest constraint error after any projection [m or rad].
    pub max_constraint_error: f64,
    /// Lock instant of each pin [s].
    pub lock_s: Vec<Option<f64>>,
    /// Sample times [s].
    pub t_s: Vec<f64>,
    /// `angle_deg[p][i]`: angle `α` of pin `p` at sample `i` [deg] (its lock
    /// angle once locked).
    pub angle_deg: Vec<Vec<f64>>,
    /// `locked[p][i]`: pin `p` locked at sample `i`.
    pub locked: Vec<Vec<bool>>,
    /// Mechanical energy at each sample [J] ([`Model::energy`]).
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
        let a = self.model.acceleration(&y.q, &y.v, &self.active)?;
        let mut out = State {
            q: y.v,
            v: [0.0; N],
        };
        out.v.copy_from_slice(&a);
        Some(out)
    }

    /// Event function of pin `p`: positive until it reaches its lock angle.
    fn g(&self, p: usize, y: &State<N>) -> f64 {
        let k = self.model.kin(&y.q, &y.v);
        let lock = self.model.sys.pins[p].lock_at_rad.unwrap_or(0.0);
        self.side[p] * (self.model.pin_angle(&k, p).0 - lock)
    }

    fn lockable(&self) -> Vec<usize> {
        (0..self.latched.len())
            .filter(|&p| !self.latched[p] && self.model.sys.pins[p].lock_at_rad.is_some())
            .collect()
    }

    /// Projects positions then velocities with the active rows.
    fn project(&mut self, y: &mut State<N>, t: f64) -> Result<(), SimError> {
        let err = self
            .model
            .project_position(&mut y.q, &self.active)
            .ok_or(SimError::Singular { t_s: t })?;
        self.out.max_constraint_error = self.out.max_constraint_error.max(err);
        self.model
            .project_velocity(&y.q, &mut y.v, &self.active)
            .ok_or(SimError::Singular { t_s: t })
    }

    fn push(&mut self, t: f64, y: &State<N>) {
        let k = self.model.kin(&y.q, &y.v);
        self.out.t_s.push(t);
        self.out.energy_j.push(self.model.energy(&y.q, &y.v));
        let err = self.model.constraint_error(&y.q, &self.active);
        self.out.constraint_error.push(err);
        for p in 0..self.latched.len() {
            let alpha = match (self.latched[p], self.model.sys.pins[p].lock_at_rad) {
                (true, Some(l)) => l,
                _ => self.model.pin_angle(&k, p).0,
            };
            self.out.angle_deg[p].push(alpha.to_degrees());
            self.out.locked[p].push(self.latched[p]);
        }
    }

    /// Applies a lock event at `t`: captures every pin within
    /// [`CAPTURE_RAD`], then the plastic impact. Returns the mobility left.
    fn lock(&mut self, t: f64, y: &mut State<N>) -> Result<usize, SimError> {
        self.project(y, t)?;
        let k = self.model.kin(&y.q, &y.v);
        let mut caught: Vec<(f64, usize)> = Vec::new();
        for p in self.lockable() {
            let lock = self.model.sys.pins[p].lock_at_rad.unwrap_or(0.0);
            let d = self.side[p] * (self.model.pin_angle(&k, p).0 - lock);
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

    fn run(mut self, times: &[f64]) -> Result<MbTrajectory, SimError> {
        let duration = times.last().copied().unwrap_or(0.0);
        let mut y = State::<N>::ZERO;
        // A pin that starts at its lock angle is held from the start (a
        // hold-down: the lock-up mode of `truss-link.md`).
        for (p, pin) in self.model.sys.pins.iter().enumerate() {
            if pin.lock_at_rad == Some(pin.offset_rad) {
                self.active[p] = true;
                self.latched[p] = true;
                self.out.lock_s[p] = Some(0.0);
            }
        }
        let m0 = self.model.mobility(&y.q, &self.active);
        self.out.mobility.push(m0);
        let mut k = 0usize;
        while k < times.len() && times[k] <= 0.0 {
            self.push(times[k], &y);
            k += 1;
        }
        let mut t = 0.0;
        let mut k1 = self.deriv(&y).ok_or(SimError::Singular { t_s: t })?;
        let mut h = 1e-4f64.min(self.opts.max_step_s);
        let mut done = m0 == 0;
        while !done && t < duration {
            h = h.min(self.opts.max_step_s).min(duration - t);
            if h < 1e-13 {
                if duration - t < 1e-12 {
                    break;
                }
                return Err(SimError::StepUnderflow { t_s: t });
            }
            let (rtol, atol) = (self.opts.rtol, self.opts.atol);
            let mut f = |_t: f64, s: &State<N>| self.deriv(s);
            let Some(att) = ode::step(&mut f, t, &y, &k1, h, rtol, atol) else {
                h *= 0.25;
                self.out.stats.rejected += 1;
                continue;
            };
            if att.err > 1.0 {
                h = ode::next_h(h, att.err);
                self.out.stats.rejected += 1;
                continue;
            }
            self.out.stats.steps += 1;
            if self.out.stats.steps + self.out.stats.rejected > MAX_STEPS {
                return Err(SimError::TooManySteps { t_s: t });
            }
            let t1 = t + h;
            let mut first: Option<f64> = None;
            if self.opts.latching {
                for p in self.lockable() {
                    if self.g(p, &att.y1) <= 0.0 {
                        let te = locate(|s| self.g(p, s), &att.dense, t, t1);
                        first = Some(first.map_or(te, |f: f64| f.min(te)));
                    }
                }
            }
            let t_end = first.unwrap_or(t1);
            while k < times.len() && (times[k] < t_end || (first.is_none() && times[k] <= t_end)) {
                let mut s = att.dense.at(times[k]);
                self.project(&mut s, times[k])?;
                self.push(times[k], &s);
                k += 1;
            }
            let mut ye = if first.is_some() {
                att.dense.at(t_end)
            } else {
                att.y1
            };
            if first.is_some() {
                self.out.stats.events += 1;
                done = self.lock(t_end, &mut ye)? == 0 && self.opts.stop_when_deployed;
                h = h.min(1e-3);
            } else {
                self.project(&mut ye, t_end)?;
                h = ode::next_h(h, att.err);
            }
            t = t_end;
            y = ye;
            k1 = self.deriv(&y).ok_or(SimError::Singular { t_s: t })?;
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
