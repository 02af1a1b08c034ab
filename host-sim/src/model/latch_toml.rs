//! Reading and writing the `[joint.latch]` table of a mechanism file
//! (`docs/spec/formats.md`, "Physical latch", this project's extension):
//! the physical latch of one joint
//! ([`deploywatch_core::physics::latch_contact`]).
//!
//! ```toml
//! [[joint]]
//! stowed_deg = -90.0
//! spring = { kind = "tape", type = "TS-1", count = 3 }
//! [joint.latch]                      # this joint's latch; absent: the ideal latch
//! model = "physical"                 # or "ideal" (no other keys)
//! switch_travel_deg = 0.05           # the switch closes this far from the stop
//! stop = { radius_mm = 40.0 }        # optional: stiffness_n_per_mm1_5 (37000), damping_ns_per_mm1_25 (3.7)
//! plunger = { preload_n = 20.0, stiffness_n_per_mm = 10.0, radius_mm = 40.0, stroke_mm = 0.8,
//!             crest_deg = 0.6, entry_ramp_deg = 30.0, hold_ramp_deg = 50.0 }
//! magnet = { force_n = 15.0, decay_mm = 0.5, reach_mm = 2.0, radius_mm = 40.0 }   # optional
//! ```
//!
//! Errors name the key path (`joint[1].latch.plunger.preload_n`), the line
//! and what was expected; [`crate::model::mechanism_toml`] places them in
//! the file.

use deploywatch_core::physics::latch_contact::{HertzStop, Magnet, PhysicalLatch, Plunger};
use deploywatch_core::Real;
use std::fmt::Write as _;
use toml_edit::{ImDocument, Item, Value};

/// The papers' contact stiffness `k` [N/mm^1.5] (seed 000 §4.2, seed 001
/// §4.2): the default of `stop.stiffness_n_per_mm1_5`.
pub const PAPER_STIFFNESS_N_PER_MM1_5: f64 = 37_000.0;

/// The papers' contact damping `c` [N·s/mm^1.25] (seed 000 §4.2, seed 001
/// §4.2): the default of `stop.damping_ns_per_mm1_25`.
pub const PAPER_DAMPING_NS_PER_MM1_25: f64 = 3.7;

const LATCH_KEYS: &[&str] = &["model", "switch_travel_deg", "stop", "plunger", "magnet"];
const STOP_KEYS: &[&str] = &[
    "radius_mm",
    "stiffness_n_per_mm1_5",
    "damping_ns_per_mm1_25",
];
const PLUNGER_KEYS: &[&str] = &[
    "preload_n",
    "stiffness_n_per_mm",
    "radius_mm",
    "stroke_mm",
    "crest_deg",
    "entry_ramp_deg",
    "hold_ramp_deg",
];
const MAGNET_KEYS: &[&str] = &["force_n", "decay_mm", "reach_mm", "radius_mm"];

/// The stop as written: Hertz contact at a radius.
#[derive(Clone, Debug, PartialEq)]
pub struct StopSpec {
    /// `radius_mm`: contact distance from the hinge axis [mm].
    pub radius_mm: f64,
    /// `stiffness_n_per_mm1_5` [N/mm^1.5].
    pub stiffness_n_per_mm1_5: f64,
    /// `damping_ns_per_mm1_25` [N·s/mm^1.25].
    pub damping_ns_per_mm1_25: f64,
}

/// The ball plunger as written.
#[derive(Clone, Debug, PartialEq)]
pub struct PlungerSpec {
    /// `preload_n` [N].
    pub preload_n: f64,
    /// `stiffness_n_per_mm` [N/mm].
    pub stiffness_n_per_mm: f64,
    /// `radius_mm` [mm].
    pub radius_mm: f64,
    /// `stroke_mm`: ball depression at the crest [mm].
    pub stroke_mm: f64,
    /// `crest_deg`: travel from the stop of the crest [deg].
    pub crest_deg: f64,
    /// `entry_ramp_deg` [deg].
    pub entry_ramp_deg: f64,
    /// `hold_ramp_deg` [deg].
    pub hold_ramp_deg: f64,
}

/// The magnet as written.
#[derive(Clone, Debug, PartialEq)]
pub struct MagnetSpec {
    /// `force_n`: attraction at contact [N].
    pub force_n: f64,
    /// `decay_mm` [mm].
    pub decay_mm: f64,
    /// `reach_mm` [mm].
    pub reach_mm: f64,
    /// `radius_mm` [mm].
    pub radius_mm: f64,
}

/// A joint's physical latch as written in `[joint.latch]`.
#[derive(Clone, Debug, PartialEq)]
pub struct LatchSpec {
    /// `switch_travel_deg` [deg].
    pub switch_travel_deg: f64,
    /// `stop`.
    pub stop: StopSpec,
    /// `plunger`.
    pub plunger: PlungerSpec,
    /// `magnet`, `None` without one.
    pub magnet: Option<MagnetSpec>,
}

