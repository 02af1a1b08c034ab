//! A planar multibody system: rigid bodies joined by revolute pins, written
//! at a reference pose, and its spanning-tree coordinates.
//!
//! Every body is described in the world frame at the **reference pose**
//! (for a wing: the stowed pose). A body's pose is the rigid motion
//! `x ↦ R(θ_b) x + t_b` that carries its reference points to where they are
//! now, so `θ_b = 0, t_b = 0` is the reference pose.
//!
//! The pins form a graph over the bodies. A spanning tree from the ground
//! (body 0) is chosen with lockable pins first (Kruskal order), so that hinge
//! and knee locks are tree coordinates whenever the graph allows; each tree
//! pin contributes one coordinate, the relative rotation
//! `q_k = θ_child − θ_parent` (rad), and every other pin is a *cut* pin that
//! closes a loop with two position constraints (Nikravesh, *Computer-Aided
//! Analysis of Mechanical Systems*, 1988, §7; Wittenburg, *Dynamics of
//! Multibody Systems*, 2008, §5.2).

use deploywatch_core::{Friction, Spring};

/// A rigid body. Body 0 of a [`System`] is the ground (the bus): fixed, its
/// mass properties unused.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// Name used in messages and output.
    pub name: String,
    /// Mass \[kg\].
    pub mass_kg: f64,
    /// Moment of inertia about the centre of mass, axis z [kg·m²].
    pub inertia_kgm2: f64,
    /// Centre of mass at the reference pose, world frame \[m\].
    pub com_m: [f64; 2],
}

/// A revolute pin between bodies `a` and `b` at a point.
///
/// Its angle is `α = offset + sign · (θ_b − θ_a)` \[rad\]: for a hinge the
/// joint angle `φ` of `physics.md`, for a knee its interior angle. Spring,
/// friction and applied torque act on `α` (a torque `τ` on `α` is the
/// generalised force `τ ∂α/∂q`).
#[derive(Clone, Debug, PartialEq)]
pub struct Pin {
    /// Name used in messages and output.
    pub name: String,
    /// The two bodies (indices into [`System::bodies`]).
    pub bodies: (usize, usize),
    /// Pin position at the reference pose, world frame \[m\].
    pub at_m: [f64; 2],
    /// `α` at the reference pose \[rad\].
    pub offset_rad: f64,
    /// `±1`: the sense of `α` against `θ_b − θ_a`.
    pub sign: f64,
    /// Spring torque on `α` (drives `α` towards 0, `physics.md` 3).
    pub spring: Spring<f64>,
    /// Friction on `α̇` (`physics.md` 4).
    pub friction: Friction<f64>,
    /// Constant applied torque on `α` [N·m].
    pub torque_nm: f64,
    /// The pin locks when `α` reaches this angle \[rad\] (`None`: never).
    pub lock_at_rad: Option<f64>,
}

impl Pin {
    /// A plain pin: `α = θ_b − θ_a`, no spring, friction, torque or lock.
    pub fn plain(name: &str, a: usize, b: usize, at_m: [f64; 2]) -> Pin {
        Pin {
            name: name.to_string(),
            bodies: (a, b),
            at_m,
            offset_rad: 0.0,
            sign: 1.0,
            spring: Spring::None,
            friction: Friction::default(),
            torque_nm: 0.0,
            lock_at_rad: None,
        }
    }
}

/// A linear spring between a point of body `a` and a point of body `b`:
/// force `c (ℓ − ℓ0)` pulling the points together when `ℓ > ℓ0`.
#[derive(Clone, Debug, PartialEq)]
pub struct PointSpring {
    /// First body and its point at the reference pose \[m\].
    pub a: (usize, [f64; 2]),
    /// Second body and its point at the reference pose \[m\].
    pub b: (usize, [f64; 2]),
    /// Stiffness `c` [N/m].
    pub stiffness_n_m: f64,
    /// Rest length `ℓ0` \[m\].
    pub rest_m: f64,
}

/// Bodies, pins and force elements.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct System {
    /// Body 0 is the ground.
    pub bodies: Vec<Body>,
    /// Revolute pins (several may share a point: a node joining several links).
    pub pins: Vec<Pin>,
    /// Point-to-point springs.
    pub springs: Vec<PointSpring>,
}

