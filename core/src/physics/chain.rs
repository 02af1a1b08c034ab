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

/// Half-width δ of the `latch_detent` zone \[deg\] (`physics.md` section 6).
pub const DETENT_ZONE_DEG: f64 = 3.0;

/// One rigid panel (`physics.md` section 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Panel<T> {
    /// `L_i`: inboard to outboard hinge \[m\].
    pub length_m: T,
    /// `m_i` \[kg\].
    pub mass_kg: T,
    /// `c_i`: centre of mass from the inboard hinge, along the panel \[m\].
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
    /// `stribeck_friction`'s excess `ΔT = T_brk − T_C` [N·m] (its `T_C` adds
    /// to `coulomb_nm`): adds the Stribeck term of
    /// [`crate::physics::friction::stribeck_excess`].
    pub stribeck_excess_nm: T,
    /// `stribeck_friction`'s Stribeck velocity `ω_st` [rad/s] (used while
    /// `stribeck_excess_nm ≠ 0`).
    pub stribeck_rad_s: T,
    /// `quadratic_damping`: adds `−c φ̇|φ̇|` [N·m·s²/rad²].
    pub quadratic_nms2_per_rad2: T,
    /// `spring_softening`: the spring torque is scaled by `(1 − s)` \[1\].
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
    /// Direction α of the tilt gravity, counter-clockwise from the bus x axis \[rad\].
    pub tilt_alpha_rad: T,
}

/// One joint: what drives and resists it (`K` as in [`JointEffects`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Joint<T, const K: usize = TABLE_MAX_KNOTS> {
    /// Stowed (initial) angle `φ_j(0)` \[rad\]; the latch angle is 0.
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
    /// Joint angles `φ` \[rad\].
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

    /// Absolute panel angles `θ = S φ` \[rad\].
    #[inline]
    pub fn absolute(phi: &[T; N]) -> [T; N] {
        absolute(N, phi)
    }

    /// The chain's equations over its `N` joints ([`ChainRef`]).
    #[inline]
    pub fn counted(&self) -> ChainRef<'_, T, N, K> {
        ChainRef {
            n: N,
            a: &self.a,
            mass_moment: &self.mass_moment,
            panels: &self.panels,
            joints: &self.joints,
            global: &self.global,
        }
    }

    /// The inertia coefficients and mass moments of the chain's `N` joints
    /// in arrays of capacity `M` (`N ≤ M`; of a longer chain, its first
    /// `M` joints), zero-padded, for [`Chain::counted_with`]. Out of line,
    /// one copy per joint count and capacity: the value returned is
    /// written where the caller keeps it.
    #[inline(never)]
    pub fn coefficients<const M: usize>(&self) -> Coefficients<T, M> {
        let n = N.min(M);
        // From a constant: built as an array expression, the zeros are
        // copied twice over on the MCU.
        let mut store = Coefficients::ZERO;
        for k in 0..n {
            for l in 0..n {
                store.a[k][l] = self.a[k][l];
            }
            store.mass_moment[k] = self.mass_moment[k];
        }
        store
    }

    /// The chain's equations over arrays of capacity `M` holding its `N`
    /// joints (`N ≤ M`; of a longer chain, its first `M` joints), with
    /// `store` its [`Chain::coefficients`]. One copy of the code that
    /// evaluates the equations serves chains of every joint count up to
    /// `M`.
    #[inline(always)]
    pub fn counted_with<'a, const M: usize>(
        &'a self,
        store: &'a Coefficients<T, M>,
    ) -> ChainRef<'a, T, M, K> {
        ChainRef {
            n: N.min(M),
            a: &store.a,
            mass_moment: &store.mass_moment,
            panels: &self.panels,
            joints: &self.joints,
            global: &self.global,
        }
    }

    /// The mass matrix in joint coordinates `M(φ) = Sᵀ D(θ) S` [kg·m²].
    pub fn mass_matrix(&self, phi: &[T; N]) -> [[T; N]; N] {
        self.counted().mass_matrix(phi)
    }

    /// Torque on joint `j` [N·m] from its spring, friction and joint effects,
    /// at angle `phi` \[rad\] and rate `phi_dot` [rad/s] on `branch`.
    #[inline]
    pub fn joint_torque(&self, j: usize, phi: T, phi_dot: T, branch: Branch) -> T {
        self.counted().joint_torque(j, phi, phi_dot, branch)
    }

    /// Power of the air drag at the state `x` \[W\] ([`ChainRef::drag_power`]).
    pub fn drag_power(&self, x: &ChainState<T, N>) -> T {
        self.counted().drag_power(x)
    }

    /// Mass matrix and right-hand side `τ + Sᵀ(Q_ext − C)` of Lagrange's
    /// equations in joint coordinates.
    pub fn equations(&self, x: &ChainState<T, N>, mode: &Mode<N>) -> ([[T; N]; N], [T; N]) {
        self.counted().equations(x, mode)
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

    /// Kinetic energy `½ φ̇ᵀ M φ̇` \[J\].
    pub fn kinetic_energy(&self, x: &ChainState<T, N>) -> T {
        let m = self.mass_matrix(&x.phi);
        let p = mat_vec(&m, &x.phi_dot);
        let mut e = T::ZERO;
        for j in 0..N {
            e += p[j] * x.phi_dot[j];
        }
        T::of(0.5) * e
    }

    /// Potential energy of the conservative forces \[J\]: the springs (on their
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

/// The inertia coefficients and mass moments of a chain, zero-padded to a
/// capacity of `M` joints ([`Chain::coefficients`]), for
/// [`Chain::counted_with`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coefficients<T, const M: usize> {
    /// `A_kl` [kg·m²].
    a: [[T; M]; M],
    /// `Σ_i m_i a_ik` [kg·m].
    mass_moment: [T; M],
}

