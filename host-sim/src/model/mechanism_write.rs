//! A mechanism written back as TOML (`docs/spec/formats.md`): what
//! `Mechanism::from_toml_str` reads back as the same mechanism.

use crate::model::mechanism::{FrictionSpec, MassTolerance, Mechanism, SpringSpec};
use crate::model::mechanism_error::{MechanismError, MechanismErrorKind};
pub use crate::model::toml_tree::{num, toml_str};
use deploywatch_core::{Interp, Panel, TapePoints};
use std::fmt::Write as _;
use std::path::Path;

/// A `[[panel]]` table, its declared tolerances when there are some.
fn panel_toml(out: &mut String, p: &Panel<f64>, tol: MassTolerance) {
    let _ = write!(
        out,
        "\n[[panel]]\nlength_m = {}\nmass_kg = {}\ncom_m = {}\ninertia_kgm2 = {}\n",
        num(p.length_m),
        num(p.mass_kg),
        num(p.com_m),
        num(p.inertia_kgm2)
    );
    for (v, key) in [
        (tol.mass_pct, "mass_tolerance_pct"),
        (tol.inertia_pct, "inertia_tolerance_pct"),
    ] {
        if v > 0.0 {
            let _ = writeln!(out, "{key} = {}", num(v));
        }
    }
}

impl Mechanism {
    /// Writes the mechanism as TOML, in the layout of `formats.md`.
    ///
    /// Deterministic byte for byte; numbers are written in Rust's shortest
    /// round-trip form, so [`Mechanism::from_toml_str`] of the output equals
    /// `self` (for a mechanism that passes validation). Tape types are written
    /// once each, in order of first use; should two joints use the same type
    /// name with different points, the later ones are renamed `"NAME (2)"`,
    /// `"NAME (3)"`, ... so that the file stays unambiguous.
    pub fn to_toml_string(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(out, "name = {}", toml_str(&self.name));
        let _ = writeln!(out, "description = {}", toml_str(&self.description));
        for (i, p) in self.panels.iter().enumerate() {
            panel_toml(&mut out, p, self.mass_tolerance(i));
        }
        let mut tapes: Vec<(String, TapePoints<f64>)> = Vec::new();
        for (i, j) in self.joints.iter().enumerate() {
            let _ = write!(
                out,
                "\n[[joint]]\nstowed_deg = {}\nspring = {}\n",
                num(j.stowed_deg),
                spring_toml(&j.spring, &mut tapes)
            );
            if j.free_play_deg > 0.0 {
                let _ = writeln!(out, "free_play_deg = {}", num(j.free_play_deg));
            }
            if j.spring_tolerance_pct > 0.0 {
                let _ = writeln!(
                    out,
                    "spring_tolerance_pct = {}",
                    num(j.spring_tolerance_pct)
                );
            }
            if j.friction != FrictionSpec::default() {
                let f = &j.friction;
                let mut s = format!(
                    "friction = {{ coulomb_nm = {}, viscous_nms = {}, coulomb_threshold_rad_s = {}",
                    num(f.coulomb_nm),
                    num(f.viscous_nms),
                    num(f.coulomb_threshold_rad_s)
                );
                if let Some((brk, st)) = f.stribeck {
                    let _ = write!(
                        s,
                        ", breakaway_nm = {}, stribeck_rad_s = {}",
                        num(brk),
                        num(st)
                    );
                }
                let _ = writeln!(out, "{s} }}");
            }
            if let Some(l) = self.latch(i) {
                out.push_str(&crate::model::latch_toml::write(l));
            }
        }
        for (name, p) in &tapes {
            let _ = write!(
                out,
                "\n[tape.{}]\na = [{}, {}]\nb = [{}, {}]\nd = [{}, {}]\nm_90 = {}\nc_180 = {}\n",
                toml_str(name),
                num(p.a.0),
                num(p.a.1),
                num(p.b.0),
                num(p.b.1),
                num(p.d.0),
                num(p.d.1),
                num(p.m_90),
                num(p.c_180)
            );
        }
        let _ = write!(
            out,
            "\n[run]\nduration_s = {}\nsample_hz = {}\nsettle_s = {}\n",
            num(self.duration_s),
            num(self.sample_hz),
            num(self.settle_s)
        );
        if let Some(t) = &self.truss {
            crate::model::truss_toml::write(t, &mut out);
        }
        if let Some(r) = &self.rig {
            crate::model::rig_toml::write(r, &mut out);
        }
        if let Some(f) = &self.flexible {
            crate::model::flex_toml::write(f, &mut out);
        }
        out
    }

    /// Writes [`Mechanism::to_toml_string`] to `path`.
    pub fn write(&self, path: &Path) -> Result<(), MechanismError> {
        std::fs::write(path, self.to_toml_string()).map_err(|source| MechanismError {
            file: path.display().to_string(),
            line: None,
            kind: MechanismErrorKind::Write { source },
        })
    }
}

fn points_toml(points: &[(f64, f64)]) -> String {
    let inner: Vec<String> = points
        .iter()
        .map(|(x, y)| format!("[{}, {}]", num(*x), num(*y)))
        .collect();
    format!("[{}]", inner.join(", "))
}

fn spring_toml(s: &SpringSpec, tapes: &mut Vec<(String, TapePoints<f64>)>) -> String {
    match s {
        SpringSpec::Linear {
            preload_nm,
            stiffness_nm_per_rad,
            count,
        } => format!(
            "{{ kind = \"linear\", preload_nm = {}, stiffness_nm_per_rad = {}, count = {count} }}",
            num(*preload_nm),
            num(*stiffness_nm_per_rad)
        ),
        SpringSpec::Tape {
            type_name,
            points,
            count,
        } => {
            let mut name = type_name.clone();
            let mut k = 1;
            loop {
                match tapes.iter().find(|(n, _)| *n == name) {
                    Some((_, p)) if p == points => break,
                    Some(_) => {
                        k += 1;
                        name = format!("{type_name} ({k})");
                    }
                    None => {
                        tapes.push((name.clone(), *points));
                        break;
                    }
                }
            }
            format!(
                "{{ kind = \"tape\", type = {}, count = {count} }}",
                toml_str(&name)
            )
        }
        SpringSpec::Curve {
            unfold,
            fold,
            interp,
            count,
        } => {
            let mut s = format!("{{ kind = \"curve\", unfold = {}", points_toml(unfold));
            if let Some(f) = fold {
                let _ = write!(s, ", fold = {}", points_toml(f));
            }
            let interp = match interp {
                Interp::Akima => "akima",
                Interp::Linear => "linear",
            };
            let _ = write!(s, ", interp = \"{interp}\", count = {count} }}");
            s
        }
    }
}

// ---------------------------------------------------------------------------
// A TOML tree with the byte spans of its values, from `toml_edit`'s parsed
// document (`ImDocument` keeps the spans; the `toml` crate's deserializer
// reads the same tree, so lines and messages agree with it). Values the
// parser has no span for (the implicit `tape` table of `[tape."TS-1"]`, a
// dotted key's table) are kept without one.
