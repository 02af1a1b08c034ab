//! The truss-link wing (`docs/spec/truss-link.md`) against the golden
//! deployments of an independent implementation (`data/reference/truss/`,
//! copied from `shared/reference/truss/`): hinge angles within 0.01° RMS,
//! ψ and the knee angles within 0.05° RMS, every lock instant within 1 ms.

use deploywatch_sim::deployment::SimOptions;
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::multibody::{
    simulate_wing, wing_options, WingRun, GOLDEN_COLUMNS, GOLDEN_LOCKS,
};
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

/// A bundled truss mechanism run with the wing's default options (what
/// `deploywatch simulate` and the truss benchmark use).
fn simulate(mech: &str) -> WingRun {
    let m = Mechanism::load(&data_dir().join(format!("mechanisms/{mech}.toml"))).unwrap();
    simulate_wing(&m, &wing_options()).unwrap()
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
    for (col, pin, tol) in GOLDEN_COLUMNS {
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
    for (name, pin) in GOLDEN_LOCKS {
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

// ------------------------------------------------------------- four-bar

use deploywatch_sim::multibody::{self, Body, Model, Pin, PointSpring, System};

/// Ground pivots 0.5 m apart, crank 0.15 m, coupler 0.45 m, rocker 0.30 m
/// (Grashof crank-rocker: no dead point).
const FOUR_BAR: [f64; 4] = [0.5, 0.15, 0.45, 0.3];

/// The upper intersection of the circles (p, r) and (q, s).
fn circles(p: [f64; 2], r: f64, q: [f64; 2], s: f64) -> [f64; 2] {
    let d = [q[0] - p[0], q[1] - p[1]];
    let l = (d[0] * d[0] + d[1] * d[1]).sqrt();
    let a = (r * r - s * s + l * l) / (2.0 * l);
    let h = (r * r - a * a).sqrt();
    let m = [p[0] + a * d[0] / l, p[1] + a * d[1] / l];
    [m[0] - h * d[1] / l, m[1] + h * d[0] / l]
}

/// Closed-form rocker angle \[rad\] at crank angle `t2` \[rad\].
fn rocker_angle(t2: f64) -> f64 {
    let [d, a, b, c] = FOUR_BAR;
    let pa = [a * t2.cos(), a * t2.sin()];
    let pb = circles(pa, b, [d, 0.0], c);
    (pb[1]).atan2(pb[0] - d)
}

/// The four-bar at crank angle 60°, driven by a torque on the crank and a
/// spring from the ground to the coupler's middle.
fn four_bar() -> Model {
    let [d, a, b, c] = FOUR_BAR;
    let t2 = 60f64.to_radians();
    let pa = [a * t2.cos(), a * t2.sin()];
    let pb = circles(pa, b, [d, 0.0], c);
    let bar = |name: &str, m: f64, l: f64, p: [f64; 2], q: [f64; 2]| Body {
        name: name.into(),
        mass_kg: m,
        inertia_kgm2: m * l * l / 12.0,
        com_m: [0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])],
    };
    let ground = Body {
        name: "ground".into(),
        mass_kg: 0.0,
        inertia_kgm2: 0.0,
        com_m: [0.0; 2],
    };
    let mut crank = Pin::plain("O2", 0, 1, [0.0, 0.0]);
    crank.offset_rad = t2;
    crank.torque_nm = 1.0;
    let mut rocker = Pin::plain("O4", 0, 3, [d, 0.0]);
    rocker.offset_rad = rocker_angle(t2);
    let mid = [0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])];
    let sys = System {
        bodies: vec![
            ground,
            bar("crank", 0.2, a, [0.0, 0.0], pa),
            bar("coupler", 0.4, b, pa, pb),
            bar("rocker", 0.3, c, [d, 0.0], pb),
        ],
        pins: vec![
            crank,
            Pin::plain("A", 1, 2, pa),
            Pin::plain("B", 2, 3, pb),
            rocker,
        ],
        springs: vec![PointSpring {
            a: (0, [0.25, 0.6]),
            b: (2, mid),
            stiffness_n_m: 50.0,
            rest_m: 0.1,
        }],
    };
    Model::new(sys).unwrap()
}

fn tight() -> SimOptions {
    SimOptions {
        rtol: 1e-11,
        atol: 1e-13,
        ..SimOptions::default()
    }
}

