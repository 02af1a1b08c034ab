//! The shape of the two library crates, checked from their sources, with
//! the layers read from the one place that states them: the fenced
//! `layers` block of `ARCHITECTURE.md` ("Code map").
//!
//! - **layers point one way**: a module never names one of a higher layer,
//!   and modules of one layer written `a ∥ b` (peers) never name each
//!   other. A layer entry is a module path (`model`, `report::plot`); a
//!   module belongs to the entry that is the longest prefix of its path,
//!   so `report::plot` (a leaf utility) can sit below `report`. Every
//!   top-level module must be in the list;
//! - **no import cycles** at file granularity, inside a layer too: each `.rs`
//!   file is a module (`foo/mod.rs` is `foo`), and a file names another when
//!   its non-test code holds a path `crate::…`, `super::…` or `self::…` that
//!   resolves to it (the longest prefix that is a file). A `pub use
//!   self::child::X` in a `mod.rs` names the child; a child naming
//!   `super::X` names its parent; a path may also start at a child module
//!   (`pub use child::X`). Nothing names the crate root (`lib.rs`):
//!   items are named by the module that holds them;
//! - **sizes**: no file over [`MAX_FILE_LINES`] lines and no function over
//!   [`MAX_FN_LINES`] lines (from its `fn` line to its closing brace);
//! - **stdout**: no `print!`/`println!` in `host-sim/src`: the library
//!   never prints, and the command line prints its result through
//!   `cli::outln!`, which a closed stdout does not stop;
//! - **the command line parses, calls, writes**: no `write!`/`writeln!`
//!   (report text), no `report::plot`/`report::markdown`/`plotters`
//!   (figures) and no numeric `const` (a threshold) in `host-sim/src/cli`:
//!   reports are written in `report/`, thresholds live in `analysis/`.
//!
//! `#[cfg(test)]` modules (inline, or files declared `#[cfg(test)] mod x;`)
//! are left out of the graph; the sizes count them.
//!
//! `cargo test -p deploywatch-tests --test structure`

#[path = "structure/lexer.rs"]
mod lexer;

use lexer::{drop_test_modules, matching_brace, strip};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Longest source file, lines.
const MAX_FILE_LINES: usize = 900;
/// Longest function, lines.
const MAX_FN_LINES: usize = 80;

/// A module path below the crate root (`["analysis", "diagnose"]`).
type ModPath = Vec<String>;

/// One crate's rule: the layer of each entry, and the peers.
#[derive(Debug, Default, PartialEq)]
struct Layers {
    /// Module path → layer (0 is the lowest).
    layer: Vec<(ModPath, u8)>,
    /// Pairs of entries of one layer that must not name each other.
    peers: Vec<(ModPath, ModPath)>,
}

impl Layers {
    /// The entry a module belongs to: the longest entry that prefixes it.
    fn entry_of(&self, m: &ModPath) -> Option<&(ModPath, u8)> {
        self.layer
            .iter()
            .filter(|(p, _)| m.starts_with(p))
            .max_by_key(|(p, _)| p.len())
    }
}

/// The `layers` block of `text` (ARCHITECTURE.md): `CRATE:` lines, each
/// followed by `N: a, b ∥ c` lines (layer N holds `a`, `b` and `c`; `c` is
/// a peer of `a` and of `b`). Returns crate name → its rule.
fn parse_layers(text: &str) -> Result<BTreeMap<String, Layers>, String> {
    let start = text
        .find("```layers\n")
        .ok_or("no ```layers block in ARCHITECTURE.md")?;
    let body = &text[start + 10..];
    let body = &body[..body
        .find("```")
        .ok_or("the ```layers block is not closed")?];
    let mut out: BTreeMap<String, Layers> = BTreeMap::new();
    let mut current: Option<String> = None;
    for line in body.lines().map(str::trim).filter(|l| !l.is_empty()) {
        if let Some(name) = line.strip_suffix(':') {
            current = Some(name.to_string());
            out.entry(name.to_string()).or_default();
            continue;
        }
        let (n, list) = line
            .split_once(':')
            .ok_or_else(|| format!("expected `N: modules`, found {line:?}"))?;
        let n: u8 = n
            .trim()
            .parse()
            .map_err(|_| format!("bad layer number in {line:?}"))?;
        let rule = out
            .get_mut(
                current
                    .as_deref()
                    .ok_or("a layer line before any `crate:` line")?,
            )
            .expect("entry made above");
        let groups: Vec<Vec<ModPath>> = list
            .split('∥')
            .map(|g| {
                g.split(',')
                    .map(|m| m.trim().split("::").map(str::to_string).collect())
                    .filter(|m: &ModPath| m.iter().all(|s| !s.is_empty()))
                    .collect()
            })
            .collect();
        for (i, g) in groups.iter().enumerate() {
            for m in g {
                rule.layer.push((m.clone(), n));
                for other in groups.iter().skip(i + 1).flatten() {
                    rule.peers.push((m.clone(), other.clone()));
                }
            }
        }
    }
    Ok(out)
}

