//! The test-only named effect of the `demo-effect` feature, `demo_drag`
//! (`EffectKind::DemoDrag`, a quadratic drag `−c φ̇|φ̇|` at a joint through
//! the core's quadratic damping): added as one variant and its arms in
//! `host-sim/src/model/effect/` only (`ARCHITECTURE.md`, "A new named
//! effect"), it is simulated, written and read back, counted in the
//! margins and, hidden in a campaign, diagnosed by name at its joint.
//!
//! `cargo test -p deploywatch-sim --features demo-effect --test demo_effect`

use deploywatch_sim::campaign::Campaign;
use deploywatch_sim::deployment::{self, SimOptions};
use deploywatch_sim::diagnose::{diagnose, DiagnoseOptions};
use deploywatch_sim::effect::{self, Effect, EffectKind, Law};
use deploywatch_sim::findings::FoundEffect;
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::progress::quiet;
use deploywatch_sim::sensor::{self, SensorModel};
use std::path::Path;

/// The seed 001 pair of mechanisms (T01, T02).
fn mechanisms() -> Vec<Mechanism> {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/mechanisms");
    ["seed001_T01", "seed001_T02"]
        .iter()
        .map(|m| Mechanism::load(&data.join(format!("{m}.toml"))).unwrap())
        .collect()
}

#[test]
fn the_demo_effect_is_one_of_the_vocabulary() {
    let e: Effect = "demo_drag:joint=2:value=0.4".parse().unwrap();
    assert_eq!(e.kind(), EffectKind::DemoDrag);
    assert_eq!(e.law, Law::DemoDrag(0.4));
    assert_eq!(e.to_string(), "demo_drag:joint=2:value=0.4");
    assert!(EffectKind::EVERY.contains(&EffectKind::DemoDrag));
    assert!(EffectKind::ALL.contains(&EffectKind::DemoDrag));
    // Its law reaches the core as the quadratic damping it is made of.
    let (je, _) = effect::to_core(&[e], 3);
    assert_eq!(je[1].quadratic_nms2_per_rad2, 0.4);
    // Its findings entry reads back as the effect written.
    let back = FoundEffect::of_effect(&e).to_effect(0).unwrap();
    assert_eq!(back, Some(e));
}

/// A `demo_drag` hidden at joint 2 of the seed 001 pair (T01, T02), with
/// the reference sensor noise: the diagnosis, which sees only the runs and
/// the nominal mechanisms, names it at its joint, within 10 % of its value.
#[test]
fn a_hidden_demo_drag_is_diagnosed_by_name_at_its_joint() {
    let mechs = mechanisms();
    let truth = [Effect::joint(EffectKind::DemoDrag, 2, 0.3)];
    let mut campaign = Campaign::default();
    for (r, m) in mechs.iter().enumerate() {
        let traj = deployment::simulate(m, &truth, &SimOptions::default()).unwrap();
        let offsets = effect::encoder_offsets_deg(&truth, m.joint_count());
        let mut run = sensor::measure(&traj, &offsets, &SensorModel::REFERENCE, 39 + r as u64);
        run.set_meta("mechanism", &m.name);
        campaign
            .push(&mechs, run, Path::new(&format!("run{r}.csv")))
            .unwrap();
    }
    let outcome = diagnose(&campaign, &DiagnoseOptions::default(), &quiet);
    let found = outcome.extended.effects();
    let named: Vec<(EffectKind, Option<usize>)> =
        found.iter().map(|e| (e.kind(), e.joint)).collect();
    assert_eq!(
        named,
        vec![(EffectKind::DemoDrag, Some(2))],
        "found {found:?}"
    );
    let v = found[0].value();
    assert!((v - 0.3).abs() < 0.03, "demo_drag = {v}, hidden 0.3");
}
