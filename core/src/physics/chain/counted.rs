//! The chain's equations over arrays of a capacity `M`, the joint count
//! known at run time ([`ChainRef`]), and the coefficients it reads
//! ([`Coefficients`]): the one body of code behind every joint count.

use super::kinematics::{absolute, congruence, st, trig};
use super::parts::{ChainState, GlobalEffects, Joint, Mode, Panel, DETENT_ZONE_DEG};
use crate::physics::real::Real;
use crate::physics::spring::Branch;
use crate::physics::torque_table::TABLE_MAX_KNOTS;

/// The inertia coefficients and mass moments of a chain, zero-padded to a
/// capacity of `M` joints ([`Chain::coefficients`](super::Chain::coefficients)), for
/// [`Chain::counted_with`](super::Chain::counted_with).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coefficients<T, const M: usize> {
    /// `A_kl` [kg·m²].
    pub(super) a: [[T; M]; M],
    /// `Σ_i m_i a_ik` [kg·m].
    pub(super) mass_moment: [T; M],
}

impl<T: Real, const M: usize> Coefficients<T, M> {
    /// Every coefficient zero.
    pub(super) const ZERO: Self = Coefficients {
        a: [[T::ZERO; M]; M],
        mass_moment: [T::ZERO; M],
    };
}

/// The torque on one joint [N·m] ([`ChainRef::joint_torque_parts`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct JointTorque<T> {
    /// Its spring's term `(1 − s) · τ_spring(φ, branch)`, `s` the
    /// joint's `spring_softening` (not multiplied when `s = 0`).
    pub spring: T,
    /// The whole torque: spring, friction, joint effects and tables.
    pub total: T,
}

/// A chain's equations over arrays of capacity `M` holding `n ≤ M` joints,
/// the count known at run time ([`Chain::counted`](super::Chain::counted), [`Chain::counted_with`](super::Chain::counted_with)).
/// Every loop runs over the first `n` joints in the order of the fixed-size
/// chain, so the arithmetic is that of [`Chain`](super::Chain) bit for bit; entries past
/// `n` of the arrays it returns are zero. The methods of [`Chain`](super::Chain) are
/// shells over these (with `n = N`), and a caller written once over `M`
/// serves chains of every joint count up to `M` with one copy of the code.
#[derive(Clone, Copy, Debug)]
pub struct ChainRef<'a, T, const M: usize, const K: usize = TABLE_MAX_KNOTS> {
    /// Joints in use, `≤ M`, `≤` the joints and panels held.
    pub(super) n: usize,
    pub(super) a: &'a [[T; M]; M],
    pub(super) mass_moment: &'a [T; M],
    pub(super) panels: &'a [Panel<T>],
    pub(super) joints: &'a [Joint<T, K>],
    pub(super) global: &'a GlobalEffects<T>,
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
        self.joint_torque_parts(j, phi, phi_dot, branch).total
    }

    /// [`ChainRef::joint_torque`] with its spring's term beside it, from
    /// the same operations (the total is the same to the bit).
    #[inline(always)]
    pub fn joint_torque_parts(
        &self,
        j: usize,
        phi: T,
        phi_dot: T,
        branch: Branch,
    ) -> JointTorque<T> {
        let Some(jt) = self.joints.get(j) else {
            return JointTorque::default();
        };
        let e = &jt.effects;
        let mut t = jt.spring.torque(phi, branch);
        if e.spring_softening != T::ZERO {
            t *= T::ONE - e.spring_softening;
        }
        let spring = t;
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
        t -= crate::physics::friction::quadratic_damping(e.quadratic_nms2_per_rad2, phi_dot);
        t += e.harness_nm_per_rad * (jt.stowed_rad - phi);
        if e.detent_nm != T::ZERO {
            let delta = T::of(DETENT_ZONE_DEG).to_radians();
            let a = phi.abs();
            if a < delta {
                let two_pi = T::of(2.0) * T::PI;
                t -= e.detent_nm * phi.signum0() * (two_pi * a / delta).sin();
            }
        }
        JointTorque {
            spring,
            total: t + e.table.torque(phi, phi_dot),
        }
    }

    /// Mass matrix and right-hand side `τ + Sᵀ(Q_ext − C)` of Lagrange's
    /// equations in joint coordinates.
    #[inline(always)]
    pub fn equations(&self, x: &ChainState<T, M>, mode: &Mode<M>) -> ([[T; M]; M], [T; M]) {
        let (m, rhs, _) = self.equations_with_torques(x, mode);
        (m, rhs)
    }

    /// [`ChainRef::equations`] with the torque of each joint `τ_j` it
    /// holds ([`ChainRef::joint_torque_parts`]; zero for a latched joint).
    #[inline(always)]
    pub fn equations_with_torques(
        &self,
        x: &ChainState<T, M>,
        mode: &Mode<M>,
    ) -> ([[T; M]; M], [T; M], [JointTorque<T>; M]) {
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
        let mut torques = [JointTorque::default(); M];
        for j in 0..n {
            if !mode.latched[j] {
                torques[j] = self.joint_torque_parts(j, x.phi[j], x.phi_dot[j], mode.branch[j]);
                rhs[j] += torques[j].total;
            }
        }
        congruence(n, &mut d);
        (d, rhs, torques)
    }
}
