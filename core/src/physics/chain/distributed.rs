//! The distributed effects of the chain (`physics.md` section 6): rig tilt
//! and air drag as generalised forces conjugate to the absolute angles, and
//! the power the drag dissipates.

use super::counted::ChainRef;
use super::kinematics::{absolute, trig};
use super::parts::ChainState;
use crate::physics::real::Real;

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

impl<T: Real, const M: usize, const K: usize> ChainRef<'_, T, M, K> {
    /// Length `L_k` of panel `k` \[m\] (0 past the panels).
    #[inline(always)]
    fn length(&self, k: usize) -> T {
        self.panels.get(k).map_or(T::ZERO, |p| p.length_m)
    }

    /// Generalised forces of the distributed effects conjugate to the
    /// absolute angles, `Q_ext` [N·m]: rig tilt and air drag.
    #[inline(always)]
    pub(super) fn external(&self, c: &[T; M], s: &[T; M], theta_dot: &[T; M]) -> [T; M] {
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
}
