//! The zero-g rig (`physics.md` §11, `docs/simulator.md` "Rig"): the
//! trolley's friction, the wire pendulum's period and the energy balance
//! with frame contacts, measured on the simulator itself.
use deploywatch_sim::deployment::SimOptions;
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::rig::{drag_trolley, simulate_rig};

/// One panel on a linear spring (preload `t0`), hanging from one trolley.
fn one_panel(rig: &str, stowed_deg: f64, t0: f64, inertia: f64) -> Mechanism {
    let text = format!(
        r#"
name = "rig-test"
[[panel]]
length_m = 1.0
mass_kg = 2.0
com_m = 0.5
inertia_kgm2 = {inertia}
[[joint]]
stowed_deg = {stowed_deg}
spring = {{ kind = "linear", preload_nm = {t0}, stiffness_nm_per_rad = 0.0, count = 1 }}
[run]
duration_s = 4.0
sample_hz = 1000.0
{rig}
"#
    );
    Mechanism::from_toml_str(&text, "rig-test.toml").expect("test mechanism")
}

fn free_run(duration_s: f64, sample_hz: f64) -> (SimOptions, Vec<f64>) {
    let opts = SimOptions {
        latching: false,
        stop_when_deployed: false,
        rtol: 1e-10,
        atol: 1e-12,
        max_step_s: 0.01,
        ..SimOptions::default()
    };
    let n = (duration_s * sample_hz).round() as usize;
    (opts, (0..=n).map(|k| k as f64 / sample_hz).collect())
}

#[test]
fn a_dragged_trolley_feels_the_dynamic_friction_of_its_load() {
    let mech = one_panel(
        "[rig]\nstatic_mu = 0.3\ndynamic_mu = 0.1\n[[rig.bar]]\nmass_kg = 1.0\n[[rig.trolley]]\npanel = 1\nbar = 1\nmass_kg = 0.5\nwire_m = 1.5\n",
        -90.0,
        1.0,
        0.1,
    );
    let rig = mech.rig.as_ref().unwrap();
    let (m_t, m_i, g) = (0.5, 2.0, rig.gravity_m_s2);
    for speed in [0.05, 0.2] {
        let pull = drag_trolley(rig, m_t, m_i, 1.5, speed, 10.0, 1e-5);
        let tail = &pull[pull.len() / 2..];
        let mean = tail.iter().sum::<f64>() / tail.len() as f64;
        let want = 0.1 * (m_t + m_i) * g;
        let rel = (mean - want).abs() / want;
        println!(
            "drag at {speed} m/s: wire force {mean:.5} N, mu_d N = {want:.5} N, off by {:.3} %",
            rel * 100.0
        );
        assert!(rel < 0.01, "{mean} vs {want}");
    }
}

#[test]
fn a_wire_pendulum_swings_with_the_period_of_its_length() {
    // The trolley parked (massive, no friction) above the deployed offload
    // point; the panel's inertia about its centre tiny against m c², no
    // spring: the panel swings about the hinge as a pendulum of the wire.
    for wire in [0.5, 2.0] {
        let rig = format!(
            "[rig]\nstatic_mu = 0.0\ndynamic_mu = 0.0\n[[rig.bar]]\nmass_kg = 1e9\n[[rig.trolley]]\npanel = 1\nbar = 1\nmass_kg = 1e9\nwire_m = {wire}\nstart_m = [0.5, 0.0]\n"
        );
        let mech = one_panel(&rig, 3.0, 0.0, 1e-6);
        let (opts, times) = free_run(4.0, 1000.0);
        let run = simulate_rig(&mech, &[], &opts, &times).expect("pendulum");
        let phi = &run.traj.phi_deg[0];
        // Zero crossings both ways, interpolated: half periods.
        let ups: Vec<f64> = (1..phi.len())
            .filter(|&i| (phi[i - 1] < 0.0) != (phi[i] < 0.0))
            .map(|i| times[i - 1] + (times[i] - times[i - 1]) * -phi[i - 1] / (phi[i] - phi[i - 1]))
            .collect();
        assert!(ups.len() >= 2, "{ups:?}");
        let period = 2.0 * (ups[ups.len() - 1] - ups[0]) / (ups.len() - 1) as f64;
        let g = mech.rig.as_ref().unwrap().gravity_m_s2;
        let want = 2.0 * std::f64::consts::PI * (wire / g).sqrt();
        let rel = (period - want).abs() / want;
        println!(
            "wire {wire} m: period {period:.5} s, 2π√(L/g) = {want:.5} s, off by {:.4} %",
            rel * 100.0
        );
        assert!(rel < 0.005);
    }
}

