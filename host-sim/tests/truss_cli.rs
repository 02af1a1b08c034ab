//! `deploywatch simulate` on truss mechanisms as a black box: a good truss
//! runs; bad truss input gives a clear error (file, key, what was expected)
//! and exit code 2, never a panic.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../data")
}

fn case2() -> String {
    std::fs::read_to_string(data().join("mechanisms/seed000_case2_truss.toml")).unwrap()
}

/// Runs `deploywatch simulate` on the given mechanism text.
fn simulate(text: &str) -> (Output, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let mech = dir.path().join("wing.toml");
    std::fs::write(&mech, text).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_deploywatch"))
        .arg("simulate")
        .arg(&mech)
        .arg("--out")
        .arg(dir.path().join("run.csv"))
        .arg("--no-noise")
        .output()
        .unwrap();
    (out, dir)
}

/// Asserts exit code 2, no panic, and every fragment in the message.
fn rejects(text: &str, fragments: &[&str]) {
    let (out, _dir) = simulate(text);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    for f in fragments {
        assert!(err.contains(f), "`{f}` missing from: {err}");
    }
}

#[test]
fn a_truss_wing_deploys_and_prints_its_mobility() {
    let (out, dir) = simulate(&case2());
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(text.contains("Gruebler 3(10 - 1) - 2·12 = 3"), "{text}");
    assert!(text.contains("3 -> 2 -> 1 -> 0"), "{text}");
    // One run CSV: the hinge columns of every run, then the documented
    // extra columns (docs/spec/formats.md), no sidecar file.
    let path = dir.path().join("run.csv");
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(
        text.contains(
            "\nt_s,phi1_deg,phi2_deg,latch1,latch2,psi_deg,kneeB_deg,kneeE_deg,kneeH_deg,kneeB,kneeE,kneeH\n"
        ),
        "{text}"
    );
    assert!(!dir.path().join("run_truss.csv").exists());
    // Every reader of runs reads it; the extra columns come back.
    let run = deploywatch_sim::run::Run::load(&path).unwrap();
    assert_eq!(run.joints(), 2);
    let knee_b = run.extra("kneeB").expect("kneeB switch");
    let latch1 = &run.latch[0];
    // Knee B and hinge O lock in the same instant (truss-link.md).
    assert_eq!(
        knee_b.values.iter().position(|&x| x == 1.0),
        latch1.iter().position(|&l| l)
    );
    let h = &run.extra("kneeH_deg").unwrap().values;
    assert!(
        h[0] < 179.0 && (h[h.len() - 1] - 180.0).abs() < 1e-9,
        "{h:?}"
    );
}

