//! The planar open chain of `N` panels: kinematics, mass matrix, Lagrange's
//! equations, joint torques, named effects and the plastic latch impulse.
//!
//! This is the one implementation of `docs/spec/physics.md` sections 1–6.
//! The host simulator integrates it in `f64`; the on-board monitor evaluates
//! it in `f32`.
//!
//! # Equations
//! Absolute angles `θ = S φ` (`S` lower-triangular ones). With
//! `A_kl = Σ_i m_i a_ik a_il + δ_kl I_k`, `a_ik = L_k (k < i), c_i (k = i), 0`,
//!
//! ```text
//! D_kl(θ) = A_kl cos(θ_k − θ_l)
//! M(φ)    = Sᵀ D S                                          (mass matrix, joint space)
//! M φ̈     = τ + Sᵀ (Q_ext − C),  C_k = Σ_l A_kl sin(θ_k − θ_l) θ̇_l²
//! ```
//!
//! `τ` are the joint torques (spring, friction, joint effects) and `Q_ext`
//! the generalised forces of distributed effects (air drag, rig tilt),
//! conjugate to the absolute angles. Locked joints are removed from the
//! coordinates ([`crate::physics::linalg::solve_spd_masked`]).

use crate::physics::friction::Friction;
use crate::physics::linalg::{mat_vec, solve_spd_masked, SolveError};
use crate::physics::real::Real;
use crate::physics::spring::{Branch, Spring};
use crate::physics::torque_table::{TorqueTable, TABLE_MAX_KNOTS};

/// Half-width δ of the `latch_detent` zone [deg] (`physics.md` section 6).
pub const DETENT_ZONE_DEG: f64 = 3.0;

/// One rigid panel (`physics.md` section 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Panel<T> {
    /// `L_i`: inboard to outboard hinge [m].
    pub length_m: T,
    /// `m_i` [kg].
    pub mass_kg: T,
    /// `c_i`: centre of mass from the inboard hinge, along the panel [m].
    pub com_m: T,
    /// `I_i`: inertia about the centre of mass, axis ∥ z [kg·m²].
    pub inertia_kgm2: T,
}

/// The named effects that act on one joint (`physics.md` section 6), all
/// zero by default. They add to the joint's own friction law. `K`: the
/// most points of each torque table ([`TABLE_MAX_KNOTS`] on the monitor).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct JointEffects<T, const K: usize = TABLE_MAX_KNOTS> {
    /// `coulomb_friction`: adds `−T_C tanh(φ̇/0.01)` [N·m].
    pub coulomb_nm: T,
    /// `viscous_damping`: adds `−f φ̇` [N·m·s/rad].
    pub viscous_nms: T,
    /// `spring_softening`: the spring torque is scaled by `(1 − s)` [1].
    pub spring_softening: T,
    /// `harness_stiffness`: adds `k_h (φ_stowed − φ)` [N·m/rad].
    pub harness_nm_per_rad: T,
    /// `latch_detent`: adds `−T_d sign(φ) sin(2π|φ|/δ)` while `|φ| < δ` [N·m].
    pub detent_nm: T,
    /// `torque_table`: adds `f(φ) + g(φ̇)` ([`crate::physics::torque_table`]).
    pub table: TorqueTable<T, K>,
}

/// The named effects that act on the whole chain (`physics.md` section 6).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct GlobalEffects<T> {
    /// `air_drag`: force per unit length `−k v_n |v_n| n_i` [kg/m²].
    pub air_drag_kg_m2: T,
    /// `rig_tilt`: in-plane gravity component `g_t` [m/s²].
    pub tilt_m_s2: T,
    /// Direction α of the tilt gravity, counter-clockwise from the bus x axis [rad].
    pub tilt_alpha_rad: T,
}

/// One joint: what drives and resists it (`K` as in [`JointEffects`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Joint<T, const K: usize = TABLE_MAX_KNOTS> {
    /// Stowed (initial) angle `φ_j(0)` [rad]; the latch angle is 0.
    pub stowed_rad: T,
    /// The hinge spring(s).
    pub spring: Spring<T>,
    /// The joint's friction law.
    pub friction: Friction<T>,
    /// Named effects acting on this joint.
    pub effects: JointEffects<T, K>,
}

