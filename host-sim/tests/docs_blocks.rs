//! Every TOML and CSV block of the docs parses: the examples a new user
//! copies from `README.md` and `docs/**/*.md` are read by the project's own
//! readers, as a user's file would be.
//!
//! - A ```` ```toml ```` block is valid TOML 1.0 (the reader's). Then, by what it
//!   holds:
//!   - a whole mechanism (`[[panel]]`): `Mechanism::from_toml_str` loads it;
//!   - a joint with its latch (`[[joint]]` without panels): loaded inside a
//!     one-panel mechanism with the tape-spring types of
//!     `data/mechanisms/seed001_T01.toml`;
//!   - a `[rig]`: loaded appended to `data/mechanisms/seed001_T01.toml`;
//!   - a `[truss]` excerpt (points and links of a larger wing) or a Cargo
//!     manifest: valid TOML only, the one thing an excerpt can be.
//! - A ```` ```csv ```` block, or an unlabelled block whose header starts `t_s`,
//!   is a run: `Run::parse` reads it.
//!
//! `cargo test -p deploywatch-sim --test docs_blocks`

mod common;

use std::path::{Path, PathBuf};

use common::data;

use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::run::Run;

/// The repository's root.
fn root() -> PathBuf {
    data().parent().expect("repository root").to_path_buf()
}

/// README.md and every Markdown file under docs/, sorted.
fn markdown_files() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).expect("docs folder") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "md") {
                out.push(path);
            }
        }
    }
    let mut out = vec![root().join("README.md")];
    walk(&root().join("docs"), &mut out);
    out.sort();
    out
}

/// One fenced block: its file, the line of its opening fence, its language
/// tag (empty when none) and its text.
struct Block {
    file: PathBuf,
    line: usize,
    lang: String,
    text: String,
}

/// The fenced blocks of a Markdown text (fences of three backticks at the
/// line's start, as the docs write them).
fn blocks(file: &Path) -> Vec<Block> {
    let text = std::fs::read_to_string(file).expect("markdown file");
    let mut out = Vec::new();
    let mut open: Option<Block> = None;
    for (i, line) in text.lines().enumerate() {
        // A fence is three backticks, not four (```` ```toml ```` is code
        // in a sentence).
        let fence = line
            .trim_start()
            .strip_prefix("```")
            .filter(|rest| !rest.starts_with('`'));
        match (fence, open.take()) {
            (Some(_), Some(block)) => out.push(block),
            (Some(tag), None) => {
                open = Some(Block {
                    file: file.to_path_buf(),
                    line: i + 1,
                    lang: tag.trim().to_string(),
                    text: String::new(),
                })
            }
            (None, Some(mut block)) => {
                block.text.push_str(line);
                block.text.push('\n');
                open = Some(block);
            }
            (None, None) => {}
        }
    }
    assert!(
        open.is_none(),
        "{}: a fence is never closed",
        file.display()
    );
    out
}

/// Whether an unlabelled block is a run: its first line that is not
/// metadata is a header starting `t_s`.
fn looks_like_run(text: &str) -> bool {
    text.lines()
        .find(|l| !l.starts_with('#'))
        .is_some_and(|l| l.starts_with("t_s"))
}

/// The text of `data/mechanisms/NAME`.
fn bundled(name: &str) -> String {
    std::fs::read_to_string(data().join("mechanisms").join(name)).expect("bundled mechanism")
}

/// The `[tape."..."]` tables of seed 001 T01 (the tape-spring types).
fn tape_types() -> String {
    let text = bundled("seed001_T01.toml");
    let start = text.find("[tape.").expect("tape types");
    let end = text.find("[run]").expect("run table");
    text[start..end].to_string()
}

/// A one-panel mechanism around a `[[joint]]` fragment.
fn around_joint(fragment: &str) -> String {
    format!(
        "name = \"docs\"\n\
         [[panel]]\nlength_m = 0.8\nmass_kg = 3.5\ncom_m = 0.4\ninertia_kgm2 = 0.27\n\n\
         {fragment}\n{}\n[run]\nduration_s = 6.0\nsample_hz = 100.0\n",
        tape_types()
    )
}

/// What a TOML block must be, by what it holds.
enum TomlKind {
    Mechanism(String),
    Excerpt,
}

