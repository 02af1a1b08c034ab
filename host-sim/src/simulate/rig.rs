//! A deployment on the zero-g rig (`physics.md` §11, this project's
//! extension): the core's chain equations with the rig's forces added as
//! generalised forces on the chain, and the trolleys and bars integrated
//! beside it (Dormand–Prince 5(4), [`crate::simulate::rig_ode`]).
//!
//! - wire: a trolley at `P_t` carrying panel `i` at its offload point `O`
//!   pulls it back like a pendulum, `F = −κ (O − P_t)`, `κ = m_i g / L_eff`
//!   (small swing), and is pulled by `−F`;
//! - rails: stick–slip friction `−N μ(v)` on each trolley (along its bar,
//!   load `N = (m_t + m_i) g`) and each bar (laterally, its whole load),
//!   [`Rig::mu`];
//! - frames: every panel's outboard tip against every frame's face, Hertz
//!   contact `F = k δ^1.5 + c δ^0.25 δ̇` \[N\] (δ \[mm\], δ̇ [mm/s], never pulling,
//!   as the latch stop of `physics.md` §10.2).
//!
//! The work every dissipative force does is integrated as a state, so the
//! energy balance can be checked ([`RigRun::energy_j`]).

use crate::model::effect::{self, Effect};
use crate::model::mechanism::{with_joints, Mechanism};
use crate::model::rig::Rig;
use crate::model::torque_table::HostChain;
use crate::simulate::rig_ode;
use crate::simulate::stowed::StowedWatch;
use crate::simulate::trajectory::{SimError, SimOptions, SimStats, Trajectory};
use deploywatch_core::physics::solve_spd_masked;
use deploywatch_core::{Branch, ChainState, Mode};

/// A contact of a panel with a frame.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameContact {
    /// The panel (1-based).
    pub panel: usize,
    /// The frame's name.
    pub frame: String,
    /// First contact \[s\].
    pub first_s: f64,
    /// Largest penetration \[mm\].
    pub max_depth_mm: f64,
    /// Largest force \[N\].
    pub max_force_n: f64,
}

/// A deployment on the rig.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RigRun {
    /// The chain's trajectory, as every simulator gives it.
    pub traj: Trajectory,
    /// `trolley_xy[t][i]`: trolley t's position at sample i \[m\].
    pub trolley_xy: Vec<Vec<[f64; 2]>>,
    /// `tip_xy[p][i]`: panel p's outboard tip at sample i \[m\].
    pub tip_xy: Vec<Vec<[f64; 2]>>,
    /// The frame contacts, in order of first contact.
    pub contacts: Vec<FrameContact>,
    /// Total energy (kinetic, springs, wires, contacts) plus the work
    /// dissipated so far, at each sample \[J\]: constant up to the
    /// integration error while no latch closes.
    pub energy_j: Vec<f64>,
}

/// The rig's model of one mechanism, with `N` joints.
struct Model<'a, const N: usize> {
    chain: HostChain<N>,
    rig: &'a Rig,
    lengths: [f64; N],
    /// Per trolley: panel index (0-based), offload distance, bar (0-based),
    /// wire stiffness κ [N/m], x load \[N\], lateral offset of the trolley on
    /// its bar \[m\].
    trolleys: Vec<(usize, f64, usize, f64, f64, f64)>,
    /// Per bar: lateral mass \[kg\] and load \[N\].
    bars: Vec<(f64, f64)>,
    /// Trolley masses \[kg\].
    trolley_mass: Vec<f64>,
    side: [f64; N],
    /// Chain dissipation besides the rig is not tracked: the chain's own
    /// friction must be zero for the energy balance.
    latched: [bool; N],
}

/// Sizes of the state vector's parts.
fn layout(n: usize, rig: &Rig) -> (usize, usize, usize) {
    let q = n + rig.trolleys.len() + rig.bars.len();
    (q, 2 * q, 2 * q + 1)
}

