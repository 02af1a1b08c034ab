//! Clean runs of wings nobody drew raise no alarm: random wings
//! (`tests/src/wing_gen.rs`: 2 to 8 panels, linear, tape and curve
//! springs, ideal, plunger and pawl latches mixed), each simulated as drawn
//! with the reference sensor's noise and rounding, two runs per wing, and
//! diagnosed with the mechanism as drawn. Nothing may be named: no effect,
//! no encoder delay taken out, no panel mode, no free-play, no latch that
//! differs from its drawing, nothing unexplained, no ambiguity listed.
//!
//! `DEPLOYWATCH_WINGS` wings (default 6); wings with a `[rig]` are left
//! out unless `DEPLOYWATCH_RIG=1` (each candidate simulates the rig: minutes
//! a wing). Every wing and what was named is printed:
//! `DEPLOYWATCH_WINGS=40 cargo test --release -p deploywatch-tests --test
//! diagnosis_clean_wings -- --nocapture`.

use deploywatch_sim::campaign::Campaign;
use deploywatch_sim::deployment::{self, SimOptions};
use deploywatch_sim::diagnose::{diagnose, Outcome};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::progress::quiet;
use deploywatch_sim::sensor::{self, SensorModel};
use deploywatch_tests::wing_gen::wing_toml;
use std::path::Path;

fn wings() -> u64 {
    std::env::var("DEPLOYWATCH_WINGS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(6)
}

/// Two runs of `m` as drawn, noise seeds `seed` and `seed + 1`.
fn campaign(m: &Mechanism, seed: u64) -> Result<Campaign, String> {
    let traj = deployment::simulate(m, &[], &SimOptions::default()).map_err(|e| e.to_string())?;
    let mut c = Campaign::default();
    for r in 0..2 {
        let mut run = sensor::measure(&traj, &[], &SensorModel::REFERENCE, seed + r);
        run.set_meta("mechanism", &m.name);
        c.push(
            std::slice::from_ref(m),
            run,
            Path::new(&format!("run{r}.csv")),
        )
        .map_err(|e| e.to_string())?;
    }
    Ok(c)
}

/// What the diagnosis named, in words (empty: nothing).
fn named(o: &Outcome) -> Vec<String> {
    let mut out: Vec<String> = o.extended.effects().iter().map(|e| e.to_string()).collect();
    if let Some(d) = o.encoder_delay.as_ref().filter(|d| d.taken_out()) {
        out.push(format!("an encoder delay of {:.2} ms", d.delay_s * 1e3));
    }
    if o.panel_mode.is_some() {
        out.push("a panel mode".into());
    }
    out.extend(
        o.free_play
            .iter()
            .map(|f| format!("free-play at joint {}", f.joint)),
    );
    out.extend(
        o.latches
            .iter()
            .filter(|l| !l.differs.is_empty() || l.cause.is_some())
            .map(|l| format!("the latch of joint {} differs from its drawing", l.joint)),
    );
    if o.unexplained.is_some() {
        out.push("something unexplained".into());
    }
    out.extend(o.ambiguities.iter().map(|g| {
        format!(
            "an ambiguity at joint {} ({} sets the runs cannot tell apart)",
            g.joint,
            g.sets.len()
        )
    }));
    out
}

#[test]
fn clean_runs_of_random_wings_name_nothing() {
    let rig = std::env::var_os("DEPLOYWATCH_RIG").is_some();
    let opts = deploywatch_tests::diagnose_options();
    let (mut tried, mut alarms) = (0u64, Vec::new());
    let mut seed = 0;
    while tried < wings() {
        let w = wing_toml(9300 + seed, 0.3);
        seed += 1;
        if w.rig && !rig {
            continue;
        }
        let m = Mechanism::from_toml_str(&w.toml, "random.toml").expect("a valid wing");
        let c = campaign(&m, 10 * seed).expect("the drawn wing simulates");
        let o = diagnose(&c, &opts, &quiet);
        tried += 1;
        let said = named(&o);
        println!(
            "wing {} ({} joints, physical latches at {:?}{}): RMS {:.4} deg, noise {:.4} deg, {:.1} s: {}",
            9300 + seed - 1,
            w.joints,
            w.physical,
            if w.rig { ", rig" } else { "" },
            o.extended.rms(),
            o.noise_sigma_deg,
            o.wall_s,
            if said.is_empty() {
                "nothing named".to_string()
            } else {
                said.join("; ")
            }
        );
        if !said.is_empty() {
            alarms.push(format!(
                "wing {}: {}\n{}",
                9300 + seed - 1,
                said.join("; "),
                w.toml
            ));
        }
    }
    assert!(
        alarms.is_empty(),
        "clean runs named:\n{}",
        alarms.join("\n\n")
    );
}
