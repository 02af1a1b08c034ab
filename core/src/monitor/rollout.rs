//! Latch / stall prediction by forward simulation of the reduced-order
//! chain: the whole remaining deployment, all joints together, with the
//! friction estimate.
//!
//! A one-joint energy balance ([`crate::monitor::margin`]) misses what the other
//! joints do to a joint: the reaction of the outer panels holds the inner
//! ones back, and the plastic latch impacts of the other joints destroy
//! kinetic energy. The rollout integrates `physics.md` §2 with the monitor's
//! chain model (its springs), the friction estimate of each joint, and the
//! latch impulse of §5:
//!
//! ```text
//! (M + h C) a = τ_s + τ_f − SᵀC_cor,   τ_f = −T_C tanh(ω/ω_c) − f ω,
//! C = diag(T_C sech²(ω/ω_c)/ω_c + f)
//! ```
//! stepped by the midpoint rule (second order: two evaluations a step),
//! each stage linearly implicit in the stiff friction (`h` = its length),
//! so a joint can come to rest in the creep regime without the step going
//! unstable. The base step `dt_s` is halved, up to [`MAX_HALVINGS`] times,
//! where a step's own error estimate exceeds [`STEP_ERROR_RAD`] (light
//! panels swinging at thousands of degrees per second), starting from the
//! shortest at the start and after each latch. While every free joint glides or creeps slowly and smoothly,
//! far from its latch, the step grows up to `glide_dt_s`
//! (`docs/monitor.md` §6, the glide): a panel coasting on its momentum
//! with its spring within a few per cent of its friction, or creeping, is
//! crossed in a few long steps instead of hundreds.
//! A joint latches in the rollout when it reaches its capture angle moving
//! inwards; the rollout ends when every joint has latched, at the horizon
//! (the deployment's deadline), or once every free joint has crept
//! (|ω| < 2 ω_c) for [`STALL_HOLD_S`] and none can break free: the rest is
//! then quasi-static creep, whose time to the capture angle is a quadrature
//! over the spring curve (`creep`). The creep speeds up where the spring
//! stiffens towards the latch (the tape springs of seed 001 do), so the rate
//! of the moment is no guide to the time it takes.
//!
//! It runs up to three times per cycle ([`crate::monitor::predictor`]), a bounded
//! amount of work per slice of [`crate::monitor::Monitor::learn_or_predict`]: with the
//! estimates `T̂_C`, `f̂`, `κ̂` (nominal: the prediction), with `T̂_C + zσ`,
//! `f̂ + zσ` and the springs at `1 + κ̂ − zσ_κ` (pessimistic), and with
//! `max(T̂_C − zσ, L)`, `f̂ − zσ` and `1 + κ̂ + zσ_κ` (optimistic, `L` the
//! friction torque the observer sees now); `z = Φ⁻¹(confidence)`. A latch of the
//! nominal rollout that the pessimistic one confirms, or a stall that the
//! optimistic one confirms, holds at that confidence for the friction
//! estimate; one that the bracket does not confirm is the best estimate only.

#[cfg(any(test, feature = "internals"))]
use crate::physics::chain::Chain;
use crate::physics::chain::{ChainRef, ChainState, Mode};
use crate::physics::friction::coulomb_shape;
use crate::physics::linalg::solve_spd_masked_n;
use crate::physics::spring::Branch;

use crate::monitor::creep::CreepRun;
#[cfg(test)]
use crate::monitor::creep::{creep, Creep, CreepJoint};

/// The most joints a rollout holds: the most a monitor has
/// (`telemetry::config::MAX_JOINTS`). The rollout's stepping (`Stepper<R>`)
/// is written over arrays of a capacity `R` with the joint count known at
/// run time ([`ChainRef`]); a monitor of `N` joints runs it with `R = N`,
/// so a firmware (one `N`) carries one copy sized for its joints and pays
/// nothing for the capacity of a longer chain.
pub const ROLLOUT_MAX_JOINTS: usize = 8;

/// Predicted time every free joint must creep before the rollout settles
/// the outcome by the creep quadrature, and between two tries \[s\].
pub const STALL_HOLD_S: f32 = 0.2;

/// Longest snap-through from the capture angle to the latch the rollout
/// allows for \[s\].
const MAX_SNAP_S: f32 = 0.05;

/// Which friction a rollout assumes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Bracket {
    /// The estimate itself: the prediction.
    #[default]
    Nominal,
    /// High friction, derated springs: a latch here is a confident latch.
    Pessimistic,
    /// Low friction, uprated springs: a stall here is a confident stall.
    Optimistic,
}

