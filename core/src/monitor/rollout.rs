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
//! unstable. While every free joint glides or creeps slowly and smoothly,
//! far from its latch, the step grows up to `glide_dt_s`
//! (`docs/monitor.md` §6, the glide): a panel coasting on its momentum
//! with its spring within a few per cent of its friction, or creeping, is
//! crossed in a few long steps instead of hundreds.
//! A joint latches in the rollout when it reaches its capture angle moving
//! inwards; the rollout ends when every joint has latched, at the horizon
//! (the deployment's deadline), or once every free joint has crept
//! (|ω| < 2 ω_c) for [`STALL_HOLD_S`] and none can break free: the rest is
//! then quasi-static creep, whose time to the capture angle is a quadrature
//! over the spring curve ([`creep`]). The creep speeds up where the spring
//! stiffens towards the latch (the tape springs of seed 001 do), so the rate
//! of the moment is no guide to the time it takes.
//!
//! It runs up to three times per cycle ([`crate::monitor::predictor`]), a bounded
//! amount of work per slice of [`crate::Monitor::predict`]: with the
//! estimates `T̂_C`, `f̂`, `κ̂` (nominal: the prediction), with `T̂_C + zσ`,
//! `f̂ + zσ` and the springs at `1 + κ̂ − zσ_κ` (pessimistic), and with
//! `max(T̂_C − zσ, L)`, `f̂ − zσ` and `1 + κ̂ + zσ_κ` (optimistic, `L` the
//! friction torque the observer sees now); `z = Φ⁻¹(confidence)`. A latch of the
//! nominal rollout that the pessimistic one confirms, or a stall that the
//! optimistic one confirms, holds at that confidence for the friction
//! estimate; one that the bracket does not confirm is the best estimate only.

use crate::physics::chain::{Chain, ChainState, Mode};
use crate::physics::friction::coulomb_shape;
use crate::physics::linalg::{articulated_inertias, solve_spd_masked};
use crate::physics::spring::Branch;

/// Predicted time every free joint must creep before the rollout settles
/// the outcome by the creep quadrature, and between two tries [s].
pub const STALL_HOLD_S: f32 = 0.2;

/// Longest snap-through from the capture angle to the latch the rollout
/// allows for [s].
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
    /// Joint angles [rad] and rates [rad/s].
    pub state: ChainState<f32, N>,
    /// Joints latched already.
    pub latched: [bool; N],
    /// Coulomb torque of each joint [N·m].
    pub coulomb_nm: [f32; N],
    /// Viscous coefficient of each joint [N·m·s/rad].
    pub viscous_nms: [f32; N],
    /// Factor on each joint's spring torque [1].
    pub spring_scale: [f32; N],
    /// Capture angle of each joint [rad].
    pub capture_rad: [f32; N],
}

/// Settings of the rollouts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RolloutConfig {
    /// Integration step of the nominal rollout (the prediction) [s].
    pub dt_s: f32,
    /// Integration step of the pessimistic and optimistic brackets [s]:
    /// they only confirm the nominal rollout's verdicts (its confidence),
    /// and may be coarser.
    pub bracket_dt_s: f32,
    /// Longest integration step [s]: while every free joint glides or
    /// creeps slowly and smoothly, far from its capture angle, the step
    /// grows from `dt_s` (or `bracket_dt_s`) up to this
    /// ([`GLIDE_TURN_RAD`], [`GLIDE_RATE_CHANGE`]); below two steps the
    /// step stays fixed.
    pub glide_dt_s: f32,
    /// Units of work per slice of [`crate::Monitor::predict`] (a unit: one
    /// step, two chain evaluations, or [`CREEP_EVALS_PER_STEP`] spring
    /// evaluations of the creep quadrature); 0 switches the rollouts off (the prediction then
    /// rests on the one-joint energy balance of [`crate::monitor::margin`] alone).
    pub steps_per_slice: u8,
    /// Slices of [`crate::Monitor::predict`] a replay runs after each
    /// sample ([`crate::Monitor::update_and_predict`]): the time the
    /// application gives the prediction between two samples, fixed so that
    /// a replay is deterministic.
    pub slices_per_sample: u8,
    /// Predicted time after which the joints not latched count as stalled
    /// [s] (the monitor shortens it to the deployment's deadline).
    pub horizon_s: f32,
    /// `ω_c` of the friction law [rad/s].
    pub coulomb_threshold_rad_s: f32,
}