#[test]
fn energy_closes_with_frame_contacts_and_rail_friction() {
    // Two panels on linear springs, no joint friction; the rig with the
    // papers' friction and contact, and a lateral frame the tip of panel 2
    // strikes.
    let text = r#"
name = "rig-energy"
[[panel]]
length_m = 0.8
mass_kg = 3.5
com_m = 0.4
inertia_kgm2 = 0.27
[[panel]]
length_m = 0.8
mass_kg = 3.5
com_m = 0.4
inertia_kgm2 = 0.27
[[joint]]
stowed_deg = -90.0
spring = { kind = "linear", preload_nm = 1.5, stiffness_nm_per_rad = 0.5, count = 1 }
[[joint]]
stowed_deg = 180.0
spring = { kind = "linear", preload_nm = 0.6, stiffness_nm_per_rad = 0.3, count = 1 }
[rig]
static_mu = 0.03
dynamic_mu = 0.01
[[rig.bar]]
mass_kg = 2.0
[[rig.trolley]]
panel = 1
bar = 1
mass_kg = 0.5
wire_m = 1.5
[[rig.trolley]]
panel = 2
bar = 1
mass_kg = 0.5
wire_m = 1.5
wire_spring_n_per_m = 2000.0
[[rig.frame]]
name = "lateral +y"
normal = [0.0, -1.0]
at_m = -0.3
"#;
    let mech = Mechanism::from_toml_str(text, "rig-energy.toml").expect("mechanism");
    let (opts, times) = free_run(3.0, 200.0);
    let run = simulate_rig(&mech, &[], &opts, &times).expect("run");
    let stored: f64 = mech
        .joints
        .iter()
        .map(|j| {
            let s = j.spring.to_spring::<f64>().unwrap();
            s.release(0.0, j.stowed_deg.to_radians().abs())
        })
        .sum();
    let e0 = run.energy_j[0];
    let worst = run
        .energy_j
        .iter()
        .map(|e| (e - e0).abs())
        .fold(0.0, f64::max);
    for (p, tip) in run.tip_xy.iter().enumerate() {
        let (lo, hi) = tip
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), q| (a.min(q[1]), b.max(q[1])));
        println!(
            "panel {} tip y in [{lo:.3}, {hi:.3}] m; phi end {:.2} deg",
            p + 1,
            run.traj.phi_deg[p].last().unwrap()
        );
    }
    println!(
        "dissipated-inclusive energy first/last {:.6} {:.6}",
        run.energy_j[0],
        run.energy_j.last().unwrap()
    );
    println!(
        "stored {stored:.6} J, energy drift {worst:.3e} J = {:.3e} of it; contacts {:?}",
        worst / stored,
        run.contacts
    );
    assert!(!run.contacts.is_empty(), "the frame is struck");
    assert!(worst <= 1e-6 * stored);
}

