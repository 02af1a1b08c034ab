//! The reliability analysis against a closed form: one panel on a linear
//! spring (`data/mechanisms/reliability_one_panel.toml`) with a Coulomb
//! friction `T_C ~ N(μ, σ)` latches within `duration_s` iff `T_C` is below
//! a critical value `T*`, found here by bisection with the simulator; the
//! exact failure probability is then the normal tail `1 − Φ((T* − μ)/σ)`.
//! `subset` and `mc` must hold it within their own 95 % intervals at 1e-2,
//! and `subset` at 1e-6 within a factor 1.5 with a c.o.v. ≤ 0.35 from at
//! most 20,000 deployments.
//!
//! `cargo test -p deploywatch-tests --test reliability`

use deploywatch_sim::analysis::reliability::criteria::Criterion;
use deploywatch_sim::analysis::reliability::mc::{self, McSettings};
use deploywatch_sim::analysis::reliability::normal;
use deploywatch_sim::analysis::reliability::subset::{self, SubsetSettings};
use deploywatch_sim::analysis::reliability::{Estimate, Problem};
use deploywatch_sim::model::effect::{Effect, EffectKind};
use deploywatch_sim::model::mechanism::Mechanism;
use deploywatch_sim::report::progress;
use deploywatch_sim::simulate::deployment::{self, SimOptions};
use deploywatch_tests::data_dir;

const SD: f64 = 0.1;

fn mechanism() -> Mechanism {
    Mechanism::load(&data_dir().join("mechanisms/reliability_one_panel.toml")).unwrap()
}

/// True when the panel latches within `duration_s` with friction `t_c`.
fn latches(mech: &Mechanism, t_c: f64) -> bool {
    let e = Effect::joint(EffectKind::CoulombFriction, 1, t_c);
    deployment::simulate(mech, &[e], &SimOptions::default())
        .unwrap()
        .deployed()
}

/// `T*` by bisection to 1e-10 N·m.
fn critical_friction(mech: &Mechanism) -> f64 {
    let (mut lo, mut hi) = (0.0, 5.0);
    assert!(latches(mech, lo) && !latches(mech, hi));
    while hi - lo > 1e-10 {
        let mid = 0.5 * (lo + hi);
        if latches(mech, mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The problem with `T_C ~ N(μ, SD)` and the exact probability, μ set so
/// that the exact probability is about `p`.
fn case(p: f64) -> (Problem, f64) {
    let mech = mechanism();
    let t_star = critical_friction(&mech);
    let mu = t_star + SD * normal::inverse_cdf(p);
    let exact = normal::tail((t_star - mu) / SD);
    let vary = format!("coulomb_friction:joint=1:normal({mu},{SD})")
        .parse()
        .unwrap();
    let problem = Problem {
        mech,
        vary: vec![vary],
        fail: vec![Criterion::NotLatched],
        corr: Vec::new(),
    };
    (problem, exact)
}

fn subset_of(problem: &Problem, seed: u64) -> Estimate {
    let s = SubsetSettings {
        samples: 2000,
        seed,
        ..SubsetSettings::default()
    };
    subset::run(problem, &s, &mut |xs| problem.g_batch(xs), &progress::quiet).unwrap()
}

fn assert_within(est: &Estimate, exact: f64) {
    assert!(
        est.ci95.0 <= exact && exact <= est.ci95.1,
        "{}: exact {exact:.4e} outside the 95 % interval [{:.4e}, {:.4e}] of p = {:.4e}",
        est.method,
        est.ci95.0,
        est.ci95.1,
        est.p_fail
    );
}

#[test]
fn subset_and_mc_hold_the_exact_probability_at_1e_2() {
    let (problem, exact) = case(1e-2);
    let s = subset_of(&problem, 0);
    assert!(s.converged);
    assert_within(&s, exact);
    let m = mc::run(
        &problem,
        &McSettings {
            samples: 20_000,
            target_cov: None,
            seed: 0,
        },
        &mut |xs| problem.g_batch(xs),
        &progress::quiet,
    )
    .unwrap();
    assert_within(&m, exact);
    assert_eq!(m.simulations, 20_000);
}

#[test]
fn subset_holds_the_exact_probability_at_1e_6() {
    let (problem, exact) = case(1e-6);
    let s = subset_of(&problem, 0);
    assert!(s.converged, "{s:?}");
    assert_within(&s, exact);
    let ratio = s.p_fail / exact;
    assert!(
        (1.0 / 1.5..=1.5).contains(&ratio),
        "p = {:.4e}, exact {exact:.4e}",
        s.p_fail
    );
    assert!(s.cov <= 0.35, "c.o.v. {}", s.cov);
    assert!(s.simulations <= 20_000, "{} deployments", s.simulations);
    // The most likely failure is just past the critical friction.
    let f = s.most_likely_failure.as_ref().unwrap();
    let t_star = critical_friction(&problem.mech);
    assert!(f.x[0] >= t_star - 1e-6 && f.x[0] < t_star + SD, "{:?}", f.x);
}

#[test]
fn the_same_seed_gives_the_same_bits_on_any_number_of_threads() {
    let (problem, _) = case(1e-3);
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| subset_of(&problem, 7))
    };
    let one = on(1);
    assert_eq!(one, on(2));
    // Batches cut into chunks of any size give the same result too.
    let chunked = subset::run(
        &problem,
        &SubsetSettings {
            samples: 2000,
            seed: 7,
            ..SubsetSettings::default()
        },
        &mut |xs| {
            let mut g = Vec::new();
            for c in xs.chunks(37) {
                g.extend(problem.g_batch(c)?);
            }
            Ok(g)
        },
        &progress::quiet,
    )
    .unwrap();
    assert_eq!(one, chunked);
    assert_ne!(
        one,
        subset_of(&problem, 8),
        "another seed draws other points"
    );
}

/// Two correlated frictions on the same joint add up: `T_C = X1 + X2`,
/// `X_i ~ N(μ/2, σ_i)` with correlation `ρ`, is `N(μ, √(σ1² + σ2² + 2ρσ1σ2))`,
/// so the exact probability is again a normal tail.
#[test]
fn correlated_parameters_hold_the_exact_probability() {
    let mech = mechanism();
    let t_star = critical_friction(&mech);
    let (s1, s2, rho): (f64, f64, f64) = (0.06, 0.08, 0.5);
    let sd = (s1 * s1 + s2 * s2 + 2.0 * rho * s1 * s2).sqrt();
    let mu = t_star + sd * normal::inverse_cdf(1e-3);
    let exact = normal::tail((t_star - mu) / sd);
    let vary = [s1, s2].map(|s| {
        format!("coulomb_friction:joint=1:normal({},{s})", mu / 2.0)
            .parse()
            .unwrap()
    });
    let problem = Problem {
        mech,
        vary: vary.to_vec(),
        fail: vec![Criterion::NotLatched],
        corr: vec!["1,2,0.5".parse().unwrap()],
    };
    let s = subset_of(&problem, 0);
    assert!(s.converged);
    assert_within(&s, exact);
    // Without the correlation the sum is narrower: the probability falls.
    let independent = Problem {
        corr: Vec::new(),
        ..problem
    };
    let i = subset_of(&independent, 0);
    assert!(i.ci95.1 < exact, "{:?} vs {exact}", i.ci95);
}
