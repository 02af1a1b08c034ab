//! A wing's planar multibody [`System`]: the open chain of `physics.md` §1,
//! or the chain with its truss (`docs/spec/truss-link.md`). Everything is
//! given at the stowed pose in the project frame (origin at hinge O,
//! `physics.md` §1). Bodies: 0 the bus, 1..=n the panels, then one body per
//! link. Pins:
//! - hinge `j` between panel `j−1` and panel `j`: angle `φ_j = stowed +`
//!   relative rotation, the mechanism's spring and friction, locks at 0;
//! - a link end on the bus or a panel: angle of the link (from its far end
//!   to the pin) relative to the carrier, stowed value from the geometry;
//! - a knee (a node of exactly two links): interior angle, locks at 180°;
//! - any other node joins its links to its reference link (three pins for
//!   the four links at F), angle = relative rotation.

use crate::model::mechanism::Mechanism;
use crate::model::truss::{angle, carrier_body, err, m, sub, Truss, TrussError, TrussPoint};
use crate::simulate::multibody::system::{Body, Pin, System};
use deploywatch_core::Spring;
use std::f64::consts::PI;

/// The open chain of `physics.md` §1 as a multibody [`System`] (hinges
/// only, no links): the same springs, friction and latches as the chain
/// simulator, to show that both simulators carry one physics.
pub fn open_chain_system(mech: &Mechanism) -> Result<System, TrussError> {
    let mut hinges_mm = vec![[0.0, 0.0]];
    let mut dir = 0.0;
    for (p, j) in mech
        .panels
        .iter()
        .zip(&mech.joints)
        .take(mech.panels.len() - 1)
    {
        dir += j.stowed_deg.to_radians();
        let h = hinges_mm[hinges_mm.len() - 1];
        hinges_mm.push([
            h[0] + 1e3 * p.length_m * dir.cos(),
            h[1] + 1e3 * p.length_m * dir.sin(),
        ]);
    }
    let open = Truss {
        hinges_mm,
        points: Vec::new(),
        links: Vec::new(),
    };
    wing_system(&open, mech)
}

/// The multibody system of the wing with its truss (checked first).
pub fn wing_system(truss: &Truss, mech: &Mechanism) -> Result<System, TrussError> {
    let np = mech.panels.len();
    truss.check(np)?;
    let mut sys = System::default();
    sys.bodies.push(Body {
        name: "bus".into(),
        mass_kg: 0.0,
        inertia_kgm2: 0.0,
        com_m: [0.0; 2],
    });
    add_panels(truss, mech, &mut sys);
    for l in &truss.links {
        let a = m(truss
            .point(&l.ends[0])
            .map(|p| p.1.at_mm)
            .unwrap_or_default());
        let b = m(truss
            .point(&l.ends[1])
            .map(|p| p.1.at_mm)
            .unwrap_or_default());
        let len = l.length_mm * 1e-3;
        sys.bodies.push(Body {
            name: format!("link {}", l.name),
            mass_kg: l.mass_kg,
            inertia_kgm2: l.mass_kg * len * len / 12.0,
            com_m: [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])],
        });
    }
    for p in &truss.points {
        add_point_pins(truss, p, np, &mut sys)?;
    }
    Ok(sys)
}

/// Panels and their hinges (`truss-link.md`: centre of mass on the
/// hinge line of the inner panel, the others turned by their stowed
/// angles).
fn add_panels(truss: &Truss, mech: &Mechanism, sys: &mut System) {
    let np = mech.panels.len();
    let first = if np > 1 {
        angle(sub(truss.hinges_mm[1], truss.hinges_mm[0]))
    } else {
        mech.joints[0].stowed_deg.to_radians()
    };
    let mut dir = first;
    for (i, (panel, joint)) in mech.panels.iter().zip(&mech.joints).enumerate() {
        if i > 0 {
            dir += joint.stowed_deg.to_radians();
        }
        let h = m(truss.hinges_mm[i]);
        sys.bodies.push(Body {
            name: format!("panel {}", i + 1),
            mass_kg: panel.mass_kg,
            inertia_kgm2: panel.inertia_kgm2,
            com_m: [
                h[0] + panel.com_m * dir.cos(),
                h[1] + panel.com_m * dir.sin(),
            ],
        });
        let mut pin = Pin::plain(&format!("hinge {}", i + 1), i, i + 1, h);
        pin.offset_rad = joint.stowed_deg.to_radians();
        pin.spring = joint.spring.to_spring().unwrap_or(Spring::None);
        pin.friction = joint.friction.to_friction();
        pin.lock_at_rad = Some(0.0);
        sys.pins.push(pin);
    }
}

/// The pins at one point.
fn add_point_pins(
    truss: &Truss,
    p: &TrussPoint,
    np: usize,
    sys: &mut System,
) -> Result<(), TrussError> {
    let links = truss.links_at(&p.name);
    let body_of = |l: usize| np + 1 + l;
    let far = |l: usize| {
        let e = &truss.links[l].ends;
        let other = if e[0] == p.name { &e[1] } else { &e[0] };
        m(truss.point(other).map(|q| q.1.at_mm).unwrap_or_default())
    };
    let at = m(p.at_mm);
    if let Some(c) = carrier_body(&p.on) {
        for &l in &links {
            let mut pin = Pin::plain(
                &format!("{}:{}", p.name, truss.links[l].name),
                c,
                body_of(l),
                at,
            );
            pin.offset_rad = angle(sub(at, far(l)));
            pin.friction = p.friction.to_friction();
            sys.pins.push(pin);
        }
        return Ok(());
    }
    let reference = match &p.reference_link {
        Some(name) => links
            .iter()
            .copied()
            .find(|&l| &truss.links[l].name == name)
            .ok_or_else(|| {
                err(
                    format!("truss.point \"{}\".reference_link", p.name),
                    format!(
                        "link \"{name}\" does not end at \"{}\"; expected one of its links",
                        p.name
                    ),
                )
            })?,
        None => links[0],
    };
    for &l in links.iter().filter(|&&l| l != reference) {
        let (a, b) = (body_of(reference), body_of(l));
        let mut pin = Pin::plain(
            &format!(
                "{}:{}-{}",
                p.name, truss.links[reference].name, truss.links[l].name
            ),
            a,
            b,
            at,
        );
        pin.friction = p.friction.to_friction();
        if p.knee {
            pin.name = p.name.clone();
            let (u1, u2) = (sub(far(reference), at), sub(far(l), at));
            let s0 = (u1[0] * u2[1] - u1[1] * u2[0]).atan2(u1[0] * u2[0] + u1[1] * u2[1]);
            pin.sign = if s0 >= 0.0 { 1.0 } else { -1.0 };
            pin.offset_rad = s0.abs();
            pin.lock_at_rad = Some(PI);
        }
        sys.pins.push(pin);
    }
    Ok(())
}
