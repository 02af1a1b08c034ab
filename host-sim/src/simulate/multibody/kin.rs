//! Kinematics and the equations of motion in tree coordinates.
//!
//! For a point `x` of body `b` (world frame) the velocity is
//! `ẋ = Σ_{k ∈ path(b)} q̇_k (x − P_k)^⊥`, `P_k` the world position of the
//! pin of coordinate `k` and `(x, y)^⊥ = (−y, x)`; the acceleration with
//! `q̈ = 0` (the velocity-product term) follows the tree outwards:
//! `a0(x) = a0(P_k) − ω_b² (x − P_k)` with `k` the body's own coordinate.
//!
//! Lagrange's equations with the loop constraints `g(q) = 0`:
//!
//! ```text
//! M(q) q̈ = Q(q, q̇) + Cᵀ λ,   C q̈ = γ,   C = ∂g/∂q,   γ = −Ċ q̇,
//! M = Σ_b m_b J_bᵀ J_b + I_b j_bᵀ j_b,
//! Q = Σ_b −m_b J_bᵀ a0(c_b) + generalised forces of pins and springs.
//! ```

use nalgebra::{DMatrix, DVector};

use super::system::{System, Tree};

/// `(x, y)^⊥ = (−y, x)`.
#[inline]
fn perp(r: [f64; 2]) -> [f64; 2] {
    [-r[1], r[0]]
}

#[inline]
fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

#[inline]
fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// A system with its tree: what the integrator evaluates.
#[derive(Clone, Debug)]
pub struct Model {
    /// Bodies, pins and force elements.
    pub sys: System,
    /// Spanning tree and coordinates.
    pub tree: Tree,
}

/// Positions and velocities of every body at one state.
#[derive(Clone, Debug, Default)]
pub struct Kin {
    /// Absolute rotation of each body from its reference pose \[rad\].
    pub theta: Vec<f64>,
    /// `(cos θ_b, sin θ_b)` of each body.
    pub rot: Vec<[f64; 2]>,
    /// Translation `t_b` of each body \[m\].
    pub trans: Vec<[f64; 2]>,
    /// Angular velocity of each body [rad/s].
    pub omega: Vec<f64>,
    /// World position of the pin of each coordinate \[m\].
    pub pin_pos: Vec<[f64; 2]>,
    /// Velocity of that pin [m/s].
    pub pin_vel: Vec<[f64; 2]>,
    /// Its acceleration with `q̈ = 0` [m/s²].
    pub pin_acc0: Vec<[f64; 2]>,
}

/// The constraint rows active in a mode: cut pins (2 rows each) and locks.
#[derive(Clone, Debug)]
pub struct Rows {
    /// `C = ∂g/∂q`.
    pub c: DMatrix<f64>,
    /// `γ = −Ċ q̇`.
    pub gamma: DVector<f64>,
    /// `g(q)` [m for cut pins, rad for locks].
    pub g: DVector<f64>,
}

/// Constraint rows written into caller-owned buffers (no allocation):
/// `c` row-major with `n` columns.
pub(crate) struct RowsOut<'a> {
    /// `C`, row-major, `rows × n` (or empty: not wanted).
    pub c: &'a mut [f64],
    /// `γ` (or empty: not wanted).
    pub gamma: &'a mut [f64],
    /// `g`.
    pub g: &'a mut [f64],
}

impl Model {
    /// Number of coordinates.
    pub fn n(&self) -> usize {
        self.tree.coord_pin.len()
    }

    /// Kinematics at `(q, q̇)`.
    pub fn kin(&self, q: &[f64], v: &[f64]) -> Kin {
        let mut k = Kin::default();
        self.kin_into(q, v, &mut k);
        k
    }

    /// Kinematics at `(q, q̇)` into `k`, reusing its buffers.
    pub fn kin_into(&self, q: &[f64], v: &[f64], k: &mut Kin) {
        self.kin_impl(q, Some(v), k);
    }

    /// Positions only (`θ`, `t_b`, pin positions) into `k`: what `g(q)`
    /// needs; velocities and accelerations are left as they were.
    pub(crate) fn kin_positions_into(&self, q: &[f64], k: &mut Kin) {
        self.kin_impl(q, None, k);
    }

