//! Reading and writing mechanism TOML files (`docs/spec/formats.md`,
//! "Mechanism: TOML").
//!
//! [`Mechanism::load`] and [`Mechanism::from_toml_str`] parse the file and
//! validate every key; anything the format does not define is rejected with
//! a [`MechanismError`] that names the file, the line (when the TOML parser
//! knows it), the key path and what was expected.
//!
//! Key paths count `[[panel]]` and `[[joint]]` tables from 1, as joints are
//! numbered everywhere else (`phi1_deg` is joint 1): `joint[2].spring.kind` is
//! the `kind` of the spring of the second `[[joint]]` table.
//!
//! Defaults, where the format leaves a key optional:
//! - `description`: empty;
//! - `friction`: all zero with `coulomb_threshold_rad_s = 0.01`
//!   ([`FrictionSpec::default`]);
//! - `interp` of a curve spring: `"akima"`;
//! - `[run] duration_s`: [`DEFAULT_DURATION_S`] (6 s), `[run] sample_hz`:
//!   [`DEFAULT_SAMPLE_HZ`] (100 Hz) and `[run] settle_s`: [`DEFAULT_SETTLE_S`]
//!   (0.2 s), each on its own, whether `[run]` is absent or only lacks that
//!   key;
//! - `free_play_deg` of a joint: 0 (no free-play declared);
//! - `mass_tolerance_pct` and `inertia_tolerance_pct` of a panel, and
//!   `spring_tolerance_pct` of a joint: 0 (no tolerance declared).
//!
//! Beyond the types, values must describe a mechanism: `com_m` within the
//! panel (0 to `length_m`), `0 < |stowed_deg| ≤ 360`, `0 ≤ free_play_deg ≤ 5`, tolerances of 0 to 20 %, friction values as
//! the matching effects allow them ([`EffectKind::allowed`]).
//!
//! `count` is required (a silently defaulted hinge count would change the
//! spring torque by a factor), and must be a TOML integer ≥ 1.
//!
//! [`Mechanism::to_toml_string`] writes a mechanism back, deterministically,
//! with every number in Rust's shortest round-trip form, so that reading the
//! output gives back an equal [`Mechanism`].

use std::path::Path;

use deploywatch_core::{Panel, Spring, TapePoints};

use crate::model::effect::EffectKind;
use crate::model::mechanism::{
    FrictionSpec, JointSpec, MassTolerance, Mechanism, SpringSpec, MAX_CHAIN_JOINTS,
};
pub use crate::model::mechanism_error::{MechanismError, MechanismErrorKind};
use crate::model::toml_tree::{join, num, Bound, Cx, Node, Res, Sp, Table};

/// `[run] duration_s` when the file does not give it (s).
pub const DEFAULT_DURATION_S: f64 = 6.0;

/// `[run] sample_hz` when the file does not give it (Hz).
pub const DEFAULT_SAMPLE_HZ: f64 = 100.0;

/// `[run] settle_s` when the file does not give it (s): a rig keeps
/// recording after the wing has latched, and the on-board monitor confirms a
/// latch on 2 of 3 switch samples, so a run needs a few samples past the last
/// latch (`formats.md`, "Run: CSV").
pub const DEFAULT_SETTLE_S: f64 = 0.2;

/// Largest `free_play_deg` (deg): a hinge with more play than this is not
/// a hinge the reduced-order model of `physics.md` describes.
const MAX_FREE_PLAY_DEG: f64 = 5.0;

/// Largest `mass_tolerance_pct`, `inertia_tolerance_pct` and
/// `spring_tolerance_pct` (%): a panel or spring known no better than this
/// is not one the drawing describes.
const MAX_TOLERANCE_PCT: f64 = 20.0;

/// Largest `|stowed_deg|` (deg): one turn. A hinge folded further than a
/// full turn is a typing error (radians for degrees, an extra digit).
pub const MAX_STOWED_DEG: f64 = 360.0;

/// Highest accepted `[run] sample_hz` (Hz): run CSV files write `t_s` with 6
/// decimals (see [`crate::data::run::Run::to_csv_string`]), so samples closer than
/// 1 µs could not be told apart.
pub const MAX_SAMPLE_HZ: f64 = 1.0e6;

