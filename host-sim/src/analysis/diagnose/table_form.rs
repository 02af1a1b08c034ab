//! The form of a torque table a diagnosis may fit at one joint.

use crate::analysis::diagnose::residual_shape::Shape;
use crate::model::effect::{Effect, Law};
use crate::model::torque_table::{HostTable, HostTorqueTable, HOST_TABLE_MAX_KNOTS as MAX_KNOTS};
/// The form of a candidate table at one joint: which tables, over which
/// span. Integers so that candidates stay comparable and hashable.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TableForm {
    /// Knots of `f(φ)` (0: no angle table).
    pub angle_knots: u8,
    /// The stroke end farthest from the latch \[deg\]; the knots are spread
    /// from it to 0 (the latch).
    pub from_deg: i32,
    /// Free knots of `g(φ̇)` (0: no rate table).
    pub rate_knots: u8,
    /// The largest rate the runs reach at this joint, with the sign of the
    /// deployment [deg/s]; the knots are spread from 0 to it.
    pub rate_max_deg_s: i32,
    /// Knots placed where the residual torque bends
    /// ([`crate::analysis::diagnose::residual_shape`]); `None`: the even knots above.
    pub placed: Option<PlacedKnots>,
}

/// Knots placed from the data, in hundredths so that forms stay comparable
/// and hashable. `angle_knots` of [`TableForm`] counts the angle knots,
/// `rate_knots` the rate knots beside the one at 0 (held at 0 N·m).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PlacedKnots {
    /// Angle knots [0.01 deg], increasing.
    pub angle_cdeg: [i32; MAX_KNOTS],
    /// Rate knots [0.01 deg/s], increasing, 0 among them.
    pub rate_cdeg_s: [i32; MAX_KNOTS],
}

/// Hundredths of `x`, as stored in [`PlacedKnots`].
fn hundredths(x: f64) -> i32 {
    (x * 100.0).round() as i32
}

impl PlacedKnots {
    /// The form of a shape fitted to a residual torque: its knots, with the
    /// stroke and rate span of the even form for the words. `None` when it
    /// has more knots than a table holds.
    pub fn form(shape: &Shape, from_deg: i32, rate_max_deg_s: i32) -> Option<TableForm> {
        let (na, nr) = (shape.angle_deg.len(), shape.rate_deg_s.len());
        if na > MAX_KNOTS || nr > MAX_KNOTS || na == 1 || nr == 1 {
            return None;
        }
        let mut k = PlacedKnots {
            angle_cdeg: [0; MAX_KNOTS],
            rate_cdeg_s: [0; MAX_KNOTS],
        };
        for (d, x) in k.angle_cdeg.iter_mut().zip(&shape.angle_deg) {
            *d = hundredths(*x);
        }
        for (d, x) in k.rate_cdeg_s.iter_mut().zip(&shape.rate_deg_s) {
            *d = hundredths(*x);
        }
        Some(TableForm {
            angle_knots: na as u8,
            from_deg,
            rate_knots: nr.saturating_sub(1) as u8,
            rate_max_deg_s,
            placed: Some(k),
        })
    }

    /// The start values of such a form: the shape's knot torques (angle
    /// knots, then the rate knots without the one at 0).
    pub fn start(shape: &Shape) -> Vec<f64> {
        let mut p = shape.angle_nm.clone();
        p.extend(
            shape
                .rate_deg_s
                .iter()
                .zip(&shape.rate_nm)
                .filter(|(x, _)| **x != 0.0)
                .map(|(_, y)| *y),
        );
        p
    }
}

impl TableForm {
    /// Knots of a discovered angle table `f(φ)`, spread evenly over the stroke
    /// (five: one every 45° of a 180° stroke, fine enough for a bump a quarter
    /// of the stroke wide, coarse enough not to follow the noise).
    pub const ANGLE_KNOTS: u8 = 5;
    /// Free knots of a discovered rate table `g(φ̇)` (beside `g(0) = 0`).
    pub const RATE_KNOTS: u8 = 2;
    /// Smallest rate span of a rate table [deg/s]: its first knot then sits
    /// at 30 deg/s or more, so that `g` never becomes a stiff damper.
    pub const MIN_RATE_SPAN_DEG_S: f64 = 60.0;
    /// Bound on a discovered knot's torque [N·m]: beyond any hinge spring of the
    /// seed mechanisms, so never active on a real torque.
    pub const BOUND_NM: f64 = crate::model::effect::TABLE_BOUND_NM;