    fn kin_impl(&self, q: &[f64], v: Option<&[f64]>, k: &mut Kin) {
        let nb = self.sys.bodies.len();
        let n = self.n();
        k.theta.resize(nb, 0.0);
        k.rot.resize(nb, [1.0, 0.0]);
        k.trans.resize(nb, [0.0; 2]);
        k.omega.resize(nb, 0.0);
        k.pin_pos.resize(n, [0.0; 2]);
        k.pin_vel.resize(n, [0.0; 2]);
        k.pin_acc0.resize(n, [0.0; 2]);
        k.theta[0] = 0.0;
        k.rot[0] = [1.0, 0.0];
        k.trans[0] = [0.0; 2];
        k.omega[0] = 0.0;
        for &b in self.tree.order.iter().skip(1) {
            let Some((a, c)) = self.tree.parent[b] else {
                continue;
            };
            let at = self.sys.pins[self.tree.coord_pin[c]].at_m;
            let p = k.world(a, at);
            if let Some(v) = v {
                k.pin_vel[c] = k.vel(&self.tree, a, p);
                k.pin_acc0[c] = k.acc0(&self.tree, a, p);
                k.omega[b] = k.omega[a] + v[c];
            }
            k.pin_pos[c] = p;
            k.theta[b] = k.theta[a] + q[c];
            let (s, co) = k.theta[b].sin_cos();
            k.rot[b] = [co, s];
            k.trans[b] = [
                p[0] - (co * at[0] - s * at[1]),
                p[1] - (s * at[0] + co * at[1]),
            ];
        }
    }

    /// Adds `w · (∂x/∂q)ᵀ f` for a world point `x` of body `b` to `out`
    /// (`f` a force: generalised force; or one Jacobian row per component).
    fn add_point_jt(&self, k: &Kin, b: usize, x: [f64; 2], f: [f64; 2], out: &mut [f64]) {
        for &c in &self.tree.path[b] {
            out[c] += dot(perp(sub(x, k.pin_pos[c])), f);
        }
    }

    /// Adds `w · ∂(θ_b − θ_a)/∂q` to `out`.
    fn add_rel_rot(&self, a: usize, b: usize, w: f64, out: &mut [f64]) {
        for &c in &self.tree.path[b] {
            out[c] += w;
        }
        for &c in &self.tree.path[a] {
            out[c] -= w;
        }
    }

    /// Angle `α` \[rad\] and rate `α̇` [rad/s] of pin `p`.
    pub fn pin_angle(&self, k: &Kin, p: usize) -> (f64, f64) {
        let pin = &self.sys.pins[p];
        let (a, b) = pin.bodies;
        (
            pin.offset_rad + pin.sign * (k.theta[b] - k.theta[a]),
            pin.sign * (k.omega[b] - k.omega[a]),
        )
    }

    /// Angle `α` \[rad\] of pin `p` at coordinates `q` (no kinematics needed:
    /// `θ_b` is the sum of the coordinates on the path to `b`).
    pub fn pin_angle_at(&self, q: &[f64], p: usize) -> f64 {
        let pin = &self.sys.pins[p];
        let (a, b) = pin.bodies;
        let theta = |b: usize| self.tree.path[b].iter().map(|&c| q[c]).sum::<f64>();
        pin.offset_rad + pin.sign * (theta(b) - theta(a))
    }

    /// Mass matrix `M(q)` and right-hand side `Q(q, q̇)` (velocity-product
    /// terms, pin torques, point springs).
    pub fn mass_and_forces(&self, k: &Kin) -> (DMatrix<f64>, DVector<f64>) {
        let n = self.n();
        let mut m = vec![0.0; n * n];
        let mut rhs = vec![0.0; n];
        self.mass_into(k, &mut m, Some(&mut rhs));
        (DMatrix::from_row_slice(n, n, &m), DVector::from_vec(rhs))
    }