/// Why a chain could not be built or evaluated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ChainError {
    /// Panel `index` (0-based) has a non-positive or non-finite mass, length or inertia.
    BadPanel {
        /// 0-based panel index.
        index: usize,
    },
    /// The mass matrix is singular or the state holds NaN.
    Singular,
}

impl core::fmt::Display for ChainError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            ChainError::BadPanel { index } => write!(
                f,
                "panel {} needs a positive finite length, mass and inertia",
                index + 1
            ),
            ChainError::Singular => {
                f.write_str("mass matrix is singular or the state is not finite")
            }
        }
    }
}

impl core::error::Error for ChainError {}

impl From<SolveError> for ChainError {
    fn from(_: SolveError) -> Self {
        ChainError::Singular
    }
}

/// The state of the chain in joint coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChainState<T, const N: usize> {
    /// Joint angles `φ` [rad].
    pub phi: [T; N],
    /// Joint rates `φ̇` [rad/s].
    pub phi_dot: [T; N],
}

/// Discrete state: which joints are latched and which spring branch each uses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mode<const N: usize> {
    /// `true` once joint j has latched (removed from the coordinates).
    pub latched: [bool; N],
    /// Spring branch of each joint.
    pub branch: [Branch; N],
}

impl<const N: usize> Default for Mode<N> {
    fn default() -> Self {
        Mode {
            latched: [false; N],
            branch: [Branch::Fold; N],
        }
    }
}

/// The chain model: panels, joints and global effects, with the constant
/// inertia coefficients precomputed. `K`: the most points of a joint's
/// torque tables ([`TABLE_MAX_KNOTS`] on the monitor; the host simulator
/// holds larger tables).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Chain<T, const N: usize, const K: usize = TABLE_MAX_KNOTS> {
    // The joints first: [`Chain::vacant`] has them written in place.
    joints: [Joint<T, K>; N],
    panels: [Panel<T>; N],
    global: GlobalEffects<T>,
    /// `A_kl` [kg·m²].
    a: [[T; N]; N],
    /// `Σ_i m_i a_ik` [kg·m] (first mass moment seen by absolute angle k).
    mass_moment: [T; N],
}

/// 8-point Gauss–Legendre nodes and weights on [−1, 1] (Abramowitz &
/// Stegun Table 25.4, as tabulated).
#[allow(clippy::excessive_precision)]
const GAUSS8: [(f64, f64); 8] = [
    (-0.960_289_856_497_536_3, 0.101_228_536_290_376_26),
    (-0.796_666_477_413_626_7, 0.222_381_034_453_374_47),
    (-0.525_532_409_916_329_0, 0.313_706_645_877_887_3),
    (-0.183_434_642_495_649_8, 0.362_683_783_378_362_0),
    (0.183_434_642_495_649_8, 0.362_683_783_378_362_0),
    (0.525_532_409_916_329_0, 0.313_706_645_877_887_3),
    (0.796_666_477_413_626_7, 0.222_381_034_453_374_47),
    (0.960_289_856_497_536_3, 0.101_228_536_290_376_26),
];

impl<T: Real, const N: usize, const K: usize> Chain<T, N, K> {
    /// Builds the chain and precomputes `A` and the mass moments.
    pub fn new(
        panels: [Panel<T>; N],
        joints: [Joint<T, K>; N],
        global: GlobalEffects<T>,
    ) -> Result<Self, ChainError> {
        Self::check_panels(&panels)?;
        let mut c = Chain {
            panels,
            joints,
            global,
            a: [[T::ZERO; N]; N],
            mass_moment: [T::ZERO; N],
        };
        c.precompute();
        Ok(c)
    }

    /// A chain of massless, zero-length panels and unsprung joints: storage
    /// to be configured in place with [`Chain::set_panels`] and
    /// [`Chain::joint_mut`] (not a mechanism: its mass matrix is singular).
    /// Out of line, as are its joints: returned values are written in
    /// place, where a chain built inline would be copied from the stack.
    #[inline(never)]
    pub(crate) fn vacant() -> Self {
        Chain {
            panels: [Panel {
                length_m: T::ZERO,
                mass_kg: T::ZERO,
                com_m: T::ZERO,
                inertia_kgm2: T::ZERO,
            }; N],
            global: GlobalEffects::default(),
            a: [[T::ZERO; N]; N],
            mass_moment: [T::ZERO; N],
            joints: Self::vacant_joints(),
        }
    }

