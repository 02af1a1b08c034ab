//! Tests of `rsm`.

use super::*;
use crate::analysis::identify::rsm_box::*;

fn approx(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

#[test]
fn ccd_sizes_and_levels() {
    let d = Ccd::new(3, CcdKind::Circumscribed, 1).unwrap();
    assert_eq!(d.runs(), 15);
    assert!(approx(d.alpha(), 1.681_792_830_507_429, 1e-12));
    let pts = d.coded_points();
    assert_eq!(pts.len(), 15);
    assert_eq!(pts[0], vec![-1.0, -1.0, -1.0]);
    assert_eq!(pts[1], vec![1.0, -1.0, -1.0]);
    assert_eq!(pts[7], vec![1.0, 1.0, 1.0]);
    assert!(approx(pts[8][0], -d.alpha(), 0.0));
    assert_eq!(pts[14], vec![0.0; 3]);
    // For k = 4 the axial runs are as far out as the factorial ones: α = 2 = √4.
    let d4 = Ccd::new(4, CcdKind::Circumscribed, 0).unwrap();
    assert!(approx(d4.alpha(), 2.0, 1e-12));
    let f = Ccd::new(2, CcdKind::FaceCentred, 3).unwrap();
    assert_eq!(f.runs(), 4 + 4 + 3);
    assert!(f
        .coded_points()
        .iter()
        .all(|p| p.iter().all(|v| v.abs() <= 1.0)));
    let i = Ccd::new(3, CcdKind::Inscribed, 1).unwrap();
    let pts = i.coded_points();
    assert!(pts.iter().all(|p| p.iter().all(|v| v.abs() <= 1.0 + 1e-15)));
    assert!(approx(pts[0][0], -1.0 / rotatable_alpha(3), 1e-15));
    assert_eq!(pts[8], vec![-1.0, 0.0, 0.0]);
    assert_eq!(Ccd::new(0, CcdKind::Inscribed, 1), Err(RsmError::NoFactors));
    // One factor: 2 factorial + 2 axial + n0.
    assert_eq!(
        Ccd::new(1, CcdKind::Circumscribed, 2)
            .unwrap()
            .coded_points()
            .len(),
        6
    );
}

#[test]
fn rotatable_design_has_equal_prediction_variance_at_equal_radius() {
    // Rotatability: xᵀ(XᵀX)⁻¹x depends only on |x|. Check two directions.
    let d = Ccd::new(3, CcdKind::Circumscribed, 3).unwrap();
    let pts = d.coded_points();
    let p = Quadratic::term_count(3);
    let mut x = DMatrix::zeros(pts.len(), p);
    for (r, pt) in pts.iter().enumerate() {
        for (c, t) in Quadratic::terms(pt).into_iter().enumerate() {
            x[(r, c)] = t;
        }
    }
    let inv = (x.transpose() * &x).try_inverse().unwrap();
    let var = |pt: &[f64]| {
        let t = DVector::from_vec(Quadratic::terms(pt));
        (t.transpose() * &inv * &t)[(0, 0)]
    };
    let r = 0.7;
    let a = var(&[r, 0.0, 0.0]);
    let b = var(&[r / 3f64.sqrt(), r / 3f64.sqrt(), r / 3f64.sqrt()]);
    let c = var(&[0.0, r / 2f64.sqrt(), -r / 2f64.sqrt()]);
    assert!(approx(a, b, 1e-9) && approx(a, c, 1e-9), "{a} {b} {c}");
}

#[test]
fn coding_round_trips() {
    let c = Coding::new(vec![0.75, 0.6, 0.1], vec![0.25, 0.3, 0.05]).unwrap();
    let x = vec![0.33, 1.1, 0.016];
    let back = c.to_natural(&c.to_coded(&x));
    assert!(x.iter().zip(&back).all(|(a, b)| approx(*a, *b, 1e-15)));
    let (lo, hi) = c.natural_box(1.0);
    assert!(approx(lo[0], 0.5, 1e-15) && approx(hi[2], 0.15, 1e-15));
    assert_eq!(Coding::new(vec![0.0], vec![0.0]), Err(RsmError::BadBox));
}

#[test]
fn coefficient_order_matches_eq_15() {
    assert_eq!(Quadratic::term_count(3), 10);
    assert_eq!(
        Quadratic::coefficient_names(3),
        ["b0", "b1", "b2", "b3", "b12", "b13", "b23", "b11", "b22", "b33"]
    );
    assert_eq!(
        Quadratic::term_names(2),
        ["1", "x1", "x2", "x1*x2", "x1^2", "x2^2"]
    );
    let q = Quadratic::new(3, (0..10).map(f64::from).collect()).unwrap();
    assert_eq!(q.interaction(0, 1), 4.0);
    assert_eq!(q.interaction(2, 0), 5.0);
    assert_eq!(q.interaction(1, 2), 6.0);
    assert_eq!(q.pure(2), 9.0);
    assert_eq!(q.interaction(1, 1), 8.0);
    // Index of pairs for k = 4: (0,1)=0 .. (0,3)=2, (1,2)=3, (1,3)=4, (2,3)=5.
    assert_eq!(pair_index(4, 1, 3), 4);
    assert_eq!(pair_index(4, 2, 3), 5);
}

/// A known quadratic in 3 variables.
fn truth() -> Quadratic {
    Quadratic::new(3, vec![2.0, -1.0, 0.5, 3.0, 0.4, -0.7, 0.2, 1.5, 2.0, 0.8]).unwrap()
}

#[test]
fn fit_recovers_an_exact_quadratic_on_a_ccd() {
    let q = truth();
    let pts = Ccd::new(3, CcdKind::Circumscribed, 2)
        .unwrap()
        .coded_points();
    let y: Vec<f64> = pts.iter().map(|p| q.eval(p)).collect();
    let fit = fit_quadratic(&pts, &y).unwrap();
    for (a, b) in fit.model.coefficients().iter().zip(q.coefficients()) {
        assert!(approx(*a, *b, 1e-10), "{a} vs {b}");
    }
    assert!(approx(fit.r2, 1.0, 1e-12));
    assert!(fit.sse < 1e-18);
}

#[test]
fn fit_errors() {
    let pts = vec![vec![0.0, 0.0]; 6];
    assert_eq!(
        fit_quadratic(&pts, &[1.0; 6]).unwrap_err(),
        RsmError::RankDeficient
    );
    assert!(matches!(
        fit_quadratic(&pts[..3], &[1.0; 3]),
        Err(RsmError::TooFewRuns { runs: 3, terms: 6 })
    ));
    assert!(matches!(
        fit_quadratic(&pts, &[1.0; 5]),
        Err(RsmError::DimensionMismatch { .. })
    ));
    let mut bad = Ccd::new(2, CcdKind::FaceCentred, 1).unwrap().coded_points();
    bad[0][0] = f64::NAN;
    assert_eq!(
        fit_quadratic(&bad, &[1.0; 9]).unwrap_err(),
        RsmError::NotFinite
    );
}

#[test]
fn r2_is_the_same_coded_or_natural_and_conversions_agree() {
    let coding = Coding::new(vec![0.75, 0.6, 0.1], vec![0.25, 0.3, 0.05]).unwrap();
    let design = Ccd::new(3, CcdKind::Circumscribed, 1).unwrap();
    let coded = design.coded_points();
    let natural = design.natural_points(&coding).unwrap();
    // A non-quadratic response, so that R² < 1.
    let y: Vec<f64> = coded
        .iter()
        .map(|p| (p[0] + 0.3 * p[1]).exp() + p[2].powi(3) + 0.1 * p[0] * p[1] * p[2])
        .collect();
    let fc = fit_quadratic(&coded, &y).unwrap();
    let fnat = fit_quadratic(&natural, &y).unwrap();
    assert!(fc.r2 < 0.9999);
    assert!(approx(fc.r2, fnat.r2, 1e-9), "{} {}", fc.r2, fnat.r2);
    assert!(approx(fc.adj_r2, fnat.adj_r2, 1e-9));
    let conv = fc.model.to_natural(&coding).unwrap();
    for (a, b) in conv.coefficients().iter().zip(fnat.model.coefficients()) {
        assert!(approx(*a, *b, 1e-7 * b.abs().max(1.0)), "{a} vs {b}");
    }
    let back = conv.to_coded(&coding).unwrap();
    for (a, b) in back.coefficients().iter().zip(fc.model.coefficients()) {
        assert!(approx(*a, *b, 1e-9 * b.abs().max(1.0)), "{a} vs {b}");
    }
    let x = [0.6, 0.4, 0.07];
    assert!(approx(
        conv.eval(&x),
        fc.model.eval(&coding.to_coded(&x)),
        1e-10
    ));
}

#[test]
fn parts_round_trip_and_gradient() {
    let q = truth();
    let (c, b, h) = q.parts();
    assert_eq!(Quadratic::from_parts(c, &b, &h).unwrap(), q);
    let x = [0.3, -0.2, 0.9];
    let g = q.gradient(&x);
    for i in 0..3 {
        let e = 1e-6;
        let mut xp = x;
        let mut xm = x;
        xp[i] += e;
        xm[i] -= e;
        let fd = (q.eval(&xp) - q.eval(&xm)) / (2.0 * e);
        assert!(approx(g[i], fd, 1e-6), "{} {}", g[i], fd);
    }
}

/// Brute force over a grid, for comparison.
fn grid_min(q: &Quadratic, lo: &[f64], hi: &[f64], n: usize) -> f64 {
    let k = q.factors();
    let mut best = f64::INFINITY;
    let mut idx = vec![0usize; k];
    loop {
        let x: Vec<f64> = (0..k)
            .map(|i| lo[i] + (hi[i] - lo[i]) * idx[i] as f64 / (n - 1) as f64)
            .collect();
        best = best.min(q.eval(&x));
        let mut i = 0;
        while i < k {
            idx[i] += 1;
            if idx[i] < n {
                break;
            }
            idx[i] = 0;
            i += 1;
        }
        if i == k {
            return best;
        }
    }
}

#[test]
fn box_minimum_interior_face_and_vertex() {
    // Convex with its unconstrained minimum inside the box.
    let q = Quadratic::new(2, vec![0.0, -2.0, -4.0, 0.0, 1.0, 1.0]).unwrap(); // (x−1)²+(y−2)²−5
    let m = minimize_in_box(&q, &[-5.0, -5.0], &[5.0, 5.0]).unwrap();
    assert!(approx(m.x[0], 1.0, 1e-12) && approx(m.x[1], 2.0, 1e-12));
    assert_eq!(m.active, vec![0, 0]);
    // Same surface, box excludes the minimum: lands on the face y = 1.
    let m = minimize_in_box(&q, &[-5.0, -1.0], &[5.0, 1.0]).unwrap();
    assert!(approx(m.x[0], 1.0, 1e-12) && approx(m.x[1], 1.0, 1e-12));
    assert_eq!(m.active, vec![0, 1]);
    // Concave: the minimum is at a vertex.
    let q = Quadratic::new(2, vec![0.0, 0.1, 0.0, 0.0, -1.0, -1.0]).unwrap();
    let m = minimize_in_box(&q, &[-1.0, -1.0], &[1.0, 1.0]).unwrap();
    assert!(approx(m.x[0], -1.0, 1e-12) && m.x[1].abs() == 1.0);
    assert!(approx(m.value, -2.1, 1e-12));
    assert_eq!(
        minimize_in_box(&q, &[1.0, -1.0], &[1.0, 1.0]),
        Err(RsmError::BadBox)
    );
}

#[test]
fn box_minimum_matches_brute_force_on_indefinite_surfaces() {
    // Saddles in 3 variables, several boxes.
    let surfaces = [
        truth(),
        Quadratic::new(
            3,
            vec![1.0, 0.3, -0.2, 0.5, 2.0, -1.0, 0.5, -0.5, 1.0, -0.2],
        )
        .unwrap(),
        Quadratic::new(3, vec![0.0, 1.0, 1.0, 1.0, 3.0, 3.0, 3.0, 1.0, 1.0, 1.0]).unwrap(),
    ];
    let boxes = [
        (vec![-1.0, -1.0, -1.0], vec![1.0, 1.0, 1.0]),
        (vec![-2.0, 0.5, -0.3], vec![0.1, 3.0, 0.4]),
    ];
    let mut convex_seen = false;
    for q in &surfaces {
        for (lo, hi) in &boxes {
            let m = minimize_in_box(q, lo, hi).unwrap();
            let g = grid_min(q, lo, hi, 61);
            assert!(m.value <= g + 1e-12, "exact {} vs grid {}", m.value, g);
            assert!(m.value >= g - 0.05 * (1.0 + g.abs()), "{} {}", m.value, g);
            assert!(m
                .x
                .iter()
                .zip(lo.iter().zip(hi))
                .all(|(x, (l, h))| x >= l && x <= h));
            // The projected method from the vertices never beats the exact
            // minimum, and finds it when the surface is convex.
            let mut starts = Vec::new();
            for v in 0..8 {
                starts.push(
                    (0..3)
                        .map(|i| if (v >> i) & 1 == 1 { hi[i] } else { lo[i] })
                        .collect(),
                );
            }
            let p = minimize_in_box_projected(q, lo, hi, &starts).unwrap();
            let tol = 1e-9 * (1.0 + m.value.abs());
            assert!(p.value >= m.value - tol, "{} {}", p.value, m.value);
            let convex = q.parts().2.symmetric_eigenvalues().min() >= 0.0;
            if convex {
                assert!(approx(p.value, m.value, tol), "{} {}", p.value, m.value);
            }
            convex_seen |= convex;
        }
    }
    assert!(convex_seen);
}

#[test]
fn many_factors_use_the_projected_method() {
    // k = 12 convex separable: minimum at clamp(target).
    let k = 12;
    let target: Vec<f64> = (0..k).map(|i| -1.5 + 0.25 * i as f64).collect();
    let mut b = DVector::zeros(k);
    let mut h = DMatrix::zeros(k, k);
    for i in 0..k {
        h[(i, i)] = 2.0;
        b[i] = -2.0 * target[i];
    }
    let q = Quadratic::from_parts(0.0, &b, &h).unwrap();
    let m = minimize_in_box(&q, &vec![-1.0; k], &vec![1.0; k]).unwrap();
    for (i, (x, t)) in m.x.iter().zip(&target).enumerate() {
        assert!(approx(*x, t.clamp(-1.0, 1.0), 1e-9), "{i}: {x}");
    }
}

#[test]
fn weighted_sum_is_the_sum_of_values() {
    let a = truth();
    let b = Quadratic::new(3, vec![1.0; 10]).unwrap();
    let s = Quadratic::weighted_sum(&[(1.0, &a), (2.0, &b)]).unwrap();
    let x = [0.2, -0.4, 0.9];
    assert!(approx(s.eval(&x), a.eval(&x) + 2.0 * b.eval(&x), 1e-12));
    let m = minimize_weighted_in_box(&[(1.0, &a), (2.0, &b)], &[-1.0; 3], &[1.0; 3]).unwrap();
    assert!(approx(
        m.value,
        minimize_in_box(&s, &[-1.0; 3], &[1.0; 3]).unwrap().value,
        0.0
    ));
    let c = Quadratic::new(2, vec![0.0; 6]).unwrap();
    assert!(matches!(
        Quadratic::weighted_sum(&[(1.0, &a), (1.0, &c)]),
        Err(RsmError::DimensionMismatch { .. })
    ));
}