/// What a finished rollout says about one joint.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct JointOutcome {
    /// True when the joint latched in the rollout (or had latched).
    pub latches: bool,
    /// Predicted time from the rollout's start to the latch [s].
    pub latch_after_s: f32,
}

/// One forward simulation in progress.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rollout<const N: usize> {
    start: RolloutStart<N>,
    x: ChainState<f32, N>,
    latched: [bool; N],
    latch_after_s: [f32; N],
    t_s: f32,
    creeping_s: f32,
    /// Each free joint's acceleration in the last step [rad/s²] (∞ before
    /// the first step and after a latch: the next step is a base step).
    accel: [f32; N],
    done: bool,
    /// The joints whose outcome is wanted: the rollout ends once all of
    /// them have latched (every joint unless [`Rollout::watching`]).
    watch: [bool; N],
    /// The creep quadrature in progress, resumed slice by slice.
    settle: Option<Settle<N>>,
}

/// The creep quadrature of a rollout in progress ([`Rollout::settle_creep`]),
/// one joint after the other, resumable.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Settle<const N: usize> {
    /// Time left to the horizon when the quadrature started [s].
    time_left: f32,
    /// Articulated inertia of each joint then [kg·m²].
    inertia: [f32; N],
    /// Creep time of each joint settled so far [s] (∞: no latch).
    after: [f32; N],
    /// The joint in progress.
    joint: u8,
    /// Its creep, once begun.
    run: Option<CreepRun>,
}

impl<const N: usize> Rollout<N> {
    /// A rollout from `start`, not yet advanced.
    pub fn new(start: RolloutStart<N>) -> Self {
        Rollout {
            x: start.state,
            latched: start.latched,
            latch_after_s: [0.0; N],
            t_s: 0.0,
            creeping_s: 0.0,
            accel: [f32::INFINITY; N],
            done: false,
            watch: [true; N],
            settle: None,
            start,
        }
    }

    /// The same rollout, ended as soon as every joint of `watch` has
    /// latched: the outcome of the others is then left as "not latched"
    /// (a bracket that only has to confirm the nominal rollout's latches
    /// stops there). A rollout watching no joint ends at the first step.
    pub fn watching(mut self, watch: [bool; N]) -> Self {
        self.watch = watch;
        self
    }

    /// Where the rollout started, with the friction and springs it assumes.
    pub fn start(&self) -> &RolloutStart<N> {
        &self.start
    }

    /// The joints whose outcome the rollout decides ([`Rollout::watching`]).
    pub fn watch(&self) -> [bool; N] {
        self.watch
    }

    /// Time simulated so far [s].
    pub fn elapsed_s(&self) -> f32 {
        self.t_s
    }

    /// True once the rollout has ended.
    pub fn is_done(&self) -> bool {
        self.done
    }

    /// The outcome of each joint (meaningful once done).
    pub fn outcome(&self) -> [JointOutcome; N] {
        core::array::from_fn(|j| JointOutcome {
            latches: self.latched[j],
            latch_after_s: self.latch_after_s[j],
        })
    }

    /// Advances by up to `cfg.steps_per_slice` units of work: a unit is
    /// one step of the chain, or [`CREEP_EVALS_PER_STEP`] spring
    /// evaluations of the creep quadrature and snap-through, so that a
    /// slice costs about the same whatever the rollout is doing.
    pub fn advance(&mut self, chain: &Chain<f32, N>, cfg: &RolloutConfig) {
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
        chain: &Chain<f32, N>,
        x: &ChainState<f32, N>,
        h: f32,
        wc: f32,
    ) -> Option<[f32; N]> {
        let mut mode = Mode::<N> {
            latched: self.latched,
            ..Mode::default()
        };
        for j in 0..N {
            mode.branch[j] = Branch::select(x.phi[j], x.phi_dot[j]);
        }
        let (mut m, mut rhs) = chain.equations(x, &mode);
        for j in 0..N {
            if self.latched[j] {
                continue;
            }
            let w = x.phi_dot[j];
            let spring = chain.joints()[j].spring.torque(x.phi[j], mode.branch[j]);
            let tc = self.start.coulomb_nm[j];
            let f = self.start.viscous_nms[j];
            let th = coulomb_shape(w, wc);
            rhs[j] += (self.start.spring_scale[j] - 1.0) * spring - tc * th - f * w;
            m[j][j] += h * (tc * (1.0 - th * th) / wc + f);
        }
        solve_spd_masked(&m, &rhs, &self.latched).ok()
    }

