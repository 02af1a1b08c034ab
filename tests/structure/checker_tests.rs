//! The checker on small trees of its own, so that it can be seen to fail.

use crate::graph::{cycles, graph, Source};
use crate::layers::{layers_of, parse_layers};
use crate::lexer::strip;
use crate::rules::{cli_violations, layer_violations, long_functions, stdout_prints};
use crate::{ModPath, MAX_FN_LINES};
use std::path::PathBuf;

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