    /// Number of parameters (knot torques).
    pub fn params(&self) -> usize {
        usize::from(self.angle_knots) + usize::from(self.rate_knots)
    }

    /// `"angle"`, `"rate"` or `"angle+rate"`.
    pub fn name(&self) -> &'static str {
        match (self.angle_knots > 0, self.rate_knots > 0) {
            (true, true) => "angle+rate",
            (true, false) => "angle",
            _ => "rate",
        }
    }

    /// The angle knots \[deg\], increasing.
    pub fn angle_xs(&self) -> Vec<f64> {
        let k = usize::from(self.angle_knots);
        if let Some(p) = &self.placed {
            return p
                .angle_cdeg
                .iter()
                .take(k)
                .map(|&c| f64::from(c) / 100.0)
                .collect();
        }
        let from = f64::from(self.from_deg);
        let mut xs: Vec<f64> = (0..k)
            .map(|i| from * (1.0 - i as f64 / (k - 1).max(1) as f64))
            .collect();
        xs.sort_by(f64::total_cmp);
        xs
    }

    /// The rate knots [deg/s], increasing, with `0` among them.
    pub fn rate_xs(&self) -> Vec<f64> {
        let k = usize::from(self.rate_knots);
        if let Some(p) = &self.placed {
            return p
                .rate_cdeg_s
                .iter()
                .take(k + 1)
                .map(|&c| f64::from(c) / 100.0)
                .collect();
        }
        let r = f64::from(self.rate_max_deg_s);
        let mut xs: Vec<f64> = (0..=k).map(|i| r * i as f64 / k.max(1) as f64).collect();
        xs.sort_by(f64::total_cmp);
        xs
    }

    /// The torque table with knot torques `p` (angle knots, then the free
    /// rate knots from the rate 0 outwards; placed knots: both in
    /// increasing order).
    pub fn table(&self, p: &[f64]) -> HostTorqueTable {
        if self.placed.is_some() {
            return self.placed_table(p);
        }
        let na = usize::from(self.angle_knots);
        let angle = (na >= 2)
            .then(|| {
                let xs = self.angle_xs();
                let mut ys = p[..na].to_vec();
                if self.from_deg > 0 {
                    // Knots were given from the stroke end to 0: reverse to
                    // match increasing angles.
                    ys.reverse();
                }
                // `angle_xs` runs from `from_deg` to 0; for a negative
                // stroke that is already increasing and the torques match.
                HostTable::new(&xs, &ys).ok()
            })
            .flatten();
        let rate = (self.rate_knots > 0)
            .then(|| {
                let xs = self.rate_xs();
                let mut ys = vec![0.0];
                ys.extend_from_slice(&p[na..na + usize::from(self.rate_knots)]);
                if self.rate_max_deg_s < 0 {
                    ys.reverse();
                }
                HostTable::new(&xs, &ys).ok()
            })
            .flatten();
        HostTorqueTable { angle, rate }
    }

    /// [`TableForm::table`] of placed knots: the values in increasing order
    /// of their knots, the rate knot at 0 held at 0.
    fn placed_table(&self, p: &[f64]) -> HostTorqueTable {
        let na = usize::from(self.angle_knots);
        let angle = (na >= 2)
            .then(|| HostTable::new(&self.angle_xs(), p.get(..na)?).ok())
            .flatten();
        let rxs = self.rate_xs();
        let mut free = p.iter().skip(na);
        let rys: Vec<f64> = rxs
            .iter()
            .map(|&x| {
                if x == 0.0 {
                    0.0
                } else {
                    free.next().copied().unwrap_or(0.0)
                }
            })
            .collect();
        let rate = (self.rate_knots > 0)
            .then(|| HostTable::new(&rxs, &rys).ok())
            .flatten();
        HostTorqueTable { angle, rate }
    }

    /// The effect at `joint` with knot torques `p`.
    pub fn effect(&self, joint: Option<usize>, p: &[f64]) -> Effect {
        let table = self.table(p);
        Effect {
            joint,
            law: Law::TorqueTable(table),
        }
    }
}
