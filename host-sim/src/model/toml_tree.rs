//! The one TOML stack of the mechanism file: the text parsed by `toml_edit`
//! into a tree of values that keep their byte spans ([`Sp`]), and the reader
//! ([`Cx`]) that checks a value's type and range and turns every problem into
//! a [`MechanismError`] naming the file, the line and the key path.
//!
//! Each table of the file is read by the module that owns it, on this tree:
//! the mechanism proper by [`crate::model::mechanism_toml`], `[truss]` by
//! [`crate::model::truss_toml`], `[joint.latch]` by
//! [`crate::model::latch_toml`]. A new table gets its own module with a
//! `read(cx: &Cx, sp: &Sp, ...) -> Res<T>` and one line in
//! [`crate::model::mechanism_toml`]'s `TOP_KEYS` and `mechanism`.

use std::ops::Range;

use crate::model::effect::{EffectKind, ValueRange};
use crate::model::file_kind::FileKind;
use crate::model::mechanism_error::{MechanismError, MechanismErrorKind};

/// A TOML value and, when known, its byte span in the text.
#[derive(Debug)]
pub(crate) struct Sp {
    /// Byte span in the text, when the parser knows it.
    pub(crate) span: Option<Range<usize>>,
    /// The value.
    pub(crate) node: Node,
}