    /// Unsprung joints without friction or effects, for [`Chain::vacant`].
    #[inline(never)]
    fn vacant_joints() -> [Joint<T, K>; N] {
        [Joint {
            stowed_rad: T::ZERO,
            spring: Spring::None,
            friction: Friction::default(),
            effects: JointEffects::default(),
        }; N]
    }

    /// Replaces the panels in place and precomputes `A` and the mass
    /// moments again, as [`Chain::new`] does; the joints and the global
    /// effects stay. On an error the chain is unchanged. Lets a chain in
    /// static memory be configured without a second one on the stack.
    pub fn set_panels(&mut self, panels: &[Panel<T>; N]) -> Result<(), ChainError> {
        Self::check_panels(panels)?;
        self.panels = *panels;
        self.precompute();
        Ok(())
    }

    /// Every panel needs a positive finite length and mass, and a
    /// non-negative finite inertia.
    fn check_panels(panels: &[Panel<T>; N]) -> Result<(), ChainError> {
        for (index, p) in panels.iter().enumerate() {
            let ok = p.length_m > T::ZERO
                && p.mass_kg > T::ZERO
                && p.inertia_kgm2 >= T::ZERO
                && p.length_m.is_finite()
                && p.mass_kg.is_finite()
                && p.inertia_kgm2.is_finite()
                && p.com_m.is_finite();
            if !ok {
                return Err(ChainError::BadPanel { index });
            }
        }
        Ok(())
    }

    fn precompute(&mut self) {
        // a_ik = L_k (k < i), c_i (k = i), 0 (k > i)
        let a_of = |p: &[Panel<T>; N], i: usize, k: usize| -> T {
            if k < i {
                p[k].length_m
            } else if k == i {
                p[i].com_m
            } else {
                T::ZERO
            }
        };
        for k in 0..N {
            for l in 0..N {
                let mut s = T::ZERO;
                for i in 0..N {
                    s += self.panels[i].mass_kg
                        * a_of(&self.panels, i, k)
                        * a_of(&self.panels, i, l);
                }
                if k == l {
                    s += self.panels[k].inertia_kgm2;
                }
                self.a[k][l] = s;
            }
            let mut mm = T::ZERO;
            for i in 0..N {
                mm += self.panels[i].mass_kg * a_of(&self.panels, i, k);
            }
            self.mass_moment[k] = mm;
        }
    }

    /// The panels.
    pub fn panels(&self) -> &[Panel<T>; N] {
        &self.panels
    }

    /// The joints.
    pub fn joints(&self) -> &[Joint<T, K>; N] {
        &self.joints
    }

    /// Joint `j` (0-based), mutable: effects and friction can be changed
    /// without rebuilding the chain (they do not enter the inertia).
    pub fn joint_mut(&mut self, j: usize) -> Option<&mut Joint<T, K>> {
        self.joints.get_mut(j)
    }

    /// The global effects.
    pub fn global(&self) -> &GlobalEffects<T> {
        &self.global
    }

    /// The global effects, mutable.
    pub fn global_mut(&mut self) -> &mut GlobalEffects<T> {
        &mut self.global
    }

    /// The constant inertia coefficients `A_kl` [kg·m²].
    pub fn inertia_coefficients(&self) -> &[[T; N]; N] {
        &self.a
    }

    /// Absolute panel angles `θ = S φ` [rad].
    #[inline]
    pub fn absolute(phi: &[T; N]) -> [T; N] {
        let mut th = [T::ZERO; N];
        let mut acc = T::ZERO;
        for i in 0..N {
            acc += phi[i];
            th[i] = acc;
        }
        th
    }

    /// `(cos θ_k, sin θ_k)` for every panel.
    #[inline]
    fn trig(theta: &[T; N]) -> ([T; N], [T; N]) {
        let mut c = [T::ZERO; N];
        let mut s = [T::ZERO; N];
        for k in 0..N {
            (s[k], c[k]) = theta[k].sin_cos();
        }
        (c, s)
    }

    /// `Sᵀ x`: `(Sᵀ x)_j = Σ_{k ≥ j} x_k`.
    #[inline]
    fn st(x: &[T; N]) -> [T; N] {
        let mut y = [T::ZERO; N];
        let mut acc = T::ZERO;
        for j in (0..N).rev() {
            acc += x[j];
            y[j] = acc;
        }
        y
    }

