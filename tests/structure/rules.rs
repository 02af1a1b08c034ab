//! The rules checked over a crate's graph and sources: layers, stdout,
//! sizes, and what the command line may hold.

use crate::graph::{Graph, Source};
use crate::layers::Layers;
use crate::lexer::{drop_test_modules, matching_brace, strip};
use crate::{MAX_FILE_LINES, MAX_FN_LINES};

/// Lines naming a module of a higher layer, a peer, or the crate root.
pub fn layer_violations(g: &Graph, rule: &Layers) -> Vec<String> {
    let mut out = Vec::new();
    for (from, tos) in &g.edges {
        if from.is_empty() {
            continue;
        }
        let file = g.files[from].display();
        let Some((ef, lf)) = rule.entry_of(from) else {
            out.push(format!(
                "{file}: module `{}` is in no layer of ARCHITECTURE.md (entries: {:?})",
                from.join("::"),
                rule.layer
                    .iter()
                    .map(|(n, _)| n.join("::"))
                    .collect::<Vec<_>>()
            ));
            continue;
        };
        for (to, line) in tos {
            if to.is_empty() {
                out.push(format!(
                    "{file}:{line}: names the crate root; name the module that holds the item"
                ));
                continue;
            }
            let (et, lt) = rule
                .entry_of(to)
                .map_or((None, u8::MAX), |(e, l)| (Some(e), *l));
            let peers = et.is_some_and(|et| {
                rule.peers
                    .iter()
                    .any(|(a, b)| (a == ef && b == et) || (a == et && b == ef))
            });
            if lt > *lf || peers {
                out.push(format!(
                    "{file}:{line}: `{}` (layer {lf}) names `{}` (layer {lt}{})",
                    from.join("::"),
                    to.join("::"),
                    if peers { ", a peer" } else { "" }
                ));
            }
        }
    }
    out
}

/// Lines of `host-sim/src` that print to stdout with `print!`/`println!`
/// (outside comments, strings and test modules).
pub fn stdout_prints(sources: &[Source], root: &str) -> Vec<String> {
    let mut out = Vec::new();
    for s in sources {
        let (code, _) = drop_test_modules(&strip(&s.text));
        for (i, line) in code.lines().enumerate() {
            let found = ["println!", "print!"].iter().any(|m| {
                line.match_indices(m).any(|(at, _)| {
                    let before = line[..at].chars().next_back();
                    before.is_none_or(|c| !(c.is_alphanumeric() || c == '_'))
                })
            });
            if found {
                out.push(format!(
                    "{root}/{}:{}: prints to stdout; use `cli::outln!` (a closed stdout must not panic)",
                    s.rel.display(),
                    i + 1
                ));
            }
        }
    }
    out
}

/// Files over [`MAX_FILE_LINES`] and functions over [`MAX_FN_LINES`].
pub fn size_violations(sources: &[Source], root: &str) -> Vec<String> {
    let mut out = Vec::new();
    for s in sources {
        let file = format!("{root}/{}", s.rel.display());
        let n = s.text.lines().count();
        if n > MAX_FILE_LINES {
            out.push(format!("{file}: {n} lines (at most {MAX_FILE_LINES})"));
        }
        for (name, line, len) in long_functions(&strip(&s.text)) {
            out.push(format!(
                "{file}:{line}: fn {name} is {len} lines (at most {MAX_FN_LINES})"
            ));
        }
    }
    out
}

/// `(name, first line, lines)` of every function longer than [`MAX_FN_LINES`].
pub fn long_functions(code: &str) -> Vec<(String, usize, usize)> {
    let mut out = Vec::new();
    let line_of = |at: usize| code[..at].matches('\n').count() + 1;
    let mut from = 0;
    while let Some(k) = code[from..].find("fn ") {
        let at = from + k;
        from = at + 3;
        let before = code[..at].chars().next_back();
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
            continue;
        }
        let name: String = code[at + 3..]
            .trim_start()
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        if name.is_empty() {
            continue;
        }
        let (Some(semi), Some(open)) = (
            code[at..].find(';').map(|x| x + at).or(Some(usize::MAX)),
            code[at..].find('{').map(|x| x + at),
        ) else {
            continue;
        };
        if semi < open {
            continue;
        }
        let close = matching_brace(code, open);
        let len = line_of(close.saturating_sub(1)) - line_of(at) + 1;
        if len > MAX_FN_LINES {
            out.push((name, line_of(at), len));
        }
    }
    out
}

/// Numeric primitive types: a `const` of one of them in `cli/` is a
/// threshold or a limit.
pub const NUMERIC: &[&str] = &[
    "f32", "f64", "u8", "u16", "u32", "u64", "u128", "usize", "i8", "i16", "i32", "i64", "i128",
    "isize",
];

/// What `host-sim/src/cli` must not hold (`ARCHITECTURE.md`, `cli/`: parse,
/// call the library, write its outputs, print its result): text built
/// with `write!`/`writeln!` (a report or a table: written in `report/`), a
/// module that draws or links figures named (`report::plot`,
/// `report::markdown`: figures are drawn in `report/`), a numeric `const`
/// (a threshold or a limit: it belongs to the analysis).
pub fn cli_violations(g: &Graph, sources: &[Source], root: &str) -> Vec<String> {
    let mut out = Vec::new();
    for (from, tos) in g
        .edges
        .iter()
        .filter(|(m, _)| m.first().is_some_and(|f| f == "cli"))
    {
        for (to, line) in tos {
            if to.starts_with(&["report".to_string(), "plot".to_string()])
                || to.starts_with(&["report".to_string(), "markdown".to_string()])
            {
                out.push(format!(
                    "{root}/{}:{line}: names `{}`: figures and report text are written in report/",
                    g.files[from].display(),
                    to.join("::")
                ));
            }
        }
    }
    for s in sources.iter().filter(|s| s.rel.starts_with("cli")) {
        let (code, _) = drop_test_modules(&strip(&s.text));
        for (i, line) in code.lines().enumerate() {
            let at = |what: &str| {
                line.match_indices(what).any(|(k, _)| {
                    line[..k]
                        .chars()
                        .next_back()
                        .is_none_or(|c| !(c.is_alphanumeric() || c == '_'))
                })
            };
            let why = if at("write!") || at("writeln!") || at("plotters") {
                "builds report text or draws: that is written in report/"
            } else if at("const ") && numeric_const(line) {
                "a numeric constant (a threshold or a limit): it belongs to analysis/"
            } else {
                continue;
            };
            out.push(format!("{root}/{}:{}: {why}", s.rel.display(), i + 1));
        }
    }
    out
}

/// True when the `const` item on `line` has a numeric type (`const X: f64`,
/// `const X: [usize; 3]`).
pub fn numeric_const(line: &str) -> bool {
    let Some(k) = line.find("const ") else {
        return false;
    };
    let rest = &line[k + 6..];
    let ty = rest
        .split_once(':')
        .map_or("", |(_, t)| t.split('=').next().unwrap_or(""));
    ty.split(|c: char| !(c.is_alphanumeric() || c == '_'))
        .any(|w| NUMERIC.contains(&w))
}