    /// One step: the midpoint rule (second order), each stage linearly
    /// implicit in the stiff friction; then the latches the step reached,
    /// and the end of the rollout or the start of the creep quadrature.
    fn step(&mut self, chain: &Chain<f32, N>, cfg: &RolloutConfig) {
        let dt = self.step_length(chain, cfg);
        let wc = cfg.coulomb_threshold_rad_s;
        let Some(crossed) = self.integrate(chain, dt, wc) else {
            self.finish();
            return;
        };
        self.t_s += dt;
        if crossed.iter().any(|c| *c) {
            self.latch_crossed(chain, &crossed, dt);
            // The impact changes every rate: a base step next.
            self.accel = [f32::INFINITY; N];
        }
        if (0..N).all(|j| self.latched[j] || !self.watch[j]) {
            self.done = true;
            return;
        }
        let creeping = (0..N).all(|j| self.latched[j] || libm::fabsf(self.x.phi_dot[j]) < 2.0 * wc);
        self.creeping_s = if creeping { self.creeping_s + dt } else { 0.0 };
        let finite = self
            .x
            .phi
            .iter()
            .chain(self.x.phi_dot.iter())
            .all(|v| v.is_finite());
        if !finite || self.t_s >= cfg.horizon_s {
            self.finish();
            return;
        }
        if self.creeping_s >= STALL_HOLD_S {
            self.begin_settle(chain, cfg);
        }
    }

    /// Length of the next step [s]: `cfg.dt_s`, or longer, up to
    /// `cfg.glide_dt_s`, while every free joint glides or creeps slowly
    /// and smoothly (`docs/monitor.md` §6, the glide): over the step each
    /// free joint turns by at most [`GLIDE_TURN_RAD`], its rate changes by
    /// at most [`GLIDE_RATE_CHANGE`] of itself (of `ω_c` when slower), its
    /// spring torque at the step's end (at the present rate) differs from
    /// the present one by at most [`GLIDE_TORQUE_CHANGE`] of the larger of
    /// the two torques that balance in the glide, spring and Coulomb (a
    /// tape spring's snap-through peak is met at the base step), and it
    /// covers at most half of what is left to its capture angle (the latch
    /// too). A step is lengthened only when these allow at least
    /// [`GLIDE_MIN_STEPS`] base steps at once.
    fn step_length(&self, chain: &Chain<f32, N>, cfg: &RolloutConfig) -> f32 {
        let base = cfg.dt_s;
        let wc = cfg.coulomb_threshold_rad_s;
        let mut h = cfg.glide_dt_s;
        for j in 0..N {
            if self.latched[j] {
                continue;
            }
            let w = libm::fabsf(self.x.phi_dot[j]);
            let left = libm::fabsf(self.x.phi[j]) - self.start.capture_rad[j];
            let limits = [
                GLIDE_TURN_RAD / w,
                0.5 * left / w,
                GLIDE_RATE_CHANGE * w.max(wc) / libm::fabsf(self.accel[j]),
            ];
            for limit in limits {
                // A NaN limit makes `h` NaN: a base step.
                if !(limit >= h) {
                    h = limit;
                }
            }
        }
        // Lengthened by at least GLIDE_MIN_STEPS base steps or not at all:
        // a swing is stepped exactly as with the fixed step.
        if !(h >= GLIDE_MIN_STEPS * base) {
            return base;
        }
        for (j, joint) in chain.joints().iter().enumerate() {
            if self.latched[j] {
                continue;
            }
            let (phi, w) = (self.x.phi[j], self.x.phi_dot[j]);
            let branch = Branch::select(phi, w);
            let scale = self.start.spring_scale[j];
            let now = scale * joint.spring.torque(phi, branch);
            let then = scale * joint.spring.torque(phi + w * h, branch);
            let balance = libm::fabsf(now).max(self.start.coulomb_nm[j]);
            if !(libm::fabsf(then - now) <= GLIDE_TORQUE_CHANGE * balance) {
                return base;
            }
        }
        h
    }