/// Why a system cannot be simulated.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SystemError {
    /// A pin names a body that does not exist or joins a body to itself.
    #[error("pin `{pin}` joins bodies {a} and {b}; expected two different bodies below {count}")]
    BadPin {
        /// Pin name.
        pin: String,
        /// First body index.
        a: usize,
        /// Second body index.
        b: usize,
        /// Number of bodies.
        count: usize,
    },
    /// A body is not connected to the ground through pins.
    #[error("body `{0}` is not connected to the ground by any chain of pins")]
    Floating(String),
    /// A moving body without mass or inertia (singular mass matrix).
    #[error("body `{0}` needs a mass > 0 and an inertia > 0")]
    Massless(String),
}

/// The spanning tree: coordinates, parents and paths.
#[derive(Clone, Debug, PartialEq)]
pub struct Tree {
    /// Pin of coordinate `k`.
    pub coord_pin: Vec<usize>,
    /// Coordinate of each pin if it is a tree pin.
    pub pin_coord: Vec<Option<usize>>,
    /// Bodies in an order where a parent precedes its children (ground first).
    pub order: Vec<usize>,
    /// `(parent body, coordinate)` of each body; `None` for the ground.
    pub parent: Vec<Option<(usize, usize)>>,
    /// Coordinates on the path from the ground to each body.
    pub path: Vec<Vec<usize>>,
    /// `+1` where the tree pin's `b` is the child, `−1` where it is its `a`.
    pub coord_sense: Vec<f64>,
}

impl System {
    /// Checks the system and builds its spanning tree.
    pub fn tree(&self) -> Result<Tree, SystemError> {
        let nb = self.bodies.len();
        for p in &self.pins {
            let (a, b) = p.bodies;
            if a >= nb || b >= nb || a == b {
                return Err(SystemError::BadPin {
                    pin: p.name.clone(),
                    a,
                    b,
                    count: nb,
                });
            }
        }
        for b in self.bodies.iter().skip(1) {
            if !(b.mass_kg > 0.0 && b.inertia_kgm2 > 0.0) {
                return Err(SystemError::Massless(b.name.clone()));
            }
        }
        let mut adj: Vec<Vec<usize>> = vec![Vec::new(); nb];
        let mut root: Vec<usize> = (0..nb).collect();
        fn find(r: &mut [usize], mut i: usize) -> usize {
            while r[i] != i {
                r[i] = r[r[i]];
                i = r[i];
            }
            i
        }
        // Kruskal with lockable pins first: locks become tree coordinates.
        let mut order: Vec<usize> = (0..self.pins.len()).collect();
        order.sort_by_key(|&i| self.pins[i].lock_at_rad.is_none());
        let mut is_tree = vec![false; self.pins.len()];
        for i in order {
            let (a, b) = self.pins[i].bodies;
            let (ra, rb) = (find(&mut root, a), find(&mut root, b));
            if ra != rb {
                root[ra] = rb;
                is_tree[i] = true;
                adj[a].push(i);
                adj[b].push(i);
            }
        }
        self.walk(&adj, &is_tree)
    }

    /// Breadth-first walk of the tree pins from the ground.
    fn walk(&self, adj: &[Vec<usize>], is_tree: &[bool]) -> Result<Tree, SystemError> {
        let nb = self.bodies.len();
        let mut tree = Tree {
            coord_pin: Vec::new(),
            pin_coord: vec![None; self.pins.len()],
            order: vec![0],
            parent: vec![None; nb],
            path: vec![Vec::new(); nb],
            coord_sense: Vec::new(),
        };
        let mut seen = vec![false; nb];
        seen[0] = true;
        let mut head = 0;
        while head < tree.order.len() {
            let body = tree.order[head];
            head += 1;
            for &pi in &adj[body] {
                let (a, b) = self.pins[pi].bodies;
                let (child, sense) = if a == body { (b, 1.0) } else { (a, -1.0) };
                if !is_tree[pi] || seen[child] {
                    continue;
                }
                seen[child] = true;
                let k = tree.coord_pin.len();
                tree.coord_pin.push(pi);
                tree.coord_sense.push(sense);
                tree.pin_coord[pi] = Some(k);
                tree.parent[child] = Some((body, k));
                let mut path = tree.path[body].clone();
                path.push(k);
                tree.path[child] = path;
                tree.order.push(child);
            }
        }
        if let Some(i) = seen.iter().position(|&s| !s) {
            return Err(SystemError::Floating(self.bodies[i].name.clone()));
        }
        Ok(tree)
    }
}
