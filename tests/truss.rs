//! The truss-link wing (`docs/spec/truss-link.md`) against the golden
//! deployments of an independent implementation (`data/reference/truss/`,
//! copied from `shared/reference/truss/`): hinge angles within 0.01° RMS,
//! ψ and the knee angles within 0.05° RMS, every lock instant within 1 ms.

use deploywatch_sim::model::mechanism::Mechanism;
use deploywatch_sim::simulate::deployment::SimOptions;
use deploywatch_sim::simulate::multibody::{simulate_wing, WingRun};
use deploywatch_tests::data_dir;

/// A golden CSV: `t_s` and the named columns.
struct Golden {
    names: Vec<String>,
    rows: Vec<Vec<f64>>,
}

impl Golden {
    fn load(stem: &str) -> Golden {
        let text = std::fs::read_to_string(data_dir().join(format!("reference/truss/{stem}.csv")))
            .unwrap();
        let mut lines = text.lines().filter(|l| !l.starts_with('#'));
        let names = lines
            .next()
            .unwrap()
            .split(',')
            .map(str::to_string)
            .collect();
        let rows = lines
            .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
            .collect();
        Golden { names, rows }
    }

    fn column(&self, name: &str) -> Vec<f64> {
        let c = self.names.iter().position(|n| n == name).unwrap();
        self.rows.iter().map(|r| r[c]).collect()
    }
}

/// The golden column and the simulator's pin it is compared with.
const COLUMNS: [(&str, &str, f64); 6] = [
    ("phi1_deg", "hinge 1", 0.01),
    ("phi2_deg", "hinge 2", 0.01),
    ("psi_deg", "C:3", 0.05),
    ("kneeB_deg", "B", 0.05),
    ("kneeE_deg", "E", 0.05),
    ("kneeH_deg", "H", 0.05),
];

/// The lock names of the golden JSON and the simulator's pins.
const LOCKS: [(&str, &str); 5] = [
    ("O", "hinge 1"),
    ("I", "hinge 2"),
    ("B", "B"),
    ("E", "E"),
    ("H", "H"),
];

fn simulate(mech: &str) -> WingRun {
    let m = Mechanism::load(&data_dir().join(format!("mechanisms/{mech}.toml"))).unwrap();
    simulate_wing(&m, &SimOptions::default()).unwrap()
}

fn check(case: u32, eft: bool) {
    let mech = format!("seed000_case{case}_truss{}", if eft { "_eft" } else { "" });
    let stem = format!(
        "seed000_case{case}_truss_{}",
        if eft { "eft" } else { "nominal" }
    );
    let run = simulate(&mech);
    let golden = Golden::load(&stem);
    let t = golden.column("t_s");
    // The golden file ends at the last sample before the final lock; the
    // run at the first sample at or after it.
    let n = t.len().min(run.run.t_s.len());
    assert!(
        run.run.t_s.len().abs_diff(t.len()) <= 1,
        "{stem}: sample counts {} and {}",
        run.run.t_s.len(),
        t.len()
    );
    for (col, pin, tol) in COLUMNS {
        let g = golden.column(col);
        let (s, _) = run.series(pin).unwrap();
        let mut sse = 0.0;
        let mut worst: f64 = 0.0;
        for i in 0..n {
            assert!((run.run.t_s[i] - t[i]).abs() < 1e-9);
            let d = s[i] - g[i];
            sse += d * d;
            worst = worst.max(d.abs());
        }
        let rms = (sse / n as f64).sqrt();
        eprintln!("{stem} {col}: RMS {rms:.2e}°, worst {worst:.2e}°");
        assert!(rms <= tol, "{stem} {col}: RMS {rms}° > {tol}°");
    }
    let meta: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(data_dir().join(format!("reference/truss/{stem}.json"))).unwrap(),
    )
    .unwrap();
    for (name, pin) in LOCKS {
        let want = meta["latch_s"][name].as_f64().unwrap();
        let got = run.lock_s(pin).unwrap_or(f64::NAN);
        eprintln!("{stem} lock {name}: {got:.6} s (golden {want:.6} s)");
        assert!(
            (got - want).abs() <= 1e-3,
            "{stem} lock {name}: {got} s, golden {want} s"
        );
    }
    // Mobility from the Jacobian's rank: 3, then one freedom per knee lock
    // (H; E with the implied I latch; B with the implied O latch).
    assert_eq!(run.run.mobility, vec![3, 2, 1, 0], "{stem}: mobility");
}

#[test]
fn case2_nominal_matches_golden() {
    check(2, false);
}

#[test]
fn case2_eft_matches_golden() {
    check(2, true);
}

#[test]
fn case3_nominal_matches_golden() {
    check(3, false);
}

#[test]
fn case3_eft_matches_golden() {
    check(3, true);
}

#[test]
fn truss_mechanisms_round_trip() {
    for name in [
        "seed000_case2_truss",
        "seed000_case2_truss_eft",
        "seed000_case3_truss",
        "seed000_case3_truss_eft",
    ] {
        let m = Mechanism::load(&data_dir().join(format!("mechanisms/{name}.toml"))).unwrap();
        assert!(m.truss.is_some(), "{name}: truss");
        let text = m.to_toml_string();
        let back = Mechanism::from_toml_str(&text, "written.toml").unwrap();
        assert_eq!(back, m, "{name}");
        assert_eq!(back.to_toml_string(), text, "{name}: writing is stable");
    }
}