#[test]
fn four_bar_follows_closed_form_kinematics_and_conserves_energy() {
    let model = four_bar();
    assert_eq!(
        model.mobility(&[0.0; 3], &[false; 4]),
        1,
        "Gruebler 3·3 − 2·4 = 1"
    );
    let times: Vec<f64> = (0..=2000).map(|k| k as f64 * 1e-3).collect();
    let run = multibody::run(&model, &times, &tight()).unwrap();
    assert_eq!(run.t_s.len(), times.len());
    let (crank, rocker) = (&run.angle_deg[0], &run.angle_deg[3]);
    let lo = crank.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = crank.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    assert!(hi - lo > 45.0, "the crank swings: {lo}° to {hi}°");
    let mut worst: f64 = 0.0;
    for i in 0..times.len() {
        let want = rocker_angle(crank[i].to_radians());
        let d = (rocker[i].to_radians() - want + std::f64::consts::PI)
            .rem_euclid(2.0 * std::f64::consts::PI)
            - std::f64::consts::PI;
        worst = worst.max(d.abs());
    }
    eprintln!("four-bar: rocker vs closed form {worst:.2e} rad");
    assert!(worst <= 1e-9, "rocker angle off by {worst} rad");
    check_invariants("four-bar", &run);
}

/// Energy within 1e-9 of its initial value (relative) and constraint error
/// within 1e-9 m at every sample.
fn check_invariants(what: &str, run: &multibody::MbTrajectory) {
    let e0 = run.energy_j[0];
    let drift = run
        .energy_j
        .iter()
        .map(|e| (e - e0).abs())
        .fold(0.0, f64::max)
        / e0.abs();
    let gmax = run.constraint_error.iter().copied().fold(0.0, f64::max);
    eprintln!("{what}: energy drift {drift:.2e} (relative), constraint {gmax:.2e} m");
    assert!(drift <= 1e-9, "{what}: energy drift {drift} (relative)");
    assert!(gmax <= 1e-9, "{what}: constraint error {gmax} m");
}

#[test]
fn truss_conserves_energy_before_the_first_lock_and_keeps_its_constraints() {
    let m = Mechanism::load(&data_dir().join("mechanisms/seed000_case2_truss.toml")).unwrap();
    // Knee H locks at 0.663 s.
    let opts = SimOptions {
        duration_s: Some(0.65),
        ..tight()
    };
    let run = simulate_wing(&m, &opts).unwrap().run;
    assert!(run.lock_s.iter().all(Option::is_none));
    check_invariants("truss", &run);
}

// ------------------------------------------------- Andrews' squeezer

/// Andrews' squeezing mechanism (Hairer & Wanner II §VII.7; the "andrews"
/// problem of the Test Set for IVP Solvers, Mazzia et al., `andrews.f`):
/// seven bodies, four of them meeting at one point E, a spring and a
/// driving torque. Constants and consistent initial values from the test
/// set; its reference solution at t = 0.03 s (`andsoln`, PSIDE at
/// tol 1e-14) is below.
mod andrews {
    use super::*;

    const M: [f64; 7] = [
        0.04325, 0.00365, 0.02373, 0.00706, 0.07050, 0.00706, 0.05498,
    ];
    const I: [f64; 7] = [
        2.194e-6, 4.410e-7, 5.255e-6, 5.667e-7, 1.169e-5, 5.667e-7, 1.912e-5,
    ];
    const XA: [f64; 2] = [-0.06934, -0.00227];
    const XB: [f64; 2] = [-0.03635, 0.03273];
    const XC: [f64; 2] = [0.014, 0.072];
    const D: f64 = 28e-3;
    const DA: f64 = 115e-4;
    const E: f64 = 2e-2;
    const EA: f64 = 1421e-5;
    const RR: f64 = 7e-3;
    const RA: f64 = 92e-5;
    const SS: f64 = 35e-3;
    const SA: f64 = 1874e-5;
    const SB: f64 = 1043e-5;
    const SC: f64 = 18e-3;
    const SD: f64 = 2e-2;
    const TA: f64 = 2308e-5;
    const TB: f64 = 916e-5;
    const U: f64 = 4e-2;
    const UA: f64 = 1228e-5;
    const UB: f64 = 449e-5;
    const ZF: f64 = 2e-2;
    const ZT: f64 = 4e-2;
    const FA: f64 = 1421e-5;
    const MOM: f64 = 0.033;
    const C0: f64 = 4530.0;
    const L0: f64 = 0.07785;

    /// β, Θ, γ, Φ, δ, Ω, ε at t = 0 (consistent), as published.
    #[allow(clippy::excessive_precision)]
    pub const Q0: [f64; 7] = [
        -0.0617138900142764496358948458001,
        0.0,
        0.455279819163070380255912382449,
        0.222668390165885884674473185609,
        0.487364979543842550225598953530,
        -0.222668390165885884674473185609,
        1.23054744454982119249735015568,
    ];

