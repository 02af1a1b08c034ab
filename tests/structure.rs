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

#[path = "structure/checker_tests.rs"]
mod checker_tests;
#[path = "structure/graph.rs"]
mod graph;
#[path = "structure/layers.rs"]
mod layers;
#[path = "structure/lexer.rs"]
mod lexer;
#[path = "structure/rules.rs"]
mod rules;

use graph::{cycles, graph, read_tree};
use layers::{layers_of, Layers};
use lexer::strip;
use rules::{cli_violations, layer_violations, size_violations, stdout_prints};
use std::path::Path;

/// Longest source file, lines.
pub const MAX_FILE_LINES: usize = 700;
/// Longest function, lines.
pub const MAX_FN_LINES: usize = 80;

/// A module path below the crate root (`["analysis", "diagnose"]`).
pub type ModPath = Vec<String>;

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
    let long_file = "core/monitor/estimator.rs: 1493 lines (at most 700)";
    assert!(is_entry(long_fn, ("core/monitor/latch.rs", "fn step")));
    assert!(!is_entry(long_fn, ("core/monitor/latch.rs", "fn step_one")));
    assert!(!is_entry(long_fn, ("core/monitor/latch.rs", "lines")));
    assert!(is_entry(long_file, ("core/monitor/estimator.rs", "lines")));
    assert!(!is_entry(
        "cycle: core/monitor/latch.rs:3 → x",
        ("core/monitor/latch.rs", "lines")
    ));
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

/// The effect code (`ARCHITECTURE.md`, "A new named effect"): the files
/// whose `match`es give each named effect its arm.
const EFFECT_CODE: &[&str] = &[
    "model/effect.rs",
    "model/effect/",
    "model/findings/effects.rs",
    "model/rig.rs",
    "simulate/truss_deployment.rs",
    "simulate/latch_deployment/setup.rs",
    "analysis/effect_margin.rs",
    "analysis/resistances.rs",
    "analysis/diagnose/candidate.rs",
    "analysis/diagnose/residual_named.rs",
    "analysis/diagnose/friction_forms.rs",
    "analysis/diagnose/table_form.rs",
    "report/diagnosis.rs",
];

/// The catch-all arms that would let a new effect compile with nothing
/// (`_ => {}`), no torque (`_ => 0.0`) or one parameter (`_ => 1`): the
/// search `rg "_ => \{\}|_ => 0\.0|_ => 1\b"`, on the code with its
/// comments and strings blanked.
fn catch_all_arms(code: &str) -> Vec<usize> {
    let mut out = Vec::new();
    for (i, line) in code.lines().enumerate() {
        let mut rest = line;
        while let Some(k) = rest.find("_ =>") {
            let before = rest[..k].chars().next_back();
            let after = rest[k + 4..].trim_start();
            let word = |c: char| c.is_alphanumeric() || c == '_';
            let body_ends = |b: &str| b.chars().next().is_none_or(|c| !word(c) && c != '.');
            let silent = after.starts_with("{}")
                || after
                    .strip_prefix("0.0")
                    .is_some_and(|b| !b.starts_with(char::is_numeric))
                || after.strip_prefix('1').is_some_and(body_ends);
            if before.is_none_or(|c| !word(c)) && silent {
                out.push(i + 1);
                break;
            }
            rest = &rest[k + 4..];
        }
    }
    out
}

/// No catch-all arm in the effect code: every `match` over the effects
/// is exhaustive, so the compiler lists each place a new effect needs its
/// arm.
#[test]
fn the_effect_code_has_no_catch_all_arm() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("../host-sim/src");
    let mut files = Vec::new();
    for entry in EFFECT_CODE {
        let path = src.join(entry);
        if entry.ends_with('/') {
            let mut dir: Vec<_> = std::fs::read_dir(&path)
                .unwrap_or_else(|e| panic!("{entry}: {e}"))
                .map(|f| f.unwrap().path())
                .filter(|p| p.extension().is_some_and(|x| x == "rs"))
                .collect();
            dir.sort();
            files.extend(dir);
        } else {
            assert!(path.is_file(), "{entry}: no such file");
            files.push(path);
        }
    }
    let mut found = Vec::new();
    for f in &files {
        let code = strip(&std::fs::read_to_string(f).unwrap());
        for line in catch_all_arms(&code) {
            found.push(format!("{}:{line}", f.display()));
        }
    }
    assert!(
        found.is_empty(),
        "catch-all arms in the effect code: {found:#?}"
    );
    // The check finds what it looks for.
    for bad in ["_ => {}", "x => 2, _ => 0.0,", "_ => 1,", "_ =>   1 }"] {
        assert_eq!(catch_all_arms(bad), vec![1], "{bad}");
    }
    for fine in [
        "_ => 1.5,",
        "_ => 10,",
        "a_ => {}",
        "_ => 0.05,",
        "_ => true",
    ] {
        assert!(catch_all_arms(fine).is_empty(), "{fine}");
    }
}