/// `(cos θ, sin θ)` of the absolute angles.
fn trig<const N: usize>(phi: &[f64]) -> ([f64; N], [f64; N]) {
    let (mut c, mut s) = ([0.0; N], [0.0; N]);
    let mut th = 0.0;
    for k in 0..N {
        th += phi[k];
        (s[k], c[k]) = th.sin_cos();
    }
    (c, s)
}

impl<const N: usize> Model<'_, N> {
    /// Position and velocity of the point `s` along panel `i`.
    fn point(&self, i: usize, s: f64, phi: &[f64], rate: &[f64]) -> ([f64; 2], [f64; 2]) {
        self.point_at(i, s, &trig::<N>(phi), rate)
    }

    /// [`Model::point`] with the absolute angles' `(cos θ, sin θ)` given.
    fn point_at(
        &self,
        i: usize,
        s: f64,
        (c, sn): &([f64; N], [f64; N]),
        rate: &[f64],
    ) -> ([f64; 2], [f64; 2]) {
        let (mut p, mut v) = ([0.0; 2], [0.0; 2]);
        let mut thd = 0.0;
        for k in 0..=i {
            thd += rate[k];
            let l = if k < i { self.lengths[k] } else { s };
            p[0] += l * c[k];
            p[1] += l * sn[k];
            v[0] -= l * sn[k] * thd;
            v[1] += l * c[k] * thd;
        }
        (p, v)
    }

    /// Adds to `q` (joint space) the generalised force of `f` at the point
    /// `s` along panel `i`.
    fn add_force(
        &self,
        q: &mut [f64; N],
        i: usize,
        s: f64,
        f: [f64; 2],
        cs: &([f64; N], [f64; N]),
    ) {
        let (c, sn) = cs;
        let mut qt = [0.0; N];
        for k in 0..=i {
            let l = if k < i { self.lengths[k] } else { s };
            qt[k] = l * (-sn[k] * f[0] + c[k] * f[1]);
        }
        let mut acc = 0.0;
        for j in (0..N).rev() {
            acc += qt[j];
            q[j] += acc;
        }
    }

    /// Trolley `t`'s position and velocity from the state.
    fn trolley(&self, t: usize, y: &[f64], nq: usize) -> ([f64; 2], [f64; 2]) {
        let (_, _, bar, _, _, y0) = self.trolleys[t];
        let nt = self.trolleys.len();
        let (x, yb) = (y[N + t], y[N + nt + bar]);
        let (vx, vyb) = (y[nq + N + t], y[nq + N + nt + bar]);
        ([x, y0 + yb], [vx, vyb])
    }

    /// The contact force \[N\] (along the frame's normal) and its
    /// dissipated power \[W\] at penetration `d` \[m\], rate `dd` [m/s]; and its
    /// stored energy \[J\].
    fn contact(&self, d: f64, dd: f64) -> (f64, f64, f64) {
        if d <= 0.0 {
            return (0.0, 0.0, 0.0);
        }
        let (dm, ddm) = (d * 1e3, dd * 1e3);
        let elastic = self.rig.contact_stiffness * dm.powf(1.5);
        let f = (elastic + self.rig.contact_damping * dm.powf(0.25) * ddm).max(0.0);
        let stored = self.rig.contact_stiffness * dm.powf(2.5) / 2.5 * 1e-3;
        (f, (f - elastic) * dd, stored)
    }

    /// The right-hand side of the whole state.
    fn deriv(&self, y: &[f64]) -> Option<Vec<f64>> {
        let (nq, _, len) = layout(N, self.rig);
        let nt = self.trolleys.len();
        let mut dy = vec![0.0; len];
        dy[..nq].copy_from_slice(&y[nq..2 * nq]);
        let phi: [f64; N] = core::array::from_fn(|j| y[j]);
        let rate: [f64; N] =
            core::array::from_fn(|j| if self.latched[j] { 0.0 } else { y[nq + j] });
        let mut mode = Mode::<N> {
            latched: self.latched,
            ..Mode::default()
        };
        for j in 0..N {
            mode.branch[j] = if phi[j] * rate[j] < 0.0 {
                Branch::Unfold
            } else {
                Branch::Fold
            };
            dy[j] = rate[j];
        }
        let x = ChainState { phi, phi_dot: rate };
        let (m, mut rhs) = self.chain.equations(&x, &mode);
        let cs = trig::<N>(&phi);
        let mut q = [0.0; N];
        let mut dissipated = 0.0;
        let mut trolley_force = vec![[0.0; 2]; nt];
        for (t, &(i, s, _, kappa, _, _)) in self.trolleys.iter().enumerate() {
            let (o, _) = self.point_at(i, s, &cs, &rate);
            let (p, _) = self.trolley(t, y, nq);
            let f = [-kappa * (o[0] - p[0]), -kappa * (o[1] - p[1])];
            self.add_force(&mut q, i, s, f, &cs);
            trolley_force[t] = [-f[0], -f[1]];
        }
        for i in 0..N {
            let (p, v) = self.point_at(i, self.lengths[i], &cs, &rate);
            for fr in &self.rig.frames {
                let d = fr.at_m - (fr.normal[0] * p[0] + fr.normal[1] * p[1]);
                let dd = -(fr.normal[0] * v[0] + fr.normal[1] * v[1]);
                let (f, loss, _) = self.contact(d, dd);
                if f > 0.0 || loss != 0.0 {
                    let force = [f * fr.normal[0], f * fr.normal[1]];
                    self.add_force(&mut q, i, self.lengths[i], force, &cs);
                    dissipated += loss;
                }
            }
        }
        for j in 0..N {
            rhs[j] += q[j];
        }
        let acc = solve_spd_masked(&m, &rhs, &self.latched).ok()?;
        for j in 0..N {
            dy[nq + j] = if self.latched[j] { 0.0 } else { acc[j] };
        }
        let mut bar_force = vec![0.0; self.bars.len()];
        for (t, &(_, _, bar, _, load, _)) in self.trolleys.iter().enumerate() {
            let v = y[nq + N + t];
            let fric = self.rig.rail_force(load, v);
            dissipated += fric * v;
            dy[nq + N + t] = (trolley_force[t][0] - fric) / self.trolley_mass[t];
            bar_force[bar] += trolley_force[t][1];
        }
        for (b, &(mass, load)) in self.bars.iter().enumerate() {
            let v = y[nq + N + nt + b];
            let fric = self.rig.rail_force(load, v);
            dissipated += fric * v;
            dy[nq + N + nt + b] = (bar_force[b] - fric) / mass;
        }
        dy[len - 1] = dissipated;
        Some(dy)
    }

    /// Total energy plus the dissipated work \[J\] at state `y`.
    fn energy(&self, y: &[f64]) -> f64 {
        let (nq, _, len) = layout(N, self.rig);
        let nt = self.trolleys.len();
        let phi: [f64; N] = core::array::from_fn(|j| y[j]);
        let rate: [f64; N] = core::array::from_fn(|j| y[nq + j]);
        let x = ChainState { phi, phi_dot: rate };
        let mut e = self.chain.kinetic_energy(&x) + self.chain.potential_energy(&phi);
        for (t, &(i, s, _, kappa, _, _)) in self.trolleys.iter().enumerate() {
            let (o, _) = self.point(i, s, &phi, &rate);
            let (p, v) = self.trolley(t, y, nq);
            e += 0.5 * kappa * ((o[0] - p[0]).powi(2) + (o[1] - p[1]).powi(2));
            e += 0.5 * self.trolley_mass[t] * v[0] * v[0];
        }
        for (b, &(mass, _)) in self.bars.iter().enumerate() {
            e += 0.5 * mass * y[nq + N + nt + b].powi(2);
        }
        for i in 0..N {
            let (p, _) = self.point(i, self.lengths[i], &phi, &rate);
            for fr in &self.rig.frames {
                let d = fr.at_m - (fr.normal[0] * p[0] + fr.normal[1] * p[1]);
                e += self.contact(d, 0.0).2;
            }
        }
        e + y[len - 1]
    }
}