impl Mechanism {
    /// Reads and validates a mechanism TOML file.
    pub fn load(path: &Path) -> Result<Mechanism, MechanismError> {
        let file = path.display().to_string();
        let bytes = std::fs::read(path).map_err(|source| MechanismError {
            file: file.clone(),
            line: None,
            kind: MechanismErrorKind::Io { source },
        })?;
        let text = crate::model::file_kind::utf8_text(bytes).map_err(|found| MechanismError {
            file: file.clone(),
            line: (found.encoding != crate::model::file_kind::Encoding::Binary)
                .then_some(found.line),
            kind: MechanismErrorKind::NotUtf8 { found },
        })?;
        Mechanism::from_toml_str(&text, &path.display().to_string())
    }

    /// Parses and validates mechanism TOML text; `source` names it in errors
    /// (usually the file's path).
    pub fn from_toml_str(text: &str, source: &str) -> Result<Mechanism, MechanismError> {
        let cx = Cx { file: source, text };
        cx.mechanism(&cx.parse()?)
    }
}

// ---------------------------------------------------------------------------
// Validation.

/// The top-level keys. A table read by its own module
/// ([`crate::model::toml_tree`]: `[truss]` by [`crate::model::truss_toml`])
/// is listed here and dispatched at the end of `mechanism`.
const TOP_KEYS: &[&str] = &[
    "name",
    "description",
    "panel",
    "joint",
    "tape",
    "run",
    "truss",
    "rig",
    "flexible_panels",
];
const PANEL_KEYS: &[&str] = &[
    "length_m",
    "mass_kg",
    "com_m",
    "inertia_kgm2",
    "mass_tolerance_pct",
    "inertia_tolerance_pct",
];
const JOINT_KEYS: &[&str] = &[
    "stowed_deg",
    "spring",
    "friction",
    "latch",
    "free_play_deg",
    "spring_tolerance_pct",
];
const LINEAR_KEYS: &[&str] = &["kind", "preload_nm", "stiffness_nm_per_rad", "count"];
const TAPE_SPRING_KEYS: &[&str] = &["kind", "type", "count"];
const CURVE_KEYS: &[&str] = &["kind", "unfold", "fold", "interp", "count"];
const FRICTION_KEYS: &[&str] = &[
    "coulomb_nm",
    "viscous_nms",
    "coulomb_threshold_rad_s",
    "breakaway_nm",
    "stribeck_rad_s",
];
const TAPE_KEYS: &[&str] = &["a", "b", "d", "m_90", "c_180"];
const RUN_KEYS: &[&str] = &["duration_s", "sample_hz", "settle_s"];