    /// Integrates the free joints over `dt` [s] by the midpoint rule, each
    /// stage linearly implicit in the friction (`ω_c` = `wc` [rad/s]).
    /// Returns the joints that reached their capture angle moving inwards,
    /// or `None` when the equations could not be solved.
    fn integrate(&mut self, chain: &Chain<f32, N>, dt: f32, wc: f32) -> Option<[bool; N]> {
        let a1 = self.acceleration(chain, &self.x, 0.5 * dt, wc)?;
        let mut mid = self.x;
        for j in 0..N {
            if !self.latched[j] {
                mid.phi_dot[j] += 0.5 * dt * a1[j];
                mid.phi[j] += 0.5 * dt * self.x.phi_dot[j];
            }
        }
        let a = self.acceleration(chain, &mid, dt, wc)?;
        let mut crossed = [false; N];
        for j in 0..N {
            if self.latched[j] {
                self.x.phi_dot[j] = 0.0;
                continue;
            }
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
        Some(crossed)
    }

    /// Latches the `crossed` joints (reached in a step of `dt` [s]).
    ///
    /// The joint covers the rest of its stroke (the snap-through) in a few
    /// milliseconds; over that time the generalised momenta of the other
    /// joints hardly change (their equations do not contain the latching
    /// joint's torque), so they are taken at the capture angle and kept
    /// through the jump to the latch angle and the plastic impact
    /// (physics.md §5).
    fn latch_crossed(&mut self, chain: &Chain<f32, N>, crossed: &[bool; N], dt: f32) {
        let p = chain.momentum(&self.x);
        // Time to the latch angle at the rate of the crossing (the
        // snap only shortens it; negative when the step overshot it):
        // the other joints move on meanwhile.
        let mut tau = f32::NEG_INFINITY;
        for j in 0..N {
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
        for j in 0..N {
            if crossed[j] {
                after[j] = true;
                self.x.phi[j] = 0.0;
            } else if !self.latched[j] {
                self.x.phi[j] += tau * self.x.phi_dot[j];
            }
        }
        self.t_s += tau;
        for j in 0..N {
            if crossed[j] {
                self.latch_after_s[j] = self.t_s;
            }
        }
        match solve_spd_masked(&chain.mass_matrix(&self.x.phi), &p, &after) {
            Ok(w) if w.iter().all(|v| v.is_finite()) => self.x.phi_dot = w,
            _ => {
                for j in 0..N {
                    if after[j] {
                        self.x.phi_dot[j] = 0.0;
                    }
                }
            }
        }
        self.latched = after;
    }

    /// Starts the creep quadrature, which runs in the next units of work;
    /// undecided (a joint breaks free in time), the integration goes on
    /// and looks again after another hold, not at every step (the
    /// quadrature and the snap-through cost up to a few hundred spring
    /// evaluations).
    fn begin_settle(&mut self, chain: &Chain<f32, N>, cfg: &RolloutConfig) {
        let m = chain.mass_matrix(&self.x.phi);
        let inertia = articulated_inertias(&m, &self.latched);
        self.settle = Some(Settle {
            time_left: cfg.horizon_s - self.t_s,
            inertia: core::array::from_fn(|j| inertia[j].unwrap_or(m[j][j])),
            after: [f32::INFINITY; N],
            joint: 0,
            run: None,
        });
        self.creeping_s = 0.0;
    }

    /// Ends the rollout by quadrature once every free joint creeps
    /// quasi-statically and none can break free: each joint's outcome is
    /// then its [`creep`] time against the time left. Runs at most `evals`
    /// spring evaluations and resumes at the next call; when some joint may
    /// still break free, drops the quadrature (the integration goes on).
    fn settle_creep(&mut self, chain: &Chain<f32, N>, cfg: &RolloutConfig, evals: u16) {
        let Some(mut settle) = self.settle.take() else {
            return;
        };
        let mut budget = evals;
        while usize::from(settle.joint) < N {
            let j = usize::from(settle.joint);
            if self.latched[j] {
                settle.joint += 1;
                continue;
            }
            let (Some(joint), Some(&inertia)) = (chain.joints().get(j), settle.inertia.get(j))
            else {
                return;
            };
            let mut run = settle.run.unwrap_or_else(|| {
                CreepRun::new(
                    CreepJoint {
                        from_rad: libm::fabsf(self.x.phi[j]),
                        capture_rad: self.start.capture_rad[j],
                        spring_scale: self.start.spring_scale[j],
                        coulomb_nm: self.start.coulomb_nm[j],
                        viscous_nms: self.start.viscous_nms[j],
                        inertia_kgm2: inertia,
                    },
                    cfg.coulomb_threshold_rad_s,
                    settle.time_left,
                )
            });
            let Some(creep) = run.run(&joint.spring, &mut budget) else {
                // Out of work for this slice: resume here.
                settle.run = Some(run);
                self.settle = Some(settle);
                return;
            };
            let time_left = settle.time_left;
            match creep {
                Creep::Covers(t) if t <= time_left => settle.after[j] = t,
                Creep::Covers(_) | Creep::Stops => {}
                Creep::BreaksFree(t) if t <= time_left => return,
                Creep::BreaksFree(_) => {}
            }
            settle.run = None;
            settle.joint += 1;
        }
        for j in 0..N {
            if !self.latched[j] && settle.after[j].is_finite() {
                self.latched[j] = true;
                self.latch_after_s[j] = self.t_s + settle.after[j];
            }
        }
        self.finish();
    }

    fn finish(&mut self) {
        self.done = true;
    }
}

/// Most a free joint may turn in one lengthened step of the glide [rad]
/// (2°: the spring torque changes little over it).
pub const GLIDE_TURN_RAD: f32 = 0.035;

/// Most a free joint's rate may change in one lengthened step of the
/// glide, relative to the rate (to `ω_c` when slower) [1].
pub const GLIDE_RATE_CHANGE: f32 = 0.1;

/// Fewest base steps a lengthened step spans [1]: below, the base step.
pub const GLIDE_MIN_STEPS: f32 = 2.0;

/// Most a free joint's spring torque may change over one lengthened step
/// of the glide, relative to the larger of its spring and Coulomb torques
/// [1].
pub const GLIDE_TORQUE_CHANGE: f32 = 0.05;

/// Sub-intervals of the creep quadrature.
const CREEP_PANELS: usize = 8;

/// Spring evaluations of the creep quadrature and snap-through that count
/// as one unit of a rollout's work (about the instructions of one step of
/// the chain on the Cortex-M4F: `docs/performance.md`).
pub const CREEP_EVALS_PER_STEP: u16 = 24;

/// Step of the one-joint snap-through integration [s].
const SNAP_DT_S: f32 = 0.002;

/// Longest snap-through from a creep the quadrature integrates [s]; a
/// longer one is left to the rollout.
const SNAP_LIMIT_S: f32 = 0.5;

/// What quasi-static creep does over the rest of a joint's stroke.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Creep {
    /// The joint creeps to its capture angle and snaps through to the latch
    /// in this time [s] (past the horizon: in no less).
    Covers(f32),
    /// The spring overcomes the Coulomb torque before the capture angle
    /// after this time [s] of creep (the joint breaks free and
    /// accelerates), or the snap-through takes longer than
    /// [`SNAP_LIMIT_S`]: the rollout has to go on.
    BreaksFree(f32),
    /// The spring cannot move the joint (no torque inwards).
    Stops,
}

/// One creeping joint, for [`creep`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CreepJoint {
    /// `|φ|` now [rad].
    pub from_rad: f32,
    /// Capture angle [rad] (0 without a snap-through).
    pub capture_rad: f32,
    /// Factor on the spring torque [1].
    pub spring_scale: f32,
    /// Coulomb torque `T_C` [N·m].
    pub coulomb_nm: f32,
    /// Viscous coefficient `f` [N·m·s/rad].
    pub viscous_nms: f32,
    /// Articulated inertia `1/(M⁻¹)_jj` [kg·m²] (for the snap-through).
    pub inertia_kgm2: f32,
}