/// The rule of crate `name` (`host-sim`, `core`) from ARCHITECTURE.md.
fn layers_of(name: &str) -> Layers {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../ARCHITECTURE.md");
    let text = std::fs::read_to_string(&path).expect("ARCHITECTURE.md at the repository root");
    let mut all = parse_layers(&text).unwrap_or_else(|e| panic!("ARCHITECTURE.md: {e}"));
    all.remove(name)
        .unwrap_or_else(|| panic!("ARCHITECTURE.md: no `{name}:` in the layers block"))
}

/// One source file: its path below `src/` and its text.
struct Source {
    rel: PathBuf,
    text: String,
}

fn read_tree(src: &Path) -> Vec<Source> {
    let mut out = Vec::new();
    let mut stack = vec![src.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let p = entry.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|e| e == "rs") {
                let text = std::fs::read_to_string(&p).unwrap();
                let rel = p.strip_prefix(src).unwrap().to_path_buf();
                out.push(Source { rel, text });
            }
        }
    }
    out.sort_by(|a, b| a.rel.cmp(&b.rel));
    out
}

/// The module a file is (`a/b.rs` and `a/b/mod.rs` are `a::b`; `lib.rs`
/// and `main.rs` are the root, `[]`).
fn module_of(rel: &Path) -> ModPath {
    let mut parts: Vec<String> = rel
        .iter()
        .map(|c| c.to_string_lossy().into_owned())
        .collect();
    let last = parts.pop().unwrap_or_default();
    let stem = last.trim_end_matches(".rs");
    if !matches!(stem, "mod" | "lib" | "main") {
        parts.push(stem.to_string());
    }
    parts
}

/// Every path a file's code names, with the byte offset naming it: `use`
/// trees (braces expanded, `as` renames dropped), then the inline
/// `crate::`/`super::` paths of the code outside `use` items.
fn named_paths(code: &str) -> Vec<(Vec<String>, usize)> {
    let mut out = Vec::new();
    let mut rest = code.to_string();
    let mut from = 0;
    while let Some(k) = find_use(&rest[from..]) {
        let at = from + k;
        let body_start = at + 4;
        let end = body_start + rest[body_start..].find(';').unwrap_or(0);
        let tree = without_renames(&rest[body_start..end]);
        let mut paths = Vec::new();
        expand_use("", &tree, &mut paths);
        out.extend(paths.into_iter().map(|p| (p, at)));
        let blank: String = rest[at..end]
            .chars()
            .map(|c| if c == '\n' { '\n' } else { ' ' })
            .collect();
        rest.replace_range(at..end, &blank);
        from = end;
    }
    for (i, _) in rest.char_indices() {
        let s = &rest[i..];
        let boundary = rest[..i]
            .chars()
            .next_back()
            .is_none_or(|p| !(p.is_alphanumeric() || p == '_' || p == ':'));
        if boundary && (s.starts_with("crate::") || s.starts_with("super::")) {
            let path: String = s
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
                .collect();
            out.push((segments(&path), i));
        }
    }
    out
}

/// A use tree without white space and without its `as name` renames.
fn without_renames(tree: &str) -> String {
    let words: Vec<&str> = tree.split_whitespace().collect();
    let mut kept = String::new();
    let mut i = 0;
    while i < words.len() {
        if words[i] == "as" && i + 1 < words.len() {
            // `as name` or `as name,` / `as name}`: keep the punctuation.
            let tail: String = words[i + 1]
                .chars()
                .skip_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            kept.push_str(&tail);
            i += 2;
        } else {
            kept.push_str(words[i]);
            i += 1;
        }
    }
    kept
}

/// The byte offset of the next `use ` item keyword.
fn find_use(s: &str) -> Option<usize> {
    let mut from = 0;
    while let Some(at) = s[from..].find("use ") {
        let i = from + at;
        let before = s[..i].chars().next_back();
        if before.is_none_or(|c| !(c.is_alphanumeric() || c == '_')) {
            return Some(i);
        }
        from = i + 4;
    }
    None
}

