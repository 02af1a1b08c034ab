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
//!   key.
//!
//! Beyond the types, values must describe a mechanism: `com_m` within the
//! panel (0 to `length_m`), `0 < |stowed_deg| ≤ 360`, friction values as
//! the matching effects allow them ([`EffectKind::allowed`]).
//!
//! `count` is required (a silently defaulted hinge count would change the
//! spring torque by a factor), and must be a TOML integer ≥ 1.
//!
//! [`Mechanism::to_toml_string`] writes a mechanism back, deterministically,
//! with every number in Rust's shortest round-trip form, so that reading the
//! output gives back an equal [`Mechanism`].

use std::ops::Range;
use std::path::Path;

use deploywatch_core::spring::{Interp, TapePoints};
use deploywatch_core::{Curve, Panel, Spring};

use crate::model::effect::{EffectKind, ValueRange};
use crate::model::mechanism::{FrictionSpec, JointSpec, Mechanism, SpringSpec, MAX_CHAIN_JOINTS};
pub use crate::model::mechanism_error::{MechanismError, MechanismErrorKind};
use crate::model::mechanism_write::{num, toml_str};

/// `[run] duration_s` when the file does not give it (s).
pub const DEFAULT_DURATION_S: f64 = 6.0;

/// `[run] sample_hz` when the file does not give it (Hz).
pub const DEFAULT_SAMPLE_HZ: f64 = 100.0;

/// `[run] settle_s` when the file does not give it (s): a rig keeps
/// recording after the wing has latched, and the on-board monitor confirms a
/// latch on 2 of 3 switch samples, so a run needs a few samples past the last
/// latch (`formats.md`, "Run: CSV").
pub const DEFAULT_SETTLE_S: f64 = 0.2;

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
        let text = std::fs::read_to_string(path).map_err(|source| MechanismError {
            file: path.display().to_string(),
            line: None,
            kind: MechanismErrorKind::Io { source },
        })?;
        Mechanism::from_toml_str(&text, &path.display().to_string())
    }

    /// Parses and validates mechanism TOML text; `source` names it in errors
    /// (usually the file's path).
    pub fn from_toml_str(text: &str, source: &str) -> Result<Mechanism, MechanismError> {
        let cx = Cx { file: source, text };
        let doc = toml_edit::ImDocument::parse(text).map_err(|e| {
            let message: Vec<&str> = e
                .message()
                .lines()
                .map(str::trim)
                .filter(|l| !l.is_empty())
                .collect();
            let message = if message.is_empty() {
                "expected a value or a key here".to_string()
            } else {
                message.join("; ")
            };
            let column = e.span().map(|s| cx.column_of(s.start));
            cx.err(
                e.span().map(|s| cx.line_of(s.start)),
                MechanismErrorKind::Syntax { column, message },
            )
        })?;
        cx.mechanism(&Sp::table(doc.as_table()))
    }
}

/// A TOML value and, when known, its byte span in the text.
#[derive(Debug)]
struct Sp {
    span: Option<Range<usize>>,
    node: Node,
}

#[derive(Debug)]
enum Node {
    Str(String),
    Int(i64),
    Float(f64),
    Bool(bool),
    Datetime(String),
    Array(Vec<Sp>),
    Table(Vec<(String, Sp)>),
}

impl Sp {
    /// A `[table]` (or the document's root table).
    fn table(t: &toml_edit::Table) -> Sp {
        Sp {
            span: t.span(),
            node: Node::Table(
                t.iter()
                    .map(|(k, v)| (k.to_string(), Sp::item(v)))
                    .collect(),
            ),
        }
    }

    /// Any item: a value, a table or an array of tables.
    fn item(item: &toml_edit::Item) -> Sp {
        match item {
            toml_edit::Item::Value(v) => Sp::value(v),
            toml_edit::Item::Table(t) => Sp::table(t),
            toml_edit::Item::ArrayOfTables(a) => Sp {
                span: a.span(),
                node: Node::Array(a.iter().map(Sp::table).collect()),
            },
            toml_edit::Item::None => Sp {
                span: None,
                node: Node::Table(Vec::new()),
            },
        }
    }

    /// A value (inline tables and arrays included).
    fn value(v: &toml_edit::Value) -> Sp {
        use toml_edit::Value as V;
        let node = match v {
            V::String(s) => Node::Str(s.value().clone()),
            V::Integer(i) => Node::Int(*i.value()),
            V::Float(x) => Node::Float(*x.value()),
            V::Boolean(b) => Node::Bool(*b.value()),
            V::Datetime(d) => Node::Datetime(d.value().to_string()),
            V::Array(a) => Node::Array(a.iter().map(Sp::value).collect()),
            V::InlineTable(t) => Node::Table(
                t.iter()
                    .map(|(k, v)| (k.to_string(), Sp::value(v)))
                    .collect(),
            ),
        };
        Sp {
            span: v.span(),
            node,
        }
    }
}