/// Where a rollout starts from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RolloutStart<const N: usize> {
    /// Joint angles \[rad\] and rates [rad/s].
    pub state: ChainState<f32, N>,
    /// Joints latched already.
    pub latched: [bool; N],
    /// Coulomb torque of each joint [N·m].
    pub coulomb_nm: [f32; N],
    /// Viscous coefficient of each joint [N·m·s/rad].
    pub viscous_nms: [f32; N],
    /// Factor on each joint's spring torque \[1\].
    pub spring_scale: [f32; N],
    /// Capture angle of each joint \[rad\].
    pub capture_rad: [f32; N],
}

/// Settings of the rollouts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RolloutConfig {
    /// Integration step of the nominal rollout (the prediction) \[s\].
    pub dt_s: f32,
    /// Integration step of the pessimistic and optimistic brackets \[s\]:
    /// they only confirm the nominal rollout's verdicts (its confidence),
    /// and may be coarser.
    pub bracket_dt_s: f32,
    /// Longest integration step \[s\]: while every free joint glides or
    /// creeps slowly and smoothly, far from its capture angle, the step
    /// grows from `dt_s` (or `bracket_dt_s`) up to this
    /// (`GLIDE_TURN_RAD`, `GLIDE_RATE_CHANGE` of `rollout/step_size.rs`); below two steps the
    /// step stays fixed.
    pub glide_dt_s: f32,
    /// Units of work per slice of [`crate::monitor::Monitor::learn_or_predict`] (a unit: one
    /// step, two chain evaluations, or [`CREEP_EVALS_PER_STEP`] spring
    /// evaluations of the creep quadrature); 0 switches the rollouts off (the prediction then
    /// rests on the one-joint energy balance of [`crate::monitor::margin`] alone).
    pub steps_per_slice: u8,
    /// Slices of [`crate::monitor::Monitor::learn_or_predict`] a replay runs after each
    /// sample ([`crate::monitor::Monitor::replay_step`]): the time the
    /// application gives the prediction between two samples, fixed so that
    /// a replay is deterministic.
    pub slices_per_sample: u8,
    /// Predicted time after which the joints not latched count as stalled
    /// \[s\] (the monitor shortens it to the deployment's deadline).
    pub horizon_s: f32,
    /// `ω_c` of the friction law [rad/s].
    pub coulomb_threshold_rad_s: f32,
}

/// What a finished rollout says about one joint.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct JointOutcome {
    /// True when the joint latched in the rollout (or had latched).
    pub latches: bool,
    /// Predicted time from the rollout's start to the latch \[s\].
    pub latch_after_s: f32,
}

/// One forward simulation in progress: a shell over the stepping written
/// over arrays of capacity `N` (`Stepper<N>`), for the tests that check it
/// against the host simulator (the monitor runs `Stepper` itself).
#[cfg(any(test, feature = "internals"))]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rollout<const N: usize> {
    core: Stepper<N>,
}

/// A rollout's state over arrays of capacity `R` (at most
/// [`ROLLOUT_MAX_JOINTS`]), the first `n` joints in use (the others
/// latched, watched by none): the one the predictor's cycle runs
/// ([`crate::monitor::predictor`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Stepper<const R: usize> {
    /// Joints in use.
    n: u8,
    start: Assumed<R>,
    x: ChainState<f32, R>,
    latched: [bool; R],
    latch_after_s: [f32; R],
    t_s: f32,
    creeping_s: f32,
    /// Each free joint's acceleration in the last step [rad/s²] (∞ before
    /// the first step and after a latch: the next step is a base step).
    accel: [f32; R],
    /// Halvings of the base step in force (at most [`MAX_HALVINGS`]), set
    /// by the error of the last base step ([`STEP_ERROR_RAD`]); the most at
    /// the start and after a latch, where no step has measured the error
    /// yet (a joint 20 ms from its neighbour's latch would cross its own
    /// capture angle in the same first step).
    halvings: u8,
    done: bool,
    /// The joints whose outcome is wanted: the rollout ends once all of
    /// them have latched (every joint unless `Rollout::watching`).
    watch: [bool; R],
    /// The creep quadrature in progress, resumed slice by slice.
    settle: Option<Settle<R>>,
}