#[test]
fn a_truss_run_with_effects_is_the_eft_mechanism() {
    // `--effect coulomb_friction` at joints 1, 2 (hinges) and 3 (the pins
    // at node F) on the nominal wing gives the wing whose file carries the
    // paper's EFT: one truss simulator, the effects on its pins.
    let dir = tempfile::tempdir().unwrap();
    let run = |mech: &str, out: &str, effects: &[&str]| {
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_deploywatch"));
        cmd.arg("simulate")
            .arg(data().join("mechanisms").join(mech))
            .arg("--out")
            .arg(dir.path().join(out))
            .args(["--no-noise", "-q"]);
        for e in effects {
            cmd.arg("--effect").arg(e);
        }
        let o = cmd.output().unwrap();
        assert_eq!(
            o.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        let r = deploywatch_sim::run::Run::load(&dir.path().join(out)).unwrap();
        (r.t_s, r.phi_deg, r.latch, r.extra)
    };
    let eft = run("seed000_case2_truss_eft.toml", "eft.csv", &[]);
    let with = run(
        "seed000_case2_truss.toml",
        "with.csv",
        &[
            "coulomb_friction:joint=1:value=0.54",
            "coulomb_friction:joint=2:value=0.472",
            "coulomb_friction:joint=3:value=0.065",
        ],
    );
    assert_eq!(eft, with);
    let none = run("seed000_case2_truss.toml", "none.csv", &[]);
    assert!(none.0.len() + 50 < eft.0.len(), "friction slows the wing");
    // An effect the truss wing does not model, or a joint it does not have.
    for (effect, fragment) in [
        (
            "harness_stiffness:joint=1:value=0.1",
            "not modelled on a wing with a truss",
        ),
        (
            "coulomb_friction:joint=4:value=0.1",
            "joint 4 does not exist",
        ),
    ] {
        let o = Command::new(env!("CARGO_BIN_EXE_deploywatch"))
            .arg("simulate")
            .arg(data().join("mechanisms/seed000_case2_truss.toml"))
            .arg("--out")
            .arg(dir.path().join("bad.csv"))
            .args(["--effect", effect])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_ne!(o.status.code(), Some(0), "{effect}");
        assert!(err.contains(fragment), "{effect}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
}

#[test]
fn a_link_whose_length_does_not_match_its_points() {
    let text = case2().replace("length_mm = 753.5785", "length_mm = 760.0");
    rejects(
        &text,
        &[
            "wing.toml",
            "truss.link[3].length_mm",
            "753.5785 mm apart",
            "expected",
        ],
    );
}

#[test]
fn a_knee_on_one_link() {
    let text = case2().replace(
        "name = \"A\"\non = \"bus\"",
        "name = \"A\"\non = \"bus\"\nknee = true",
    );
    rejects(
        &text,
        &[
            "wing.toml",
            "truss.point[1].knee",
            "knee \"A\" joins 1 link(s)",
            "expected a free node of exactly two links",
        ],
    );
}

#[test]
fn a_free_node_on_no_link() {
    let text = format!(
        "{}\n[[truss.point]]\nname = \"Z\"\non = \"node\"\nat_mm = [1.0, 2.0]\n",
        case2()
    );
    rejects(
        &text,
        &[
            "wing.toml",
            "truss.point[9].on",
            "free node \"Z\" is on 0 link(s)",
            "expected",
        ],
    );
}

#[test]
fn a_loop_that_cannot_close_at_the_stowed_pose() {
    // Node F moved 1 mm: links 2, 3, 5 and 7 can no longer all reach it.
    let text = case2().replace("at_mm = [-34.44, 884.27]", "at_mm = [-34.44, 885.27]");
    rejects(
        &text,
        &[
            "wing.toml",
            "truss.link[2].length_mm",
            "expected them to agree",
        ],
    );
}

/// Three more links (A–D, D–G, A–F) pin both panels and node F: 0 DOF.
#[test]
fn a_truss_that_locks_up() {
    let p = |x: f64, y: f64| [x, y];
    let (a, d, g, f) = (
        p(-70.0, 299.0),
        p(-56.0, 651.0),
        p(56.4, 163.0),
        p(-34.44, 884.27),
    );
    let len = |u: [f64; 2], v: [f64; 2]| ((u[0] - v[0]).powi(2) + (u[1] - v[1]).powi(2)).sqrt();
    let mut text = case2();
    for (name, e0, e1, l) in [
        ("8", "A", "D", len(a, d)),
        ("9", "D", "G", len(d, g)),
        ("10", "A", "F", len(a, f)),
    ] {
        text.push_str(&format!(
            "\n[[truss.link]]\nname = \"{name}\"\nends = [\"{e0}\", \"{e1}\"]\nmass_kg = 0.1\nlength_mm = {l}\n"
        ));
    }
    rejects(
        &text,
        &[
            "wing.toml",
            "`truss`",
            "locked up at the stowed pose",
            "expected",
        ],
    );
}

#[test]
fn unknown_truss_keys_and_bad_carriers() {
    let text = case2().replace("on = \"bus\"", "on = \"wall\"");
    rejects(
        &text,
        &[
            "wing.toml",
            "truss.point[1].on",
            "expected \"bus\", \"node\" or \"panel1\"",
        ],
    );
    let text = case2().replace("hinges_mm =", "hinge_mm =");
    rejects(&text, &["wing.toml", "truss.hinge_mm", "unknown key"]);
}

/// The 1-based line of the first line of `text` holding `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    1 + text
        .lines()
        .position(|l| l.contains(needle))
        .unwrap_or_else(|| panic!("`{needle}` not in the text"))
}

#[test]
fn truss_errors_name_their_line() {
    // A value of the wrong kind: its own line.
    let text = case2().replace("on = \"bus\"", "on = \"wall\"");
    let line = line_of(&text, "on = \"wall\"");
    rejects(
        &text,
        &[&format!("wing.toml:{line}: "), "truss.point[1].on"],
    );
    // A check of the whole truss: the line of the key it names.
    let text = case2().replace("length_mm = 753.5785", "length_mm = 760.0");
    let line = line_of(&text, "length_mm = 760.0");
    rejects(
        &text,
        &[&format!("wing.toml:{line}: "), "truss.link[3].length_mm"],
    );
    let text = case2().replace(
        "name = \"A\"\non = \"bus\"",
        "name = \"A\"\non = \"bus\"\nknee = true",
    );
    let line = line_of(&text, "knee = true");
    rejects(
        &text,
        &[&format!("wing.toml:{line}: "), "truss.point[1].knee"],
    );
}
