//! Every test vector of `docs/spec/paper-vectors.md`: the numbers the seed
//! papers print, recomputed from their inputs. Each test states the paper's
//! number and the tolerance; where the paper's own text is inconsistent the
//! test checks what paper-vectors.md says to check and prints what it found
//! (`cargo test -p deploywatch-tests --test paper_vectors -- --nocapture`).

use deploywatch_core::{Branch, Spring};
use deploywatch_sim::design_margin::{joint_margin, margin_pct, Standard};
use deploywatch_sim::identify::rsm::{fit_quadratic, Ccd, CcdKind, Coding, Fit, Quadratic};
use deploywatch_sim::identify::rsm_box::{minimize_in_box, minimize_in_box_projected};
use deploywatch_sim::kinematics::{
    planar_mobility, spatial_mobility, FIXED_CONSTRAINTS, REVOLUTE_CONSTRAINTS,
};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::truss_synthesis::{synthesize, TrussInput};
use deploywatch_tests::data_dir;
use std::f64::consts::{FRAC_PI_2, PI};

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

fn load(name: &str) -> Mechanism {
    let path = data_dir().join("mechanisms").join(name);
    Mechanism::load(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn spring(m: &Mechanism, joint: usize) -> Spring<f64> {
    m.joints[joint].spring.to_spring().expect("valid spring")
}

// ------------------------------------------------------------------ mobility

/// Seed 000 Table 1 (Eq. 1): Type 1 has 9 DOF, Type 2 has 7 (exact).
#[test]
fn gruebler_mobility_seed000_table1() {
    // Type 1 (RADARSAT-1): bus + 11 links = 12 bodies, 12 revolute joints.
    assert_eq!(planar_mobility(12, 12, 0), 9);
    // Type 2 (RADARSAT-2): bus + 9 links = 10 bodies, 10 revolute joints.
    assert_eq!(planar_mobility(10, 10, 0), 7);
}

/// Seed 000 Table 1, Type 2 corrected (`truss-link.md`): F joins four links,
/// so it is three joints, not one: 12 revolute joints and 3 DOF — counted
/// from the truss file and confirmed by the constraint Jacobian's rank.
#[test]
fn gruebler_mobility_seed000_table1_corrected_from_the_truss_file() {
    use deploywatch_sim::kinematics::truss_bodies_and_joints;
    use deploywatch_sim::multibody::wing_model;
    let m = load("seed000_case2_truss.toml");
    let (bodies, joints) = truss_bodies_and_joints(m.truss.as_ref().unwrap(), m.panels.len());
    assert_eq!((bodies, joints), (10, 12));
    assert_eq!(planar_mobility(10, 10, 0), 7, "as printed (F counted once)");
    assert_eq!(planar_mobility(bodies, joints, 0), 3, "corrected");
    let model = wing_model(&m).unwrap();
    let q = vec![0.0; model.n()];
    assert_eq!(model.mobility(&q, &vec![false; model.sys.pins.len()]), 3);
}

/// Seed 001 Eq. 3: 4 bodies · 6 − (1 fixed · 6 + 3 revolute · 5) = 3 (exact).
#[test]
fn spatial_mobility_seed001_eq3() {
    let joints = [
        FIXED_CONSTRAINTS,
        REVOLUTE_CONSTRAINTS,
        REVOLUTE_CONSTRAINTS,
        REVOLUTE_CONSTRAINTS,
    ];
    assert_eq!(spatial_mobility(4, &joints), 3);
}

// ------------------------------------------------------------------ truss links

/// Seed 000 Table 3 (Eqs. 2–10 as corrected in paper-vectors.md): every output
/// to the printed digits, tolerance 0.02 mm and 0.01°.
#[test]
fn truss_link_synthesis_seed000_table3() {
    let o = synthesize(&TrussInput::seed000_table3());
    let mm = 0.02;
    let deg = 0.01;
    let pts = [
        ("B", o.b, (60.79, -148.05)),
        ("E", o.e, (97.34, -573.34)),
        // The inputs give H = (−93.17, −812.91); Table 3 prints −93.18.
        ("H", o.h, (-93.18, -812.91)),
    ];
    for (name, got, want) in pts {
        assert!(
            (got.0 - want.0).abs() <= mm && (got.1 - want.1).abs() <= mm,
            "{name} = ({:.3}, {:.3}), Table 3 ({}, {})",
            got.0,
            got.1,
            want.0,
            want.1
        );
    }
    let lengths = [
        ("L2", o.l2_mm, 726.28),
        ("L3", o.l3_mm, 753.58),
        ("L5", o.l5_mm, 309.38),
        ("L7", o.l7_mm, 129.54),
    ];
    for (name, got, want) in lengths {
        assert!(
            (got - want).abs() <= mm,
            "{name} = {got:.3} mm, Table 3 {want}"
        );
    }
    // φ2 = 93.11° needs acos((xF − xB)/L2), not the extracted (xB − xF).
    let angles = [
        ("phi2", o.phi2_deg, 93.11),
        ("phi3", o.phi3_deg, 91.64),
        ("phi5", o.phi5_deg, 104.20),
        ("phi7", o.phi7_deg, 27.77),
    ];
    for (name, got, want) in angles {
        assert!(
            (got - want).abs() <= deg,
            "{name} = {got:.4}°, Table 3 {want}°"
        );
    }
}

// ------------------------------------------------------------------ RSM, Table 9

/// Seed 000 Table 9, verbatim: (EFT1, EFT2, EFT3) [N·m], TE1, TE2 [%].
const TABLE9: [[f64; 5]; 15] = [
    [1.17, 0.60, 0.10, 28.65, 20.75],
    [0.75, 1.10, 0.10, 15.90, 28.03],
    [0.75, 0.60, 0.10, 16.32, 13.07],
    [1.00, 0.30, 0.15, 25.69, 15.20],
    [0.33, 0.60, 0.10, 15.49, 13.32],
    [0.75, 0.095, 0.10, 25.35, 3.66],
    [0.50, 0.90, 0.05, 11.10, 22.03],
    [1.00, 0.30, 0.05, 23.98, 8.73],
    [1.00, 0.90, 0.05, 24.64, 21.46],
    [0.50, 0.30, 0.05, 18.07, 6.70],
    [0.75, 0.60, 0.016, 19.46, 13.29],
    [0.50, 0.30, 0.15, 20.60, 10.84],
    [1.00, 0.90, 0.15, 24.64, 25.36],
    [0.75, 0.60, 0.18, 20.28, 15.88],
    [0.50, 0.90, 0.15, 13.71, 28.34],
];

/// Seed 000 Eq. 16 as printed (the signs were lost in the source text).
const EQ16: [f64; 10] = [
    16.329, 3.713, 1.703, 1.107, 0.823, 1.290, 0.658, 2.040, 1.529, 1.262,
];

/// The design of paper-vectors.md: centre (0.75, 0.60, 0.10), half-ranges
/// (0.25, 0.30, 0.05) N·m.
fn coding() -> Coding {
    Coding::new(vec![0.75, 0.60, 0.10], vec![0.25, 0.30, 0.05]).unwrap()
}

fn natural_runs() -> Vec<Vec<f64>> {
    TABLE9.iter().map(|r| r[..3].to_vec()).collect()
}

fn response(col: usize) -> Vec<f64> {
    TABLE9.iter().map(|r| r[col]).collect()
}

fn fit_natural(col: usize) -> Fit {
    fit_quadratic(&natural_runs(), &response(col)).unwrap()
}

fn fit_coded(col: usize) -> Fit {
    let c = coding();
    let coded: Vec<Vec<f64>> = natural_runs().iter().map(|x| c.to_coded(x)).collect();
    fit_quadratic(&coded, &response(col)).unwrap()
}

/// Table 9 is a rotatable CCD: 8 factorial + 6 axial + 1 centre run with
/// α = (2³)^(1/4) ≈ 1.682. Every printed run matches one design run to the
/// printed rounding (0.005 N·m: e.g. 0.095 for 0.6 − 1.682·0.3 = 0.0955).
#[test]
fn table9_is_a_rotatable_ccd() {
    let design = Ccd::new(3, CcdKind::Circumscribed, 1).unwrap();
    assert!((design.alpha() - 1.68).abs() < 0.005);
    let mut ours = design.natural_points(&coding()).unwrap();
    assert_eq!(ours.len(), TABLE9.len());
    for row in &TABLE9 {
        let (i, d) = ours
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let d = p
                    .iter()
                    .zip(&row[..3])
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                (i, d)
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap();
        assert!(
            d <= 0.005,
            "run {:?} is {d} N·m from the nearest design run",
            &row[..3]
        );
        ours.remove(i);
    }
    assert!(ours.is_empty());
}

/// Seed 000 section 4.3: R² = 0.978 for the ten-term quadratic (Eq. 15) of
/// TE1, tolerance 0.001, whether the factors are coded or not.
#[test]
fn table9_r2_is_0978_coded_and_uncoded() {
    let nat = fit_natural(3);
    let cod = fit_coded(3);
    println!(
        "TE1: R² natural {:.5}, coded {:.5}; adjusted {:.5}; RMS residual {:.3} %",
        nat.r2,
        cod.r2,
        cod.adj_r2,
        cod.rms_residual()
    );
    assert!((nat.r2 - 0.978).abs() <= 0.001, "natural R² {}", nat.r2);
    assert!((cod.r2 - 0.978).abs() <= 0.001, "coded R² {}", cod.r2);
    let te2 = fit_coded(4);
    println!(
        "TE2 (not printed by the paper): R² {:.5}, adjusted {:.5}",
        te2.r2, te2.adj_r2
    );
    assert!(te2.r2 > 0.9 && te2.r2 < 1.0);
}

/// The coefficients fitted to Table 9 (reported in docs/identification.md):
/// paper-vectors.md gives β0 ≈ 16.48, β1 ≈ 4.22, β2 ≈ −2.20 for TE1 in coded
/// units (tolerance 0.01); the natural-unit fit is the same surface.
#[test]
fn table9_fitted_coefficients() {
    let names = Quadratic::coefficient_names(3);
    for (col, label) in [(3, "TE1"), (4, "TE2")] {
        let cod = fit_coded(col);
        let nat = fit_natural(col);
        println!(
            "{label} coded:   {}",
            fmt_coef(&names, cod.model.coefficients())
        );
        println!(
            "{label} natural: {}",
            fmt_coef(&names, nat.model.coefficients())
        );
        let conv = cod.model.to_natural(&coding()).unwrap();
        for (a, b) in conv.coefficients().iter().zip(nat.model.coefficients()) {
            assert!((a - b).abs() <= 1e-6 * b.abs().max(1.0), "{a} vs {b}");
        }
    }
    let te1 = fit_coded(3).model;
    assert!(
        (te1.intercept() - 16.48).abs() <= 0.01,
        "β0 {}",
        te1.intercept()
    );
    assert!((te1.linear(0) - 4.22).abs() <= 0.01, "β1 {}", te1.linear(0));
    assert!((te1.linear(1) + 2.20).abs() <= 0.01, "β2 {}", te1.linear(1));
}

fn fmt_coef(names: &[String], c: &[f64]) -> String {
    names
        .iter()
        .zip(c)
        .map(|(n, v)| format!("{n}={v:.4}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// Eq. 16 does not follow from Table 9 (paper-vectors.md: do not test
/// against it). Whatever signs are put back on its magnitudes, and whether
/// the runs are coded or not, it fits Table 9's TE1 and TE2 worse than the
/// least-squares surface; the best sign choice is reported.
#[test]
fn eq16_is_not_the_least_squares_surface_of_table9() {
    let c = coding();
    let coded: Vec<Vec<f64>> = natural_runs().iter().map(|x| c.to_coded(x)).collect();
    let mut best = (f64::INFINITY, 0u32, 0usize, "");
    for (runs, units) in [(&coded, "coded"), (&natural_runs(), "natural")] {
        for col in [3, 4] {
            let y = response(col);
            for signs in 0u32..512 {
                let mut b = EQ16.to_vec();
                for (i, v) in b.iter_mut().skip(1).enumerate() {
                    if (signs >> i) & 1 == 1 {
                        *v = -*v;
                    }
                }
                let q = Quadratic::new(3, b).unwrap();
                let rms = (runs
                    .iter()
                    .zip(&y)
                    .map(|(x, y)| (q.eval(x) - y).powi(2))
                    .sum::<f64>()
                    / y.len() as f64)
                    .sqrt();
                if rms < best.0 {
                    best = (rms, signs, col, units);
                }
            }
        }
    }
    let signs: String = (0..9)
        .map(|i| if (best.1 >> i) & 1 == 1 { '-' } else { '+' })
        .collect();
    let ls = fit_coded(best.2).rms_residual();
    println!(
        "closest Eq. 16: signs of β1..β33 {signs}, {} units, against TE{}: RMS {:.3} % \
         (least squares: {:.3} %)",
        best.3,
        best.2 - 2,
        best.0,
        ls
    );
    assert!(
        best.0 > 1.5 * ls,
        "Eq. 16 RMS {} vs least squares {}",
        best.0,
        ls
    );
}

/// Minima of the fitted TE1, TE2 and TE1 + TE2 in the design box
/// (the factorial box, centre ± half-range). The paper's optimum is
/// EFT = (0.54, 0.472, 0.065) N·m with TE1 = 7.69 %, TE2 = 6.62 % in
/// simulation; paper-vectors.md: TE1 + TE2 is least near (0.57, 0.33, 0.06)
/// (tolerance 0.01 N·m). Each minimum must lie in the box, be no higher than
/// the surface at any design run in the box nor at the paper's optimum, and
/// agree with the multi-start projected method.
#[test]
fn table9_minima_in_the_design_box() {
    let c = coding();
    let (lo, hi) = c.natural_box(1.0);
    let te1 = fit_natural(3).model;
    let te2 = fit_natural(4).model;
    let sum = Quadratic::weighted_sum(&[(1.0, &te1), (1.0, &te2)]).unwrap();
    let paper = [0.54, 0.472, 0.065];
    let runs = natural_runs();
    let mut starts = runs.clone();
    for v in 0..8 {
        starts.push(
            (0..3)
                .map(|i| if (v >> i) & 1 == 1 { hi[i] } else { lo[i] })
                .collect(),
        );
    }
    let mut minima = Vec::new();
    for (label, q) in [("TE1", &te1), ("TE2", &te2), ("TE1+TE2", &sum)] {
        let m = minimize_in_box(q, &lo, &hi).unwrap();
        println!(
            "min {label} in the box: EFT = ({:.4}, {:.4}, {:.4}) N·m, {label} = {:.3} %, \
             TE1 = {:.3} %, TE2 = {:.3} %, active {:?}",
            m.x[0],
            m.x[1],
            m.x[2],
            m.value,
            te1.eval(&m.x),
            te2.eval(&m.x),
            m.active
        );
        for i in 0..3 {
            assert!(
                m.x[i] >= lo[i] && m.x[i] <= hi[i],
                "{label}: {:?} outside the box",
                m.x
            );
        }
        for r in runs
            .iter()
            .filter(|r| (0..3).all(|i| r[i] >= lo[i] && r[i] <= hi[i]))
        {
            assert!(
                m.value <= q.eval(r) + 1e-12,
                "{label}: higher than at run {r:?}"
            );
        }
        assert!(m.value <= q.eval(&paper) + 1e-12);
        let p = minimize_in_box_projected(q, &lo, &hi, &starts).unwrap();
        assert!(
            (p.value - m.value).abs() <= 1e-8,
            "{label}: {} vs {}",
            p.value,
            m.value
        );
        minima.push(m);
    }
    println!(
        "fitted surfaces at the paper's optimum (0.54, 0.472, 0.065): TE1 {:.3} %, TE2 {:.3} % \
         (paper's simulation: 7.69 %, 6.62 %)",
        te1.eval(&paper),
        te2.eval(&paper)
    );
    let s = &minima[2].x;
    assert!(
        (s[0] - 0.57).abs() <= 0.01 && (s[1] - 0.33).abs() <= 0.01 && (s[2] - 0.06).abs() <= 0.01,
        "TE1+TE2 minimum at {s:?}"
    );
}

/// How the paper may have combined TE1 and TE2 (it does not say): sweep the
/// weight `w` of `w · TE1 + (1 − w) · TE2` over [0, 1] in steps of 0.01 and
/// take the minimum in the design box closest to the paper's optimum
/// (0.54, 0.472, 0.065) N·m. Expected: some weight lands within 0.01 N·m of
/// it in every factor (it does near w = 0.6); the weight is reported.
#[test]
fn table9_paper_optimum_is_a_weighted_minimum() {
    let (lo, hi) = coding().natural_box(1.0);
    let te1 = fit_natural(3).model;
    let te2 = fit_natural(4).model;
    let paper = [0.54, 0.472, 0.065];
    let mut best = (f64::INFINITY, 0.0, Vec::new());
    for step in 0..=100 {
        let w = step as f64 / 100.0;
        let m = deploywatch_sim::identify::rsm_box::minimize_weighted_in_box(
            &[(w, &te1), (1.0 - w, &te2)],
            &lo,
            &hi,
        )
        .unwrap();
        let d =
            m.x.iter()
                .zip(&paper)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
        if d < best.0 {
            best = (d, w, m.x);
        }
    }
    let (d, w, x) = best;
    println!(
        "closest weighted minimum: w = {w:.2}: EFT = ({:.4}, {:.4}, {:.4}) N·m, {d:.4} N·m from \
         the paper's optimum; fitted TE1 {:.2} %, TE2 {:.2} %",
        x[0],
        x[1],
        x[2],
        te1.eval(&x),
        te2.eval(&x)
    );
    assert!(
        d <= 0.01,
        "no weighting reproduces the paper's optimum: best {d} at w = {w}"
    );
}

// ------------------------------------------------------------------ margins, seed 000

/// Seed 000 Tables 8/11: the driving torque at the stowed angle is 2.17 N·m
/// (joint O, 90°), 2.38 N·m (joint I, cases 1–2) and 3.57 N·m (joint I,
/// case 3), printed to 0.01 N·m (tolerance 0.005 N·m); and Table 10's E_D =
/// 2.818, 4.484, 6.726 J from the bundled linear springs, tolerance 0.1 %.
#[test]
fn seed000_table10_driving_energy_and_torque() {
    let cases = [
        ("seed000_case1.toml", 0, 2.17, 2.818),
        ("seed000_case1.toml", 1, 2.38, 4.484),
        ("seed000_case3.toml", 0, 2.17, 2.818),
        ("seed000_case3.toml", 1, 3.57, 6.726),
    ];
    for (file, j, t_d, e_d) in cases {
        let m = load(file);
        let s = spring(&m, j);
        let stroke = m.joints[j].stowed_deg.abs().to_radians();
        let got_t = s.magnitude(stroke, Branch::Unfold);
        let got_e = s.release(0.0, stroke);
        println!(
            "{file} joint {}: T_D {got_t:.4} N·m, E_D {got_e:.4} J",
            j + 1
        );
        assert!(
            (got_t - t_d).abs() <= 0.005,
            "{file} joint {}: T_D {got_t}",
            j + 1
        );
        assert!(
            rel(got_e, e_d) <= 1e-3,
            "{file} joint {}: E_D {got_e}",
            j + 1
        );
    }
}

/// Seed 000 Table 11 from Table 10's printed E_D and E_R (Eq. 21), tolerance
/// 0.01 % (percentage points): 232.31, 204.41, 203.80, 355.69 %.
#[test]
fn seed000_table11_margins_from_printed_energies() {
    let rows = [
        (2.818, 0.848, 232.31),
        (4.484, 1.473, 204.41),
        (4.484, 1.476, 203.80),
        (6.726, 1.476, 355.69),
    ];
    for (e_d, e_r, tm) in rows {
        let got = margin_pct(e_d, e_r);
        assert!(
            (got - tm).abs() <= 0.01,
            "{e_d}/{e_r}: {got:.4} % vs Table 11 {tm} %"
        );
        assert!(got > 0.0, "Table 11: every case passes");
    }
}

/// Seed 000 Tables 10–11 recomputed end to end: E_D from the mechanism's
/// springs, E_R = EFT · stroke with EFT = (0.54, 0.472) N·m.
///
/// Joint O: E_R = 0.54 · π/2 = 0.848 J and TM = 232.31 % (tolerance 0.1 %).
/// Joint I: E_R = 0.472 · π = 1.483 J, but Table 10 prints 1.473 / 1.476 J:
/// the paper's E_R is 0.5–0.7 % below its EFT (paper-vectors.md), so the
/// margins come out about 2 points lower (202.4 % vs 204.41 / 203.80 %,
/// 353.6 % vs 355.69 %); tolerance 1 % on those, and every case passes.
#[test]
fn seed000_tables10_11_from_springs_and_eft() {
    let cases = [
        (
            "seed000_case1.toml",
            0,
            0.54,
            FRAC_PI_2,
            0.848,
            232.31,
            1e-3,
        ),
        ("seed000_case1.toml", 1, 0.472, PI, 1.473, 204.41, 1e-2),
        // Case 2 is case 1 with truss links: same springs.
        ("seed000_case1.toml", 1, 0.472, PI, 1.476, 203.80, 1e-2),
        (
            "seed000_case3.toml",
            0,
            0.54,
            FRAC_PI_2,
            0.848,
            232.31,
            1e-3,
        ),
        ("seed000_case3.toml", 1, 0.472, PI, 1.476, 355.69, 1e-2),
    ];
    for (file, j, eft, stroke, e_r, tm, tol) in cases {
        let m = load(file);
        assert!((m.joints[j].stowed_deg.abs().to_radians() - stroke).abs() < 1e-12);
        let jm = joint_margin(
            &spring(&m, j),
            m.joints[j].stowed_deg.to_radians(),
            eft,
            Standard::None,
            None,
        );
        let got = jm.energy_margin_pct();
        println!(
            "{file} joint {}: E_D {:.4} J, E_R {:.4} J (Table 10: {e_r}), TM {got:.2} % \
             (Table 11: {tm} %)",
            j + 1,
            jm.driving_energy_j,
            jm.resisting_energy_j
        );
        assert!(
            rel(jm.resisting_energy_j, e_r) <= tol,
            "E_R {}",
            jm.resisting_energy_j
        );
        assert!(rel(got, tm) <= tol, "TM {got} vs {tm}");
        assert!(jm.energy_pass() && jm.torque_pass());
    }
    // The joint-I E_R discrepancy itself: EFT · π exceeds both printed values.
    let e_r = 0.472 * PI;
    assert!(rel(e_r, 1.473) > 0.004 && rel(e_r, 1.476) > 0.003);
}

// ------------------------------------------------------------------ margins, seed 001

/// Seed 001 Table 5: T_D = count × TS moment at the stowed angle (3.6, 2.92,
/// 1.48, 0.77 N·m, tolerance 0.005), T_R = (2.63, 1.7, 0.001) N·m, TM by
/// Eq. 7. Printed: 38.0, 71.8, 1479, −70.7 %. The formula gives 36.9 % for
/// T01 joint 1 (tolerance 0.05) and 147 900 % for joint 3 (the paper dropped
/// the ×100; tolerance 50); 71.8 and −70.7 are reproduced to 0.05. Sign and
/// pass/fail as in the table: T01 passes, T02 fails at joint 1.
#[test]
fn seed001_table5_torque_margins() {
    let t_r = [2.63, 1.7, 0.001];
    // (file, joint, T_D printed, TM expected from the formula, pass)
    let rows: [(&str, usize, f64, f64, bool); 6] = [
        ("seed001_T01.toml", 0, 3.6, 36.9, true),
        ("seed001_T01.toml", 1, 2.92, 71.8, true),
        ("seed001_T01.toml", 2, 1.48, 147_900.0, true),
        ("seed001_T02.toml", 0, 0.77, -70.7, false),
        ("seed001_T02.toml", 1, 2.92, 71.8, true),
        ("seed001_T02.toml", 2, 1.48, 147_900.0, true),
    ];
    for (file, j, t_d, tm, pass) in rows {
        let m = load(file);
        let jm = joint_margin(
            &spring(&m, j),
            m.joints[j].stowed_deg.to_radians(),
            t_r[j],
            Standard::None,
            None,
        );
        let got = jm.torque_margin_pct();
        println!(
            "{file} joint {}: T_D {:.4} N·m, T_R {} N·m, TM {got:.2} %",
            j + 1,
            jm.driving_torque_nm,
            t_r[j]
        );
        assert!(
            (jm.driving_torque_nm - t_d).abs() <= 0.005,
            "T_D {}",
            jm.driving_torque_nm
        );
        let tol = if tm.abs() > 1000.0 { 50.0 } else { 0.05 };
        assert!((got - tm).abs() <= tol, "TM {got} vs {tm}");
        assert_eq!(got >= 0.0, pass, "sign of TM");
        assert_eq!(jm.torque_pass(), pass, "pass/fail");
    }
}