/// Quasi-static creep of one joint from `|φ| = from_rad` to its capture
/// angle, then the snap-through to the latch. With inertia negligible the
/// friction balances the spring,
///
/// ```text
/// T_C tanh(ω/ω_c) + f ω = s τ_s(φ)  ⇒  ω ≈ ω_c artanh(s τ_s / T_C)
/// ```
/// (plus one Newton step for `f`), while `s τ_s < T_C`; the time is
/// `∫ dφ / ω(φ)` by the midpoint rule over [`CREEP_PANELS`] panels. The
/// creep rate grows as the spring torque grows along the stroke, so this is
/// where a constant-rate extrapolation would call a stall too early.
///
/// A joint that creeps up to the capture angle does not latch there: it
/// breaks free where the spring's snap-through peak first exceeds `T_C`
/// and accelerates from its creep rate, which with the whole outer chain to
/// move takes a few tenths of a second. That part is integrated for the
/// joint alone, `I φ̈ = s τ_s − T_C tanh(ω/ω_c) − f ω` with `I` its
/// articulated inertia, in steps of [`SNAP_DT_S`] linearly implicit in the
/// friction.
///
/// `horizon_s` is the time that matters [s]: the integration stops once it
/// is passed (the joint does not latch within it either way).
pub fn creep(
    spring: &crate::physics::spring::Spring<f32>,
    joint: &CreepJoint,
    wc: f32,
    horizon_s: f32,
) -> Creep {
    let mut run = CreepRun::new(*joint, wc, horizon_s);
    loop {
        let mut budget = u16::MAX;
        if let Some(out) = run.run(spring, &mut budget) {
            return out;
        }
    }
}

