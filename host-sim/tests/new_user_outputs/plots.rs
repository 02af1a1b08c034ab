//! Plots, and the diagnosis report's links to them.

use super::*;

#[test]
fn identify_plot_has_a_residual_panel_per_run() {
    let dir = tempfile::tempdir().expect("tempdir");
    let png = dir.path().join("eft.png");
    succeeds(&identify_a(&["--quiet", "--plot", s(&png)]));
    // One panel per run and joint, plus one residual panel per run, each
    // 300 px high under a 40 px title (report/plot.rs).
    let (runs, joints) = (2, 3);
    assert_eq!(png_height(&png), 40 + 300 * runs * (joints + 1));
}

#[test]
fn simulate_and_replay_write_their_plots_quietly() {
    let dir = tempfile::tempdir().expect("tempdir");
    let csv = dir.path().join("t02.csv");
    let png = dir.path().join("t02.png");
    succeeds(&deploywatch(&[
        "simulate",
        s(&data(T02)),
        "--out",
        s(&csv),
        "--plot",
        s(&png),
        "-q",
    ]));
    assert_eq!(png_height(&png), 40 + 300);
    let status_png = dir.path().join("status.png");
    succeeds(&deploywatch(&[
        "replay",
        s(&csv),
        "--mechanism",
        s(&data(T02)),
        "--plot",
        s(&status_png),
        "-q",
    ]));
    assert_eq!(png_height(&status_png), 40 + 3 * 300);
}

/// The image links of a Markdown report: the targets of `![alt](target)`.
fn image_links(md: &str) -> Vec<String> {
    md.split("![")
        .skip(1)
        .filter_map(|rest| {
            let open = rest.find("](")?;
            let tail = &rest[open + 2..];
            Some(tail[..tail.find(')')?].to_string())
        })
        .collect()
}

/// A link target percent-decoded (ASCII bytes and UTF-8).
fn percent_decoded(t: &str) -> String {
    let b = t.as_bytes();
    let (mut out, mut i) = (Vec::new(), 0);
    while i < b.len() {
        if b[i] == b'%' && i + 3 <= b.len() {
            let hex = std::str::from_utf8(&b[i + 1..i + 3]).unwrap();
            out.push(u8::from_str_radix(hex, 16).unwrap());
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).unwrap()
}

/// Splits a shell line into words: plain words and '…' quotes.
fn shell_words(line: &str) -> Vec<String> {
    let (mut words, mut cur, mut quoted, mut any) = (Vec::new(), String::new(), false, false);
    for c in line.chars() {
        match c {
            '\'' => {
                quoted = !quoted;
                any = true;
            }
            ' ' if !quoted => {
                if any {
                    words.push(std::mem::take(&mut cur));
                }
                any = false;
            }
            c => {
                cur.push(c);
                any = true;
            }
        }
    }
    if any {
        words.push(cur);
    }
    words
}

/// A report written where the path holds spaces: every image link is one
/// Markdown link (no bare space) to a file that exists, the residual-torque
/// figures among them; the report ends with the next step, a `margin
/// --from` command that runs as written.
#[test]
fn the_diagnosis_report_links_files_with_spaces_and_ends_with_a_next_step_that_runs() {
    let dir = tempfile::tempdir().expect("temp dir");
    let folder = dir.path().join("rig runs");
    std::fs::create_dir(&folder).unwrap();
    let json = folder.join("my diagnosis.json");
    succeeds(&diagnose_t01(&json));
    let md = std::fs::read_to_string(folder.join("my diagnosis.md")).unwrap();
    let links = image_links(&md);
    assert!(
        links.iter().filter(|l| l.contains("torque_")).count() >= 2,
        "{links:?}"
    );
    for l in &links {
        assert!(!l.contains(' ') && !l.contains('('), "broken link {l:?}");
        let file = folder.join(percent_decoded(l));
        assert!(file.is_file(), "link {l:?}: no file {}", file.display());
    }
    let next = md.rfind("## Next step").expect("a next step section");
    let tail = &md[next..];
    assert!(
        !tail[13..].contains("\n## "),
        "not the last section:\n{tail}"
    );
    let command = tail
        .lines()
        .find(|l| l.starts_with("deploywatch margin"))
        .expect("a margin command");
    let words = shell_words(command);
    assert!(words.iter().any(|w| w == s(&json)), "{words:?}");
    let args: Vec<&str> = words[1..].iter().map(String::as_str).collect();
    let out = succeeds(&deploywatch(&args));
    let from = format!("resistances from: diagnose ({})", json.display());
    assert!(out.contains(&from), "{out}");
}

/// Two runs of one file name in different folders (`test01/run.csv`,
/// `test02/run.csv`, as rigs store them): each has its own report
/// section and plots, named by its folder, none overwritten, and the JSON
/// tells them apart.
#[test]
fn runs_of_one_file_name_keep_their_own_plots() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut runs = Vec::new();
    for (folder, given) in [
        ("test01", "a_seed001_eft"),
        ("test02", "c_seed001_friction_harness"),
    ] {
        std::fs::create_dir(dir.path().join(folder)).unwrap();
        let run = dir.path().join(folder).join("run.csv");
        std::fs::copy(data(&format!("examples/{given}/seed001_T01.csv")), &run).unwrap();
        runs.push(run);
    }
    let json = dir.path().join("d.json");
    succeeds(&deploywatch(&[
        "diagnose",
        "--mechanism",
        s(&data(T01)),
        "--json",
        s(&json),
        "-q",
        "--max-effects",
        "1",
        s(&runs[0]),
        s(&runs[1]),
    ]));
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(
        doc["runs"],
        serde_json::json!(["test01/run.csv", "test02/run.csv"])
    );
    let md = std::fs::read_to_string(dir.path().join("d.md")).unwrap();
    let links = image_links(&md);
    for folder in ["test01", "test02"] {
        assert!(md.contains(&format!("### {folder}/run\n")), "{md}");
        for plot in ["angles", "residuals"] {
            let file = format!("d_{folder}_run_{plot}.png");
            assert!(links.contains(&file), "{file} not linked: {links:?}");
            assert!(dir.path().join(&file).is_file(), "{file}");
        }
    }
}