/// Millimetres per metre.
const MM_PER_M: f64 = 1000.0;

impl LatchSpec {
    /// The core's latch, in `f64` for the simulator or `f32` for the
    /// on-board monitor, for a joint stowed at `stowed_deg`, with the
    /// plunger's preload and rate scaled by `plunger_scale` and the magnet's
    /// force by `magnet_scale` (`1 − weakening`).
    pub fn to_core<T: Real>(
        &self,
        stowed_deg: f64,
        plunger_scale: f64,
        magnet_scale: f64,
    ) -> PhysicalLatch<T> {
        let (s, p) = (&self.stop, &self.plunger);
        let mm = |x: f64| T::of(x / MM_PER_M);
        let rad = |deg: f64| T::of(deg.to_radians());
        let magnet = match &self.magnet {
            Some(m) => Magnet {
                force_n: T::of(m.force_n * magnet_scale),
                decay_mm: T::of(m.decay_mm),
                reach_mm: T::of(m.reach_mm),
                radius_m: mm(m.radius_mm),
            },
            None => Magnet {
                force_n: T::ZERO,
                decay_mm: T::ONE,
                reach_mm: T::ZERO,
                radius_m: mm(s.radius_mm),
            },
        };
        PhysicalLatch {
            side: if stowed_deg >= 0.0 { T::ONE } else { -T::ONE },
            stop: HertzStop {
                stiffness_n_per_mm1_5: T::of(s.stiffness_n_per_mm1_5),
                damping_ns_per_mm1_25: T::of(s.damping_ns_per_mm1_25),
                radius_m: mm(s.radius_mm),
            },
            plunger: Plunger {
                preload_n: T::of(p.preload_n * plunger_scale),
                stiffness_n_per_mm: T::of(p.stiffness_n_per_mm * plunger_scale),
                radius_m: mm(p.radius_mm),
                stroke_mm: T::of(p.stroke_mm),
                crest_rad: rad(p.crest_deg),
                entry_ramp_rad: rad(p.entry_ramp_deg),
                hold_ramp_rad: rad(p.hold_ramp_deg),
            },
            magnet,
            switch_travel_rad: rad(self.switch_travel_deg),
        }
    }
}

/// Why a `[joint.latch]` table was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("`{key}`: expected {expected}")]
pub struct LatchTomlError {
    /// Key path, e.g. `joint[1].latch.plunger.preload_n`.
    pub key: String,
    /// What was expected there.
    pub expected: String,
    /// 1-based line of the value or its table, when known.
    pub line: Option<usize>,
}

/// The text being read, for line numbers.
struct Text<'a>(&'a str);

impl Text<'_> {
    fn line(&self, span: Option<std::ops::Range<usize>>) -> Option<usize> {
        let end = span?.start.min(self.0.len());
        Some(
            self.0.as_bytes()[..end]
                .iter()
                .filter(|&&b| b == b'\n')
                .count()
                + 1,
        )
    }

    fn err(
        &self,
        key: &str,
        expected: &str,
        span: Option<std::ops::Range<usize>>,
    ) -> LatchTomlError {
        LatchTomlError {
            key: key.to_string(),
            expected: expected.to_string(),
            line: self.line(span),
        }
    }
}

/// The `[joint.latch]` of every `[[joint]]` of a mechanism file's text, in
/// order (`None`: the ideal latch). Syntax errors are left to the
/// mechanism's own reader (this returns no latches then).
pub fn read(text: &str) -> Result<Vec<Option<LatchSpec>>, LatchTomlError> {
    let Ok(doc) = ImDocument::parse(text) else {
        return Ok(Vec::new());
    };
    let t = Text(text);
    let mut out = Vec::new();
    let joints: Vec<Option<Node<'_>>> = match doc.get("joint") {
        Some(Item::ArrayOfTables(a)) => a
            .iter()
            .map(|j| j.get("latch").and_then(Node::of_item))
            .collect(),
        Some(Item::Value(Value::Array(a))) => a
            .iter()
            .map(|j| {
                j.as_inline_table()
                    .and_then(|t| t.get("latch"))
                    .map(Node::of_value)
            })
            .collect(),
        _ => return Ok(Vec::new()),
    };
    for (i, latch) in joints.into_iter().enumerate() {
        let path = format!("joint[{}].latch", i + 1);
        out.push(match latch {
            None => None,
            Some(node) => latch_table(&t, node, &path)?,
        });
    }
    Ok(out)
}

