//! Where an identification's result sits in its design box: a response
//! surface minimised at the edge of the box it was fitted in did not reach
//! the minimum (`docs/identification.md`).

use crate::analysis::identify::Identification;

/// Relative distance to a box edge [ratio of the edge value] within which
/// an EFT counts as on the edge (the minimiser stops at the bound to
/// rounding).
pub const EDGE_RTOL: f64 = 1e-9;

/// The joints whose response-surface EFT lies on the edge of the box the
/// surface was minimised in (not at the bound 0): the design did not
/// reach the minimum.
pub fn at_design_edge(id: &Identification) -> Vec<usize> {
    let Some(r) = &id.rsm else {
        return Vec::new();
    };
    let on = |v: f64, edge: f64| (v - edge).abs() <= EDGE_RTOL * edge.abs().max(1e-12);
    id.joints
        .iter()
        .zip(&r.box_nm)
        .filter(|(j, [lo, hi])| on(j.coulomb_nm, *hi) || (*lo > 0.0 && on(j.coulomb_nm, *lo)))
        .map(|(j, _)| j.joint)
        .collect()
}