/// Simulates `mech` (with `effects`) on its rig, sampled at `times`.
pub fn simulate_rig(
    mech: &Mechanism,
    effects: &[Effect],
    opts: &SimOptions,
    times: &[f64],
) -> Result<RigRun, SimError> {
    let rig = mech
        .active_rig()
        .ok_or_else(|| SimError::Invalid(format!("`{}` has no rig", mech.name)))?
        .with_effects(effects);
    let rig = &rig;
    let n = mech.joint_count();
    let (je, g) = effect::to_core(effects, n);
    let bad = || SimError::Invalid(format!("mechanism `{}` cannot be built", mech.name));
    with_joints!(n, N => {
        let chain = mech.chain::<N>(&je, g).ok_or_else(bad)?;
        run::<N>(model::<N>(mech, rig, chain), opts, times, mech)
    }, else Err(bad()))
}

/// Refuses a rig cause (`rig_friction`, `wire_length`, `frame_offset`) on a mechanism
/// without an active rig: there is nothing for it to act on (a flight
/// unit, `--flight`, has no rig).
pub fn check_rig_effects(mech: &Mechanism, effects: &[Effect]) -> Result<(), SimError> {
    match effects.iter().find(|e| e.kind().is_rig()) {
        Some(e) if mech.active_rig().is_none() => Err(SimError::Invalid(format!(
            "{}: `{}` has no active [rig] for it to act on (a rig cause; the flight unit has none)",
            e.kind(),
            mech.name
        ))),
        _ => Ok(()),
    }
}