/// What a rollout assumes of each joint ([`RolloutStart`] without the
/// state, which the rollout moves on from).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Assumed<const R: usize> {
    /// Joints latched at the start.
    latched: [bool; R],
    /// Coulomb torque of each joint [N·m].
    coulomb_nm: [f32; R],
    /// Viscous coefficient of each joint [N·m·s/rad].
    viscous_nms: [f32; R],
    /// Factor on each joint's spring torque \[1\].
    spring_scale: [f32; R],
    /// Capture angle of each joint \[rad\].
    capture_rad: [f32; R],
}

/// The creep quadrature of a rollout in progress (`Stepper::settle_creep`),
/// one joint after the other, resumable.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Settle<const R: usize> {
    /// Time left to the horizon when the quadrature started \[s\].
    time_left: f32,
    /// Articulated inertia of each joint then [kg·m²].
    inertia: [f32; R],
    /// Creep time of each joint settled so far \[s\] (∞: no latch).
    after: [f32; R],
    /// The joint in progress.
    joint: u8,
    /// Its creep, once begun.
    run: Option<CreepRun>,
}

/// `v` of `N` joints in an array of capacity [`ROLLOUT_MAX_JOINTS`], the
/// rest `fill`.
#[cfg(any(test, feature = "internals"))]
fn pad<T: Copy, const N: usize, const R: usize>(v: &[T; N], fill: T) -> [T; R] {
    let mut out = [fill; R];
    for (o, x) in out.iter_mut().zip(v.iter()) {
        *o = *x;
    }
    out
}

/// The first `N` of `v`, the rest (none unless `N > R`) `fill`.
#[cfg(any(test, feature = "internals"))]
// The unit tests use part of it; `internals` shows all of it.
#[cfg_attr(not(feature = "internals"), allow(dead_code))]
fn unpad<T: Copy, const N: usize, const R: usize>(v: &[T; R], fill: T) -> [T; N] {
    core::array::from_fn(|j| v.get(j).copied().unwrap_or(fill))
}

#[cfg(any(test, feature = "internals"))]
// The unit tests use part of it; `internals` shows all of it.
#[cfg_attr(not(feature = "internals"), allow(dead_code))]
impl<const N: usize> Rollout<N> {
    /// A rollout from `start`, not yet advanced.
    pub fn new(start: RolloutStart<N>) -> Self {
        const { assert!(N <= ROLLOUT_MAX_JOINTS, "a rollout holds at most 8 joints") };
        let start = RolloutStart {
            state: ChainState {
                phi: pad(&start.state.phi, 0.0),
                phi_dot: pad(&start.state.phi_dot, 0.0),
            },
            latched: pad(&start.latched, true),
            coulomb_nm: pad(&start.coulomb_nm, 0.0),
            viscous_nms: pad(&start.viscous_nms, 0.0),
            spring_scale: pad(&start.spring_scale, 1.0),
            capture_rad: pad(&start.capture_rad, 0.0),
        };
        Rollout {
            core: Stepper::new(N, &start),
        }
    }

    /// The same rollout, ended as soon as every joint of `watch` has
    /// latched: the outcome of the others is then left as "not latched"
    /// (a bracket that only has to confirm the nominal rollout's latches
    /// stops there). A rollout watching no joint ends at the first step.
    pub fn watching(mut self, watch: [bool; N]) -> Self {
        self.core = self.core.watching(pad(&watch, false));
        self
    }

    /// The joints latched when the rollout started.
    pub fn started_latched(&self) -> [bool; N] {
        unpad(&self.core.started_latched(), true)
    }

    /// The joints whose outcome the rollout decides (`Rollout::watching`).
    pub fn watch(&self) -> [bool; N] {
        unpad(&self.core.watch(), false)
    }

    /// Time simulated so far \[s\].
    pub fn elapsed_s(&self) -> f32 {
        self.core.elapsed_s()
    }

    /// True once the rollout has ended.
    pub fn is_done(&self) -> bool {
        self.core.is_done()
    }

    /// The outcome of each joint (meaningful once done).
    pub fn outcome(&self) -> [JointOutcome; N] {
        let out = self.core.outcome();
        core::array::from_fn(|j| out.get(j).copied().unwrap_or_default())
    }

    /// Advances by up to `cfg.steps_per_slice` units of work
    /// ([`Stepper::advance`]).
    pub fn advance(&mut self, chain: &Chain<f32, N>, cfg: &RolloutConfig) {
        let store = chain.coefficients();
        self.core.advance(&chain.counted_with(&store), cfg);
    }
}