#[test]
fn flight_is_the_mechanism_without_its_rig() {
    use deploywatch_sim::deployment;
    use deploywatch_sim::effect::{Effect, EffectKind};
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/mechanisms");
    let on_rig = Mechanism::load(&data.join("seed001_T01_rig.toml")).expect("rig example");
    assert!(on_rig.active_rig().is_some());
    let bare = Mechanism::load(&data.join("seed001_T01.toml")).expect("T01");
    let eft: Vec<Effect> = [2.63, 1.7, 0.001]
        .iter()
        .enumerate()
        .map(|(j, v)| Effect::joint(EffectKind::CoulombFriction, j + 1, *v))
        .collect();
    let opts = SimOptions::default();
    let flight = deployment::simulate(&on_rig.flight(), &[], &opts).expect("flight");
    let nominal = deployment::simulate(&bare, &eft, &opts).expect("nominal");
    assert_eq!(flight.latch_s, nominal.latch_s);
    // On the rig the rails' friction slows joint 1 and a panel meets a frame.
    let grid = deployment::sample_grid(&on_rig, &opts).unwrap();
    let times: Vec<f64> = (0..).map_while(|k| grid.get(k)).collect();
    let rig = simulate_rig(&on_rig, &[], &opts, &times).expect("rig");
    println!(
        "latch on the rig {:?}, in flight {:?}; contacts {:?}",
        rig.traj.latch_s, flight.latch_s, rig.contacts
    );
    assert!(rig.traj.latch_s[0].unwrap() > flight.latch_s[0].unwrap());
    assert!(!rig.contacts.is_empty());
}