impl Node {
    fn type_name(&self) -> &'static str {
        match self {
            Node::Str(_) => "a string",
            Node::Int(_) => "an integer",
            Node::Float(_) => "a float",
            Node::Bool(_) => "a boolean",
            Node::Datetime(_) => "a date-time",
            Node::Array(_) => "an array",
            Node::Table(_) => "a table",
        }
    }

    /// The value as TOML, shortened, for messages.
    fn show(&self) -> String {
        let s = match self {
            Node::Str(s) => toml_str(s),
            Node::Int(i) => i.to_string(),
            Node::Float(x) => num(*x),
            Node::Bool(b) => b.to_string(),
            Node::Datetime(d) => d.clone(),
            Node::Array(a) => format!(
                "[{}]",
                a.iter()
                    .map(|v| v.node.show())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            Node::Table(_) => "a table".to_string(),
        };
        if s.chars().count() > 60 {
            let mut t: String = s.chars().take(57).collect();
            t.push_str("...");
            t
        } else {
            s
        }
    }
}

// ---------------------------------------------------------------------------
// Validation.

type Res<T> = Result<T, MechanismError>;

const TOP_KEYS: &[&str] = &[
    "name",
    "description",
    "panel",
    "joint",
    "tape",
    "run",
    "truss",
];
const PANEL_KEYS: &[&str] = &["length_m", "mass_kg", "com_m", "inertia_kgm2"];
const JOINT_KEYS: &[&str] = &["stowed_deg", "spring", "friction"];
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

/// What a number must be.
#[derive(Clone, Copy)]
enum Bound {
    Finite,
    NonZero,
    NonNegative,
    Positive,
    BelowOne,
}

impl Bound {
    /// The values an effect allows ([`EffectKind::allowed`]).
    fn of(kind: EffectKind) -> Bound {
        match kind.allowed() {
            ValueRange::Finite => Bound::Finite,
            ValueRange::NonNegative => Bound::NonNegative,
            ValueRange::BelowOne => Bound::BelowOne,
        }
    }

    fn ok(self, x: f64) -> bool {
        x.is_finite()
            && match self {
                Bound::Finite => true,
                Bound::NonZero => x != 0.0,
                Bound::NonNegative => x >= 0.0,
                Bound::Positive => x > 0.0,
                Bound::BelowOne => x < 1.0,
            }
    }

    fn describe(self, unit: &str) -> String {
        let what = match self {
            Bound::Finite => "a finite number",
            Bound::NonZero => "a finite non-zero number",
            Bound::NonNegative => "a finite number ≥ 0",
            Bound::Positive => "a finite number > 0",
            Bound::BelowOne => "a finite number < 1",
        };
        if unit.is_empty() {
            what.to_string()
        } else {
            format!("{what} [{unit}]")
        }
    }
}

/// The file being read.
struct Cx<'a> {
    file: &'a str,
    text: &'a str,
}

/// The keys of one table, checked against the allowed ones.
struct Table<'a> {
    entries: &'a [(String, Sp)],
    path: String,
    line: Option<usize>,
}

impl<'a> Table<'a> {
    fn get(&self, key: &str) -> Option<&'a Sp> {
        self.entries.iter().find(|(k, _)| k == key).map(|(_, v)| v)
    }

    fn key(&self, key: &str) -> String {
        join(&self.path, key)
    }
}

fn join(path: &str, key: &str) -> String {
    let key = if !key.is_empty()
        && key
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    {
        key.to_string()
    } else {
        toml_str(key)
    };
    if path.is_empty() {
        key
    } else {
        format!("{path}.{key}")
    }
}