    /// β, Θ, γ, Φ, δ, Ω, ε at t = 0.03 s (the test set's reference).
    pub const Q_REF: [f64; 7] = [
        0.1581077119629904e2,
        -0.1575637105984298e2,
        0.4082224013073101e-1,
        -0.5347301163226948,
        0.5244099658805304,
        0.5347301163226948,
        0.1048080741042263e1,
    ];

    fn at(p: [f64; 2], r: f64, a: f64) -> [f64; 2] {
        [p[0] + r * a.cos(), p[1] + r * a.sin()]
    }

    fn body(m: f64, i: f64, com_m: [f64; 2]) -> Body {
        Body {
            name: String::new(),
            mass_kg: m,
            inertia_kgm2: i,
            com_m,
        }
    }

    fn pin(a: usize, b: usize, p: [f64; 2], offset_rad: f64) -> Pin {
        let mut pin = Pin::plain("", a, b, p);
        pin.offset_rad = offset_rad;
        pin
    }

    /// Bodies at the initial pose; pins 0..=6 carry β, Θ, γ, Φ, δ, Ω, ε.
    pub fn model() -> Model {
        let [be, th, ga, ph, de, om, ep] = Q0;
        let o = [0.0, 0.0];
        let f = at(o, RR, be);
        let e = at(f, -D, be + th);
        // E is also at the end of body 3 (`g1`, `g2` of andrews.f).
        let e3 = [XB[0] + SS * ga.sin(), XB[1] - SS * ga.cos()];
        assert!((e[0] - e3[0]).hypot(e[1] - e3[1]) < 1e-14);
        let p = at(XA, ZT, de);
        let q = at(XA, U, ep - std::f64::consts::FRAC_PI_2);
        let dpt = [
            XB[0] + SD * ga.cos() + SC * ga.sin(),
            XB[1] + SD * ga.sin() - SC * ga.cos(),
        ];
        let ground = body(0.0, 0.0, o);
        let bodies = vec![
            ground,
            body(M[0], I[0], at(o, RA, be)),
            body(M[1], I[1], at(f, -DA, be + th)),
            body(M[2], I[2], at(XB, SA.hypot(SB), ga)),
            body(M[4], I[4], at(XA, TA.hypot(TB), de)),
            body(
                M[3],
                I[3],
                at(p, E - EA, ph + de - std::f64::consts::FRAC_PI_2),
            ),
            body(M[6], I[6], at(XA, UA.hypot(UB), ep)),
            body(M[5], I[5], at(q, ZF - FA, om + ep)),
        ];
        let mut crank = pin(0, 1, o, be);
        crank.torque_nm = MOM;
        let pins = vec![
            crank,
            pin(1, 2, f, th),
            pin(0, 3, XB, ga),
            pin(4, 5, p, ph),
            pin(0, 4, XA, de),
            pin(6, 7, q, om),
            pin(0, 6, XA, ep),
            pin(2, 3, e, 0.0),
            pin(2, 5, e, 0.0),
            pin(2, 7, e, 0.0),
        ];
        let springs = vec![PointSpring {
            a: (0, XC),
            b: (3, dpt),
            stiffness_n_m: C0,
            rest_m: L0,
        }];
        Model::new(System {
            bodies,
            pins,
            springs,
        })
        .unwrap()
    }
}

#[test]
fn andrews_squeezer_matches_the_test_set_reference_at_30_ms() {
    let model = andrews::model();
    assert_eq!(model.n(), 7);
    assert!(model.constraint_error(&[0.0; 7], &[false; 10]) < 1e-15);
    assert_eq!(model.mobility(&[0.0; 7], &[false; 10]), 1);
    let opts = SimOptions {
        rtol: 1e-12,
        atol: 1e-14,
        max_step_s: 1e-3,
        ..SimOptions::default()
    };
    let run = multibody::run(&model, &[0.0, 0.03], &opts).unwrap();
    for (p, want) in andrews::Q_REF.iter().enumerate() {
        let got = run.angle_deg[p][1].to_radians();
        let rel = (got - want).abs() / want.abs();
        eprintln!(
            "andrews q{}: {got:.15e} vs {want:.15e} (relative {rel:.1e})",
            p + 1
        );
        assert!(rel <= 1e-6, "angle {}: {got} vs {want} ({rel:e})", p + 1);
    }
}

