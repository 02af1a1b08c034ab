//! A truss of pin-jointed links on a panel wing (`docs/spec/truss-link.md`,
//! the `[truss]` table of `docs/spec/formats.md`): its points, links and
//! checks. Its planar multibody system is built by
//! `simulate::multibody::build`.
//!
//! Everything is given at the stowed pose in the project frame (origin at
//! hinge O, `physics.md` §1). Bodies: 0 the bus, 1..=n the panels, then one
//! body per link. Pins:
//! - hinge `j` between panel `j−1` and panel `j`: angle `φ_j = stowed +`
//!   relative rotation, the mechanism's spring and friction, locks at 0;
//! - a link end on the bus or a panel: angle of the link (from its far end
//!   to the pin) relative to the carrier, stowed value from the geometry;
//! - a knee (a node of exactly two links): interior angle, locks at 180°;
//! - any other node joins its links to its reference link (three pins for
//!   the four links at F), angle = relative rotation.

use crate::model::friction_spec::FrictionSpec;

/// What a point of the truss is fixed to.
#[derive(Clone, Debug, PartialEq)]
pub enum Carrier {
    /// The bus (fixed).
    Bus,
    /// Panel `i` (1-based, bus outwards).
    Panel(usize),
    /// A free node: only the links that meet there hold it.
    Node,
}

/// A named point.
#[derive(Clone, Debug, PartialEq)]
pub struct TrussPoint {
    /// Name (`"A"`, `"F"`...).
    pub name: String,
    /// What it is fixed to.
    pub on: Carrier,
    /// Position at the stowed pose \[mm\].
    pub at_mm: [f64; 2],
    /// A knee: a node of two links that locks when they are straight.
    pub knee: bool,
    /// For a node of three or more links: the link the others turn
    /// against (default the first link that names the point).
    pub reference_link: Option<String>,
    /// Friction on every pin at this point (on the relative rotation).
    pub friction: FrictionSpec,
}

/// A pin-jointed bar.
#[derive(Clone, Debug, PartialEq)]
pub struct TrussLink {
    /// Name (`"1"`...`"7"`).
    pub name: String,
    /// Its two end points.
    pub ends: [String; 2],
    /// Mass \[kg\]; centre of mass at mid-length, inertia `m L²/12`.
    pub mass_kg: f64,
    /// Length \[mm\] (checked against the points).
    pub length_mm: f64,
}

/// The truss of a wing.
#[derive(Clone, Debug, PartialEq)]
pub struct Truss {
    /// Hinge `j` position at the stowed pose \[mm\], one per joint (O first).
    pub hinges_mm: Vec<[f64; 2]>,
    /// Named points.
    pub points: Vec<TrussPoint>,
    /// Links.
    pub links: Vec<TrussLink>,
}

/// True for a knee name that can name run columns (`knee<P>_deg`,
/// `knee<P>`): 1 to 16 ASCII letters or digits.
pub fn valid_knee_name(p: &str) -> bool {
    (1..=16).contains(&p.len()) && p.bytes().all(|b| b.is_ascii_alphanumeric())
}

/// Largest mismatch between a link's length and its points \[mm\].
pub const LENGTH_TOL_MM: f64 = 0.01;

/// `[x, y]` in mm as metres.
pub fn m(p: [f64; 2]) -> [f64; 2] {
    [p[0] * 1e-3, p[1] * 1e-3]
}

/// Why a truss is not a valid mechanism (the key path names the place).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("`{key}`: {message}")]
pub struct TrussError {
    /// Key path, e.g. `truss.link[3].length_mm`.
    pub key: String,
    /// What is wrong and what was expected.
    pub message: String,
}

/// A [`TrussError`] at `key`.
pub fn err(key: impl Into<String>, message: impl Into<String>) -> TrussError {
    TrussError {
        key: key.into(),
        message: message.into(),
    }
}

/// `a − b`.
pub fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

/// The direction of `v` \[rad\].
pub fn angle(v: [f64; 2]) -> f64 {
    v[1].atan2(v[0])
}

