//! The friction law of a joint as the mechanism file writes it.

use deploywatch_core::Friction;

/// The friction law of a joint as written in the file (`friction = {...}`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionSpec {
    /// `coulomb_nm` [N·m], default 0.
    pub coulomb_nm: f64,
    /// `viscous_nms` [N·m·s/rad], default 0.
    pub viscous_nms: f64,
    /// `coulomb_threshold_rad_s` [rad/s], default 0.01.
    pub coulomb_threshold_rad_s: f64,
    /// `breakaway_nm` and `stribeck_rad_s`, both or neither.
    pub stribeck: Option<(f64, f64)>,
}

impl Default for FrictionSpec {
    fn default() -> Self {
        FrictionSpec {
            coulomb_nm: 0.0,
            viscous_nms: 0.0,
            coulomb_threshold_rad_s: deploywatch_core::physics::COULOMB_THRESHOLD_RAD_S,
            stribeck: None,
        }
    }
}

impl FrictionSpec {
    /// The core friction law.
    pub fn to_friction(self) -> Friction<f64> {
        let (breakaway_nm, stribeck_rad_s) = self.stribeck.unwrap_or((self.coulomb_nm, 1.0));
        Friction {
            coulomb_nm: self.coulomb_nm,
            breakaway_nm,
            viscous_nms: self.viscous_nms,
            stribeck_rad_s,
            coulomb_threshold_rad_s: self.coulomb_threshold_rad_s,
        }
    }
}