fn toml_kind(text: &str) -> TomlKind {
    let has = |table: &str| text.lines().any(|l| l.trim_start().starts_with(table));
    if has("[[panel]]") {
        TomlKind::Mechanism(text.to_string())
    } else if has("[[joint]]") {
        TomlKind::Mechanism(around_joint(text))
    } else if has("[rig]") {
        TomlKind::Mechanism(format!("{}\n{text}", bundled("seed001_T01.toml")))
    } else {
        TomlKind::Excerpt
    }
}

fn check_toml(block: &Block) -> Result<(), String> {
    toml_edit::ImDocument::parse(block.text.as_str())
        .map_err(|e| format!("not valid TOML 1.0: {e}"))?;
    match toml_kind(&block.text) {
        TomlKind::Mechanism(text) => Mechanism::from_toml_str(&text, "block")
            .map(|_| ())
            .map_err(|e| format!("not a mechanism the reader loads: {e}")),
        TomlKind::Excerpt => Ok(()),
    }
}

#[test]
fn every_toml_and_csv_block_of_the_docs_parses() {
    let (mut tomls, mut runs, mut mechanisms) = (0, 0, 0);
    let mut failures = Vec::new();
    for file in markdown_files() {
        for block in blocks(&file) {
            let at = format!("{}:{}", block.file.display(), block.line);
            let result = match block.lang.as_str() {
                "toml" => {
                    tomls += 1;
                    if matches!(toml_kind(&block.text), TomlKind::Mechanism(_)) {
                        mechanisms += 1;
                    }
                    check_toml(&block)
                }
                "csv" => {
                    runs += 1;
                    Run::parse(&block.text, &at)
                        .map(|_| ())
                        .map_err(|e| e.to_string())
                }
                "" if looks_like_run(&block.text) => {
                    runs += 1;
                    Err("a run without the `csv` tag: write ```csv".to_string())
                }
                _ => Ok(()),
            };
            if let Err(e) = result {
                failures.push(format!("{at}: {e}"));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    // The docs hold the format's examples: a test that found none would
    // pass on nothing.
    assert!(
        tomls >= 5 && mechanisms >= 3 && runs >= 2,
        "{tomls} toml, {mechanisms} mechanisms, {runs} runs"
    );
}

#[test]
fn a_broken_example_is_caught() {
    // The checks fail on what they must: a multi-line inline table (TOML
    // 1.1), a joint with an unknown key, a run with a column missing.
    let block = |lang: &str, text: &str| Block {
        file: PathBuf::from("x.md"),
        line: 1,
        lang: lang.to_string(),
        text: text.to_string(),
    };
    let multi_line = "[[joint]]\nstowed_deg = 90.0\nspring = { kind = \"linear\", preload_nm = 1.0,\n  stiffness_nm_per_rad = 0.5, count = 1 }\n";
    let e = check_toml(&block("toml", multi_line)).unwrap_err();
    assert!(e.contains("not valid TOML"), "{e}");
    let unknown = "[[joint]]\nstowed_deg = 90.0\nspring = { kind = \"linear\", preload_nm = 1.0, stiffness_nm_per_rad = 0.5, count = 1 }\nstowd = 1.0\n";
    let e = check_toml(&block("toml", unknown)).unwrap_err();
    assert!(e.contains("stowd"), "{e}");
    let good = "[[joint]]\nstowed_deg = 90.0\nspring = { kind = \"linear\", preload_nm = 1.0, stiffness_nm_per_rad = 0.5, count = 1 }\n";
    check_toml(&block("toml", good)).expect("a good joint loads");
    assert!(Run::parse("t_s,phi1_deg\n0,1\n", "x").is_err());
}

#[test]
fn a_multi_line_inline_table_is_refused_with_the_way_out() {
    let text = around_joint(
        "[[joint]]\nstowed_deg = 90.0\nspring = { kind = \"linear\", preload_nm = 1.0,\n  stiffness_nm_per_rad = 0.5, count = 1 }\n",
    );
    let e = Mechanism::from_toml_str(&text, "m.toml")
        .unwrap_err()
        .to_string();
    // The line of `spring = {`, which the table does not close.
    assert!(e.contains("m.toml:10:"), "{e}");
    assert!(e.contains("must close on the line it opens"), "{e}");
    assert!(e.contains("sub-table"), "{e}");
}