impl<T: Real, const M: usize> Coefficients<T, M> {
    /// Every coefficient zero.
    const ZERO: Self = Coefficients {
        a: [[T::ZERO; M]; M],
        mass_moment: [T::ZERO; M],
    };
}

/// A chain's equations over arrays of capacity `M` holding `n ≤ M` joints,
/// the count known at run time ([`Chain::counted`], [`Chain::counted_with`]).
/// Every loop runs over the first `n` joints in the order of the fixed-size
/// chain, so the arithmetic is that of [`Chain`] bit for bit; entries past
/// `n` of the arrays it returns are zero. The methods of [`Chain`] are
/// shells over these (with `n = N`), and a caller written once over `M`
/// serves chains of every joint count up to `M` with one copy of the code.
#[derive(Clone, Copy, Debug)]
pub struct ChainRef<'a, T, const M: usize, const K: usize = TABLE_MAX_KNOTS> {
    /// Joints in use, `≤ M`, `≤` the joints and panels held.
    n: usize,
    a: &'a [[T; M]; M],
    mass_moment: &'a [T; M],
    panels: &'a [Panel<T>],
    joints: &'a [Joint<T, K>],
    global: &'a GlobalEffects<T>,
}

impl<T: Real, const M: usize, const K: usize> ChainRef<'_, T, M, K> {
    /// The number of joints in use.
    #[inline(always)]
    pub fn joint_count(&self) -> usize {
        self.n.min(M)
    }

    /// The constant inertia coefficients `A_kl` [kg·m²] (zero past the
    /// joints in use).
    #[inline(always)]
    pub fn inertia_coefficients(&self) -> &[[T; M]; M] {
        self.a
    }

    /// The joints in use.
    #[inline(always)]
    pub fn joints(&self) -> &[Joint<T, K>] {
        self.joints.get(..self.joint_count()).unwrap_or(&[])
    }

    /// The mass matrix in joint coordinates `M(φ) = Sᵀ D(θ) S` [kg·m²].
    #[inline(always)]
    pub fn mass_matrix(&self, phi: &[T; M]) -> [[T; M]; M] {
        let n = self.joint_count();
        let th = absolute(n, phi);
        let (c, s) = trig(n, &th);
        let mut d = [[T::ZERO; M]; M];
        for k in 0..n {
            for l in 0..n {
                d[k][l] = self.a[k][l] * (c[k] * c[l] + s[k] * s[l]);
            }
        }
        congruence(n, &mut d);
        d
    }

    /// Torque on joint `j` [N·m] from its spring, friction and joint effects,
    /// at angle `phi` \[rad\] and rate `phi_dot` [rad/s] on `branch`.
    #[inline(always)]
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
        if e.stribeck_excess_nm != T::ZERO && e.stribeck_rad_s > T::ZERO {
            t -= crate::physics::friction::stribeck_excess(
                e.stribeck_excess_nm,
                phi_dot,
                e.stribeck_rad_s,
            );
        }
        t -= e.viscous_nms * phi_dot;
        t -= e.quadratic_nms2_per_rad2 * phi_dot * phi_dot.abs();
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

    /// Length `L_k` of panel `k` \[m\] (0 past the panels).
    #[inline(always)]
    fn length(&self, k: usize) -> T {
        self.panels.get(k).map_or(T::ZERO, |p| p.length_m)
    }

    /// Generalised forces of the distributed effects conjugate to the
    /// absolute angles, `Q_ext` [N·m]: rig tilt and air drag.
    #[inline(always)]
    fn external(&self, c: &[T; M], s: &[T; M], theta_dot: &[T; M]) -> [T; M] {
        let n = self.joint_count();
        let mut q = [T::ZERO; M];
        let g = self.global;
        if g.tilt_m_s2 != T::ZERO {
            // Q_k = g_t sin(α − θ_k) Σ_i m_i a_ik
            let (ca, sa) = (g.tilt_alpha_rad.cos(), g.tilt_alpha_rad.sin());
            for k in 0..n {
                q[k] += g.tilt_m_s2 * (sa * c[k] - ca * s[k]) * self.mass_moment[k];
            }
        }
        if g.air_drag_kg_m2 != T::ZERO {
            let d = self.drag(c, s, theta_dot);
            for k in 0..n {
                q[k] += d[k];
            }
        }
        q
    }

    /// The air drag's generalised forces conjugate to the absolute angles
    /// [N·m] (`physics.md` section 6, `air_drag`).
    #[inline(always)]
    fn drag(&self, c: &[T; M], s: &[T; M], theta_dot: &[T; M]) -> [T; M] {
        let n = self.joint_count();
        let mut q = [T::ZERO; M];
        let g = self.global;
        let half = T::of(0.5);
        for i in 0..n {
            // v_n(s) = Σ_{k<i} L_k θ̇_k cos(θ_i − θ_k) + s θ̇_i
            let mut base = T::ZERO;
            for k in 0..i {
                base += self.length(k) * theta_dot[k] * (c[i] * c[k] + s[i] * s[k]);
            }
            let len = self.length(i);
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
                q[k] += self.length(k) * (c[i] * c[k] + s[i] * s[k]) * f0;
            }
            q[i] += f1;
        }
        q
    }

    /// Power of the air drag at the state `x` \[W\] (`Q_drag · θ̇`, ≤ 0): the
    /// work an energy ledger books as dissipated; 0 without drag.
    pub fn drag_power(&self, x: &ChainState<T, M>) -> T {
        if self.global.air_drag_kg_m2 == T::ZERO {
            return T::ZERO;
        }
        let n = self.joint_count();
        let th = absolute(n, &x.phi);
        let thd = absolute(n, &x.phi_dot);
        let (c, s) = trig(n, &th);
        let q = self.drag(&c, &s, &thd);
        let mut p = T::ZERO;
        for k in 0..n {
            p += q[k] * thd[k];
        }
        p
    }

    /// Mass matrix and right-hand side `τ + Sᵀ(Q_ext − C)` of Lagrange's
    /// equations in joint coordinates.
    #[inline(always)]
    pub fn equations(&self, x: &ChainState<T, M>, mode: &Mode<M>) -> ([[T; M]; M], [T; M]) {
        let n = self.joint_count();
        let th = absolute(n, &x.phi);
        let thd = absolute(n, &x.phi_dot);
        let (c, s) = trig(n, &th);
        let mut d = [[T::ZERO; M]; M];
        let mut cor = [T::ZERO; M];
        for k in 0..n {
            for l in 0..n {
                let cos_kl = c[k] * c[l] + s[k] * s[l];
                let sin_kl = s[k] * c[l] - c[k] * s[l];
                d[k][l] = self.a[k][l] * cos_kl;
                cor[k] += self.a[k][l] * sin_kl * thd[l] * thd[l];
            }
        }
        let q = self.external(&c, &s, &thd);
        let mut diff = [T::ZERO; M];
        for k in 0..n {
            diff[k] = q[k] - cor[k];
        }
        let mut rhs = st(n, &diff);
        for j in 0..n {
            if !mode.latched[j] {
                rhs[j] += self.joint_torque(j, x.phi[j], x.phi_dot[j], mode.branch[j]);
            }
        }
        congruence(n, &mut d);
        (d, rhs)
    }
}

