//! The physical latch in the full simulator (`docs/spec/physics.md`
//! section 10, `docs/simulator.md` "Physical latch"): energy bookkeeping
//! over the bundled latch runs, a single impact's coefficient of
//! restitution against the Hunt–Crossley closed form, the outcomes of the
//! example mechanisms, and the option off leaving the ideal latch alone.

use deploywatch_core::physics::latch_contact::{
    HertzStop, LatchMark, Magnet, PhysicalLatch, Plunger,
};
use deploywatch_core::{Chain, Friction, GlobalEffects, Joint, JointEffects, Panel, Spring};
use deploywatch_sim::deployment::{self, SimOptions};
use deploywatch_sim::effect::Effect;
use deploywatch_sim::latch_deployment::{self, LatchEnd, LatchEventKind, LatchRun, PlungerEnd};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::ode::State;
use deploywatch_sim::torque_table::HostChain;
use deploywatch_sim::trajectory::Samples;
use std::path::Path;

fn mechanism(name: &str) -> Mechanism {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../data/mechanisms")
        .join(name);
    Mechanism::load(&p).unwrap_or_else(|e| panic!("{e}"))
}

/// Tight tolerances: the ledger closes to the integration's accuracy.
fn tight() -> SimOptions {
    SimOptions {
        rtol: 1e-11,
        atol: 1e-13,
        ..SimOptions::default()
    }
}

fn run(mech: &Mechanism, effects: &[&str], opts: &SimOptions) -> LatchRun {
    let effects: Vec<Effect> = effects.iter().map(|e| e.parse().unwrap()).collect();
    let grid = deployment::sample_grid(mech, opts).unwrap();
    latch_deployment::simulate_physical(mech, &effects, opts, grid)
        .unwrap_or_else(|e| panic!("{e}"))
}

/// A single rigid panel hinged at the bus, no spring, no plunger, no
/// magnet: only the stop acts during the impact.
#[allow(clippy::field_reassign_with_default)]
fn bare_stop(r_mm: f64) -> (HostChain<1>, PhysicalLatch<f64>) {
    let panel = Panel {
        length_m: 0.8,
        mass_kg: 3.5,
        com_m: 0.4,
        inertia_kgm2: 0.27,
    };
    let joint = Joint {
        stowed_rad: 0.2,
        spring: Spring::None,
        friction: Friction::default(),
        effects: JointEffects::default(),
    };
    let latch = PhysicalLatch {
        side: 1.0,
        stop: HertzStop {
            stiffness_n_per_mm1_5: 37_000.0,
            damping_ns_per_mm1_25: 3.7,
            radius_m: r_mm / 1000.0,
        },
        plunger: Plunger {
            preload_n: 0.0,
            stiffness_n_per_mm: 0.0,
            radius_m: 0.04,
            stroke_mm: 0.0,
            crest_rad: 0.0,
            entry_ramp_rad: 0.5,
            hold_ramp_rad: 0.5,
        },
        magnet: Magnet {
            force_n: 0.0,
            decay_mm: 1.0,
            reach_mm: 0.0,
            radius_m: 0.04,
        },
        switch_travel_rad: 0.0,
        lock: deploywatch_core::physics::latch_contact::Lock::Detent,
    };
    let chain = Chain::new([panel], [joint], GlobalEffects::default()).unwrap();
    (chain, latch)
}

/// The Hunt–Crossley closed form (docs/spec/physics.md section 10.4): for
/// `F = k δ^n + c δ^p δ̇` at small damping, the energy lost in one impact
/// over the energy brought is
/// `4 c δm^(p+1) B((p+1)/(n+1), 3/2) / ((n+1) m v0)`, with
/// `δm = ((n+1) m v0² / (2k))^(1/(n+1))`; for n = 1.5, p = 0.25 the Beta
/// function is B(1/2, 3/2) = π/2 and the ratio `0.8 π c √(1.25/(m k))`
/// does not depend on v0. Units: N, mm, s (m in N·s²/mm = 1000 kg).
fn restitution_closed_form(m_eff_kg: f64, v0_mm_s: f64) -> f64 {
    let (k, c, n, p) = (37_000.0f64, 3.7f64, 1.5f64, 0.25f64);
    let m = m_eff_kg / 1000.0;
    let delta_max = ((n + 1.0) * m * v0_mm_s * v0_mm_s / (2.0 * k)).powf(1.0 / (n + 1.0));
    let beta = std::f64::consts::FRAC_PI_2; // B(0.5, 1.5)
    let ratio = 4.0 * c * delta_max.powf(p + 1.0) * beta / ((n + 1.0) * m * v0_mm_s);
    (1.0 - ratio).sqrt()
}

