//! What the sample path hands the slow path: the samples queued for the
//! friction learning, and the state the learning keeps between them (the
//! centred fit's window, whose turn the energy margin is).

use crate::monitor::smoother::{Centre, CentredFit};
use heapless::Deque;

/// Samples the learning queue holds \[1\]: at 100 Hz, 80 ms of a slow path
/// kept from running (at the replay's schedule it is emptied after every
/// sample).
pub const LEARNING_QUEUE: usize = 4;

/// What the friction learning and the energy margin need of one sample,
/// queued by [`crate::monitor::Monitor::update`] for [`crate::monitor::Monitor::learn_or_predict`].
#[derive(Clone, Copy, Debug)]
pub(super) struct Learning<const N: usize> {
    /// Time stamp \[s\].
    pub(super) t: f32,
    /// The sample is fit to learn from: settled (no snap, latch or gap
    /// within `settle_s`), no gap, a positive time step.
    pub(super) clean: bool,
    /// No snap, latch or gap within `settle_s` (the margin's condition).
    pub(super) quiet: bool,
    /// Each joint's part of the sample.
    pub(super) joints: [JointLearning; N],
}

/// One joint's part of a [`Learning`] sample (8 bytes: the flags share
/// the reading's alignment).
#[derive(Clone, Copy, Debug)]
pub(super) struct JointLearning {
    /// The reading the rate filter used \[rad\], NaN where none (missing,
    /// out of range, stuck or gated out).
    pub(super) used: f32,
    /// The model sits the joint at 0.
    pub(super) locked: bool,
    /// Declared latched at the sample (logged by the slow path: a log line
    /// costs a thousand instructions over semihosting).
    pub(super) newly: bool,
}

impl<const N: usize> Learning<N> {
    /// The readings the rate filters used \[rad\], NaN where none.
    pub(super) fn used(&self) -> [f32; N] {
        core::array::from_fn(|j| self.joints[j].used)
    }

    /// The joints the model sits at 0.
    pub(super) fn locked(&self) -> [bool; N] {
        core::array::from_fn(|j| self.joints[j].locked)
    }

    /// [`Learning::locked`] over an array of capacity
    /// `R` (the rollout's capacity, the monitor's `N`), the joints past the monitor's locked.
    pub(super) fn locked_padded<const R: usize>(&self) -> [bool; R] {
        let mut locked = [true; R];
        for (l, joint) in locked.iter_mut().zip(self.joints.iter()) {
            *l = joint.locked;
        }
        locked
    }
}

/// The centred fit ([`Centre`]) over arrays of capacity `R` (the
/// rollout's, the monitor's `N`), the joints past the monitor's locked at
/// 0: what the learning and the hand-over to the prediction read of it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Fitted<const R: usize> {
    /// Time of the middle sample \[s\].
    pub(super) t_s: f32,
    /// Time since the previous middle sample \[s\].
    pub(super) dt_s: f32,
    /// Joint angles \[rad\].
    pub(super) phi: [f32; R],
    /// Joint rates [rad/s].
    pub(super) rate: [f32; R],
    /// Variance of each rate [rad²/s²].
    pub(super) rate_var: [f32; R],
    /// Joints locked at the middle sample.
    pub(super) locked: [bool; R],
}

impl<const R: usize> Fitted<R> {
    /// The fit `c` of `N` joints, padded.
    pub(super) fn of<const N: usize>(c: &Centre<N>) -> Self {
        let mut f = Fitted {
            t_s: c.t_s,
            dt_s: c.dt_s,
            phi: [0.0; R],
            rate: [0.0; R],
            rate_var: [0.0; R],
            locked: [true; R],
        };
        for j in 0..N.min(R) {
            f.phi[j] = c.phi[j];
            f.rate[j] = c.rate[j];
            f.rate_var[j] = c.rate_var[j];
            f.locked[j] = c.locked[j];
        }
        f
    }
}

/// The queue of samples [`crate::monitor::Monitor::update`] hands to
/// [`crate::monitor::Monitor::learn_or_predict`], oldest first.
pub(super) type LearningQueue<const N: usize> = Deque<Learning<N>, LEARNING_QUEUE>;

/// What the slow path's learning keeps from one learned sample to the
/// next.
#[derive(Clone, Debug)]
pub(super) struct Learner<const N: usize> {
    /// Samples dropped from a full queue (the slow path fell behind by
    /// more than [`LEARNING_QUEUE`] samples).
    pub(super) overruns: u32,
    /// The last readings, for the friction observer's centred rates.
    pub(super) fit: CentredFit<N>,
    /// Whether the previous sample gave a centred fit (the observers run
    /// on without a restart).
    pub(super) fit_run: bool,
    /// Time of the last centred fit \[s\].
    pub(super) t_centre: f32,
    /// The joint whose energy margin is evaluated at the next learned
    /// sample.
    pub(super) next_margin: u8,
}

impl<const N: usize> Learner<N> {
    /// Nothing learned.
    pub(super) fn new() -> Self {
        Learner {
            overruns: 0,
            fit: CentredFit::new(),
            fit_run: false,
            t_centre: f32::NEG_INFINITY,
            next_margin: 0,
        }
    }

    /// Back to [`Learner::new`], in place.
    pub(super) fn reset(&mut self) {
        self.overruns = 0;
        self.fit = CentredFit::new();
        self.fit_run = false;
        self.t_centre = f32::NEG_INFINITY;
        self.next_margin = 0;
    }

    /// Queues `sample` on `queue`. A full queue drops its oldest sample and
    /// breaks the fit's run there (the observers restart), counted in
    /// [`Learner::overruns`]: never silently.
    pub(super) fn push(&mut self, queue: &mut LearningQueue<N>, sample: Learning<N>) {
        if queue.is_full() {
            let _ = queue.pop_front();
            if let Some(next) = queue.front_mut() {
                next.clean = false;
            }
            self.overruns = self.overruns.saturating_add(1);
            // Once: a log line costs more than the sample path's budget
            // over semihosting, and a starved slow path must not be
            // starved further; the counter tells the rest.
            if self.overruns == 1 {
                warn!("learning queue full: samples dropped (see learning_overruns)");
            }
        }
        let _ = queue.push_back(sample);
    }
}