/// Expands a whitespace-free use tree (`a::{b,c::{d,e}}`) into paths.
fn expand_use(prefix: &str, tree: &str, out: &mut Vec<Vec<String>>) {
    let tree = tree.trim_start_matches("::");
    if let Some(open) = tree.find('{') {
        let head = format!("{prefix}{}", &tree[..open]);
        let inner = &tree[open + 1..tree.rfind('}').unwrap_or(tree.len())];
        for part in split_top(inner) {
            expand_use(&head, &part, out);
        }
    } else {
        out.push(segments(&format!("{prefix}{tree}")));
    }
}

/// Splits at top-level commas.
fn split_top(s: &str) -> Vec<String> {
    let (mut parts, mut cur, mut depth) = (Vec::new(), String::new(), 0);
    for c in s.chars() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                parts.push(std::mem::take(&mut cur));
                continue;
            }
            _ => {}
        }
        cur.push(c);
    }
    if !cur.is_empty() {
        parts.push(cur);
    }
    parts
}

fn segments(path: &str) -> Vec<String> {
    path.split("::")
        .filter(|s| !s.is_empty())
        .map(str::to_string)
        .collect()
}

/// Resolves a named path from module `at` to the file module it lands in
/// (`None` for paths outside the crate: `std::`, other crates).
fn resolve(at: &ModPath, path: &[String], modules: &BTreeSet<ModPath>) -> Option<ModPath> {
    let first = path.first()?;
    let mut base: ModPath = match first.as_str() {
        "crate" => Vec::new(),
        "self" | "super" => at.clone(),
        // A path relative to this module (`pub use child::X`).
        _ if modules.contains(&[at.as_slice(), std::slice::from_ref(first)].concat()) => at.clone(),
        _ => return None,
    };
    let mut i = if path[0] == "crate" { 1 } else { 0 };
    while i < path.len() && (path[i] == "super" || path[i] == "self") {
        if path[i] == "super" {
            base.pop();
        }
        i += 1;
    }
    let mut best = base.clone();
    let mut cur = base;
    for seg in &path[i..] {
        cur.push(seg.clone());
        if modules.contains(&cur) {
            best = cur.clone();
        } else {
            break;
        }
    }
    Some(best)
}

/// One crate's module graph: module → (named module → first line naming it).
struct Graph {
    edges: BTreeMap<ModPath, BTreeMap<ModPath, usize>>,
    files: BTreeMap<ModPath, PathBuf>,
}

fn graph(sources: &[Source]) -> Graph {
    let modules: BTreeSet<ModPath> = sources.iter().map(|s| module_of(&s.rel)).collect();
    let mut test_mods: BTreeSet<ModPath> = BTreeSet::new();
    let mut code: BTreeMap<ModPath, String> = BTreeMap::new();
    let mut files = BTreeMap::new();
    for s in sources {
        let m = module_of(&s.rel);
        let (c, tests) = drop_test_modules(&strip(&s.text));
        for t in tests {
            let mut child = m.clone();
            child.push(t);
            test_mods.insert(child);
        }
        code.insert(m.clone(), c);
        files.insert(m, s.rel.clone());
    }
    let mut edges: BTreeMap<ModPath, BTreeMap<ModPath, usize>> = BTreeMap::new();
    for (m, c) in &code {
        if test_mods.iter().any(|t| m.starts_with(t)) {
            continue;
        }
        let e = edges.entry(m.clone()).or_default();
        for (p, at) in named_paths(c) {
            if let Some(to) = resolve(m, &p, &modules) {
                if &to != m && !test_mods.contains(&to) {
                    let line = c[..at].matches('\n').count() + 1;
                    let first = e.entry(to).or_insert(line);
                    *first = (*first).min(line);
                }
            }
        }
    }
    Graph { edges, files }
}