#[test]
fn single_impact_restitution_matches_hunt_crossley_within_2_percent() {
    for r_mm in [20.0, 40.0] {
        let (chain, latch) = bare_stop(r_mm);
        let j_hinge = 0.27 + 3.5 * 0.4 * 0.4;
        let m_eff = j_hinge / (r_mm / 1000.0f64).powi(2);
        for v0 in [0.01, 0.1, 1.0] {
            let y0 = State {
                q: [1e-4],
                v: [-v0],
            };
            let times = Samples::Grid {
                rate_hz: 1000.0,
                count: 101,
            };
            let out =
                latch_deployment::run_from(&chain, [Some(latch)], y0, times, &tight()).unwrap();
            let stops: Vec<_> = out
                .events
                .iter()
                .filter(|e| e.kind == LatchEventKind::Mark(LatchMark::Stop))
                .collect();
            assert!(stops.len() >= 2, "r {r_mm} mm, v0 {v0}: {:?}", out.events);
            let e_sim = -stops[1].rate_rad_s / stops[0].rate_rad_s;
            let e_hc = restitution_closed_form(m_eff, v0 * r_mm);
            println!(
                "r = {r_mm} mm, m_eff = {m_eff:.1} kg, v0 = {v0} rad/s ({:.1} mm/s): e = {e_sim:.5}, closed form {e_hc:.5}, contact loss {:.3e} J",
                v0 * r_mm,
                out.energy.contact_j
            );
            assert!((e_sim - e_hc).abs() < 0.02 * e_hc, "e {e_sim} vs {e_hc}");
            assert!(out.energy.contact_j > 0.0);
        }
    }
}

/// Every bundled physical-latch scenario: mechanism, effects.
const SCENARIOS: [(&str, &[&str]); 5] = [
    ("seed000_case1_physical_latch.toml", &[]),
    ("seed001_T02_physical_latch.toml", &[]),
    ("seed001_T01_physical_latch.toml", &[]),
    ("one_panel_physical_latch.toml", &[]),
    (
        "one_panel_physical_latch.toml",
        &["plunger_weakening:joint=1:value=0.5"],
    ),
];

#[test]
fn energy_ledger_closes_to_1e_6_of_the_stored_energy() {
    for (name, effects) in SCENARIOS {
        let mech = mechanism(name);
        let out = run(&mech, effects, &tight());
        let e = out.energy;
        let rel = e.worst_drift_j / e.stored_j;
        println!(
            "{name} {effects:?}: stored {:.6} J, friction {:.6} J, contact {:.6} J, worst drift {:.3e} J = {rel:.2e} of stored",
            e.stored_j, e.friction_j, e.contact_j, e.worst_drift_j
        );
        assert!(rel < 1e-6, "{name}: drift {rel:e}");
        assert!(e.contact_j > 0.0, "the stops dissipate");
        // Each event carries the evaluations made by then: they grow along
        // the run and stay within its total.
        let counts: Vec<usize> = out.events.iter().map(|ev| ev.evaluations).collect();
        assert!(!counts.is_empty(), "{name}: no event");
        assert!(
            counts.windows(2).all(|w| w[0] <= w[1]),
            "{name}: {counts:?}"
        );
        let total = out.traj.stats.evaluations;
        assert!(
            counts.iter().all(|&c| 0 < c && c <= total),
            "{name}: {counts:?} of {total}"
        );
    }
}

fn outcome(
    mech: &Mechanism,
    out: &LatchRun,
    joint: usize,
    effects: &[&str],
) -> latch_deployment::LatchOutcome {
    let effects: Vec<Effect> = effects.iter().map(|e| e.parse().unwrap()).collect();
    let latches = latch_deployment::latches::<3>(mech, &effects);
    let latch = latches[joint - 1]
        .or_else(|| latch_deployment::latches::<1>(mech, &effects)[0])
        .unwrap();
    out.outcome(joint, &latch).unwrap()
}

#[test]
fn t02_joint_2_bounces_and_holds_joint_3_escapes_and_relatches() {
    let mech = mechanism("seed001_T02_physical_latch.toml");
    let out = run(&mech, &[], &SimOptions::default());
    let j2 = outcome(&mech, &out, 2, &[]);
    assert!(
        j2.impacts >= 5 && j2.escapes == 0 && j2.end == LatchEnd::Plunger(PlungerEnd::Held),
        "{j2:?}"
    );
    assert!(
        j2.switch_closings >= 2,
        "the switch bounces with the joint: {j2:?}"
    );
    let j3 = outcome(&mech, &out, 3, &[]);
    assert!(
        j3.escapes >= 1
            && j3.engagements == j3.escapes + 1
            && j3.end == LatchEnd::Plunger(PlungerEnd::Held),
        "{j3:?}"
    );
    assert!(out.traj.latched[1].last() == Some(&true) && out.traj.latched[2].last() == Some(&true));
}

#[test]
fn t01_joint_2_escapes_and_never_relatches() {
    let mech = mechanism("seed001_T01_physical_latch.toml");
    let out = run(&mech, &[], &SimOptions::default());
    let j2 = outcome(&mech, &out, 2, &[]);
    assert!(
        j2.escapes >= 1 && j2.end == LatchEnd::Plunger(PlungerEnd::ShortOfPlunger),
        "{j2:?}"
    );
    assert_eq!(out.traj.latch_s[1], None);
    assert_eq!(
        outcome(&mech, &out, 1, &[]).end,
        LatchEnd::Plunger(PlungerEnd::Held)
    );
}