/// The lock-up mode of `truss-link.md`: with the outer panel held folded
/// (hinge I held at −180° from the start) the inner panel deploys and the
/// wing locks in the second fully locked pose near `φ_O = 0`,
/// `φ_I = −179.75°`, with the outer panel stowed.
#[test]
fn lock_up_mode_finds_the_second_locked_pose() {
    let m = Mechanism::load(&data_dir().join("mechanisms/seed000_case2_truss.toml")).unwrap();
    let mut model = deploywatch_sim::multibody::wing_model(&m).unwrap();
    let hold = &mut model.sys.pins[1];
    assert_eq!(hold.name, "hinge 2");
    hold.lock_at_rad = Some(hold.offset_rad);
    let times: Vec<f64> = (0..=600).map(|k| k as f64 * 0.01).collect();
    let run = multibody::run(&model, &times, &SimOptions::default()).unwrap();
    let names: Vec<&str> = model.sys.pins.iter().map(|p| p.name.as_str()).collect();
    eprintln!(
        "lock-up: end {:.4} s, φ_O {:.4}°, mobility {:?}, locks {:?} {:?}",
        run.end_s,
        run.angle_deg[0].last().unwrap(),
        run.mobility,
        names,
        run.lock_s
    );
    let knee_h = *run.angle_deg[8].last().unwrap();
    eprintln!("lock-up: knee H {knee_h:.4}° at the end");
    assert_eq!(run.mobility.last(), Some(&0));
    // With the hold, O, B and E lock and the held wing has no freedom left;
    // H is not yet straight (about 170°).
    for p in [0, 6, 7] {
        assert!(run.lock_s[p].is_some(), "{} locks", names[p]);
    }
    // Released, the outer panel closes H: the pose with O, B, E and H
    // locked next to the stowed outer panel is the second locked pose.
    model.sys.pins[1].lock_at_rad = Some(0.0);
    let mut locked = vec![false; model.sys.pins.len()];
    for p in [0, 6, 7, 8] {
        locked[p] = true;
    }
    let mut q = run.final_q.clone();
    let err = model.project_position(&mut q, &locked).unwrap();
    let k = model.kin(&q, &vec![0.0; q.len()]);
    let phi_i = model.pin_angle(&k, 1).0.to_degrees();
    eprintln!("second locked pose: φ_I {phi_i:.4}°, closure {err:.1e}");
    assert!(err < 1e-9, "the pose closes: {err}");
    assert!((phi_i + 179.75).abs() < 0.01, "φ_I {phi_i}°");
    assert_eq!(model.mobility(&q, &locked), 0);
}

/// One physics: the open chain of seed 000 case 1 built as a multibody
/// system (hinges only) reproduces the chain's golden deployments
/// (`data/reference/seed000_case1_*`) like the chain simulator does.
#[test]
fn multibody_reproduces_the_chain_goldens_without_a_truss() {
    use deploywatch_sim::multibody::build::open_chain_system;
    use deploywatch_sim::run::Run;
    // Latch instants of the golden JSON files.
    let cases = [
        ("nominal", [0.0, 0.0], [2.302428, 1.571546]),
        ("eft", [0.54, 0.472], [2.734546, 1.788456]),
    ];
    for (variant, friction, latch_s) in cases {
        let mut m = Mechanism::load(&data_dir().join("mechanisms/seed000_case1.toml")).unwrap();
        for (j, f) in m.joints.iter_mut().zip(friction) {
            j.friction.coulomb_nm = f;
        }
        let golden =
            Run::load(&data_dir().join(format!("reference/seed000_case1_{variant}.csv"))).unwrap();
        let model = Model::new(open_chain_system(&m).unwrap()).unwrap();
        let run = multibody::run(&model, &golden.t_s, &SimOptions::default()).unwrap();
        let n = golden.len().min(run.t_s.len());
        assert!(golden.len().abs_diff(run.t_s.len()) <= 1);
        for (j, want_s) in latch_s.iter().enumerate() {
            let sse: f64 = (0..n)
                .map(|i| (run.angle_deg[j][i] - golden.phi_deg[j][i]).powi(2))
                .sum();
            let rms = (sse / n as f64).sqrt();
            eprintln!(
                "chain {variant} joint {}: RMS {rms:.2e}°, lock {:?}",
                j + 1,
                run.lock_s[j]
            );
            assert!(rms <= 0.01, "{variant} joint {}: {rms}°", j + 1);
            assert!((run.lock_s[j].unwrap() - want_s).abs() <= 1e-3);
        }
    }
}