/// [`creep`] in progress: resumable, a bounded number of spring
/// evaluations at a time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CreepRun {
    joint: CreepJoint,
    wc: f32,
    horizon_s: f32,
    stage: CreepStage,
}

/// Where a [`CreepRun`] is.
#[derive(Clone, Copy, Debug, PartialEq)]
enum CreepStage {
    /// Panel `k` of the quadrature next, `t` [s] of creep so far.
    Quadrature { k: u8, t: f32 },
    /// The snap-through: creep time `t` [s], `|φ|` [rad], rate `w`
    /// [rad/s] and time of the snap so far [s].
    Snap { t: f32, abs: f32, w: f32, snap: f32 },
}

impl CreepRun {
    /// The creep of `joint` (see [`creep`]), not yet begun.
    pub fn new(joint: CreepJoint, wc: f32, horizon_s: f32) -> Self {
        CreepRun {
            joint,
            wc,
            horizon_s,
            stage: CreepStage::Quadrature { k: 0, t: 0.0 },
        }
    }

    /// Goes on for at most `budget` spring evaluations (taken off it);
    /// `Some` once the outcome is known, `None` when the budget ran out.
    pub fn run(
        &mut self,
        spring: &crate::physics::spring::Spring<f32>,
        budget: &mut u16,
    ) -> Option<Creep> {
        loop {
            if *budget == 0 {
                return None;
            }
            *budget -= 1;
            let outcome = match self.stage {
                CreepStage::Quadrature { k, t } => self.quadrature(spring, k, t),
                CreepStage::Snap { t, abs, w, snap } => self.snap(spring, t, abs, w, snap),
            };
            if outcome.is_some() {
                return outcome;
            }
        }
    }

