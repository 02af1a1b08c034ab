//! A crate's sources read into its module graph (which file names which),
//! and the import cycles of that graph.

use crate::lexer::{drop_test_modules, strip};
use crate::ModPath;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// One source file: its path below `src/` and its text.
pub struct Source {
    pub rel: PathBuf,
    pub text: String,
}

pub fn read_tree(src: &Path) -> Vec<Source> {
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
pub fn module_of(rel: &Path) -> ModPath {
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
pub fn named_paths(code: &str) -> Vec<(Vec<String>, usize)> {
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
pub fn without_renames(tree: &str) -> String {
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
pub fn find_use(s: &str) -> Option<usize> {
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
pub fn expand_use(prefix: &str, tree: &str, out: &mut Vec<Vec<String>>) {
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
pub fn split_top(s: &str) -> Vec<String> {
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

pub fn segments(path: &str) -> Vec<String> {
    path.split("::")
        .filter(|s| !s.is_empty())
        .map(str::to_string)
        .collect()
}

/// Resolves a named path from module `at` to the file module it lands in
/// (`None` for paths outside the crate: `std::`, other crates).
pub fn resolve(at: &ModPath, path: &[String], modules: &BTreeSet<ModPath>) -> Option<ModPath> {
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
pub struct Graph {
    pub edges: BTreeMap<ModPath, BTreeMap<ModPath, usize>>,
    pub files: BTreeMap<ModPath, PathBuf>,
}

pub fn graph(sources: &[Source]) -> Graph {
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

/// The shortest cycle through each module that is on one, each distinct
/// cycle once, with the lines that close it.
pub fn cycles(g: &Graph) -> Vec<String> {
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
pub fn shortest_cycle(g: &Graph, start: &ModPath) -> Option<Vec<ModPath>> {
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