    /// [`Model::mass_and_forces`] into buffers: `m` (`n × n`, row-major,
    /// full) and, when given, `rhs` (`n`).
    pub(crate) fn mass_into(&self, k: &Kin, m: &mut [f64], rhs: Option<&mut [f64]>) {
        m.iter_mut().for_each(|x| *x = 0.0);
        let n = self.n();
        for (b, body) in self.sys.bodies.iter().enumerate().skip(1) {
            let c = k.world(b, body.com_m);
            let path = &self.tree.path[b];
            for (ii, &i) in path.iter().enumerate() {
                let ri = sub(c, k.pin_pos[i]);
                for &j in &path[..=ii] {
                    m[i * n + j] +=
                        body.mass_kg * dot(ri, sub(c, k.pin_pos[j])) + body.inertia_kgm2;
                }
            }
        }
        // Each pair of path coordinates was added once, in whichever
        // triangle its order on the path put it: fold both into a full
        // symmetric matrix.
        for i in 0..n {
            for j in 0..i {
                let s = m[i * n + j] + m[j * n + i];
                m[i * n + j] = s;
                m[j * n + i] = s;
            }
        }
        let Some(rhs) = rhs else {
            return;
        };
        rhs.iter_mut().for_each(|x| *x = 0.0);
        for (b, body) in self.sys.bodies.iter().enumerate().skip(1) {
            let c = k.world(b, body.com_m);
            let a0 = k.acc0(&self.tree, b, c);
            self.add_point_jt(k, b, c, [-body.mass_kg * a0[0], -body.mass_kg * a0[1]], rhs);
        }
        for (p, pin) in self.sys.pins.iter().enumerate() {
            let (alpha, rate) = self.pin_angle(k, p);
            let tau = pin.spring.torque(alpha, deploywatch_core::Branch::Unfold)
                + pin.friction.torque(rate)
                + pin.torque_nm;
            if tau != 0.0 {
                self.add_rel_rot(pin.bodies.0, pin.bodies.1, tau * pin.sign, rhs);
            }
        }
        for s in &self.sys.springs {
            let (xa, xb) = (k.world(s.a.0, s.a.1), k.world(s.b.0, s.b.1));
            let d = sub(xb, xa);
            let len = dot(d, d).sqrt();
            let f = -s.stiffness_n_m * (len - s.rest_m) / len;
            self.add_point_jt(k, s.b.0, xb, [f * d[0], f * d[1]], rhs);
            self.add_point_jt(k, s.a.0, xa, [-f * d[0], -f * d[1]], rhs);
        }
    }