    /// Panel `k` of the quadrature after `t` [s] of creep, or, past the
    /// last panel, the start of the snap-through from the capture angle at
    /// the creep rate there. `Some` once the outcome is known.
    fn quadrature(
        &mut self,
        spring: &crate::physics::spring::Spring<f32>,
        k: u8,
        mut t: f32,
    ) -> Option<Creep> {
        let joint = self.joint;
        let wc = self.wc;
        let (scale, tc, f) = (joint.spring_scale, joint.coulomb_nm, joint.viscous_nms);
        let to_rad = joint.capture_rad.max(0.0);
        let span = joint.from_rad - to_rad;
        if span > 0.0 && usize::from(k) < CREEP_PANELS {
            let h = span / CREEP_PANELS as f32;
            let abs = joint.from_rad - (f32::from(k) + 0.5) * h;
            let torque = scale * spring.magnitude(abs, Branch::Unfold);
            if !(torque > 0.0) {
                return Some(Creep::Stops);
            }
            if !(torque < tc) {
                return Some(Creep::BreaksFree(t));
            }
            match creep_rate(torque, tc, f, wc) {
                Some(w) => t += h / w,
                None => return Some(Creep::Stops),
            }
            self.stage = CreepStage::Quadrature { k: k + 1, t };
            return None;
        }
        let abs = to_rad.min(joint.from_rad.max(0.0));
        let w = creep_rate(scale * spring.magnitude(abs, Branch::Unfold), tc, f, wc).unwrap_or(0.0);
        if !(joint.inertia_kgm2 > 0.0) {
            return Some(Creep::BreaksFree(t));
        }
        self.stage = CreepStage::Snap {
            t,
            abs,
            w,
            snap: 0.0,
        };
        None
    }

    /// One step of the snap-through after `t` [s] of creep, at `|φ|` =
    /// `abs` [rad] with rate `w` [rad/s], `snap` [s] into it. `Some` once
    /// the outcome is known.
    fn snap(
        &mut self,
        spring: &crate::physics::spring::Spring<f32>,
        t: f32,
        mut abs: f32,
        mut w: f32,
        mut snap: f32,
    ) -> Option<Creep> {
        let joint = self.joint;
        let wc = self.wc;
        let (scale, tc, f) = (joint.spring_scale, joint.coulomb_nm, joint.viscous_nms);
        let inertia = joint.inertia_kgm2;
        if abs > 0.0 {
            if t + snap > self.horizon_s {
                return Some(Creep::Covers(t + snap));
            }
            if snap >= SNAP_LIMIT_S {
                return Some(Creep::BreaksFree(t + snap));
            }
            let th = coulomb_shape(w, wc);
            let torque = scale * spring.magnitude(abs, Branch::Unfold) - tc * th - f * w;
            let damping = tc * (1.0 - th * th) / wc + f;
            let dw = SNAP_DT_S * torque / (inertia + SNAP_DT_S * damping);
            let step = SNAP_DT_S * (w + 0.5 * dw);
            if !step.is_finite() {
                return Some(Creep::Stops);
            }
            if !(step >= abs && step > 0.0) {
                abs -= step;
                w += dw;
                snap += SNAP_DT_S;
                self.stage = CreepStage::Snap { t, abs, w, snap };
                return None;
            }
            snap += SNAP_DT_S * abs / step;
        }
        let total = t + snap;
        Some(if total.is_finite() {
            Creep::Covers(total)
        } else {
            Creep::Stops
        })
    }
}

/// The quasi-static creep rate [rad/s] under a spring torque `torque`
/// below `T_C`: `ω_c artanh(τ/T_C)`, then one Newton step on
/// `T_C tanh(ω/ω_c) + f ω − τ = 0` for the viscous part. `None` when the
/// spring cannot move the joint or overcomes the friction.
fn creep_rate(torque: f32, tc: f32, f: f32, wc: f32) -> Option<f32> {
    if !(torque > 0.0) || !(torque < tc) {
        return None;
    }
    let w0 = wc * libm::atanhf(torque / tc);
    let th = libm::tanhf(w0 / wc);
    let slope = tc * (1.0 - th * th) / wc + f;
    let w = if slope > 0.0 { w0 - f * w0 / slope } else { w0 };
    (w > 0.0 && w.is_finite()).then_some(w)
}

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

#[cfg(test)]
mod tests;