#[test]
fn a_written_rig_mechanism_reads_back_the_same() {
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/mechanisms");
    for f in ["seed001_T01_rig.toml", "seed001_T02_rig.toml"] {
        let m = Mechanism::load(&data.join(f)).expect("example");
        let back =
            Mechanism::from_toml_str(&m.to_toml_string(), "written.toml").expect("reads back");
        assert_eq!(back.rig, m.rig, "{f}");
    }
    // Bad input names the key.
    let bad = "name = \"x\"\n[[panel]]\nlength_m = 1.0\nmass_kg = 1.0\ncom_m = 0.5\ninertia_kgm2 = 0.1\n[[joint]]\nstowed_deg = 90.0\nspring = { kind = \"linear\", preload_nm = 1.0, stiffness_nm_per_rad = 0.0, count = 1 }\n[rig]\nstatic_mu = 0.1\ndynamic_mu = 0.2\n";
    let e = Mechanism::from_toml_str(bad, "bad.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("rig") && e.contains("dynamic_mu"), "{e}");
    let bad = bad.replace(
        "static_mu = 0.1\ndynamic_mu = 0.2\n",
        "[[rig.trolley]]\npanel = 2\nbar = 1\nmass_kg = 1.0\nwire_m = 1.0\n",
    );
    let e = Mechanism::from_toml_str(&bad, "bad.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("panel 2"), "{e}");
}

#[test]
fn the_rig_causes_act_on_the_rig_the_simulator_integrates() {
    use deploywatch_sim::deployment;
    use deploywatch_sim::effect::{Effect, EffectKind};
    // wire_length: the pendulum of a 1.0 m wire made 1.5 m swings with the
    // period of 1.5 m.
    let rig = "[rig]\nstatic_mu = 0.0\ndynamic_mu = 0.0\n[[rig.bar]]\nmass_kg = 1e9\n[[rig.trolley]]\npanel = 1\nbar = 1\nmass_kg = 1e9\nwire_m = 1.0\nstart_m = [0.5, 0.0]\n";
    let mech = one_panel(rig, 3.0, 0.0, 1e-6);
    let (opts, times) = free_run(4.0, 1000.0);
    let longer = Effect::global(EffectKind::WireLength, 0.5);
    let run = simulate_rig(&mech, &[longer], &opts, &times).expect("pendulum");
    let phi = &run.traj.phi_deg[0];
    let ups: Vec<f64> = (1..phi.len())
        .filter(|&i| (phi[i - 1] < 0.0) != (phi[i] < 0.0))
        .map(|i| times[i - 1] + (times[i] - times[i - 1]) * -phi[i - 1] / (phi[i] - phi[i - 1]))
        .collect();
    let period = 2.0 * (ups[ups.len() - 1] - ups[0]) / (ups.len() - 1) as f64;
    let want = 2.0 * std::f64::consts::PI * (1.5 / 9.80665f64).sqrt();
    assert!((period - want).abs() < 0.005 * want, "{period} vs {want}");
    // rig_friction: the rails of the drawing (0.3 / 0.1) raised by Δμ in
    // the drawing's ratio, and the seed 001 T01 deployment slowed by it.
    let drawn = Mechanism::load(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../data/mechanisms/seed001_T01_rig.toml"),
    )
    .unwrap();
    let more = Effect::global(EffectKind::RigFriction, 0.1);
    let r = drawn.rig.as_ref().unwrap().with_effects(&[more]);
    assert!((r.dynamic_mu - 0.2).abs() < 1e-12 && (r.static_mu - 0.6).abs() < 1e-12);
    let o = SimOptions::default();
    let t0 = deployment::simulate(&drawn, &[], &o).unwrap().latch_s[0].unwrap();
    let t1 = deployment::simulate(&drawn, &[more], &o).unwrap().latch_s[0].unwrap();
    assert!(
        t1 > t0 + 0.05,
        "joint 1 latched at {t0} s, with more rail friction {t1} s"
    );
    // A rig cause on the flight unit (no rig) is refused, not ignored.
    let err = deployment::simulate(&drawn.flight(), &[more], &o).unwrap_err();
    assert!(err.to_string().contains("rig_friction"), "{err}");
    let nearer = Effect::global(EffectKind::FrameOffset, 0.02);
    let err = deployment::simulate(&drawn.flight(), &[nearer], &o).unwrap_err();
    assert!(err.to_string().contains("frame_offset"), "{err}");
}

#[test]
fn a_frame_offset_moves_every_frame_toward_the_panels() {
    use deploywatch_sim::effect::{Effect, EffectKind};
    let drawn = Mechanism::load(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../data/mechanisms/seed001_T01_rig.toml"),
    )
    .unwrap();
    let rig = drawn.rig.as_ref().unwrap();
    let nearer = Effect::global(EffectKind::FrameOffset, 0.02);
    let moved = rig.with_effects(&[nearer]);
    for (a, b) in rig.frames.iter().zip(&moved.frames) {
        // a ← a + Δd along the unit normal (into the allowed side, toward
        // the panels): 20 mm less clearance on either side.
        assert!((b.at_m - a.at_m - 0.02).abs() < 1e-12, "{}", a.name);
        assert_eq!(a.normal, b.normal);
    }
    // Seed 001 T01 on the rig: panel 3 meets `lateral -y` (0.25 mm deep, a
    // few mm before it would have turned back);
    // the frame 20 mm nearer is met earlier, 2 mm farther later, and 20 mm
    // farther not at all (no evidence of where it stands).
    let opts = SimOptions::default();
    let grid = deploywatch_sim::deployment::sample_grid(&drawn, &opts).unwrap();
    let times: Vec<f64> = (0..).map_while(|k| grid.get(k)).collect();
    let contact = |d: f64| {
        let e = [Effect::global(EffectKind::FrameOffset, d)];
        let run = simulate_rig(&drawn, &e, &opts, &times).expect("rig");
        run.contacts.into_iter().find(|c| c.frame == "lateral -y")
    };
    let (near, nominal, far) = (
        contact(0.02).expect("met 20 mm nearer"),
        contact(0.0).expect("met"),
        contact(-0.002).expect("met 2 mm farther"),
    );
    println!(
        "lateral -y met at {} s ({} mm deep) 20 mm nearer, {} s ({} mm), {} s ({} mm) 2 mm farther",
        near.first_s,
        near.max_depth_mm,
        nominal.first_s,
        nominal.max_depth_mm,
        far.first_s,
        far.max_depth_mm
    );
    assert!(near.first_s < nominal.first_s && nominal.first_s < far.first_s);
    assert!(contact(-0.02).is_none());
}