/// Absolute panel angles `θ = S φ` \[rad\] of the first `n ≤ M` joints.
#[inline(always)]
fn absolute<T: Real, const M: usize>(n: usize, phi: &[T; M]) -> [T; M] {
    let n = n.min(M);
    let mut th = [T::ZERO; M];
    let mut acc = T::ZERO;
    for i in 0..n {
        acc += phi[i];
        th[i] = acc;
    }
    th
}

/// `(cos θ_k, sin θ_k)` for the first `n ≤ M` panels.
#[inline(always)]
fn trig<T: Real, const M: usize>(n: usize, theta: &[T; M]) -> ([T; M], [T; M]) {
    let n = n.min(M);
    let mut c = [T::ZERO; M];
    let mut s = [T::ZERO; M];
    for k in 0..n {
        (s[k], c[k]) = theta[k].sin_cos();
    }
    (c, s)
}

/// `Sᵀ x`: `(Sᵀ x)_j = Σ_{j ≤ k < n} x_k`.
#[inline(always)]
fn st<T: Real, const M: usize>(n: usize, x: &[T; M]) -> [T; M] {
    let n = n.min(M);
    let mut y = [T::ZERO; M];
    let mut acc = T::ZERO;
    for j in (0..n).rev() {
        acc += x[j];
        y[j] = acc;
    }
    y
}

/// `Sᵀ D S` from `D`, over the first `n ≤ M` joints, in place: `d` holds
/// `D` on entry and `Sᵀ D S` on return (each entry is read once before
/// it is overwritten, so the sums are those of separate matrices; one
/// matrix fewer to clear and copy on the MCU).
#[inline(always)]
fn congruence<T: Real, const M: usize>(n: usize, d: &mut [[T; M]; M]) {
    let n = n.min(M);
    // R = D S (suffix sums along columns), M = Sᵀ R (suffix sums along rows).
    for row in d.iter_mut().take(n) {
        let mut acc = T::ZERO;
        for k in (0..n).rev() {
            acc += row[k];
            row[k] = acc;
        }
    }
    for k in 0..n {
        let mut acc = T::ZERO;
        for j in (0..n).rev() {
            acc += d[j][k];
            d[j][k] = acc;
        }
    }
}

#[cfg(test)]
mod tests;