/// The rig's model of `mech` with its chain.
fn model<'a, const N: usize>(mech: &Mechanism, rig: &'a Rig, chain: HostChain<N>) -> Model<'a, N> {
    let g = rig.gravity_m_s2;
    let lengths = core::array::from_fn(|i| mech.panels[i].length_m);
    let stowed: Vec<f64> = mech
        .joints
        .iter()
        .map(|j| j.stowed_deg.to_radians())
        .collect();
    let mut m = Model {
        chain,
        rig,
        lengths,
        trolleys: Vec::new(),
        bars: rig
            .bars
            .iter()
            .map(|b| (b.mass_kg, b.mass_kg * g))
            .collect(),
        trolley_mass: rig.trolleys.iter().map(|t| t.mass_kg.max(1e-6)).collect(),
        side: core::array::from_fn(|j| stowed[j].signum()),
        latched: [false; N],
    };
    for t in &rig.trolleys {
        let i = t.panel - 1;
        let carried = mech.panels[i].mass_kg;
        let (o, _) = m.point(i, t.offload_m, &stowed, &[0.0; N]);
        let o = t.start_m.unwrap_or(o);
        let kappa = carried * g / rig.pendulum_m(t, carried);
        let load = (carried + t.mass_kg) * g;
        m.trolleys
            .push((i, t.offload_m, t.bar - 1, kappa, load, o[1]));
        m.bars[t.bar - 1].0 += t.mass_kg;
        m.bars[t.bar - 1].1 += load;
    }
    for b in &mut m.bars {
        b.0 = b.0.max(1e-6);
    }
    m
}

/// The integration's bookkeeping of [`run`].
struct Recorder {
    run: RigRun,
    stats: SimStats,
}

impl Recorder {
    fn new(n: usize, trolleys: usize) -> Self {
        let mut run = RigRun::default();
        run.traj.phi_deg = vec![Vec::new(); n];
        run.traj.rate_deg_s = vec![Vec::new(); n];
        run.traj.latched = vec![Vec::new(); n];
        run.traj.latch_s = vec![None; n];
        run.trolley_xy = vec![Vec::new(); trolleys];
        run.tip_xy = vec![Vec::new(); n];
        Recorder {
            run,
            stats: SimStats::default(),
        }
    }

