//! Tests of the run CSV reader.
use super::*;

const TRUSS: &str = "# mechanism = \"w\"\n\
    t_s,phi1_deg,latch1,psi_deg,kneeB_deg,kneeB\n\
    0.000,90.0,0,-10.5,150.25,0\n\
    0.010,0.0,1,-20.0,180.0,1\n";

#[test]
fn a_missing_angle_column_is_named_whatever_its_place() {
    // Four joints without `phi3_deg`; three joints without `phi1_deg`.
    for (header, missing) in [
        (
            "t_s,phi1_deg,phi2_deg,phi4_deg,latch1,latch2,latch3,latch4",
            "phi3_deg",
        ),
        ("t_s,phi2_deg,phi3_deg,latch1,latch2,latch3", "phi1_deg"),
        ("t_s,phi1_deg,phi3_deg,latch1,latch2", "phi2_deg"),
    ] {
        let width = header.split(',').count();
        let row = vec!["0.0"; width].join(",");
        let e = Run::parse(&format!("{header}\n{row}\n"), "m.csv")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(&format!("missing column `{missing}`")),
            "{header}: {e}"
        );
    }
    // A number far past the columns stays a misspelt column.
    let e = Run::parse("t_s,phi1_deg,phi9_deg,latch1,latch2\n0,0,0,0,0\n", "m.csv")
        .unwrap_err()
        .to_string();
    assert!(!e.contains("missing column `phi3_deg`"), "{e}");
}

#[test]
fn documented_extra_columns_are_read_kept_and_written_back() {
    let run = Run::parse(TRUSS, "w.csv").unwrap();
    assert_eq!(run.joints(), 1);
    assert_eq!(run.phi_deg[0], [90.0, 0.0]);
    let names: Vec<&str> = run.extra.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["psi_deg", "kneeB_deg", "kneeB"]);
    assert_eq!(run.extra("kneeB_deg").unwrap().values, [150.25, 180.0]);
    assert_eq!(run.extra("kneeB").unwrap().kind, ExtraKind::KneeSwitch);
    assert_eq!(run.extra("kneeB").unwrap().values, [0.0, 1.0]);
    let text = run.to_csv_string();
    assert!(text.contains("t_s,phi1_deg,latch1,psi_deg,kneeB_deg,kneeB\n0.000,90.000000,0,-10.500000,150.250000,0\n"), "{text}");
    assert_eq!(Run::parse(&text, "again").unwrap(), run);
    run.validate("w.csv").unwrap();
}

#[test]
fn an_angle_that_rounds_to_zero_is_written_without_a_sign() {
    let text = TRUSS.replace("0.010,0.0,1,-20.0", "0.010,-0.0000004,1,-0.0");
    let out = Run::parse(&text, "w.csv").unwrap().to_csv_string();
    assert!(out.contains("\n0.010,0.000000,1,0.000000,"), "{out}");
    assert!(!out.contains("-0.000000"), "{out}");
    let mut s = String::new();
    for x in [-4e-7, -5e-7, -6e-7, 0.0, -0.0, f64::NAN] {
        push_fixed6(&mut s, x);
    }
    assert_eq!(s, ",0.000000,0.000000,-0.000001,0.000000,0.000000,NaN");
}

fn error(text: &str) -> String {
    Run::parse(text, "w.csv").unwrap_err().to_string()
}

#[test]
fn undocumented_or_misplaced_extra_columns_are_errors() {
    let e = error(&TRUSS.replace("kneeB\n", "kneeB,speed\n"));
    assert!(
        e.contains("w.csv:2") && e.contains("extra column `speed` (column 7)"),
        "{e}"
    );
    assert!(e.contains("psi_deg, knee<P>_deg, knee<P>"), "{e}");
    let e = error("t_s,phi1_deg,latch1,kneeB,phi2_deg\n0,1,0,0,1\n");
    assert!(
        e.contains("`phi2_deg` (column 5) comes after the extra column `kneeB`"),
        "{e}"
    );
    let e = error(&TRUSS.replace("kneeB_deg,kneeB", "kneeB,kneeB"));
    assert!(e.contains("column `kneeB` appears twice"), "{e}");
    let e = error(&TRUSS.replace("150.25,0", "150.25,2"));
    assert!(
        e.contains("w.csv:3") && e.contains("column `kneeB`: expected 0 or 1"),
        "{e}"
    );
    let e = error(&TRUSS.replace("150.25", "abc"));
    assert!(
        e.contains("column `kneeB_deg`: expected a finite number"),
        "{e}"
    );
    // A knee name with an underscore is not documented.
    let e = error(&TRUSS.replace("kneeB_deg", "knee_B_deg"));
    assert!(
        e.contains("extra column `knee_B_deg`") || e.contains("unknown column"),
        "{e}"
    );
    let mut run = Run::parse(TRUSS, "w.csv").unwrap();
    run.extra[0].values.pop();
    let e = run.validate("out.csv").unwrap_err().to_string();
    assert!(
        e.contains("extra column \"psi_deg\" has 1 samples; expected 2"),
        "{e}"
    );
}