#[test]
fn one_panel_stops_on_the_ramp_with_the_switch_open_and_relatches_with_a_weak_plunger() {
    let mech = mechanism("one_panel_physical_latch.toml");
    let out = run(&mech, &[], &SimOptions::default());
    let o = outcome(&mech, &out, 1, &[]);
    assert_eq!(o.end, LatchEnd::Plunger(PlungerEnd::OnRamp), "{o:?}");
    let crest = mech.latch(0).unwrap().plunger.crest_deg;
    assert!(
        o.end_travel_deg > crest && o.end_travel_deg < crest + 1.0,
        "{o:?}"
    );
    assert_eq!(
        out.traj.latched[0].last(),
        Some(&false),
        "switch open on the ramp"
    );
    // Held on the ramp by the plunger against spring and magnet: it creeps
    // (the Coulomb law is regularised) towards their balance, never over.
    assert!(
        out.traj.rate_deg_s[0].last().unwrap().abs() < 0.05,
        "at rest"
    );

    let weak = ["plunger_weakening:joint=1:value=0.5"];
    let out = run(&mech, &weak, &SimOptions::default());
    let o = outcome(&mech, &out, 1, &weak);
    assert!(
        o.escapes >= 1 && o.end == LatchEnd::Plunger(PlungerEnd::Held),
        "{o:?}"
    );
    assert!(out.traj.latch_s[0].is_some());
}

#[test]
fn option_off_is_the_ideal_latch_and_latch_effects_need_a_physical_latch() {
    let mut mech = mechanism("seed001_T02_physical_latch.toml");
    let text = mech.to_toml_string();
    let back = Mechanism::from_toml_str(&text, "written.toml").unwrap();
    assert_eq!(back, mech, "the latch tables read back as written");
    mech.latches.clear();
    let plain = mechanism("seed001_T02.toml");
    let opts = SimOptions::default();
    let weak: Effect = "plunger_weakening:joint=1:value=0.5".parse().unwrap();
    assert!(
        deployment::simulate(&plain, &[weak], &opts).is_err(),
        "no physical latch to weaken"
    );
    // Without latches the physical file is the ideal run of the same
    // mechanism with its friction.
    let ideal = deployment::simulate(&mech, &[], &opts).unwrap();
    assert!(ideal.latch_s[2].is_some());
    assert!(
        ideal
            .latched
            .iter()
            .all(|l| l.windows(2).all(|w| w[0] <= w[1])),
        "switch steps once"
    );
}

#[test]
fn bad_latch_keys_are_refused_with_their_line() {
    let mech = mechanism("one_panel_physical_latch.toml");
    let text = mech.to_toml_string();
    let bad = text.replace("preload_n = 10.0", "preload_n = -1.0");
    let e = Mechanism::from_toml_str(&bad, "bad.toml").unwrap_err();
    let line = bad
        .lines()
        .position(|l| l.contains("preload_n = -1.0"))
        .unwrap()
        + 1;
    assert_eq!(e.line, Some(line), "{e}");
    assert!(
        e.to_string().contains("joint[1].latch.plunger.preload_n"),
        "{e}"
    );
    let bad = text.replace("model = \"physical\"", "model = \"magic\"");
    assert!(Mechanism::from_toml_str(&bad, "bad.toml")
        .unwrap_err()
        .to_string()
        .contains("model"));
}

/// The bundled latch runs: folder, file, mechanism, effects (their
/// READMEs give the same `simulate` commands, `--seed 1`).
const BUNDLED: [(&str, &str, &str, &[&str]); 4] = [
    (
        "latch_clean_bounce",
        "seed001_T02.csv",
        "seed001_T02_physical_latch.toml",
        &[],
    ),
    (
        "latch_escape_relatch",
        "one_panel.csv",
        "one_panel_physical_latch.toml",
        &["plunger_weakening:joint=1:value=0.5"],
    ),
    (
        "latch_ramp_stop",
        "one_panel.csv",
        "one_panel_physical_latch.toml",
        &[],
    ),
    (
        "latch_escape_never",
        "seed001_T01.csv",
        "seed001_T01_physical_latch.toml",
        &[],
    ),
];

#[test]
fn bundled_latch_runs_are_what_their_commands_make() {
    use deploywatch_sim::run::Run;
    use deploywatch_sim::sensor::{self, SensorModel};
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data");
    for (dir, file, mech_file, effects) in BUNDLED {
        let run = Run::load(&data.join("examples").join(dir).join(file)).unwrap();
        let mech = mechanism(mech_file);
        assert_eq!(run.mechanism(), Some(mech.name.as_str()));
        let out = self::run(&mech, effects, &SimOptions::default());
        let again = sensor::measure(
            &out.traj,
            &vec![0.0; mech.joint_count()],
            &SensorModel::REFERENCE,
            1,
        );
        assert_eq!(again.latch, run.latch, "{dir}: the switch columns");
        for j in 0..mech.joint_count() {
            let worst = again.phi_deg[j]
                .iter()
                .zip(&run.phi_deg[j])
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(worst < 1e-5, "{dir} joint {}: {worst} deg", j + 1);
        }
    }
}
