//! Reading the `kind = "curve"` spring of a joint (`docs/spec/formats.md`):
//! its unfolding and folding branches as points `[deg, N·m]`, the angle
//! `|φ|` from the deployed pose, checked by the core's [`Curve`].

use deploywatch_core::{Curve, Interp};

use crate::model::mechanism::SpringSpec;
use crate::model::mechanism_error::MechanismErrorKind;
use crate::model::toml_tree::{Cx, Node, Res, Sp, Table};

impl Cx<'_> {
    /// `kind = "curve"`: `unfold`, optional `fold` and `interp`, `count`.
    pub(super) fn curve_spring(&self, t: &Table<'_>) -> Res<SpringSpec> {
        let interp = match t.get("interp") {
            None => Interp::Akima,
            Some(i) => match self.string(i, &t.key("interp"))? {
                "akima" => Interp::Akima,
                "linear" => Interp::Linear,
                _ => return Err(self.invalid(i, &t.key("interp"), "\"akima\" or \"linear\"")),
            },
        };
        let unfold = match t.get("unfold") {
            Some(u) => self.curve(u, &t.key("unfold"), interp)?,
            None => return Err(self.missing(t, "unfold", "an array of [deg, N·m] points")),
        };
        let fold = t
            .get("fold")
            .map(|f| self.curve(f, &t.key("fold"), interp))
            .transpose()?;
        Ok(SpringSpec::Curve {
            unfold,
            fold,
            interp,
            count: self.count(t)?,
        })
    }

    /// `[[deg, N·m], ...]`, checked by the core.
    fn curve(&self, sp: &Sp, key: &str, interp: Interp) -> Res<Vec<(f64, f64)>> {
        let Node::Array(items) = &sp.node else {
            return Err(self.wrong_type(sp, key, "an array of [deg, N·m] points"));
        };
        let mut points = Vec::with_capacity(items.len());
        for (i, p) in items.iter().enumerate() {
            let item = format!("{key}[{}]", i + 1);
            let point = self.pair(p, &item, "[deg, N·m]")?;
            if !(point.0 >= 0.0) {
                let why = "[deg, N·m] with an angle ≥ 0: the angle from the deployed pose, |φ| \
                           (physics.md 3; 0 at the latch, |stowed_deg| stowed), not the joint's \
                           signed angle";
                return Err(self.invalid(p, &item, why));
            }
            if !(point.1 >= 0.0) {
                let why = "[deg, N·m] with a torque ≥ 0 (physics.md 3: a hinge spring drives its joint towards 0°)";
                return Err(self.invalid(p, &item, why));
            }
            points.push(point);
        }
        Curve::new(&points, interp).map_err(|source| {
            self.err(
                self.line(sp),
                MechanismErrorKind::BadCurve {
                    key: key.to_string(),
                    source,
                },
            )
        })?;
        Ok(points)
    }
}