    /// `Sᵀ D S` from `D`.
    #[inline]
    fn congruence(d: &[[T; N]; N]) -> [[T; N]; N] {
        // R = D S (suffix sums along columns), M = Sᵀ R (suffix sums along rows).
        let mut r = [[T::ZERO; N]; N];
        for a in 0..N {
            let mut acc = T::ZERO;
            for k in (0..N).rev() {
                acc += d[a][k];
                r[a][k] = acc;
            }
        }
        let mut m = [[T::ZERO; N]; N];
        for k in 0..N {
            let mut acc = T::ZERO;
            for j in (0..N).rev() {
                acc += r[j][k];
                m[j][k] = acc;
            }
        }
        m
    }

    /// The mass matrix in joint coordinates `M(φ) = Sᵀ D(θ) S` [kg·m²].
    pub fn mass_matrix(&self, phi: &[T; N]) -> [[T; N]; N] {
        let th = Self::absolute(phi);
        let (c, s) = Self::trig(&th);
        let mut d = [[T::ZERO; N]; N];
        for k in 0..N {
            for l in 0..N {
                d[k][l] = self.a[k][l] * (c[k] * c[l] + s[k] * s[l]);
            }
        }
        Self::congruence(&d)
    }

    /// Torque on joint `j` [N·m] from its spring, friction and joint effects,
    /// at angle `phi` [rad] and rate `phi_dot` [rad/s] on `branch`.
    #[inline]
    pub fn joint_torque(&self, j: usize, phi: T, phi_dot: T, branch: Branch) -> T {
        let Some(jt) = self.joints.get(j) else {
            return T::ZERO;
        };
        let e = &jt.effects;
        let mut t = jt.spring.torque(phi, branch);
        if e.spring_softening != T::ZERO {
            t *= T::ONE - e.spring_softening;
        }
        t += jt.friction.torque(phi_dot);
        // `coulomb_friction` (physics.md 6): the EFT of the one friction law.
        if e.coulomb_nm != T::ZERO {
            t += crate::physics::friction::Friction::coulomb(e.coulomb_nm).torque(phi_dot);
        }
        t -= e.viscous_nms * phi_dot;
        t += e.harness_nm_per_rad * (jt.stowed_rad - phi);
        if e.detent_nm != T::ZERO {
            let delta = T::of(DETENT_ZONE_DEG).to_radians();
            let a = phi.abs();
            if a < delta {
                let two_pi = T::of(2.0) * T::PI;
                t -= e.detent_nm * phi.signum0() * (two_pi * a / delta).sin();
            }
        }
        t + e.table.torque(phi, phi_dot)
    }

    /// Generalised forces of the distributed effects conjugate to the
    /// absolute angles, `Q_ext` [N·m]: rig tilt and air drag.
    fn external(&self, c: &[T; N], s: &[T; N], theta_dot: &[T; N]) -> [T; N] {
        let mut q = [T::ZERO; N];
        let g = &self.global;
        if g.tilt_m_s2 != T::ZERO {
            // Q_k = g_t sin(α − θ_k) Σ_i m_i a_ik
            let (ca, sa) = (g.tilt_alpha_rad.cos(), g.tilt_alpha_rad.sin());
            for k in 0..N {
                q[k] += g.tilt_m_s2 * (sa * c[k] - ca * s[k]) * self.mass_moment[k];
            }
        }
        if g.air_drag_kg_m2 != T::ZERO {
            let half = T::of(0.5);
            for i in 0..N {
                // v_n(s) = Σ_{k<i} L_k θ̇_k cos(θ_i − θ_k) + s θ̇_i
                let mut base = T::ZERO;
                for k in 0..i {
                    base += self.panels[k].length_m * theta_dot[k] * (c[i] * c[k] + s[i] * s[k]);
                }
                let len = self.panels[i].length_m;
                let (mut f0, mut f1) = (T::ZERO, T::ZERO);
                for &(x, w) in GAUSS8.iter() {
                    let sp = half * len * (T::ONE + T::of(x));
                    let wp = half * len * T::of(w);
                    let vn = base + sp * theta_dot[i];
                    let f = -g.air_drag_kg_m2 * vn * vn.abs();
                    f0 += wp * f;
                    f1 += wp * f * sp;
                }
                for k in 0..i {
                    q[k] += self.panels[k].length_m * (c[i] * c[k] + s[i] * s[k]) * f0;
                }
                q[i] += f1;
            }
        }
        q
    }