#[derive(Debug)]
pub(crate) enum Node {
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
    pub(crate) fn table(t: &toml_edit::Table) -> Sp {
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
    pub(crate) fn item(item: &toml_edit::Item) -> Sp {
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
    pub(crate) fn value(v: &toml_edit::Value) -> Sp {
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

impl Sp {
    /// The value at a key path below this one (`truss.link[3].length_mm`
    /// from the `[truss]` table: the first segment names this value, `[i]`
    /// counts from 1), or the deepest value on the way that exists.
    pub(crate) fn at_path(&self, path: &str) -> &Sp {
        let mut at = self;
        for (depth, segment) in path.split('.').enumerate() {
            let (key, index) = match segment.split_once('[') {
                Some((k, i)) => (k, i.trim_end_matches(']').parse::<usize>().ok()),
                None => (segment, None),
            };
            if depth > 0 {
                let Node::Table(entries) = &at.node else {
                    return at;
                };
                match entries.iter().find(|(k, _)| k == key) {
                    Some((_, v)) => at = v,
                    None => return at,
                }
            }
            if let Some(i) = index {
                match &at.node {
                    Node::Array(items) if i >= 1 && i <= items.len() => at = &items[i - 1],
                    _ => return at,
                }
            }
        }
        at
    }
}

impl Node {
    pub(crate) fn type_name(&self) -> &'static str {
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
    pub(crate) fn show(&self) -> String {
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

/// A result whose error names the file, line and key.
pub(crate) type Res<T> = Result<T, MechanismError>;

/// What a number must be.
#[derive(Clone, Copy)]
pub(crate) enum Bound {
    Finite,
    NonZero,
    NonNegative,
    Positive,
    BelowOne,
}

impl Bound {
    /// The values an effect allows ([`EffectKind::allowed`]).
    pub(crate) fn of(kind: EffectKind) -> Bound {
        match kind.allowed() {
            ValueRange::Finite => Bound::Finite,
            ValueRange::NonNegative => Bound::NonNegative,
            ValueRange::BelowOne => Bound::BelowOne,
            ValueRange::Fraction => Bound::NonNegative,
        }
    }

    pub(crate) fn ok(self, x: f64) -> bool {
        x.is_finite()
            && match self {
                Bound::Finite => true,
                Bound::NonZero => x != 0.0,
                Bound::NonNegative => x >= 0.0,
                Bound::Positive => x > 0.0,
                Bound::BelowOne => x < 1.0,
            }
    }

    pub(crate) fn describe(self, unit: &str) -> String {
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
pub(crate) struct Cx<'a> {
    /// The file's name in errors.
    pub(crate) file: &'a str,
    /// Its text.
    pub(crate) text: &'a str,
}

/// The keys of one table, checked against the allowed ones.
pub(crate) struct Table<'a> {
    /// The keys and values, in file order.
    pub(crate) entries: &'a [(String, Sp)],
    /// The table's key path (`joint[2].spring`).
    pub(crate) path: String,
    /// The table's line, when known.
    pub(crate) line: Option<usize>,
}

impl<'a> Table<'a> {
    pub(crate) fn get(&self, key: &str) -> Option<&'a Sp> {
        self.entries.iter().find(|(k, _)| k == key).map(|(_, v)| v)
    }

    pub(crate) fn key(&self, key: &str) -> String {
        join(&self.path, key)
    }
}

pub(crate) fn join(path: &str, key: &str) -> String {
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

/// What a syntax error in an inline table adds: TOML 1.0, which the reader
/// follows, closes an inline table on the line that opens it (several lines
/// are TOML 1.1).
const INLINE_TABLE_HINT: &str = " (an inline table `{ ... }` must close on the line it opens, TOML 1.0: write a longer one as a sub-table, e.g. `[joint.latch.plunger]` with one key a line)";

/// The first header `[name.…]` (its line, the header, `name`) that comes
/// before the first `[[name]]` of the text: a sub-table written above the
/// array-of-tables entry it belongs to, which TOML reads as `name` defined
/// twice.
fn sub_table_before_its_array(text: &str) -> Option<(usize, &str, &str)> {
    let headers: Vec<(usize, &str)> = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.split('#').next().unwrap_or("").trim()))
        .filter(|(_, l)| l.starts_with('['))
        .collect();
    headers.iter().find_map(|&(at, h)| {
        let name = h.strip_prefix('[').filter(|n| !n.starts_with('['))?;
        let name = name.split(['.', ']']).next()?.trim();
        let array = format!("[[{name}]]");
        let first_array = headers.iter().find(|(_, g)| g.replace(' ', "") == array)?;
        (first_array.0 > at).then_some((at, h, name))
    })
}

impl Cx<'_> {
    /// The text parsed into a tree of values with their spans; a syntax
    /// error names its line and column.
    pub(crate) fn parse(&self) -> Res<Sp> {
        let cx = self;
        let text = self.text;
        let doc = toml_edit::ImDocument::parse(text).map_err(|e| {
            let message: Vec<&str> = e
                .message()
                .lines()
                .map(str::trim)
                .filter(|l| !l.is_empty())
                .collect();
            let mut message = if message.is_empty() {
                "expected a value or a key here".to_string()
            } else {
                message.join("; ")
            };
            if message.contains("inline table") {
                message.push_str(INLINE_TABLE_HINT);
            }
            if let Some(kind @ (FileKind::RunCsv | FileKind::Json)) = FileKind::of_text(text) {
                message.push_str(&format!("; the file reads as {kind}, not a mechanism TOML"));
            }
            let mut column = e.span().map(|s| cx.column_of(s.start));
            let mut line = e.span().map(|s| cx.line_of(s.start));
            if let Some((at, header, array)) = sub_table_before_its_array(text) {
                if message.contains(&format!("duplicate key `{array}`")) {
                    (line, column) = (Some(at), Some(1));
                    message = format!("`{header}` comes before any [[{array}]]: a `[{array}.…]` table belongs to the last [[{array}]] above it; expected it below the [[{array}]] it is part of");
                }
            }
            cx.err(line, MechanismErrorKind::Syntax { column, message })
        })?;
        Ok(Sp::table(doc.as_table()))
    }

    /// An error at `line` of this file.
    pub(crate) fn err(&self, line: Option<usize>, kind: MechanismErrorKind) -> MechanismError {
        MechanismError {
            file: self.file.to_string(),
            line,
            kind,
        }
    }

    pub(crate) fn line_of(&self, byte: usize) -> usize {
        let end = byte.min(self.text.len());
        self.text.as_bytes()[..end]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
            + 1
    }

    /// 1-based column, in characters, of byte `byte`.
    pub(crate) fn column_of(&self, byte: usize) -> usize {
        let mut end = byte.min(self.text.len());
        while !self.text.is_char_boundary(end) {
            end -= 1;
        }
        let start = self.text[..end].rfind('\n').map_or(0, |i| i + 1);
        self.text[start..end].chars().count() + 1
    }

    pub(crate) fn line(&self, sp: &Sp) -> Option<usize> {
        sp.span.as_ref().map(|s| self.line_of(s.start))
    }

    /// The line of `sp`, or of the first of its values that has one.
    pub(crate) fn first_line(&self, sp: &Sp) -> Option<usize> {
        match (&sp.node, self.line(sp)) {
            (_, Some(l)) => Some(l),
            (Node::Table(entries), None) => entries.iter().find_map(|(_, v)| self.first_line(v)),
            _ => None,
        }
    }

    pub(crate) fn wrong_type(&self, sp: &Sp, key: &str, expected: &str) -> MechanismError {
        self.err(
            self.line(sp),
            MechanismErrorKind::WrongType {
                key: key.to_string(),
                expected: expected.to_string(),
                found: sp.node.type_name().to_string(),
            },
        )
    }

    pub(crate) fn invalid(&self, sp: &Sp, key: &str, expected: &str) -> MechanismError {
        self.err(
            self.line(sp),
            MechanismErrorKind::InvalidValue {
                key: key.to_string(),
                expected: expected.to_string(),
                found: sp.node.show(),
            },
        )
    }

    pub(crate) fn missing(&self, t: &Table<'_>, key: &str, expected: &str) -> MechanismError {
        self.err(
            t.line,
            MechanismErrorKind::MissingKey {
                key: t.key(key),
                expected: expected.to_string(),
            },
        )
    }

    /// `sp` as a table whose keys are all in `allowed`.
    pub(crate) fn table<'s>(&self, sp: &'s Sp, path: &str, allowed: &[&str]) -> Res<Table<'s>> {
        let Node::Table(entries) = &sp.node else {
            return Err(self.wrong_type(sp, path, "a table"));
        };
        for (k, v) in entries {
            if !allowed.contains(&k.as_str()) {
                // A table made by a dotted header has no span: its first
                // key's line is the header's.
                let line = self.first_line(v).or_else(|| self.line(sp));
                let array = path.split('[').next().unwrap_or(path);
                let kind = if k.bytes().all(|b| b.is_ascii_digit()) && array != path {
                    MechanismErrorKind::NumberedTable {
                        key: join(path, k),
                        array: array.to_string(),
                    }
                } else {
                    MechanismErrorKind::UnknownKey {
                        key: join(path, k),
                        expected: allowed.join(", "),
                    }
                };
                return Err(self.err(line, kind));
            }
        }
        Ok(Table {
            entries,
            path: path.to_string(),
            line: self.line(sp),
        })
    }

    pub(crate) fn number(&self, sp: &Sp, key: &str, range: Bound, unit: &str) -> Res<f64> {
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

    pub(crate) fn req_number(
        &self,
        t: &Table<'_>,
        key: &str,
        range: Bound,
        unit: &str,
    ) -> Res<f64> {
        match t.get(key) {
            Some(sp) => self.number(sp, &t.key(key), range, unit),
            None => Err(self.missing(t, key, &range.describe(unit))),
        }
    }

    pub(crate) fn opt_number(
        &self,
        t: &Table<'_>,
        key: &str,
        range: Bound,
        unit: &str,
    ) -> Res<Option<f64>> {
        t.get(key)
            .map(|sp| self.number(sp, &t.key(key), range, unit))
            .transpose()
    }

    /// `[[T.name]]`: the tables of an array of tables in `t` (none when
    /// absent).
    pub(crate) fn tables<'s>(&self, t: &Table<'s>, name: &str) -> Res<&'s [Sp]> {
        match t.get(name) {
            None => Ok(&[]),
            Some(sp) => match &sp.node {
                Node::Array(items) => Ok(items),
                _ => Err(self.wrong_type(sp, &t.key(name), "an array of tables [[...]]")),
            },
        }
    }