    /// The cut pins (pins that are not tree coordinates).
    pub fn cut_pins(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.sys.pins.len()).filter(|&p| self.tree.pin_coord[p].is_none())
    }

    /// Number of constraint rows with the pins `locked`.
    pub(crate) fn row_count(&self, locked: &[bool]) -> usize {
        2 * self.cut_pins().count() + locked.iter().filter(|&&l| l).count()
    }

    /// Constraint rows at a state: two per cut pin, one per locked pin
    /// (`locked[p]`), in that order.
    pub fn rows(&self, k: &Kin, locked: &[bool]) -> Rows {
        let n = self.n();
        let m = self.row_count(locked);
        let mut c = vec![0.0; m * n];
        let mut gamma = vec![0.0; m];
        let mut g = vec![0.0; m];
        self.rows_into(
            k,
            locked,
            RowsOut {
                c: &mut c,
                gamma: &mut gamma,
                g: &mut g,
            },
        );
        Rows {
            c: DMatrix::from_row_slice(m, n, &c),
            gamma: DVector::from_vec(gamma),
            g: DVector::from_vec(g),
        }
    }

    /// [`Model::rows`] into buffers of at least [`Model::row_count`] rows;
    /// `C` and `γ` only when their buffers are not empty. Returns the
    /// number of rows.
    pub(crate) fn rows_into(&self, k: &Kin, locked: &[bool], out: RowsOut<'_>) -> usize {
        let n = self.n();
        let want_c = !out.c.is_empty();
        let want_gamma = !out.gamma.is_empty();
        let mut r = 0;
        for p in self.cut_pins() {
            let pin = &self.sys.pins[p];
            let (a, b) = pin.bodies;
            let (xa, xb) = (k.world(a, pin.at_m), k.world(b, pin.at_m));
            out.g[r] = xb[0] - xa[0];
            out.g[r + 1] = xb[1] - xa[1];
            if want_gamma {
                let (aa, ab) = (k.acc0(&self.tree, a, xa), k.acc0(&self.tree, b, xb));
                out.gamma[r] = -(ab[0] - aa[0]);
                out.gamma[r + 1] = -(ab[1] - aa[1]);
            }
            if want_c {
                let (cx, rest) = out.c[r * n..(r + 2) * n].split_at_mut(n);
                cx.iter_mut().for_each(|x| *x = 0.0);
                rest.iter_mut().for_each(|x| *x = 0.0);
                // ∂x/∂q_c = (x − P_c)^⊥ = (−(y − P_y), x − P_x).
                for &c in &self.tree.path[b] {
                    let d = sub(xb, k.pin_pos[c]);
                    cx[c] -= d[1];
                    rest[c] += d[0];
                }
                for &c in &self.tree.path[a] {
                    let d = sub(xa, k.pin_pos[c]);
                    cx[c] += d[1];
                    rest[c] -= d[0];
                }
            }
            r += 2;
        }
        for (p, _) in locked.iter().enumerate().filter(|(_, &l)| l) {
            let pin = &self.sys.pins[p];
            if want_c {
                let row = &mut out.c[r * n..(r + 1) * n];
                row.iter_mut().for_each(|x| *x = 0.0);
                self.add_rel_rot(pin.bodies.0, pin.bodies.1, pin.sign, row);
            }
            if want_gamma {
                out.gamma[r] = 0.0;
            }
            out.g[r] = self.pin_angle(k, p).0 - pin.lock_at_rad.unwrap_or(0.0);
            r += 1;
        }
        r
    }

    /// Mechanical energy \[J\]: kinetic `½ q̇ᵀ M q̇`, plus the pin springs'
    /// `∫₀^|α| T` (`Spring::release`), plus `½ c (ℓ − ℓ0)²` of the point
    /// springs, minus the work potential `τ α` of the applied torques.
    /// Conserved without friction and locks.
    pub fn energy(&self, q: &[f64], v: &[f64]) -> f64 {
        let k = self.kin(q, v);
        let n = self.n();
        self.energy_at(&k, v, &mut vec![0.0; n * n])
    }

    /// [`Model::energy`] at kinematics `k` with velocities `v`, `m` an
    /// `n × n` scratch buffer.
    pub(crate) fn energy_at(&self, k: &Kin, v: &[f64], m: &mut [f64]) -> f64 {
        let n = self.n();
        self.mass_into(k, m, None);
        let mut e = 0.0;
        for i in 0..n {
            let mut mv = 0.0;
            for j in 0..n {
                mv += m[i * n + j] * v[j];
            }
            e += 0.5 * v[i] * mv;
        }
        for (p, pin) in self.sys.pins.iter().enumerate() {
            let alpha = self.pin_angle(k, p).0;
            e += pin.spring.release(0.0, alpha.abs()) - pin.torque_nm * alpha;
        }
        for s in &self.sys.springs {
            let d = sub(k.world(s.b.0, s.b.1), k.world(s.a.0, s.a.1));
            let stretch = dot(d, d).sqrt() - s.rest_m;
            e += 0.5 * s.stiffness_n_m * stretch * stretch;
        }
        e
    }
}

impl Kin {
    /// World position of a point of body `b` given at the reference pose.
    #[inline]
    pub fn world(&self, b: usize, x: [f64; 2]) -> [f64; 2] {
        let [c, s] = self.rot[b];
        [
            c * x[0] - s * x[1] + self.trans[b][0],
            s * x[0] + c * x[1] + self.trans[b][1],
        ]
    }

    /// Velocity of the world point `x` of body `b`.
    #[inline]
    fn vel(&self, tree: &Tree, b: usize, x: [f64; 2]) -> [f64; 2] {
        match tree.parent[b] {
            None => [0.0; 2],
            Some((_, c)) => {
                let r = perp(sub(x, self.pin_pos[c]));
                let w = self.omega[b];
                [self.pin_vel[c][0] + w * r[0], self.pin_vel[c][1] + w * r[1]]
            }
        }
    }

    /// Acceleration of the world point `x` of body `b` with `q̈ = 0`.
    #[inline]
    fn acc0(&self, tree: &Tree, b: usize, x: [f64; 2]) -> [f64; 2] {
        match tree.parent[b] {
            None => [0.0; 2],
            Some((_, c)) => {
                let r = sub(x, self.pin_pos[c]);
                let w2 = self.omega[b] * self.omega[b];
                [
                    self.pin_acc0[c][0] - w2 * r[0],
                    self.pin_acc0[c][1] - w2 * r[1],
                ]
            }
        }
    }
}
