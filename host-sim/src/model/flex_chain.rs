//! The chain of a wing with flexible panels (`physics.md` §12,
//! [`crate::model::flex`]): `2N` joints, hinge `j` at joint `2j` (0-based),
//! the flex joint of panel `j` at `2j + 1`, the flex joints' stiffness and
//! damping set by the deployed wing's first mode.

use crate::model::flex::{halves, PanelFlex, MAX_FLEXIBLE_PANELS};
use crate::model::mechanism::{Mechanism, MAX_CHAIN_JOINTS};
use crate::model::torque_table::{HostChain, HostJointEffects};
use deploywatch_core::{Chain, Friction, GlobalEffects, Joint, Spring};

// A flexible wing's chain has two joints per panel.
const _: () = assert!(2 * MAX_FLEXIBLE_PANELS == MAX_CHAIN_JOINTS);

/// The flex joints' stiffness `k` [N·m/rad] and damping `c` [N·m·s/rad]
/// of `flex` on `mech`'s panels (`physics.md` §12); `None` when the chain
/// cannot be built or its `M_ff` is not positive.
fn stiffness_damping<const M: usize>(flex: &PanelFlex, mech: &Mechanism) -> Option<(f64, f64)> {
    let probe = flexible::<M>(mech, &[], GlobalEffects::default(), 1.0, 0.0)?;
    let full = probe.mass_matrix(&[0.0; M]);
    let n = M / 2;
    let mff = nalgebra::DMatrix::from_fn(n, n, |r, c| full[2 * r + 1][2 * c + 1]);
    let lambda_max = mff.symmetric_eigenvalues().max();
    let w1 = 2.0 * core::f64::consts::PI * flex.first_mode_hz;
    let k = w1 * w1 * lambda_max;
    (k.is_finite() && k > 0.0).then(|| (k, 2.0 * flex.damping_ratio * k / w1))
}

impl Mechanism {
    /// True when this wing can be simulated with flexible panels: an open
    /// chain of at most [`MAX_FLEXIBLE_PANELS`] panels with ideal latches,
    /// no truss and no enabled rig (what `[flexible_panels]` is refused
    /// without).
    pub fn can_be_flexible(&self) -> bool {
        !self.has_physical_latch()
            && self.truss.is_none()
            && self.active_rig().is_none()
            && self.joint_count() <= MAX_FLEXIBLE_PANELS
    }

    /// `Err` with why, when this mechanism has `[flexible_panels]` and
    /// cannot be simulated with them ([`Mechanism::can_be_flexible`]).
    pub fn check_flexible(&self) -> Result<(), String> {
        if self.flexible.is_none() || self.can_be_flexible() {
            return Ok(());
        }
        Err(format!(
            "mechanism `{}`: flexible panels are simulated on an open chain of at most \
             {MAX_FLEXIBLE_PANELS} panels with ideal latches only (no physical latch, truss \
             or enabled rig)",
            self.name
        ))
    }

    /// The core chain of this mechanism with flexible panels: `M = 2N`
    /// joints (module doc), `effects` given per hinge (`N` of them) and
    /// `global` on every half. `None` when the mechanism has no
    /// `[flexible_panels]`, `M` is not twice its joint count, or the chain
    /// cannot be built.
    pub fn flexible_chain<const M: usize>(
        &self,
        effects: &[HostJointEffects],
        global: GlobalEffects<f64>,
    ) -> Option<HostChain<M>> {
        let flex = self.flexible?;
        if M != 2 * self.joint_count() || effects.len() != self.joint_count() {
            return None;
        }
        let (k, c) = stiffness_damping::<M>(&flex, self)?;
        flexible::<M>(self, effects, global, k, c)
    }
}

/// The flexible chain of `mech` with flex stiffness `k` and damping `c`;
/// `effects` per hinge (an empty list: none).
fn flexible<const M: usize>(
    mech: &Mechanism,
    effects: &[HostJointEffects],
    global: GlobalEffects<f64>,
    k: f64,
    c: f64,
) -> Option<HostChain<M>> {
    if M != 2 * mech.joint_count() || mech.panels.len() * 2 != M {
        return None;
    }
    let mut panels = [mech.panels[0]; M];
    for (i, p) in mech.panels.iter().enumerate() {
        let [inner, outer] = halves(p);
        panels[2 * i] = inner;
        panels[2 * i + 1] = outer;
    }
    let flex_joint = Joint {
        stowed_rad: 0.0,
        spring: Spring::Linear {
            preload_nm: 0.0,
            stiffness_nm_per_rad: k,
            count: 1.0,
        },
        friction: Friction {
            viscous_nms: c,
            ..Friction::coulomb(0.0)
        },
        effects: HostJointEffects::default(),
    };
    let mut joints = [flex_joint; M];
    for (i, j) in mech.joints.iter().enumerate() {
        joints[2 * i] = Joint {
            stowed_rad: j.stowed_deg.to_radians(),
            spring: j.spring.to_spring().ok()?,
            friction: j.friction.to_friction(),
            effects: effects.get(i).copied().unwrap_or_default(),
        };
    }
    Chain::new(panels, joints, global).ok()
}