/// Lines naming a module of a higher layer, a peer, or the crate root.
fn layer_violations(g: &Graph, rule: &Layers) -> Vec<String> {
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
fn stdout_prints(sources: &[Source], root: &str) -> Vec<String> {
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

/// The shortest cycle through each module that is on one, each distinct
/// cycle once, with the lines that close it.
fn cycles(g: &Graph) -> Vec<String> {
    let mut out = Vec::new();
    let mut seen: BTreeSet<BTreeSet<ModPath>> = BTreeSet::new();
    for start in g.edges.keys() {
        let Some(cycle) = shortest_cycle(g, start) else {
            continue;
        };
        if !seen.insert(cycle.iter().cloned().collect()) {
            continue;
        }
        let text: Vec<String> = cycle
            .windows(2)
            .map(|w| {
                let line = g.edges[&w[0]][&w[1]];
                format!("{}:{line} → {}", g.files[&w[0]].display(), w[1].join("::"))
            })
            .collect();
        out.push(format!("cycle: {}", text.join(", ")));
    }
    out
}

/// The shortest path from `start` back to itself (breadth first).
fn shortest_cycle(g: &Graph, start: &ModPath) -> Option<Vec<ModPath>> {
    let mut prev: BTreeMap<ModPath, ModPath> = BTreeMap::new();
    let mut queue = std::collections::VecDeque::from([start.clone()]);
    while let Some(m) = queue.pop_front() {
        for to in g.edges.get(&m).into_iter().flat_map(|e| e.keys()) {
            if to == start {
                let mut path = vec![m.clone()];
                let mut cur = m.clone();
                while &cur != start {
                    cur = prev[&cur].clone();
                    path.push(cur.clone());
                }
                path.reverse();
                path.push(start.clone());
                return Some(path);
            }
            if !prev.contains_key(to) && to != start {
                prev.insert(to.clone(), m.clone());
                queue.push_back(to.clone());
            }
        }
    }
    None
}

/// Files over [`MAX_FILE_LINES`] and functions over [`MAX_FN_LINES`].
fn size_violations(sources: &[Source], root: &str) -> Vec<String> {
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
fn long_functions(code: &str) -> Vec<(String, usize, usize)> {
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
const NUMERIC: &[&str] = &[
    "f32", "f64", "u8", "u16", "u32", "u64", "u128", "usize", "i8", "i16", "i32", "i64", "i128",
    "isize",
];

/// What `host-sim/src/cli` must not hold (`ARCHITECTURE.md`, `cli/`: parse,
/// call the library, write its outputs, print its result): text built
/// with `write!`/`writeln!` (a report or a table: written in `report/`), a
/// module that draws or links figures named (`report::plot`,
/// `report::markdown`: figures are drawn in `report/`), a numeric `const`
/// (a threshold or a limit: it belongs to the analysis).
fn cli_violations(g: &Graph, sources: &[Source], root: &str) -> Vec<String> {
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
fn numeric_const(line: &str) -> bool {
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

fn check_crate(root: &str, rule: &Layers) -> Vec<String> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(root)
        .join("src");
    let sources = read_tree(&src);
    let g = graph(&sources);
    let mut out = layer_violations(&g, rule);
    out.extend(cycles(&g));
    out.extend(size_violations(&sources, root));
    if root == "host-sim" {
        out.extend(stdout_prints(&sources, root));
        out.extend(cli_violations(&g, &sources, root));
    }
    out
}

/// Findings not resolved yet, each `(file, what)`: the file below the
/// repository root and `"lines"` (the file's size) or `"fn NAME"`. The
/// list only shrinks: a finding not in it fails the test, and so does an
/// entry that no longer matches a finding (remove it).
const NOT_YET: &[(&str, &str)] = &[];

/// True when `finding` is the entry `(file, what)` of [`NOT_YET`].
fn is_entry(finding: &str, (file, what): (&str, &str)) -> bool {
    let Some(rest) = finding.strip_prefix(file) else {
        return false;
    };
    match what {
        "lines" => {
            rest.starts_with(": ") && rest.ends_with(&format!("lines (at most {MAX_FILE_LINES})"))
        }
        name => rest.starts_with(':') && rest.contains(&format!(": {name} is ")),
    }
}

/// Fails with every finding of crate `root` outside [`NOT_YET`], and with
/// every entry of [`NOT_YET`] under `root` that no finding matches.
fn assert_clean(root: &str, found: Vec<String>) {
    let new: Vec<&str> = found
        .iter()
        .map(String::as_str)
        .filter(|f| !NOT_YET.iter().any(|&e| is_entry(f, e)))
        .collect();
    let gone: Vec<&(&str, &str)> = NOT_YET
        .iter()
        .filter(|(file, _)| file.starts_with(&format!("{root}/")))
        .filter(|&&e| !found.iter().any(|f| is_entry(f, e)))
        .collect();
    assert!(
        new.is_empty() && gone.is_empty(),
        "{} findings:\n{}\nentries of NOT_YET resolved (remove them): {gone:?}",
        new.len(),
        new.join("\n")
    );
}

#[test]
fn host_sim_layers_point_one_way_without_cycles_or_long_code() {
    assert_clean("host-sim", check_crate("host-sim", &layers_of("host-sim")));
}

#[test]
fn core_layers_point_one_way_without_cycles_or_long_code() {
    assert_clean("core", check_crate("core", &layers_of("core")));
}

#[test]
fn not_yet_entries_match_only_their_own_finding() {
    let long_fn = "core/monitor/latch.rs:287: fn step is 164 lines (at most 80)";
    let long_file = "core/monitor/estimator.rs: 1493 lines (at most 900)";
    assert!(is_entry(long_fn, ("core/monitor/latch.rs", "fn step")));
    assert!(!is_entry(long_fn, ("core/monitor/latch.rs", "fn step_one")));
    assert!(!is_entry(long_fn, ("core/monitor/latch.rs", "lines")));
    assert!(is_entry(long_file, ("core/monitor/estimator.rs", "lines")));
    assert!(!is_entry(
        "cycle: core/monitor/latch.rs:3 → x",
        ("core/monitor/latch.rs", "lines")
    ));
}

// The checker on small trees of its own, so that it can be seen to fail.

fn tree(files: &[(&str, &str)]) -> Vec<Source> {
    files
        .iter()
        .map(|(rel, text)| Source {
            rel: PathBuf::from(rel),
            text: text.to_string(),
        })
        .collect()
}

#[test]
fn checker_finds_a_two_file_cycle_through_a_use_group() {
    let t = tree(&[
        ("lib.rs", "pub mod model;\n"),
        ("model/mod.rs", "pub mod a;\npub mod b;\n"),
        (
            "model/a.rs",
            "use crate::model::{b::B, x};\npub struct A;\n",
        ),
        ("model/b.rs", "pub struct B(super::a::A);\n"),
    ]);
    let found = cycles(&graph(&t));
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(found[0].contains("model/a.rs:1"), "{found:?}");
}

#[test]
fn checker_finds_a_parent_child_cycle_and_ignores_test_modules() {
    let t = tree(&[
        ("lib.rs", "pub mod m;\n"),
        ("m/mod.rs", "mod c;\npub use c::C;\npub struct P;\n"),
        (
            "m/c.rs",
            "pub struct C(super::P);\n#[cfg(test)]\nmod tests {\n use crate::m::P;\n}\n",
        ),
        (
            "m/d.rs",
            "#[cfg(test)]\nmod tests { use super::super::P; }\n",
        ),
    ]);
    let found = cycles(&graph(&t));
    assert_eq!(found.len(), 1, "{found:?}");
    let g = graph(&t);
    assert!(g.edges[&vec!["m".to_string(), "d".to_string()]].is_empty());
}

#[test]
fn checker_finds_an_upward_import_and_a_peer_import() {
    let t = tree(&[
        (
            "lib.rs",
            "pub mod model; pub mod cli; pub mod analysis; pub mod onboard;\n",
        ),
        ("model.rs", "fn f() { crate::cli::run(); }\n"),
        ("cli.rs", "use crate::model;\n"),
        ("analysis.rs", "use crate::onboard::X;\n"),
        ("onboard.rs", "pub struct X;\n"),
    ]);
    let found = layer_violations(&graph(&t), &layers_of("host-sim"));
    assert_eq!(found.len(), 2, "{found:?}");
    assert!(
        found.iter().any(|f| f.starts_with("model.rs:1")),
        "{found:?}"
    );
    assert!(found.iter().any(|f| f.contains("a peer")), "{found:?}");
}

#[test]
fn checker_ignores_paths_in_comments_and_strings() {
    let t = tree(&[
        ("lib.rs", "pub mod model; pub mod cli;\n"),
        (
            "model.rs",
            "// crate::cli::run()\nconst S: &str = \"crate::cli\";\n/* use crate::cli; */\n",
        ),
        ("cli.rs", "use crate::model;\n"),
    ]);
    assert!(layer_violations(&graph(&t), &layers_of("host-sim")).is_empty());
}

#[test]
fn checker_measures_functions_from_fn_to_closing_brace() {
    let body = "    let x = 1;\n".repeat(MAX_FN_LINES);
    let long = format!("fn long() {{\n{body}}}\nfn short() {{ let s = \"}}\"; }}\n");
    let found = long_functions(&strip(&long));
    assert_eq!(found, vec![("long".to_string(), 1, MAX_FN_LINES + 2)]);
}

#[test]
fn the_layers_block_is_parsed_with_sub_module_entries_and_peers() {
    let text = "x\n```layers\nhost-sim:\n  0: paper, report::plot\n  1: model\n  4: analysis ∥ onboard\n  5: report\ncore:\n  0: physics\n```\n";
    let all = parse_layers(text).unwrap();
    let host = &all["host-sim"];
    let p = |s: &str| -> ModPath { s.split("::").map(str::to_string).collect() };
    assert_eq!(host.entry_of(&p("report::plot::x")).unwrap().1, 0);
    assert_eq!(host.entry_of(&p("report::diagnosis")).unwrap().1, 5);
    assert_eq!(host.peers, vec![(p("analysis"), p("onboard"))]);
    assert_eq!(all["core"].layer, vec![(p("physics"), 0)]);
    assert!(parse_layers("no block").is_err());
}

#[test]
fn checker_finds_a_leaf_utility_naming_its_higher_parent_and_a_print() {
    let t = tree(&[
        ("lib.rs", "pub mod report; pub mod cli;\n"),
        ("report/mod.rs", "pub mod plot;\npub struct R;\n"),
        ("report/plot.rs", "use super::R;\n"),
        ("cli.rs", "fn f() { println!(\"x\"); eprintln!(\"y\"); }\n"),
    ]);
    let found = layer_violations(&graph(&t), &layers_of("host-sim"));
    assert!(
        found.iter().any(|f| f.starts_with("report/plot.rs:1")),
        "{found:?}"
    );
    let prints = stdout_prints(&t, "host-sim");
    assert_eq!(prints.len(), 1, "{prints:?}");
    assert!(prints[0].starts_with("host-sim/cli.rs:1"), "{prints:?}");
}

#[test]
fn checker_finds_report_writing_and_a_threshold_in_cli() {
    let t = tree(&[
        ("lib.rs", "pub mod report; pub mod cli;\n"),
        ("report/mod.rs", "pub mod plot;\npub mod files;\n"),
        ("report/plot.rs", "pub fn draw() {}\n"),
        ("report/files.rs", "pub struct Outputs;\n"),
        (
            "cli/mod.rs",
            "use crate::report::files::Outputs;\nuse crate::report::plot;\n\
             const LIMIT: f64 = 3.0;\nconst NAME: &str = \"x\";\n\
             fn f(md: &mut String) { let _ = writeln!(md, \"# title\"); }\n\
             #[cfg(test)]\nmod tests { const N: usize = 3; }\n",
        ),
    ]);
    let found = cli_violations(&graph(&t), &t, "host-sim");
    assert_eq!(found.len(), 3, "{found:?}");
    assert!(
        found[0].starts_with("host-sim/cli/mod.rs:2: names `report::plot`"),
        "{found:?}"
    );
    assert!(
        found[1].starts_with("host-sim/cli/mod.rs:3: a numeric constant"),
        "{found:?}"
    );
    assert!(
        found[2].starts_with("host-sim/cli/mod.rs:5: builds report text"),
        "{found:?}"
    );
}

/// The layers of `deploywatch-sim` are private to the crate (`mod
/// analysis;`): what others use is the curated root of `lib.rs`
/// (`ARCHITECTURE.md`, "The public API of `deploywatch-sim`"). The one
/// public file module is `cli`, which the binary runs.
#[test]
fn host_sim_layers_are_private_behind_the_public_api() {
    let lib = Path::new(env!("CARGO_MANIFEST_DIR")).join("../host-sim/src/lib.rs");
    let code = strip(&std::fs::read_to_string(lib).unwrap());
    let public: Vec<&str> = code
        .lines()
        .map(str::trim)
        .filter_map(|l| l.strip_prefix("pub mod ")?.strip_suffix(';'))
        .filter(|m| *m != "cli")
        .collect();
    assert!(
        public.is_empty(),
        "public layers {public:?}: declare them `mod x;` and re-export what is used"
    );
    let layers = layers_of("host-sim");
    for (entry, _) in layers.layer.iter().filter(|(e, _)| e.len() == 1) {
        let name = &entry[0];
        if name == "cli" {
            continue;
        }
        assert!(
            code.lines().any(|l| l.trim() == format!("mod {name};")),
            "lib.rs: expected `mod {name};`"
        );
    }
}