impl Cx<'_> {
    /// An error at `line` of this file.
    fn err(&self, line: Option<usize>, kind: MechanismErrorKind) -> MechanismError {
        MechanismError {
            file: self.file.to_string(),
            line,
            kind,
        }
    }

    fn line_of(&self, byte: usize) -> usize {
        let end = byte.min(self.text.len());
        self.text.as_bytes()[..end]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
            + 1
    }

    /// 1-based column, in characters, of byte `byte`.
    fn column_of(&self, byte: usize) -> usize {
        let mut end = byte.min(self.text.len());
        while !self.text.is_char_boundary(end) {
            end -= 1;
        }
        let start = self.text[..end].rfind('\n').map_or(0, |i| i + 1);
        self.text[start..end].chars().count() + 1
    }

    fn line(&self, sp: &Sp) -> Option<usize> {
        sp.span.as_ref().map(|s| self.line_of(s.start))
    }

    fn wrong_type(&self, sp: &Sp, key: &str, expected: &str) -> MechanismError {
        self.err(
            self.line(sp),
            MechanismErrorKind::WrongType {
                key: key.to_string(),
                expected: expected.to_string(),
                found: sp.node.type_name().to_string(),
            },
        )
    }

    fn invalid(&self, sp: &Sp, key: &str, expected: &str) -> MechanismError {
        self.err(
            self.line(sp),
            MechanismErrorKind::InvalidValue {
                key: key.to_string(),
                expected: expected.to_string(),
                found: sp.node.show(),
            },
        )
    }

    fn missing(&self, t: &Table<'_>, key: &str, expected: &str) -> MechanismError {
        self.err(
            t.line,
            MechanismErrorKind::MissingKey {
                key: t.key(key),
                expected: expected.to_string(),
            },
        )
    }

    /// `sp` as a table whose keys are all in `allowed`.
    fn table<'s>(&self, sp: &'s Sp, path: &str, allowed: &[&str]) -> Res<Table<'s>> {
        let Node::Table(entries) = &sp.node else {
            return Err(self.wrong_type(sp, path, "a table"));
        };
        for (k, v) in entries {
            if !allowed.contains(&k.as_str()) {
                return Err(self.err(
                    self.line(v).or_else(|| self.line(sp)),
                    MechanismErrorKind::UnknownKey {
                        key: join(path, k),
                        expected: allowed.join(", "),
                    },
                ));
            }
        }
        Ok(Table {
            entries,
            path: path.to_string(),
            line: self.line(sp),
        })
    }

    fn number(&self, sp: &Sp, key: &str, range: Bound, unit: &str) -> Res<f64> {
        let x = match sp.node {
            Node::Float(x) => x,
            Node::Int(i) => i as f64,
            _ => return Err(self.wrong_type(sp, key, &range.describe(unit))),
        };
        if range.ok(x) {
            Ok(x)
        } else {
            Err(self.invalid(sp, key, &range.describe(unit)))
        }
    }

    fn req_number(&self, t: &Table<'_>, key: &str, range: Bound, unit: &str) -> Res<f64> {
        match t.get(key) {
            Some(sp) => self.number(sp, &t.key(key), range, unit),
            None => Err(self.missing(t, key, &range.describe(unit))),
        }
    }

    fn opt_number(&self, t: &Table<'_>, key: &str, range: Bound, unit: &str) -> Res<Option<f64>> {
        t.get(key)
            .map(|sp| self.number(sp, &t.key(key), range, unit))
            .transpose()
    }

    fn string<'s>(&self, sp: &'s Sp, key: &str) -> Res<&'s str> {
        match &sp.node {
            Node::Str(s) => Ok(s),
            _ => Err(self.wrong_type(sp, key, "a string")),
        }
    }

    /// `[x, y]`: two numbers.
    fn pair(&self, sp: &Sp, key: &str, what: &str) -> Res<(f64, f64)> {
        let expected = format!("a pair of finite numbers {what}");
        let Node::Array(items) = &sp.node else {
            return Err(self.wrong_type(sp, key, &expected));
        };
        if items.len() != 2 {
            return Err(self.invalid(sp, key, &expected));
        }
        let x = self.number(&items[0], &format!("{key}[1]"), Bound::Finite, "")?;
        let y = self.number(&items[1], &format!("{key}[2]"), Bound::Finite, "")?;
        Ok((x, y))
    }

    fn count(&self, t: &Table<'_>) -> Res<u32> {
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

    // -----------------------------------------------------------------------

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
        for (i, sp) in panel_items.iter().enumerate() {
            panels.push(self.panel(sp, &format!("panel[{}]", i + 1))?);
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
        for (i, sp) in joint_items.iter().enumerate() {
            joints.push(self.joint(sp, i + 1, &tapes)?);
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

        Ok(Mechanism {
            name,
            description,
            panels,
            joints,
            duration_s,
            sample_hz,
            settle_s,
            truss: crate::model::truss_toml::read(self.text)
                .map_err(|source| self.err(None, MechanismErrorKind::Truss { source }))?,
        })
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

    fn panel(&self, sp: &Sp, path: &str) -> Res<Panel<f64>> {
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
        Ok(Panel {
            length_m,
            mass_kg,
            com_m,
            inertia_kgm2: self.req_number(&t, "inertia_kgm2", Bound::Positive, "kg·m²")?,
        })
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
        Ok(JointSpec {
            stowed_deg,
            spring,
            friction,
        })
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

    /// `kind = "curve"`: `unfold`, optional `fold` and `interp`, `count`.
    fn curve_spring(&self, t: &Table<'_>) -> Res<SpringSpec> {
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
            points.push(self.pair(p, &format!("{key}[{}]", i + 1), "[deg, N·m]")?);
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
