//! The output of an ideal-latch chain run (`deployment.rs`): the
//! trajectory sampled at the run's times as the steps pass them.

use crate::simulate::ode::State;
use crate::simulate::trajectory::{
    Samples, SimError, SimOptions, Trajectory, MAX_SAMPLES, SAMPLE_TIME_SLACK_S,
};

/// The output: the trajectory and the next sample time to fill.
pub(crate) struct Sampler<'t> {
    /// The sample times.
    pub times: Samples<'t>,
    /// The next sample to fill.
    pub k: usize,
    /// The trajectory so far.
    pub out: Trajectory,
}

impl<'t> Sampler<'t> {
    /// No sample filled yet of a run of `joints` joints at `times`.
    pub fn new(times: Samples<'t>, joints: usize) -> Self {
        Sampler {
            times,
            k: 0,
            out: Trajectory::with_joints(joints),
        }
    }

    /// Appends one sample (latched joints at 0, at rest).
    pub fn push<const N: usize>(
        &mut self,
        t: f64,
        s: &State<N>,
        latched: &[bool; N],
    ) -> Result<(), SimError> {
        if self.out.t_s.len() >= MAX_SAMPLES {
            return Err(SimError::TooManySamples { t_s: t });
        }
        self.out.t_s.push(t);
        for j in 0..N {
            let (q, v) = if latched[j] {
                (0.0, 0.0)
            } else {
                (s.q[j], s.v[j])
            };
            self.out.phi_deg[j].push(q.to_degrees());
            self.out.rate_deg_s[j].push(v.to_degrees());
            self.out.latched[j].push(latched[j]);
        }
        Ok(())
    }

    /// Appends the next samples while `inside(t_k)`, the state at `t_k`
    /// given by `state`.
    pub fn push_while<const N: usize>(
        &mut self,
        inside: impl Fn(f64) -> bool,
        state: impl Fn(f64) -> State<N>,
        latched: &[bool; N],
    ) -> Result<(), SimError> {
        while let Some(tk) = self.times.get(self.k).filter(|&tk| inside(tk)) {
            self.push(tk, &state(tk), latched)?;
            self.k += 1;
        }
        Ok(())
    }

    /// Closes the run at time `t`, state `y`. Deployed (`done`): the first
    /// sample at or after the last latch, then `settle_s` more of the
    /// deployed state (every joint latched: nothing moves), or with
    /// `stop_when_deployed` off the deployed state to the last sample. Not
    /// deployed: the samples left up to `t`.
    pub fn close<const N: usize>(
        &mut self,
        t: f64,
        y: &State<N>,
        latched: &[bool; N],
        done: bool,
        opts: &SimOptions,
    ) -> Result<(), SimError> {
        if !done {
            return self.push_while(|tk| tk <= t + SAMPLE_TIME_SLACK_S, |_| *y, latched);
        }
        let Some(first) = self.times.get(self.k) else {
            return Ok(());
        };
        let end = if opts.stop_when_deployed {
            first + opts.settle_s.unwrap_or(0.0) + SAMPLE_TIME_SLACK_S
        } else {
            f64::INFINITY
        };
        self.push_while(|tk| tk <= end, |_| *y, latched)
    }
}