impl Cx<'_> {
    pub(super) fn count(&self, t: &Table<'_>) -> Res<u32> {
        let expected = "an integer ≥ 1 (number of identical hinges)";
        let Some(sp) = t.get("count") else {
            return Err(self.missing(t, "count", expected));
        };
        let key = t.key("count");
        match sp.node {
            Node::Int(i) if i >= 1 => u32::try_from(i)
                .map_err(|_| self.invalid(sp, &key, "an integer ≥ 1 that fits 32 bits")),
            Node::Int(_) => Err(self.invalid(sp, &key, expected)),
            _ => Err(self.wrong_type(sp, &key, expected)),
        }
    }

    fn mechanism(&self, root: &Sp) -> Res<Mechanism> {
        let top = self.table(root, "", TOP_KEYS)?;

        let name = match top.get("name") {
            Some(sp) => {
                let s = self.string(sp, "name")?;
                if s.trim().is_empty() {
                    return Err(self.invalid(sp, "name", "a non-empty string"));
                }
                s.to_string()
            }
            None => return Err(self.missing(&top, "name", "a string (runs refer to it)")),
        };
        let description = match top.get("description") {
            Some(sp) => self.string(sp, "description")?.to_string(),
            None => String::new(),
        };

        let tapes = match top.get("tape") {
            Some(sp) => self.tapes(sp)?,
            None => Vec::new(),
        };

        let panel_items = self.array_of_tables(&top, "panel")?;
        let mut panels = Vec::with_capacity(panel_items.len());
        let mut mass_tolerances = Vec::with_capacity(panel_items.len());
        for (i, sp) in panel_items.iter().enumerate() {
            let (panel, tolerance) = self.panel(sp, &format!("panel[{}]", i + 1))?;
            panels.push(panel);
            mass_tolerances.push(tolerance);
        }
        if panels.is_empty() || panels.len() > MAX_CHAIN_JOINTS {
            return Err(self.err(
                panel_items
                    .get(MAX_CHAIN_JOINTS)
                    .and_then(|sp| self.line(sp)),
                MechanismErrorKind::PanelCount {
                    found: panels.len(),
                },
            ));
        }

        let joint_items = self.array_of_tables(&top, "joint")?;
        let mut joints = Vec::with_capacity(joint_items.len());
        let mut latches = Vec::with_capacity(joint_items.len());
        for (i, sp) in joint_items.iter().enumerate() {
            joints.push(self.joint(sp, i + 1, &tapes)?);
            latches.push(self.latch(sp, i + 1, joints[i].stowed_deg)?);
        }
        if joints.len() != panels.len() {
            return Err(self.err(
                joint_items.get(panels.len()).and_then(|sp| self.line(sp)),
                MechanismErrorKind::JointCount {
                    panels: panels.len(),
                    joints: joints.len(),
                },
            ));
        }

        let (duration_s, sample_hz, settle_s) = match top.get("run") {
            Some(sp) => self.run_settings(sp)?,
            None => (DEFAULT_DURATION_S, DEFAULT_SAMPLE_HZ, DEFAULT_SETTLE_S),
        };

        let (truss, rig, flexible) = self.extensions(&top, &panels, &joints, &latches)?;
        Ok(Mechanism {
            name,
            description,
            panels,
            mass_tolerances,
            joints,
            duration_s,
            sample_hz,
            settle_s,
            truss,
            latches,
            rig,
            flexible,
        })
    }

    /// `[truss]`, `[rig]` and `[flexible_panels]` of a wing of `joints`:
    /// each further table is read by its own module, on the
    /// same tree. An enabled rig with a physical latch is refused
    /// (`formats.md`, "Rig": the rig is simulated with ideal latches only),
    /// never dropped silently.
    #[allow(clippy::type_complexity)]
    fn extensions(
        &self,
        top: &Table<'_>,
        panels: &[Panel<f64>],
        joints: &[JointSpec],
        latches: &[Option<crate::model::latch::LatchSpec>],
    ) -> Res<(
        Option<crate::model::truss::Truss>,
        Option<crate::model::rig::Rig>,
        Option<crate::model::flex::PanelFlex>,
    )> {
        let truss = top
            .get("truss")
            .map(|sp| crate::model::truss_toml::read(self, sp, panels.len()))
            .transpose()?;
        let stowed: Vec<f64> = joints.iter().map(|j| j.stowed_deg).collect();
        let rig = top
            .get("rig")
            .map(|sp| crate::model::rig_toml::read(self, sp, panels, &stowed))
            .transpose()?;
        let physical: Vec<usize> = (1..=latches.len())
            .filter(|&j| latches.get(j - 1).is_some_and(Option::is_some))
            .collect();
        if let (Some(sp), Some(true), false) = (
            top.get("rig"),
            rig.as_ref().map(|r| r.enabled),
            physical.is_empty(),
        ) {
            return Err(self.err(
                self.line(sp),
                MechanismErrorKind::RigWithPhysicalLatch { joints: physical },
            ));
        }
        let enabled_rig = rig.as_ref().is_some_and(|r| r.enabled);
        let flexible = top
            .get("flexible_panels")
            .map(|sp| {
                let truss = truss.is_some();
                crate::model::flex_toml::read(self, sp, panels.len(), latches, truss, enabled_rig)
            })
            .transpose()?;
        Ok((truss, rig, flexible))
    }

    /// `[run]`: `(duration_s, sample_hz, settle_s)`, each defaulted on its own.
    fn run_settings(&self, sp: &Sp) -> Res<(f64, f64, f64)> {
        let run = self.table(sp, "run", RUN_KEYS)?;
        let duration_s = self.opt_number(&run, "duration_s", Bound::Positive, "s")?;
        let settle_s = self.opt_number(&run, "settle_s", Bound::NonNegative, "s")?;
        let mut sample_hz = DEFAULT_SAMPLE_HZ;
        if let Some(sp) = run.get("sample_hz") {
            let key = run.key("sample_hz");
            sample_hz = self.number(sp, &key, Bound::Positive, "Hz")?;
            if sample_hz > MAX_SAMPLE_HZ {
                return Err(self.invalid(sp, &key, "a finite number > 0 and ≤ 1e6 [Hz]"));
            }
        }
        Ok((
            duration_s.unwrap_or(DEFAULT_DURATION_S),
            sample_hz,
            settle_s.unwrap_or(DEFAULT_SETTLE_S),
        ))
    }

    /// `[[key]]`: an array of tables (`key = [{...}, ...]` is the same in TOML).
    fn array_of_tables<'s>(&self, top: &Table<'s>, key: &str) -> Res<&'s [Sp]> {
        let expected = format!("1 to {MAX_CHAIN_JOINTS} [[{key}]] tables");
        let Some(sp) = top.get(key) else {
            return Err(self.missing(top, key, &expected));
        };
        match &sp.node {
            Node::Array(items) => Ok(items),
            _ => Err(self.wrong_type(sp, key, &expected)),
        }
    }

    /// The optional half band `key` of table `t` \[`unit`\]: 0 when absent,
    /// `expected` in the error when above `max`.
    fn half_band(
        &self,
        t: &Table,
        sp: &Sp,
        (key, unit): (&str, &str),
        max: f64,
        expected: &str,
    ) -> Res<f64> {
        let v = self
            .opt_number(t, key, Bound::NonNegative, unit)?
            .unwrap_or(0.0);
        if v > max {
            let sp = t.get(key).unwrap_or(sp);
            return Err(self.invalid(sp, &t.key(key), expected));
        }
        Ok(v)
    }

    /// A `[[panel]]` and its declared mass-property tolerance.
    fn panel(&self, sp: &Sp, path: &str) -> Res<(Panel<f64>, MassTolerance)> {
        let t = self.table(sp, path, PANEL_KEYS)?;
        let length_m = self.req_number(&t, "length_m", Bound::Positive, "m")?;
        let mass_kg = self.req_number(&t, "mass_kg", Bound::Positive, "kg")?;
        let com_m = self.req_number(&t, "com_m", Bound::Finite, "m")?;
        if !(0.0..=length_m).contains(&com_m) {
            let expected = format!(
                "a distance from the panel's hinge within the panel, 0 to length_m = {} [m]",
                num(length_m)
            );
            let sp = t.get("com_m").unwrap_or(sp);
            return Err(self.invalid(sp, &t.key("com_m"), &expected));
        }
        let panel = Panel {
            length_m,
            mass_kg,
            com_m,
            inertia_kgm2: self.req_number(&t, "inertia_kgm2", Bound::Positive, "kg·m²")?,
        };
        let expected = "a half band of 0 to 20 [%] of the drawn value";
        let tolerance = MassTolerance {
            mass_pct: self.half_band(
                &t,
                sp,
                ("mass_tolerance_pct", "%"),
                MAX_TOLERANCE_PCT,
                expected,
            )?,
            inertia_pct: self.half_band(
                &t,
                sp,
                ("inertia_tolerance_pct", "%"),
                MAX_TOLERANCE_PCT,
                expected,
            )?,
        };
        Ok((panel, tolerance))
    }

    fn joint(&self, sp: &Sp, j: usize, tapes: &[(String, TapePoints<f64>)]) -> Res<JointSpec> {
        let path = format!("joint[{j}]");
        let t = self.table(sp, &path, JOINT_KEYS)?;
        let stowed_deg = self.req_number(&t, "stowed_deg", Bound::NonZero, "deg")?;
        if stowed_deg.abs() > MAX_STOWED_DEG {
            let sp = t.get("stowed_deg").unwrap_or(sp);
            let expected = "a finite non-zero angle within ±360 [deg] (at most one turn)";
            return Err(self.invalid(sp, &t.key("stowed_deg"), expected));
        }
        let spring = match t.get("spring") {
            Some(s) => self.spring(s, &t.key("spring"), j, tapes)?,
            None => {
                return Err(self.missing(
                    &t,
                    "spring",
                    "a table { kind = \"linear\" | \"tape\" | \"curve\", ... }",
                ))
            }
        };
        let friction = match t.get("friction") {
            Some(f) => self.friction(f, &t.key("friction"))?,
            None => FrictionSpec::default(),
        };
        let free_play_deg = self.half_band(
            &t,
            sp,
            ("free_play_deg", "deg"),
            MAX_FREE_PLAY_DEG,
            "a half band of free-play of at most 5 [deg]",
        )?;
        let spring_tolerance_pct = self.half_band(
            &t,
            sp,
            ("spring_tolerance_pct", "%"),
            MAX_TOLERANCE_PCT,
            "a half band of 0 to 20 [%] of the drawn spring torque",
        )?;
        Ok(JointSpec {
            stowed_deg,
            spring,
            friction,
            free_play_deg,
            spring_tolerance_pct,
        })
    }

    /// `[joint.latch]` of joint `j` (1-based), `None` for the ideal latch;
    /// within the joint's stroke `|stowed_deg|` ([`crate::model::latch_toml::read`]).
    fn latch(
        &self,
        sp: &Sp,
        j: usize,
        stowed_deg: f64,
    ) -> Res<Option<crate::model::latch::LatchSpec>> {
        let Node::Table(entries) = &sp.node else {
            return Ok(None);
        };
        match entries.iter().find(|(k, _)| k == "latch") {
            Some((_, latch)) => crate::model::latch_toml::read(
                self,
                latch,
                &format!("joint[{j}].latch"),
                stowed_deg,
                JOINT_KEYS,
            ),
            None => Ok(None),
        }
    }

    fn spring(
        &self,
        sp: &Sp,
        path: &str,
        j: usize,
        tapes: &[(String, TapePoints<f64>)],
    ) -> Res<SpringSpec> {
        let Node::Table(entries) = &sp.node else {
            return Err(self.wrong_type(sp, path, "a table { kind = ..., ... }"));
        };
        let kind_key = join(path, "kind");
        let kind = match entries.iter().find(|(k, _)| k == "kind") {
            Some((_, k)) => (k, self.string(k, &kind_key)?),
            None => {
                return Err(self.err(
                    self.line(sp),
                    MechanismErrorKind::MissingKey {
                        key: kind_key,
                        expected: "one of \"linear\", \"tape\", \"curve\"".to_string(),
                    },
                ))
            }
        };
        let spec = match kind.1 {
            "linear" => self.linear_spring(&self.table(sp, path, LINEAR_KEYS)?)?,
            "tape" => self.tape_spring(&self.table(sp, path, TAPE_SPRING_KEYS)?, tapes)?,
            "curve" => self.curve_spring(&self.table(sp, path, CURVE_KEYS)?)?,
            other => {
                return Err(self.err(
                    self.line(kind.0),
                    MechanismErrorKind::UnknownSpringKind {
                        key: kind_key,
                        joint: j,
                        found: other.to_string(),
                    },
                ))
            }
        };
        // The core's own check (the pieces were checked above; this cannot
        // fail unless the core's rules grow).
        spec.to_spring::<f64>().map_err(|source| {
            self.err(
                self.line(sp),
                MechanismErrorKind::BadCurve {
                    key: path.to_string(),
                    source,
                },
            )
        })?;
        Ok(spec)
    }

    /// `kind = "linear"`: `preload_nm`, `stiffness_nm_per_rad`, `count`.
    fn linear_spring(&self, t: &Table<'_>) -> Res<SpringSpec> {
        let stiffness = "stiffness_nm_per_rad";
        Ok(SpringSpec::Linear {
            preload_nm: self.req_number(t, "preload_nm", Bound::NonNegative, "N·m")?,
            stiffness_nm_per_rad: self.req_number(t, stiffness, Bound::NonNegative, "N·m/rad")?,
            count: self.count(t)?,
        })
    }

    /// `kind = "tape"`: a `type` defined by a `[tape."NAME"]` table, `count`.
    fn tape_spring(&self, t: &Table<'_>, tapes: &[(String, TapePoints<f64>)]) -> Res<SpringSpec> {
        let Some(ty) = t.get("type") else {
            return Err(self.missing(t, "type", "the name of a [tape.\"NAME\"] table"));
        };
        let type_key = t.key("type");
        let type_name = self.string(ty, &type_key)?;
        let Some((_, points)) = tapes.iter().find(|(n, _)| n == type_name) else {
            return Err(self.err(
                self.line(ty),
                MechanismErrorKind::UnknownTapeType {
                    key: type_key,
                    found: type_name.to_string(),
                    defined: tapes.iter().map(|(n, _)| n.clone()).collect(),
                },
            ));
        };
        Ok(SpringSpec::Tape {
            type_name: type_name.to_string(),
            points: *points,
            count: self.count(t)?,
        })
    }

    fn friction(&self, sp: &Sp, path: &str) -> Res<FrictionSpec> {
        let t = self.table(sp, path, FRICTION_KEYS)?;
        let mut f = FrictionSpec::default();
        // The same values as the matching effects (`--effect`) allow.
        let coulomb = Bound::of(EffectKind::CoulombFriction);
        if let Some(x) = self.opt_number(&t, "coulomb_nm", coulomb, "N·m")? {
            f.coulomb_nm = x;
        }
        let viscous = Bound::of(EffectKind::ViscousDamping);
        if let Some(x) = self.opt_number(&t, "viscous_nms", viscous, "N·m·s/rad")? {
            f.viscous_nms = x;
        }
        if let Some(x) = self.opt_number(&t, "coulomb_threshold_rad_s", Bound::Positive, "rad/s")? {
            f.coulomb_threshold_rad_s = x;
        }
        let brk = self.opt_number(&t, "breakaway_nm", Bound::NonNegative, "N·m")?;
        let st = self.opt_number(&t, "stribeck_rad_s", Bound::Positive, "rad/s")?;
        f.stribeck = match (brk, st) {
            (Some(b), Some(s)) => Some((b, s)),
            (None, None) => None,
            (Some(_), None) => {
                return Err(self.missing(
                    &t,
                    "stribeck_rad_s",
                    "a finite number > 0 [rad/s] with breakaway_nm (both or neither)",
                ))
            }
            (None, Some(_)) => {
                return Err(self.missing(
                    &t,
                    "breakaway_nm",
                    "a finite number ≥ 0 [N·m] with stribeck_rad_s (both or neither)",
                ))
            }
        };
        Ok(f)
    }

    /// `[tape."NAME"]` tables, in file order.
    fn tapes(&self, sp: &Sp) -> Res<Vec<(String, TapePoints<f64>)>> {
        let Node::Table(entries) = &sp.node else {
            return Err(self.wrong_type(sp, "tape", "tables [tape.\"NAME\"]"));
        };
        let mut out = Vec::with_capacity(entries.len());
        for (name, v) in entries {
            let path = join("tape", name);
            let t = self.table(v, &path, TAPE_KEYS)?;
            let get_pair = |k: &str| match t.get(k) {
                Some(p) => self.pair(p, &t.key(k), "[deg, N·m per hinge]"),
                None => Err(self.missing(&t, k, "a pair of finite numbers [deg, N·m per hinge]")),
            };
            let a = get_pair("a")?;
            let b = get_pair("b")?;
            let d = get_pair("d")?;
            let m_90 = self.req_number(&t, "m_90", Bound::NonNegative, "N·m per hinge")?;
            let c_180 = self.req_number(&t, "c_180", Bound::NonNegative, "N·m per hinge")?;
            // Angles: the unfolding branch runs through 0, D, B, 90°, 180°
            // and the folding knee through 0, A; moments are magnitudes.
            let check = |k: &str, ok: bool, expected: &str| -> Res<()> {
                if ok {
                    Ok(())
                } else {
                    let sp = t.get(k).unwrap_or(v);
                    Err(self.invalid(sp, &t.key(k), expected))
                }
            };
            check(
                "a",
                a.0 > 0.0 && a.0 < 90.0,
                "[deg, N·m] with 0 < deg < 90 and N·m ≥ 0",
            )?;
            check("a", a.1 >= 0.0, "[deg, N·m] with 0 < deg < 90 and N·m ≥ 0")?;
            check(
                "d",
                d.0 > 0.0,
                "[deg, N·m] with 0 < deg < b's deg and N·m ≥ 0",
            )?;
            check(
                "d",
                d.1 >= 0.0,
                "[deg, N·m] with 0 < deg < b's deg and N·m ≥ 0",
            )?;
            check(
                "b",
                b.0 > d.0 && b.0 < 90.0,
                "[deg, N·m] with d's deg < deg < 90 and N·m ≥ 0",
            )?;
            check(
                "b",
                b.1 >= 0.0,
                "[deg, N·m] with d's deg < deg < 90 and N·m ≥ 0",
            )?;
            let points = TapePoints {
                a,
                b,
                d,
                m_90,
                c_180,
            };
            Spring::tape(&points, 1.0).map_err(|source| {
                self.err(
                    self.line(v),
                    MechanismErrorKind::BadCurve {
                        key: path.clone(),
                        source,
                    },
                )
            })?;
            out.push((name.clone(), points));
        }
        Ok(out)
    }
}