/// The chain as the rollout evaluates it.
type Model<'a, const R: usize> = ChainRef<'a, f32, R>;

/// The mass matrix `M(φ)` of the joints in use ([`ChainRef::mass_matrix`]),
/// out of line: one copy for the rollout's three uses and the slow path's
/// energy margin, for every joint count.
#[inline(never)]
pub(crate) fn mass_matrix<const R: usize>(chain: &Model<'_, R>, phi: &[f32; R]) -> [[f32; R]; R] {
    chain.mass_matrix(phi)
}

/// `M x = b` on the first `n` joints, those not `locked`
/// ([`solve_spd_masked_n`]), out of line: one copy for the rollout's two
/// uses. `None` when the free block is not positive definite.
#[inline(never)]
fn solve<const R: usize>(
    n: usize,
    m: &[[f32; R]; R],
    b: &[f32; R],
    locked: &[bool; R],
) -> Option<[f32; R]> {
    solve_spd_masked_n(n, m, b, locked).ok()
}

impl<const R: usize> Stepper<R> {
    /// A rollout of the first `n` joints (at most [`ROLLOUT_MAX_JOINTS`])
    /// from `start`, not yet advanced, watching every joint in use; the
    /// joints past `n` count as latched and watched by none.
    pub(crate) fn new(n: usize, start: &RolloutStart<R>) -> Self {
        let n = n.min(R);
        let mut latched = start.latched;
        for (j, l) in latched.iter_mut().enumerate() {
            *l |= j >= n;
        }
        Stepper {
            n: n as u8,
            x: start.state,
            latched,
            latch_after_s: [0.0; R],
            t_s: 0.0,
            creeping_s: 0.0,
            accel: [f32::INFINITY; R],
            halvings: MAX_HALVINGS,
            done: false,
            watch: core::array::from_fn(|j| j < n),
            settle: None,
            start: Assumed {
                latched,
                coulomb_nm: start.coulomb_nm,
                viscous_nms: start.viscous_nms,
                spring_scale: start.spring_scale,
                capture_rad: start.capture_rad,
            },
        }
    }

    /// `Rollout::watching`: the joints in use of `watch`.
    pub(crate) fn watching(mut self, watch: [bool; R]) -> Self {
        let n = self.count();
        self.watch = core::array::from_fn(|j| j < n && watch[j]);
        self
    }

    /// The joints latched when the rollout started (those past the count
    /// too).
    pub(crate) fn started_latched(&self) -> [bool; R] {
        self.start.latched
    }

    /// The joints whose outcome the rollout decides.
    pub(crate) fn watch(&self) -> [bool; R] {
        self.watch
    }

    /// Time simulated so far \[s\].
    #[cfg(any(test, feature = "internals"))]
    #[cfg_attr(not(feature = "internals"), allow(dead_code))]
    pub(crate) fn elapsed_s(&self) -> f32 {
        self.t_s
    }

    /// True once the rollout has ended.
    pub(crate) fn is_done(&self) -> bool {
        self.done
    }

    /// The outcome of each joint (meaningful once done; past the count:
    /// latched at the start).
    pub(crate) fn outcome(&self) -> [JointOutcome; R] {
        core::array::from_fn(|j| JointOutcome {
            latches: self.latched[j],
            latch_after_s: self.latch_after_s[j],
        })
    }

    /// The joints in use.
    fn count(&self) -> usize {
        usize::from(self.n).min(R)
    }

    /// Advances by up to `cfg.steps_per_slice` units of work: a unit is
    /// one step of the chain, or [`CREEP_EVALS_PER_STEP`] spring
    /// evaluations of the creep quadrature and snap-through, so that a
    /// slice costs about the same whatever the rollout is doing. One copy
    /// for every joint count.
    #[inline(never)]
    pub(crate) fn advance(&mut self, chain: &Model<'_, R>, cfg: &RolloutConfig) {
        for _ in 0..cfg.steps_per_slice {
            if self.done {
                return;
            }
            if self.settle.is_some() {
                self.settle_creep(chain, cfg, CREEP_EVALS_PER_STEP);
            } else {
                self.step(chain, cfg);
            }
        }
    }