    /// `key` of `t` as `true` or `false`; `default` when absent.
    pub(crate) fn opt_bool(&self, t: &Table<'_>, key: &str, default: bool) -> Res<bool> {
        match t.get(key) {
            None => Ok(default),
            Some(Sp {
                node: Node::Bool(b),
                ..
            }) => Ok(*b),
            Some(s) => Err(self.wrong_type(s, &t.key(key), "true or false")),
        }
    }

    pub(crate) fn string<'s>(&self, sp: &'s Sp, key: &str) -> Res<&'s str> {
        match &sp.node {
            Node::Str(s) => Ok(s),
            _ => Err(self.wrong_type(sp, key, "a string")),
        }
    }

    /// `[x, y]`: two numbers.
    pub(crate) fn pair(&self, sp: &Sp, key: &str, what: &str) -> Res<(f64, f64)> {
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
}

/// A TOML string, quoted and escaped by `toml_edit`.
pub fn toml_str(s: &str) -> String {
    toml_edit::Value::from(s).to_string()
}

/// A float in Rust's shortest round-trip form, valid TOML.
pub fn num(x: f64) -> String {
    if x.is_nan() {
        "nan".to_string()
    } else if x.is_infinite() {
        if x > 0.0 { "inf" } else { "-inf" }.to_string()
    } else {
        format!("{x:?}")
    }
}
