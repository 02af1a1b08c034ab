//! Truss-link configuration synthesis of seed 000 (section 2.2, Eqs. 2–10,
//! Tables 2–3): from the designer's inputs in the stowed configuration, the
//! coordinates of the latch points B, E, H and the lengths and angles of the
//! truss links 2, 3, 5, 7 that all meet at joint F.
//!
//! Coordinates are `(x, z)` in the plane of the wing \[mm\], angles in degrees
//! at the interface (radians inside). The equations, as corrected in
//! `docs/spec/paper-vectors.md`:
//!
//! ```text
//! B = (xA − L1 cos φ1, zA + L1 sin φ1)
//! E = (xD − L4 cos φ4, zD + L4 sin φ4)
//! H = (xG + L6 cos φ6, zG − L6 sin φ6)
//! L2 = |B − F|, L3 = |F − C|, L5 = |E − F|, L7 = |F − H|
//! φ2 = acos((xF − xB)/L2), φ3 = acos((xF − xC)/L3),
//! φ5 = acos((xF − xE)/L5), φ7 = acos((xF − xH)/L7)
//! ```
//!
//! The paper's extracted text writes `φ2 = acos((xB − xF)/L2)`, which gives
//! the supplement (86.89° instead of Table 3's 93.11°); this module follows
//! the table, i.e. the same form as φ3, φ5, φ7.

/// A point `(x, z)` \[mm\].
pub type Point = (f64, f64);

/// Inputs of the synthesis (seed 000 Table 2, "Input").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrussInput {
    /// φ1 \[deg\], angle of link 1 (A→B).
    pub phi1_deg: f64,
    /// φ4 \[deg\], angle of link 4 (D→E).
    pub phi4_deg: f64,
    /// φ6 \[deg\], angle of link 6 (G→H).
    pub phi6_deg: f64,
    /// L1 \[mm\].
    pub l1_mm: f64,
    /// L4 \[mm\].
    pub l4_mm: f64,
    /// L6 \[mm\].
    pub l6_mm: f64,
    /// Point A \[mm\].
    pub a: Point,
    /// Point C \[mm\].
    pub c: Point,
    /// Point D \[mm\].
    pub d: Point,
    /// Joint F, where all truss links meet \[mm\].
    pub f: Point,
    /// Point G \[mm\].
    pub g: Point,
}

impl TrussInput {
    /// The inputs of seed 000 Table 3.
    pub fn seed000_table3() -> Self {
        TrussInput {
            phi1_deg: 91.55,
            phi4_deg: 129.18,
            phi6_deg: 92.06,
            l1_mm: 140.00,
            l4_mm: 86.00,
            l6_mm: 661.34,
            a: (57.00, -288.00),
            c: (43.00, -120.00),
            d: (43.00, -640.00),
            f: (21.44, -873.27),
            g: (-69.40, -152.00),
        }
    }
}

/// Outputs of the synthesis (seed 000 Table 2, "Output").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrussOutput {
    /// Latch point B \[mm\].
    pub b: Point,
    /// Latch point E \[mm\].
    pub e: Point,
    /// Latch point H \[mm\].
    pub h: Point,
    /// L2 = |B − F| \[mm\].
    pub l2_mm: f64,
    /// L3 = |F − C| \[mm\].
    pub l3_mm: f64,
    /// L5 = |E − F| \[mm\].
    pub l5_mm: f64,
    /// L7 = |F − H| \[mm\].
    pub l7_mm: f64,
    /// φ2 \[deg\].
    pub phi2_deg: f64,
    /// φ3 \[deg\].
    pub phi3_deg: f64,
    /// φ5 \[deg\].
    pub phi5_deg: f64,
    /// φ7 \[deg\].
    pub phi7_deg: f64,
}

fn dist(p: Point, q: Point) -> f64 {
    (p.0 - q.0).hypot(p.1 - q.1)
}

/// `acos((xF − xP)/L)` \[deg\], clamped against rounding past ±1; NaN if `L = 0`.
fn link_angle_deg(f: Point, p: Point, l: f64) -> f64 {
    ((f.0 - p.0) / l).clamp(-1.0, 1.0).acos().to_degrees()
}

/// Seed 000 Eqs. 2–10 (see the module documentation).
pub fn synthesize(i: &TrussInput) -> TrussOutput {
    let (p1, p4, p6) = (
        i.phi1_deg.to_radians(),
        i.phi4_deg.to_radians(),
        i.phi6_deg.to_radians(),
    );
    let b = (i.a.0 - i.l1_mm * p1.cos(), i.a.1 + i.l1_mm * p1.sin());
    let e = (i.d.0 - i.l4_mm * p4.cos(), i.d.1 + i.l4_mm * p4.sin());
    let h = (i.g.0 + i.l6_mm * p6.cos(), i.g.1 - i.l6_mm * p6.sin());
    let l2 = dist(b, i.f);
    let l3 = dist(i.f, i.c);
    let l5 = dist(e, i.f);
    let l7 = dist(i.f, h);
    TrussOutput {
        b,
        e,
        h,
        l2_mm: l2,
        l3_mm: l3,
        l5_mm: l5,
        l7_mm: l7,
        phi2_deg: link_angle_deg(i.f, b, l2),
        phi3_deg: link_angle_deg(i.f, i.c, l3),
        phi5_deg: link_angle_deg(i.f, e, l5),
        phi7_deg: link_angle_deg(i.f, h, l7),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_link_along_x_has_zero_angle_and_its_length() {
        let i = TrussInput {
            phi1_deg: 90.0,
            phi4_deg: 90.0,
            phi6_deg: 90.0,
            l1_mm: 10.0,
            l4_mm: 10.0,
            l6_mm: 10.0,
            a: (0.0, 0.0),
            c: (0.0, 0.0),
            d: (0.0, 0.0),
            f: (5.0, 0.0),
            g: (0.0, 0.0),
        };
        let o = synthesize(&i);
        assert!((o.l3_mm - 5.0).abs() < 1e-12);
        assert!(o.phi3_deg.abs() < 1e-9);
        // B straight above A, H straight below G (φ = 90°).
        assert!((o.b.0).abs() < 1e-12 && (o.b.1 - 10.0).abs() < 1e-12);
        assert!((o.h.0).abs() < 1e-12 && (o.h.1 + 10.0).abs() < 1e-12);
        assert!((o.l2_mm - 125f64.sqrt()).abs() < 1e-12);
    }
}
