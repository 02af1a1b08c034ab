//! The `layers` block of `ARCHITECTURE.md` read into each crate's rule.

use crate::ModPath;
use std::collections::BTreeMap;
use std::path::Path;

/// One crate's rule: the layer of each entry, and the peers.
#[derive(Debug, Default, PartialEq)]
pub struct Layers {
    /// Module path → layer (0 is the lowest).
    pub layer: Vec<(ModPath, u8)>,
    /// Pairs of entries of one layer that must not name each other.
    pub peers: Vec<(ModPath, ModPath)>,
}

impl Layers {
    /// The entry a module belongs to: the longest entry that prefixes it.
    pub fn entry_of(&self, m: &ModPath) -> Option<&(ModPath, u8)> {
        self.layer
            .iter()
            .filter(|(p, _)| m.starts_with(p))
            .max_by_key(|(p, _)| p.len())
    }
}

/// The `layers` block of `text` (ARCHITECTURE.md): `CRATE:` lines, each
/// followed by `N: a, b ∥ c` lines (layer N holds `a`, `b` and `c`; `c` is
/// a peer of `a` and of `b`). Returns crate name → its rule.
pub fn parse_layers(text: &str) -> Result<BTreeMap<String, Layers>, String> {
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
pub fn layers_of(name: &str) -> Layers {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../ARCHITECTURE.md");
    let text = std::fs::read_to_string(&path).expect("ARCHITECTURE.md at the repository root");
    let mut all = parse_layers(&text).unwrap_or_else(|e| panic!("ARCHITECTURE.md: {e}"));
    all.remove(name)
        .unwrap_or_else(|| panic!("ARCHITECTURE.md: no `{name}:` in the layers block"))
}