    /// Mass matrix and right-hand side `τ + Sᵀ(Q_ext − C)` of Lagrange's
    /// equations in joint coordinates.
    pub fn equations(&self, x: &ChainState<T, N>, mode: &Mode<N>) -> ([[T; N]; N], [T; N]) {
        let th = Self::absolute(&x.phi);
        let thd = Self::absolute(&x.phi_dot);
        let (c, s) = Self::trig(&th);
        let mut d = [[T::ZERO; N]; N];
        let mut cor = [T::ZERO; N];
        for k in 0..N {
            for l in 0..N {
                let cos_kl = c[k] * c[l] + s[k] * s[l];
                let sin_kl = s[k] * c[l] - c[k] * s[l];
                d[k][l] = self.a[k][l] * cos_kl;
                cor[k] += self.a[k][l] * sin_kl * thd[l] * thd[l];
            }
        }
        let q = self.external(&c, &s, &thd);
        let mut diff = [T::ZERO; N];
        for k in 0..N {
            diff[k] = q[k] - cor[k];
        }
        let mut rhs = Self::st(&diff);
        for j in 0..N {
            if !mode.latched[j] {
                rhs[j] += self.joint_torque(j, x.phi[j], x.phi_dot[j], mode.branch[j]);
            }
        }
        (Self::congruence(&d), rhs)
    }

    /// Joint accelerations `φ̈` [rad/s²]; zero for latched joints.
    pub fn acceleration(&self, x: &ChainState<T, N>, mode: &Mode<N>) -> Result<[T; N], ChainError> {
        let (m, rhs) = self.equations(x, mode);
        Ok(solve_spd_masked(&m, &rhs, &mode.latched)?)
    }

    /// Inverse dynamics: the joint torques [N·m] the model lacks for the
    /// state `x` to have the accelerations `accel` [rad/s²],
    /// `τ_missing = M(φ) φ̈ − (τ + Sᵀ(Q_ext − C))` (Lagrange's equations of
    /// [`Chain::equations`] solved for the torque instead of `φ̈`). Latched
    /// joints hold no acceleration (theirs is taken as 0) and get 0: their
    /// torque is the latch's reaction.
    pub fn missing_torque(&self, x: &ChainState<T, N>, accel: &[T; N], mode: &Mode<N>) -> [T; N] {
        let (m, rhs) = self.equations(x, mode);
        let mut a = *accel;
        for (aj, &locked) in a.iter_mut().zip(mode.latched.iter()) {
            if locked {
                *aj = T::ZERO;
            }
        }
        let ma = mat_vec(&m, &a);
        let mut out = [T::ZERO; N];
        for j in 0..N {
            if !mode.latched[j] {
                out[j] = ma[j] - rhs[j];
            }
        }
        out
    }

    /// Rates just after a perfectly plastic latch (`physics.md` section 5).
    ///
    /// `latched_after` is the set of joints locked after the impact (those
    /// already latched and those latching now). The generalised momentum
    /// conjugate to every joint that stays free is conserved and the rates of
    /// the locked joints become zero, which is the projection
    /// `φ̇⁺ = φ̇⁻ − M⁻¹E (EᵀM⁻¹E)⁻¹ Eᵀ φ̇⁻` with `M` the mass matrix of the
    /// joints free before the impact and `E` the joints latching now.
    pub fn latch_impulse(
        &self,
        x: &ChainState<T, N>,
        latched_after: &[bool; N],
    ) -> Result<[T; N], ChainError> {
        let m = self.mass_matrix(&x.phi);
        // `mat_vec` written out: the monitor runs this in its sample path,
        // where the firmware's `opt-level = "z"` would make it a call.
        let mut p = [T::ZERO; N];
        for i in 0..N {
            for j in 0..N {
                p[i] += m[i][j] * x.phi_dot[j];
            }
        }
        Ok(solve_spd_masked(&m, &p, latched_after)?)
    }