/// The body a point's carrier is (`None` for a node).
pub fn carrier_body(c: &Carrier) -> Option<usize> {
    match c {
        Carrier::Bus => Some(0),
        Carrier::Panel(i) => Some(*i),
        Carrier::Node => None,
    }
}

impl Truss {
    /// The friction nodes: the free nodes that are not knees (F of the seed
    /// 000 wing), in file order, as indices into [`Truss::points`]. Each is
    /// one friction parameter acting on every pin at that node, numbered
    /// after the hinges: joint `n + k` of an effect or an identification is
    /// the `k`-th friction node (the paper's EFT3 at F is joint 3 of the
    /// two-panel wing, `docs/identification.md`).
    pub fn friction_nodes(&self) -> Vec<usize> {
        (0..self.points.len())
            .filter(|&i| self.points[i].on == Carrier::Node && !self.points[i].knee)
            .collect()
    }

    /// The point named `name`, with its index.
    pub fn point(&self, name: &str) -> Option<(usize, &TrussPoint)> {
        self.points.iter().enumerate().find(|(_, p)| p.name == name)
    }

    /// Checks the geometry and the topology (lengths, knees, nodes).
    pub fn check(&self, panels: usize) -> Result<(), TrussError> {
        if self.hinges_mm.len() != panels {
            return Err(err(
                "truss.hinges_mm",
                format!(
                    "{} hinge positions; expected one per joint ({panels})",
                    self.hinges_mm.len()
                ),
            ));
        }
        for (i, l) in self.links.iter().enumerate() {
            let key = format!("truss.link[{}]", i + 1);
            let mut at = [[0.0; 2]; 2];
            for (e, name) in l.ends.iter().enumerate() {
                at[e] = self
                    .point(name)
                    .ok_or_else(|| err(format!("{key}.ends"), format!("no point named \"{name}\"; expected one of the [[truss.point]] names")))?
                    .1
                    .at_mm;
            }
            let d = sub(at[1], at[0]);
            let dist = (d[0] * d[0] + d[1] * d[1]).sqrt();
            if (dist - l.length_mm).abs() > LENGTH_TOL_MM {
                return Err(err(
                    format!("{key}.length_mm"),
                    format!(
                        "link \"{}\" is {:.4} mm long but its points {} and {} are {:.4} mm apart; expected them to agree within {} mm",
                        l.name, l.length_mm, l.ends[0], l.ends[1], dist, LENGTH_TOL_MM
                    ),
                ));
            }
        }
        for (i, p) in self.points.iter().enumerate() {
            let key = format!("truss.point[{}]", i + 1);
            let n = self.links_at(&p.name).len();
            if let Carrier::Panel(j) = p.on {
                if j == 0 || j > panels {
                    return Err(err(
                        format!("{key}.on"),
                        format!("panel {j}; expected 1 to {panels}"),
                    ));
                }
            }
            if p.knee && (p.on != Carrier::Node || n != 2) {
                return Err(err(
                    format!("{key}.knee"),
                    format!(
                        "knee \"{}\" joins {n} link(s); expected a free node of exactly two links",
                        p.name
                    ),
                ));
            }
            if p.knee && !valid_knee_name(&p.name) {
                return Err(err(
                    format!("{key}.name"),
                    format!(
                        "knee name {:?}; expected 1 to 16 ASCII letters or digits (it names the run's columns knee<P>_deg and knee<P>)",
                        p.name
                    ),
                ));
            }
            if p.on == Carrier::Node && n < 2 {
                return Err(err(
                    format!("{key}.on"),
                    format!(
                        "free node \"{}\" is on {n} link(s); expected a node on at least two links",
                        p.name
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Indices of the links with an end at the point `name`.
    pub fn links_at(&self, name: &str) -> Vec<usize> {
        (0..self.links.len())
            .filter(|&i| self.links[i].ends.iter().any(|e| e == name))
            .collect()
    }
}