    /// Accelerations at `x`, linearly implicit in the friction over `h`:
    /// `(M + h C) a = τ_s + τ_f − SᵀC_cor`.
    fn acceleration(
        &self,
        chain: &Model<'_, R>,
        x: &ChainState<f32, R>,
        h: f32,
        wc: f32,
    ) -> Option<[f32; R]> {
        let n = self.count();
        let mut mode = Mode::<R> {
            latched: self.latched,
            ..Mode::default()
        };
        for j in 0..n {
            mode.branch[j] = Branch::select(x.phi[j], x.phi_dot[j]);
        }
        let (mut m, mut rhs) = chain.equations(x, &mode);
        for j in 0..n {
            let (false, Some(joint)) = (self.latched[j], chain.joints().get(j)) else {
                continue;
            };
            let w = x.phi_dot[j];
            let spring = joint.spring.torque(x.phi[j], mode.branch[j]);
            let tc = self.start.coulomb_nm[j];
            let f = self.start.viscous_nms[j];
            let th = coulomb_shape(w, wc);
            rhs[j] += (self.start.spring_scale[j] - 1.0) * spring - tc * th - f * w;
            m[j][j] += h * (tc * (1.0 - th * th) / wc + f);
        }
        solve(n, &m, &rhs, &self.latched)
    }

    /// One step: the midpoint rule (second order), each stage linearly
    /// implicit in the stiff friction; then the latches the step reached,
    /// and the end of the rollout or the start of the creep quadrature.
    fn step(&mut self, chain: &Model<'_, R>, cfg: &RolloutConfig) {
        let n = self.count();
        let base = self.base_step(cfg);
        let dt = self.step_length(chain, cfg, base);
        let wc = cfg.coulomb_threshold_rad_s;
        let Some(crossed) = self.integrate(chain, dt, wc, dt <= base) else {
            self.finish();
            return;
        };
        self.t_s += dt;
        if crossed.iter().any(|c| *c) {
            self.latch_crossed(chain, &crossed, dt);
            // The impact changes every rate: a base step next, the
            // shortest, grown again as its error allows.
            self.accel = [f32::INFINITY; R];
            self.halvings = MAX_HALVINGS;
        }
        if (0..n).all(|j| self.latched[j] || !self.watch[j]) {
            self.done = true;
            return;
        }
        let creeping = (0..n).all(|j| self.latched[j] || libm::fabsf(self.x.phi_dot[j]) < 2.0 * wc);
        self.creeping_s = if creeping { self.creeping_s + dt } else { 0.0 };
        let finite = (0..n).all(|j| self.x.phi[j].is_finite() && self.x.phi_dot[j].is_finite());
        if !finite || self.t_s >= cfg.horizon_s {
            self.finish();
            return;
        }
        if self.creeping_s >= STALL_HOLD_S {
            self.begin_settle(chain, cfg);
        }
    }

    /// Integrates the free joints over `dt` \[s\] by the midpoint rule, each
    /// stage linearly implicit in the friction (`ω_c` = `wc` [rad/s]).
    /// Returns the joints that reached their capture angle moving inwards,
    /// or `None` when the equations could not be solved. A base step
    /// (`base`) sets the halvings of the next ones by its error estimate,
    /// the angle by which its two stages' rate changes part over the step,
    /// `½ dt² |a_mid − a_start|` (the midpoint rule against Euler's):
    /// above [`STEP_ERROR_RAD`] the base step is halved, below an eighth
    /// of it (a doubled step's estimate, four times this one, within half
    /// the bound) doubled again, never beyond `cfg.dt_s`.
    fn integrate(
        &mut self,
        chain: &Model<'_, R>,
        dt: f32,
        wc: f32,
        base: bool,
    ) -> Option<[bool; R]> {
        let n = self.count();
        let a1 = self.acceleration(chain, &self.x, 0.5 * dt, wc)?;
        let mut mid = self.x;
        for j in 0..n {
            if !self.latched[j] {
                mid.phi_dot[j] += 0.5 * dt * a1[j];
                mid.phi[j] += 0.5 * dt * self.x.phi_dot[j];
            }
        }
        let a = self.acceleration(chain, &mid, dt, wc)?;
        let mut crossed = [false; R];
        let mut apart = 0.0f32;
        for j in 0..n {
            if self.latched[j] {
                self.x.phi_dot[j] = 0.0;
                continue;
            }
            apart = apart.max(libm::fabsf(a[j] - a1[j]));
            let before = self.x.phi[j];
            self.x.phi[j] += dt * mid.phi_dot[j];
            self.x.phi_dot[j] += dt * a[j];
            self.accel[j] = a[j];
            let after = self.x.phi[j];
            let inward = before * mid.phi_dot[j] < 0.0;
            // The capture angle is a shortcut for a joint that snaps
            // through: one that arrives slower than the rest of its stroke
            // in MAX_SNAP_S is integrated on to the latch angle.
            let snaps = libm::fabsf(after) <= self.start.capture_rad[j]
                && libm::fabsf(after) <= MAX_SNAP_S * libm::fabsf(self.x.phi_dot[j]);
            let reached = snaps || before * after <= 0.0;
            crossed[j] = inward && reached;
        }
        if base {
            let error = 0.5 * dt * dt * apart;
            if error > STEP_ERROR_RAD && self.halvings < MAX_HALVINGS {
                self.halvings += 1;
            } else if error < 0.125 * STEP_ERROR_RAD && self.halvings > 0 {
                self.halvings -= 1;
            }
        }
        Some(crossed)
    }