    /// Records the sample at `t`.
    fn sample<const N: usize>(&mut self, m: &Model<'_, N>, t: f64, y: &[f64]) {
        let (nq, _, _) = layout(N, m.rig);
        let r = &mut self.run;
        r.traj.t_s.push(t);
        let phi: Vec<f64> = y[..N].to_vec();
        let rate: Vec<f64> = y[nq..nq + N].to_vec();
        for j in 0..N {
            r.traj.phi_deg[j].push(phi[j].to_degrees());
            r.traj.rate_deg_s[j].push(rate[j].to_degrees());
            r.traj.latched[j].push(m.latched[j]);
            r.tip_xy[j].push(m.point(j, m.lengths[j], &phi, &rate).0);
        }
        for t in 0..m.trolleys.len() {
            r.trolley_xy[t].push(m.trolley(t, y, nq).0);
        }
        r.energy_j.push(m.energy(y));
    }

    /// Notes the frame contacts at state `y`, time `t`.
    fn contacts<const N: usize>(&mut self, m: &Model<'_, N>, t: f64, y: &[f64]) {
        let (nq, _, _) = layout(N, m.rig);
        for i in 0..N {
            let (p, v) = m.point(i, m.lengths[i], &y[..N], &y[nq..nq + N]);
            for fr in &m.rig.frames {
                let d = fr.at_m - (fr.normal[0] * p[0] + fr.normal[1] * p[1]);
                if d <= 0.0 {
                    continue;
                }
                let dd = -(fr.normal[0] * v[0] + fr.normal[1] * v[1]);
                let f = m.contact(d, dd).0;
                let list = &mut self.run.contacts;
                let k = match list
                    .iter()
                    .position(|c| c.panel == i + 1 && c.frame == fr.name)
                {
                    Some(k) => k,
                    None => {
                        list.push(FrameContact {
                            panel: i + 1,
                            frame: fr.name.clone(),
                            first_s: t,
                            max_depth_mm: 0.0,
                            max_force_n: 0.0,
                        });
                        list.len() - 1
                    }
                };
                list[k].max_depth_mm = list[k].max_depth_mm.max(d * 1e3);
                list[k].max_force_n = list[k].max_force_n.max(f);
            }
        }
    }
}

/// The initial state: stowed, trolleys above their offload points, at rest.
fn initial<const N: usize>(m: &Model<'_, N>, mech: &Mechanism) -> Vec<f64> {
    let (nq, _, len) = layout(N, m.rig);
    let mut y = vec![0.0; len];
    let stowed: Vec<f64> = mech
        .joints
        .iter()
        .map(|j| j.stowed_deg.to_radians())
        .collect();
    y[..N].copy_from_slice(&stowed);
    for (t, &(i, s, ..)) in m.trolleys.iter().enumerate() {
        let start = mech.active_rig().and_then(|r| r.trolleys[t].start_m);
        y[N + t] = start.unwrap_or(m.point(i, s, &stowed, &[0.0; N]).0)[0];
    }
    let _ = nq;
    y
}

/// Latches joint `j` at state `y` (its angle set to 0): the plastic
/// impulse of `physics.md` section 5 on the chain.
fn latch<const N: usize>(m: &mut Model<'_, N>, y: &mut [f64], j: usize) -> Option<()> {
    let (nq, _, _) = layout(N, m.rig);
    y[j] = 0.0;
    let mut after = m.latched;
    after[j] = true;
    let x = ChainState {
        phi: core::array::from_fn(|k| y[k]),
        phi_dot: core::array::from_fn(|k| y[nq + k]),
    };
    let v = m.chain.latch_impulse(&x, &after).ok()?;
    y[nq..nq + N].copy_from_slice(&v);
    m.latched = after;
    Some(())
}

