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
//!
//! One module per part: `parts` (panels, joints, effects, state, mode and
//! errors), the owned [`Chain`] here, `counted` (its equations over a joint
//! count known at run time, [`ChainRef`]), `distributed` (rig tilt and air
//! drag) and `kinematics` (absolute angles and `S`).

mod counted;
mod distributed;
mod kinematics;
mod parts;

pub use counted::{ChainRef, Coefficients, JointTorque};
pub use parts::{
    ChainError, ChainState, GlobalEffects, Joint, JointEffects, Mode, Panel, DETENT_ZONE_DEG,
};

use crate::physics::friction::Friction;
use crate::physics::linalg::{mat_vec, solve_spd_masked};
use crate::physics::real::Real;
use crate::physics::spring::{Branch, Spring};
use crate::physics::torque_table::TABLE_MAX_KNOTS;
use kinematics::absolute;

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
    pub(crate) fn set_panels(&mut self, panels: &[Panel<T>; N]) -> Result<(), ChainError> {
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
    pub(crate) fn joint_mut(&mut self, j: usize) -> Option<&mut Joint<T, K>> {
        self.joints.get_mut(j)
    }

    /// The global effects.
    pub fn global(&self) -> &GlobalEffects<T> {
        &self.global
    }

    /// The global effects, mutable.
    pub(crate) fn global_mut(&mut self) -> &mut GlobalEffects<T> {
        &mut self.global
    }

    /// Absolute panel angles `θ = S φ` \[rad\].
    #[inline]
    pub fn absolute(phi: &[T; N]) -> [T; N] {
        absolute(N, phi)
    }

    /// The chain's equations over its `N` joints ([`ChainRef`]).
    #[inline]
    pub(crate) fn counted(&self) -> ChainRef<'_, T, N, K> {
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
    pub(crate) fn coefficients<const M: usize>(&self) -> Coefficients<T, M> {
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
    pub(crate) fn counted_with<'a, const M: usize>(
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

    /// [`Chain::acceleration`] with the joint torques it was found from
    /// ([`ChainRef::equations_with_torques`]; zero for latched joints).
    pub fn acceleration_with_torques(
        &self,
        x: &ChainState<T, N>,
        mode: &Mode<N>,
    ) -> Result<([T; N], [JointTorque<T>; N]), ChainError> {
        let (m, rhs, torques) = self.counted().equations_with_torques(x, mode);
        Ok((solve_spd_masked(&m, &rhs, &mode.latched)?, torques))
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

#[cfg(test)]
mod tests;