    /// Latches the `crossed` joints (reached in a step of `dt` \[s\]).
    ///
    /// The joint covers the rest of its stroke (the snap-through) in a few
    /// milliseconds; over that time the generalised momenta of the other
    /// joints hardly change (their equations do not contain the latching
    /// joint's torque), so they are taken at the capture angle and kept
    /// through the jump to the latch angle and the plastic impact
    /// (physics.md §5).
    fn latch_crossed(&mut self, chain: &Model<'_, R>, crossed: &[bool; R], dt: f32) {
        let n = self.count();
        // `p = M(φ) φ̇` (`Chain::momentum`) over the joints in use.
        let m = mass_matrix(chain, &self.x.phi);
        let mut p = [0.0f32; R];
        for i in 0..n {
            for j in 0..n {
                p[i] += m[i][j] * self.x.phi_dot[j];
            }
        }
        // Time to the latch angle at the rate of the crossing (the
        // snap only shortens it; negative when the step overshot it):
        // the other joints move on meanwhile.
        let mut tau = f32::NEG_INFINITY;
        for j in 0..n {
            if crossed[j] {
                let w = self.x.phi_dot[j];
                let t_j = if w != 0.0 { -self.x.phi[j] / w } else { 0.0 };
                if t_j.is_finite() {
                    tau = tau.max(t_j.max(-dt).min(MAX_SNAP_S));
                }
            }
        }
        let tau = if tau.is_finite() { tau } else { 0.0 };
        let mut after = self.latched;
        for j in 0..n {
            if crossed[j] {
                after[j] = true;
                self.x.phi[j] = 0.0;
            } else if !self.latched[j] {
                self.x.phi[j] += tau * self.x.phi_dot[j];
            }
        }
        self.t_s += tau;
        for j in 0..n {
            if crossed[j] {
                self.latch_after_s[j] = self.t_s;
            }
        }
        match solve(n, &mass_matrix(chain, &self.x.phi), &p, &after) {
            Some(w) if w.iter().all(|v| v.is_finite()) => self.x.phi_dot = w,
            _ => {
                for j in 0..n {
                    if after[j] {
                        self.x.phi_dot[j] = 0.0;
                    }
                }
            }
        }
        self.latched = after;
    }

    fn finish(&mut self) {
        self.done = true;
    }
}

/// Error estimate of a base step above which the next base steps are
/// halved \[rad\] (`Stepper::integrate`).
pub const STEP_ERROR_RAD: f32 = 0.002;

/// Most halvings of the base step \[1\]: at most 8 times as many steps as
/// the configured `dt_s` takes, so a rollout's work stays bounded.
pub const MAX_HALVINGS: u8 = 3;

/// Spring evaluations of the creep quadrature and snap-through that count
/// as one unit of a rollout's work (about the instructions of one step of
/// the chain on the Cortex-M4F: `docs/performance.md`).
pub const CREEP_EVALS_PER_STEP: u16 = 24;

/// `z` with `Φ(z) = p` for `p` in (0.5, 1), by Newton's method on the
/// normal distribution function (a handful of `erfc`/`exp` calls, run only
/// when a rollout starts).
pub fn normal_quantile(p: f32) -> f32 {
    let p = p.clamp(0.5, 0.999_999);
    let mut z = 0.0f32;
    for _ in 0..8 {
        let f = crate::monitor::margin::normal_cdf(z) - p;
        let pdf = 0.398_942_3 * libm::expf(-0.5 * z * z);
        if !(pdf > 1e-12) {
            break;
        }
        z -= f / pdf;
    }
    if z.is_finite() {
        z.clamp(0.0, 6.0)
    } else {
        0.0
    }
}

mod settle;
mod step_size;

#[cfg(test)]
mod tests;
