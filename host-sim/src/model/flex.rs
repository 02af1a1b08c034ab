//! Flexible panels (`docs/spec/physics.md` §12, this project's extension):
//! each panel two rigid halves joined at mid-span by a torsion spring and a
//! damper, one stiffness for every panel, set by the deployed wing's first
//! mode.
//!
//! A panel `(L, m, c, I)` (length, mass, centre of mass from its inboard
//! hinge, inertia about it) becomes an inner half from the panel's hinge to
//! `L/2` and an outer half from `L/2` to `L`, each of mass `m/2`, their
//! centres at `c ∓ d` and their own inertias `(I − m d²)/2`, so that the two
//! halves rigidly together have the panel's mass, centre and inertia.
//! `d = min(L/4, 0.7 √(I/m))`: `L/4` for a uniform panel (each half uniform
//! too), less where the panel's inertia is too small for that split.
//!
//! The chain of a wing of `N` panels is then `2N` joints: hinge `j` is
//! joint `2j` of the flexible chain (0-based), the flex joint of panel `j`
//! is joint `2j + 1`, stowed at 0 (the panel straight), never latched, its
//! spring `k φ_f` and its damper `c φ̇_f`. With every hinge latched the flex
//! joints' mass matrix is `M_ff` (at the deployed angles) and their
//! stiffness `k I`, so the deployed wing's first mode is
//! `ω₁² = k / λ_max(M_ff)`; `k = ω₁² λ_max(M_ff)` puts it at
//! [`PanelFlex::first_mode_hz`], and the damping proportional to stiffness,
//! `c = 2 ζ k / ω₁`, gives that mode the ratio [`PanelFlex::damping_ratio`].
//! The encoders read the hinges; the flex joints are read by nothing.

use deploywatch_core::Panel;

/// The first mode's damping ratio when the file does not give it \[1\]:
/// the middle of the 1–3 % that deployed solar-array wings show.
pub const DEFAULT_DAMPING_RATIO: f64 = 0.02;

/// Most panels of a flexible wing: its chain has two joints per panel, at
/// most [`crate::model::mechanism::MAX_CHAIN_JOINTS`] (checked in
/// [`crate::model::flex_chain`]).
pub const MAX_FLEXIBLE_PANELS: usize = 4;

/// Half-offset of the halves' centres as a share of the panel's radius of
/// gyration `√(I/m)` at most, so that each half keeps an inertia of its own.
const MAX_OFFSET_GYRATION: f64 = 0.7;

/// `[flexible_panels]`: every panel flexible, the deployed wing's first mode
/// at `first_mode_hz`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PanelFlex {
    /// The deployed wing's first mode, every hinge latched \[Hz\].
    pub first_mode_hz: f64,
    /// That mode's damping ratio ζ \[1\], `0 ≤ ζ < 1`.
    pub damping_ratio: f64,
}

/// The two halves of panel `p` (module doc): inner, outer.
pub fn halves(p: &Panel<f64>) -> [Panel<f64>; 2] {
    let half_l = 0.5 * p.length_m;
    let half_m = 0.5 * p.mass_kg;
    let d = (0.25 * p.length_m).min(MAX_OFFSET_GYRATION * (p.inertia_kgm2 / p.mass_kg).sqrt());
    let own = 0.5 * (p.inertia_kgm2 - p.mass_kg * d * d);
    [
        Panel {
            length_m: half_l,
            mass_kg: half_m,
            com_m: p.com_m - d,
            inertia_kgm2: own,
        },
        Panel {
            length_m: half_l,
            mass_kg: half_m,
            com_m: p.com_m + d - half_l,
            inertia_kgm2: own,
        },
    ]
}

/// Which joints of a flexible chain of `M` joints latch: the hinges (even
/// indices), not the flex joints.
pub fn latching<const M: usize>() -> [bool; M] {
    core::array::from_fn(|i| i % 2 == 0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_halves_together_are_the_panel() {
        for p in [
            Panel {
                length_m: 1.2,
                mass_kg: 3.0,
                com_m: 0.6,
                inertia_kgm2: 3.0 * 1.44 / 12.0,
            },
            // An inertia too small for L/4: the offset shrinks.
            Panel {
                length_m: 1.0,
                mass_kg: 2.0,
                com_m: 0.45,
                inertia_kgm2: 0.01,
            },
        ] {
            let [a, b] = halves(&p);
            let xa = a.com_m;
            let xb = a.length_m + b.com_m;
            let m = a.mass_kg + b.mass_kg;
            let com = (a.mass_kg * xa + b.mass_kg * xb) / m;
            let about_com = a.inertia_kgm2
                + b.inertia_kgm2
                + a.mass_kg * (xa - com).powi(2)
                + b.mass_kg * (xb - com).powi(2);
            assert!((m - p.mass_kg).abs() < 1e-12);
            assert!((com - p.com_m).abs() < 1e-12, "{com} vs {}", p.com_m);
            assert!((about_com - p.inertia_kgm2).abs() < 1e-12);
            assert!(a.inertia_kgm2 > 0.0 && b.inertia_kgm2 > 0.0);
            assert!((a.length_m + b.length_m - p.length_m).abs() < 1e-12);
        }
    }
}