/// Integrates to every sample time.
fn run<const N: usize>(
    mut m: Model<'_, N>,
    opts: &SimOptions,
    times: &[f64],
    mech: &Mechanism,
) -> Result<RigRun, SimError> {
    let mut y = initial(&m, mech);
    let mut rec = Recorder::new(N, m.trolleys.len());
    let (mut t, mut h): (f64, f64) = (0.0, 1e-4);
    let settle = opts.settle_s.unwrap_or(mech.settle_s);
    let mut deployed_at: Option<f64> = None;
    let mut watch = StowedWatch::stowed_at(core::array::from_fn(|j| y[j]));
    for &target in times {
        while t < target - 1e-12 {
            if rec.stats.steps + rec.stats.rejected > crate::simulate::trajectory::MAX_STEPS {
                return Err(SimError::TooManySteps { t_s: t });
            }
            let hs = h.min(target - t).min(opts.max_step_s);
            let mut f = |z: &[f64]| m.deriv(z);
            let Some((y1, err)) = rig_ode::step(&mut f, &y, hs, opts.rtol, opts.atol) else {
                return Err(SimError::Invalid("the rig's equations are singular".into()));
            };
            rec.stats.evaluations += 7;
            let grow = (0.9 * err.max(1e-10).powf(-0.2)).clamp(0.2, 5.0);
            if err > 1.0 {
                rec.stats.rejected += 1;
                h = hs * grow;
                continue;
            }
            let crossed =
                (0..N).find(|&j| opts.latching && !m.latched[j] && m.side[j] * y1[j] <= 0.0);
            if let Some(j) = crossed {
                // The crossing on the step's chord, then one step to it.
                let a = (y[j] / (y[j] - y1[j])).clamp(0.0, 1.0);
                let mut f = |z: &[f64]| m.deriv(z);
                let (y2, _) = rig_ode::step(&mut f, &y, hs * a, opts.rtol, opts.atol)
                    .ok_or_else(|| SimError::Invalid("the rig's equations are singular".into()))?;
                y = y2;
                t += hs * a;
                latch(&mut m, &mut y, j)
                    .ok_or_else(|| SimError::Invalid("a singular latch impulse".into()))?;
                rec.run.traj.latch_s[j] = Some(t);
                watch.point(t, &core::array::from_fn(|j| y[j]), &m.latched);
                rec.stats.events += 1;
                h = (hs * a).max(1e-6);
                continue;
            }
            y = y1;
            t += hs;
            watch.point(t, &core::array::from_fn(|j| y[j]), &m.latched);
            rec.stats.steps += 1;
            rec.contacts(&m, t, &y);
            h = hs * grow;
        }
        rec.sample(&m, target, &y);
        if opts.stop_when_deployed && deployed_at.is_none() && m.latched.iter().all(|l| *l) {
            deployed_at = Some(target);
        }
        if deployed_at.is_some_and(|d| target >= d + settle - 1e-12) {
            break;
        }
    }
    rec.run.traj.end_s = t;
    rec.run.traj.stats = rec.stats;
    rec.run.traj.past_stowed = watch.found();
    Ok(rec.run)
}

/// A trolley of `trolley_kg` carrying `carried_kg` by a wire of `wire_m`,
/// dragged along its rail by an offload point moving at the constant
/// `speed_m_s`, the trolley started sliding with it and its wire stretched
/// to pull with the dynamic friction: the wire's force on it \[N\] at every
/// step of `dt_s` up to `duration_s` (semi-implicit Euler). The same wire
/// stiffness, load and rail friction as [`simulate_rig`]: while it slides
/// steadily the wire pulls with `N μ(v)`, the dynamic friction
/// `μ_d (m_t + m_i) g` once `v ≫` the stick speed. (Started from rest on a
/// soft wire a trolley sticks and slips instead: the lag oscillation of
/// the wire has no damping but the friction's.)
pub fn drag_trolley(
    rig: &Rig,
    trolley_kg: f64,
    carried_kg: f64,
    wire_m: f64,
    speed_m_s: f64,
    duration_s: f64,
    dt_s: f64,
) -> Vec<f64> {
    let g = rig.gravity_m_s2;
    let kappa = carried_kg * g / wire_m;
    let load = (carried_kg + trolley_kg) * g;
    let (mut x, mut v) = (-rig.rail_force(load, 1e9) / kappa, speed_m_s);
    let steps = (duration_s / dt_s).round() as usize;
    let mut out = Vec::with_capacity(steps);
    for k in 1..=steps {
        let o = speed_m_s * k as f64 * dt_s;
        let pull = kappa * (o - x);
        v += (pull - rig.rail_force(load, v)) / trolley_kg * dt_s;
        x += v * dt_s;
        out.push(pull);
    }
    out
}