/// A TOML node of the latch table: a table, an inline table or a value.
#[derive(Clone, Copy)]
enum Node<'a> {
    Table(&'a toml_edit::Table),
    Inline(&'a toml_edit::InlineTable),
    Value(&'a Value),
}

type Span = Option<std::ops::Range<usize>>;

impl<'a> Node<'a> {
    fn of_item(item: &'a Item) -> Option<Node<'a>> {
        match item {
            Item::Table(t) => Some(Node::Table(t)),
            Item::Value(v) => Some(Node::of_value(v)),
            _ => None,
        }
    }

    fn of_value(v: &'a Value) -> Node<'a> {
        match v {
            Value::InlineTable(t) => Node::Inline(t),
            other => Node::Value(other),
        }
    }

    fn span(&self) -> Span {
        match self {
            Node::Table(t) => t.span(),
            Node::Inline(t) => t.span(),
            Node::Value(v) => v.span(),
        }
    }

    fn as_str(&self) -> Option<&'a str> {
        match self {
            Node::Value(v) => v.as_str(),
            _ => None,
        }
    }
}

/// The entries of a table or inline table, with its span.
type Entries<'a> = (Vec<(String, Node<'a>)>, Span);

fn entries<'a>(
    t: &Text<'_>,
    node: Node<'a>,
    path: &str,
    allowed: &[&str],
) -> Result<Entries<'a>, LatchTomlError> {
    let list: Vec<(String, Node<'a>)> = match node {
        Node::Table(tb) => tb
            .iter()
            .filter_map(|(k, v)| Some((k.to_string(), Node::of_item(v)?)))
            .collect(),
        Node::Inline(tb) => tb
            .iter()
            .map(|(k, v)| (k.to_string(), Node::of_value(v)))
            .collect(),
        Node::Value(v) => return Err(t.err(path, "a table", v.span())),
    };
    let span = node.span();
    for (k, v) in &list {
        if !allowed.contains(&k.as_str()) {
            let expected = format!("one of the keys {}", allowed.join(", "));
            return Err(t.err(&format!("{path}.{k}"), &expected, v.span().or(span.clone())));
        }
    }
    Ok((list, span))
}

/// A number of a table: finite and within `ok`, else an error saying `expected`.
fn number(
    t: &Text<'_>,
    (list, span): &Entries<'_>,
    path: &str,
    key: &str,
    default: Option<f64>,
    (ok, expected): (fn(f64) -> bool, &str),
) -> Result<f64, LatchTomlError> {
    let key_path = format!("{path}.{key}");
    let Some((_, item)) = list.iter().find(|(k, _)| k == key) else {
        return default
            .ok_or_else(|| t.err(&key_path, &format!("{expected} (missing)"), span.clone()));
    };
    let x = match item {
        Node::Value(Value::Float(f)) => *f.value(),
        Node::Value(Value::Integer(i)) => *i.value() as f64,
        _ => f64::NAN,
    };
    if x.is_finite() && ok(x) {
        Ok(x)
    } else {
        Err(t.err(&key_path, expected, item.span()))
    }
}

const NON_NEGATIVE: (fn(f64) -> bool, &str) = (|x| x >= 0.0, "a finite number ≥ 0");
const POSITIVE: (fn(f64) -> bool, &str) = (|x| x > 0.0, "a finite number > 0");
const RAMP: (fn(f64) -> bool, &str) = (|x| x > 0.0 && x < 90.0, "an angle in (0, 90) [deg]");

fn latch_table(
    t: &Text<'_>,
    item: Node<'_>,
    path: &str,
) -> Result<Option<LatchSpec>, LatchTomlError> {
    let e = entries(t, item, path, LATCH_KEYS)?;
    let model = e.0.iter().find(|(k, _)| k == "model").map(|(_, v)| *v);
    let model_path = format!("{path}.model");
    let expected = "\"physical\" or \"ideal\"";
    match model.map(|m| (m.as_str(), m.span())) {
        Some((Some("ideal"), _)) if e.0.len() == 1 => return Ok(None),
        Some((Some("ideal"), span)) => {
            return Err(t.err(
                &model_path,
                "no other latch keys with model = \"ideal\"",
                span,
            ))
        }
        Some((Some("physical"), _)) => {}
        Some((_, span)) => return Err(t.err(&model_path, expected, span)),
        None => return Err(t.err(&model_path, &format!("{expected} (missing)"), e.1.clone())),
    }
    let switch_travel_deg = number(t, &e, path, "switch_travel_deg", None, NON_NEGATIVE)?;
    let sub = |key: &str| e.0.iter().find(|(k, _)| k == key).map(|(_, v)| *v);
    let stop_path = format!("{path}.stop");
    let stop_item = sub("stop").ok_or_else(|| {
        t.err(
            &stop_path,
            "a table { radius_mm = ... } (missing)",
            e.1.clone(),
        )
    })?;
    let stop = stop_spec(t, stop_item, &stop_path)?;
    let plunger_path = format!("{path}.plunger");
    let plunger_item = sub("plunger").ok_or_else(|| {
        t.err(
            &plunger_path,
            "a table { preload_n = ..., ... } (missing)",
            e.1.clone(),
        )
    })?;
    let plunger = plunger_spec(t, plunger_item, &plunger_path)?;
    let magnet = match sub("magnet") {
        Some(m) => Some(magnet_spec(t, m, &format!("{path}.magnet"))?),
        None => None,
    };
    let spec = LatchSpec {
        switch_travel_deg,
        stop,
        plunger,
        magnet,
    };
    spec.to_core::<f64>(1.0, 1.0, 1.0)
        .check()
        .map_err(|why| t.err(path, &format!("a physical latch: {why}"), e.1.clone()))?;
    Ok(Some(spec))
}