    /// Generalised momenta `p = M(φ) φ̇` [N·m·s].
    pub fn momentum(&self, x: &ChainState<T, N>) -> [T; N] {
        mat_vec(&self.mass_matrix(&x.phi), &x.phi_dot)
    }

    /// Kinetic energy `½ φ̇ᵀ M φ̇` [J].
    pub fn kinetic_energy(&self, x: &ChainState<T, N>) -> T {
        let m = self.mass_matrix(&x.phi);
        let p = mat_vec(&m, &x.phi_dot);
        let mut e = T::ZERO;
        for j in 0..N {
            e += p[j] * x.phi_dot[j];
        }
        T::of(0.5) * e
    }

    /// Potential energy of the conservative forces [J]: the springs (on their
    /// unfolding branch, scaled by any softening), harnesses and rig tilt.
    pub fn potential_energy(&self, phi: &[T; N]) -> T {
        let mut v = T::ZERO;
        for (j, jt) in self.joints.iter().enumerate() {
            let soft = T::ONE - jt.effects.spring_softening;
            v += soft * jt.spring.release(T::ZERO, phi[j].abs());
            let d = phi[j] - jt.stowed_rad;
            v += T::of(0.5) * jt.effects.harness_nm_per_rad * d * d;
        }
        let g = &self.global;
        if g.tilt_m_s2 != T::ZERO {
            // V = −Σ_i m_i g·r_i; r_i·e = Σ_k a_ik (cos θ_k cos α + sin θ_k sin α)
            let th = Self::absolute(phi);
            let (ca, sa) = (g.tilt_alpha_rad.cos(), g.tilt_alpha_rad.sin());
            for k in 0..N {
                v -= g.tilt_m_s2 * self.mass_moment[k] * (th[k].cos() * ca + th[k].sin() * sa);
            }
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn panel() -> Panel<f64> {
        Panel {
            length_m: 0.8,
            mass_kg: 3.5,
            com_m: 0.4,
            inertia_kgm2: 0.27,
        }
    }

    fn joint(stowed: f64) -> Joint<f64> {
        Joint {
            stowed_rad: stowed,
            spring: Spring::Linear {
                preload_nm: 1.0,
                stiffness_nm_per_rad: 0.5,
                count: 1.0,
            },
            friction: Friction::default(),
            effects: JointEffects::default(),
        }
    }

    fn chain3() -> Chain<f64, 3> {
        Chain::new(
            [panel(); 3],
            [joint(-1.0), joint(2.0), joint(-2.0)],
            GlobalEffects::default(),
        )
        .unwrap()
    }

    #[test]
    fn mass_matrix_matches_kinetic_energy_by_finite_velocities() {
        // ½ φ̇ᵀ M φ̇ equals Σ ½ (m |ṙ|² + I θ̇²) computed from positions.
        let c = chain3();
        let phi = [0.3, -1.1, 0.7];
        let phid = [0.5, -0.2, 1.3];
        let x = ChainState { phi, phi_dot: phid };
        let ke = c.kinetic_energy(&x);
        let pos = |phi: &[f64; 3]| {
            let th = Chain::<f64, 3>::absolute(phi);
            let mut h = (0.0, 0.0);
            let mut r = [(0.0, 0.0); 3];
            for i in 0..3 {
                r[i] = (h.0 + 0.4 * th[i].cos(), h.1 + 0.4 * th[i].sin());
                h = (h.0 + 0.8 * th[i].cos(), h.1 + 0.8 * th[i].sin());
            }
            (r, th)
        };
        let eps = 1e-6;
        let mut p1 = phi;
        let mut p0 = phi;
        for j in 0..3 {
            p1[j] += eps * phid[j];
            p0[j] -= eps * phid[j];
        }
        let (r1, t1) = pos(&p1);
        let (r0, t0) = pos(&p0);
        let mut ke2 = 0.0;
        for i in 0..3 {
            let vx = (r1[i].0 - r0[i].0) / (2.0 * eps);
            let vy = (r1[i].1 - r0[i].1) / (2.0 * eps);
            let w = (t1[i] - t0[i]) / (2.0 * eps);
            ke2 += 0.5 * (3.5 * (vx * vx + vy * vy) + 0.27 * w * w);
        }
        assert!((ke - ke2).abs() < 1e-8 * ke2, "{ke} vs {ke2}");
    }

    #[test]
    fn latch_impulse_stops_the_joint_and_keeps_the_others_momentum() {
        let c = chain3();
        let x = ChainState {
            phi: [0.0, -0.4, 0.9],
            phi_dot: [1.5, -0.8, 0.6],
        };
        let after = c.latch_impulse(&x, &[true, false, false]).unwrap();
        assert_eq!(after[0], 0.0);
        let m = c.mass_matrix(&x.phi);
        let p0 = mat_vec(&m, &x.phi_dot);
        let p1 = mat_vec(&m, &after);
        assert!((p0[1] - p1[1]).abs() < 1e-12 && (p0[2] - p1[2]).abs() < 1e-12);
        // A plastic impact never adds energy.
        let x1 = ChainState {
            phi: x.phi,
            phi_dot: after,
        };
        assert!(c.kinetic_energy(&x1) < c.kinetic_energy(&x));
    }

    #[test]
    fn tilt_force_is_minus_the_potential_gradient() {
        let mut c = chain3();
        c.global_mut().tilt_m_s2 = 0.3;
        c.global_mut().tilt_alpha_rad = 0.7;
        for j in 0..3 {
            c.joint_mut(j).unwrap().spring = Spring::None;
        }
        let phi = [0.2, -0.5, 1.0];
        let x = ChainState {
            phi,
            phi_dot: [0.0; 3],
        };
        let (_, rhs) = c.equations(&x, &Mode::default());
        for j in 0..3 {
            let mut a = phi;
            let mut b = phi;
            a[j] += 1e-6;
            b[j] -= 1e-6;
            let grad = (c.potential_energy(&a) - c.potential_energy(&b)) / 2e-6;
            assert!((rhs[j] + grad).abs() < 1e-7, "{j}: {} vs {}", rhs[j], -grad);
        }
    }

    #[test]
    fn missing_torque_is_the_torque_an_extra_effect_adds() {
        // Accelerations of a chain with a viscous damper at joint 2, seen by
        // the chain without it: the missing torque is −f φ̇₂ at joint 2 only.
        let plain = chain3();
        let mut damped = plain;
        damped.joint_mut(1).unwrap().effects.viscous_nms = 0.7;
        let x = ChainState {
            phi: [0.2, -0.5, 1.0],
            phi_dot: [0.4, -1.0, 2.0],
        };
        let mode = Mode::default();
        let acc = damped.acceleration(&x, &mode).unwrap();
        let tau = plain.missing_torque(&x, &acc, &mode);
        assert!(tau[0].abs() < 1e-12 && tau[2].abs() < 1e-12, "{tau:?}");
        assert!((tau[1] - 0.7).abs() < 1e-12, "{tau:?}");
        let latched = Mode {
            latched: [true, false, false],
            ..Mode::default()
        };
        let acc = damped.acceleration(&x, &latched).unwrap();
        let tau = plain.missing_torque(&x, &acc, &latched);
        assert_eq!(tau[0], 0.0);
        assert!((tau[1] - 0.7).abs() < 1e-12, "{tau:?}");
    }

    #[test]
    fn air_drag_dissipates() {
        let mut c = chain3();
        c.global_mut().air_drag_kg_m2 = 0.25;
        for j in 0..3 {
            c.joint_mut(j).unwrap().spring = Spring::None;
        }
        let x = ChainState {
            phi: [0.2, -0.5, 1.0],
            phi_dot: [0.4, -1.0, 2.0],
        };
        let (_, rhs) = c.equations(&x, &Mode::default());
        // Power of the drag forces: Σ τ_j φ̇_j < 0 (Coriolis does no work).
        let m = c.mass_matrix(&x.phi);
        let _ = m;
        let cor_free = {
            let mut c2 = c;
            c2.global_mut().air_drag_kg_m2 = 0.0;
            c2.equations(&x, &Mode::default()).1
        };
        let power: f64 = (0..3).map(|j| (rhs[j] - cor_free[j]) * x.phi_dot[j]).sum();
        assert!(power < 0.0);
    }

    #[test]
    fn bad_panel_is_an_error() {
        let mut p = [panel(); 3];
        p[1].mass_kg = 0.0;
        assert_eq!(
            Chain::new(p, [joint(1.0); 3], GlobalEffects::default()).err(),
            Some(ChainError::BadPanel { index: 1 })
        );
    }
}