fn stop_spec(t: &Text<'_>, item: Node<'_>, path: &str) -> Result<StopSpec, LatchTomlError> {
    let e = entries(t, item, path, STOP_KEYS)?;
    Ok(StopSpec {
        radius_mm: number(t, &e, path, "radius_mm", None, POSITIVE)?,
        stiffness_n_per_mm1_5: number(
            t,
            &e,
            path,
            "stiffness_n_per_mm1_5",
            Some(PAPER_STIFFNESS_N_PER_MM1_5),
            NON_NEGATIVE,
        )?,
        damping_ns_per_mm1_25: number(
            t,
            &e,
            path,
            "damping_ns_per_mm1_25",
            Some(PAPER_DAMPING_NS_PER_MM1_25),
            NON_NEGATIVE,
        )?,
    })
}

fn plunger_spec(t: &Text<'_>, item: Node<'_>, path: &str) -> Result<PlungerSpec, LatchTomlError> {
    let e = entries(t, item, path, PLUNGER_KEYS)?;
    let n = |key: &str, range| number(t, &e, path, key, None, range);
    Ok(PlungerSpec {
        preload_n: n("preload_n", NON_NEGATIVE)?,
        stiffness_n_per_mm: n("stiffness_n_per_mm", NON_NEGATIVE)?,
        radius_mm: n("radius_mm", POSITIVE)?,
        stroke_mm: n("stroke_mm", NON_NEGATIVE)?,
        crest_deg: n("crest_deg", NON_NEGATIVE)?,
        entry_ramp_deg: n("entry_ramp_deg", RAMP)?,
        hold_ramp_deg: n("hold_ramp_deg", RAMP)?,
    })
}

fn magnet_spec(t: &Text<'_>, item: Node<'_>, path: &str) -> Result<MagnetSpec, LatchTomlError> {
    let e = entries(t, item, path, MAGNET_KEYS)?;
    let n = |key: &str, range| number(t, &e, path, key, None, range);
    Ok(MagnetSpec {
        force_n: n("force_n", NON_NEGATIVE)?,
        decay_mm: n("decay_mm", POSITIVE)?,
        reach_mm: n("reach_mm", NON_NEGATIVE)?,
        radius_mm: n("radius_mm", POSITIVE)?,
    })
}

/// The `[joint.latch]` table of `spec`, written after its `[[joint]]`
/// (what [`read`] reads back as the same spec).
pub fn write(spec: &LatchSpec) -> String {
    let (s, p) = (&spec.stop, &spec.plunger);
    let mut out = String::new();
    let _ = write!(
        out,
        "[joint.latch]\nmodel = \"physical\"\nswitch_travel_deg = {:?}\n\
         stop = {{ radius_mm = {:?}, stiffness_n_per_mm1_5 = {:?}, damping_ns_per_mm1_25 = {:?} }}\n\
         plunger = {{ preload_n = {:?}, stiffness_n_per_mm = {:?}, radius_mm = {:?}, stroke_mm = {:?}, \
         crest_deg = {:?}, entry_ramp_deg = {:?}, hold_ramp_deg = {:?} }}\n",
        spec.switch_travel_deg,
        s.radius_mm,
        s.stiffness_n_per_mm1_5,
        s.damping_ns_per_mm1_25,
        p.preload_n,
        p.stiffness_n_per_mm,
        p.radius_mm,
        p.stroke_mm,
        p.crest_deg,
        p.entry_ramp_deg,
        p.hold_ramp_deg
    );
    if let Some(m) = &spec.magnet {
        let _ = writeln!(
            out,
            "magnet = {{ force_n = {:?}, decay_mm = {:?}, reach_mm = {:?}, radius_mm = {:?} }}",
            m.force_n, m.decay_mm, m.reach_mm, m.radius_mm
        );
    }
    out
}
