//! The pawl, a positive lock (`docs/spec/physics.md` §10.5,
//! `docs/simulator.md` "A pawl"), in the full simulator and the monitor:
//!
//! - a new user's 5 kg panel whose ball plunger (15 N, then
//!   300 N) lets the rebound climb back out is held by a pawl on the same
//!   stop;
//! - a pawl whose breaking torque is below the rebound's peak load breaks,
//!   and the run says when; one with twice the peak holds (the peak from
//!   the Hertz closed form of §10.4 at the rebound's measured speed, not
//!   from the simulator's break logic);
//! - the energy ledger closes to 1e-6 of the stored energy across the drop
//!   (the click's energy booked) and a break;
//! - the TOML table reads back as written, and its mistakes are refused
//!   with the key path;
//! - the monitor on simulated pawl runs with sensor noise: latched at the
//!   end, never escaped, no latch flag; on a broken pawl, `escaped` with
//!   `latch_disagree` from the break to the end, also back on its stop with
//!   the switch closed, and predicted `stall` (confidence 1);
//! - as-built pawls (`Mechanism::as_built`, `LatchTolerance::default`),
//!   with and without a named effect, are never refused by `simulate`:
//!   `DEPLOYWATCH_PAWL_DRAWS` draws (default 200; the measurement of
//!   `docs/simulator.md` runs 1,000:
//!   `DEPLOYWATCH_PAWL_DRAWS=1000 cargo test --release -p deploywatch-tests --test latch_pawl -- --nocapture`).

use deploywatch_core::monitor::{Fault, LatchState, Prediction};
use deploywatch_core::monitor::{Monitor, Sample, Status};
use deploywatch_core::physics::latch_contact::PhysicalLatch;
use deploywatch_sim::deployment::{self, SimOptions};
use deploywatch_sim::effect::Effect;
use deploywatch_sim::latch::{LatchTolerance, PlungerSpec};
use deploywatch_sim::latch_deployment::{
    self, LatchEnd, LatchEventKind, LatchOutcome, LatchRun, PawlEnd,
};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::monitor_config::{monitor_config, samples};
use deploywatch_sim::sensor::{measure, SensorModel};
use deploywatch_tests::{data_dir, SplitMix};
use rayon::prelude::*;

fn mechanism(name: &str) -> Mechanism {
    Mechanism::load(&data_dir().join("mechanisms").join(name)).unwrap_or_else(|e| panic!("{e}"))
}

/// Tight tolerances: the ledger closes to the integration's accuracy. The
/// 5 kg panel's 40 hard impacts on stop and pawl drift 2e-5 of the stored
/// energy at `simulate`'s default `rtol` 1e-8, 7e-7 at 1e-11 and 6e-7 at
/// 1e-12 (measured by this test); the click and the break are booked
/// exactly (`pawl_j` is `E_click` to 1e-12).
fn tight() -> SimOptions {
    SimOptions {
        rtol: 1e-12,
        atol: 1e-14,
        ..SimOptions::default()
    }
}

fn simulate(mech: &Mechanism, effects: &[Effect], opts: &SimOptions) -> Result<LatchRun, String> {
    let grid = deployment::sample_grid(mech, opts).map_err(|e| e.to_string())?;
    latch_deployment::simulate_physical(mech, effects, opts, grid).map_err(|e| e.to_string())
}

fn core_latch(mech: &Mechanism, j: usize) -> PhysicalLatch<f64> {
    let stowed = mech.joints[j].stowed_deg;
    mech.latch(j).expect("latch").to_core(stowed, 1.0, 1.0)
}

/// Joint `j`'s (0-based) outcome; where the run ended is its last sample
/// (every run here is sampled to its end).
fn outcome(mech: &Mechanism, run: &LatchRun, j: usize) -> LatchOutcome {
    let last = *run.traj.phi_deg[j].last().expect("a sample");
    let end = run.end_phi_deg[j];
    assert!(
        (end - last).abs() <= 1e-9,
        "ended at {end} deg, last sample {last} deg"
    );
    run.outcome(j + 1, &core_latch(mech, j)).expect("outcome")
}

/// The one-panel pawl mechanism with a ball plunger of preload `p0` \[N\]
/// (rate `p0 / 6` N/mm) in place of its pawl, on the same stop.
fn with_plunger(p0: f64) -> Mechanism {
    let mut m = mechanism("one_panel_pawl.toml");
    let l = m.latches[0].as_mut().expect("latch");
    l.pawl = None;
    l.plunger = PlungerSpec {
        preload_n: p0,
        stiffness_n_per_mm: p0 / 6.0,
        radius_mm: 40.0,
        stroke_mm: 1.0,
        crest_deg: 0.6,
        entry_ramp_deg: 30.0,
        hold_ramp_deg: 50.0,
    };
    m
}

fn with_breaking_torque(nm: f64) -> Mechanism {
    let mut m = mechanism("one_panel_pawl.toml");
    if let Some(p) = m.latches[0].as_mut().and_then(|l| l.pawl.as_mut()) {
        p.breaking_torque_nm = nm;
    }
    m
}

#[test]
fn a_plunger_lets_the_5_kg_panel_climb_back_out_a_pawl_on_the_same_stop_holds_it() {
    for p0 in [15.0, 300.0] {
        let m = with_plunger(p0);
        let run = simulate(&m, &[], &SimOptions::default()).expect("plunger run");
        let o = outcome(&m, &run, 0);
        println!("plunger {p0} N: {o:?}");
        assert!(o.escapes >= 1, "plunger {p0} N: {o:?}");
        assert_eq!(o.pawl_drops, 0);
    }
    let m = mechanism("one_panel_pawl.toml");
    let l = core_latch(&m, 0);
    let run = simulate(&m, &[], &SimOptions::default()).expect("pawl run");
    let o = outcome(&m, &run, 0);
    println!("pawl: {o:?}");
    assert_eq!((o.pawl_drops, o.pawl_broke_s), (1, None), "{o:?}");
    assert_eq!(o.end, LatchEnd::Pawl(PawlEnd::InNotch));
    assert!(o.impacts >= 2, "it rebounds: {o:?}");
    let drop_t = run
        .events
        .iter()
        .find(|e| e.kind == LatchEventKind::PawlDrop)
        .map(|e| e.t_s)
        .expect("a drop");
    // From the drop on, never back beyond the notch and the contact's give.
    let limit = l.breaking_travel_rad().to_degrees();
    for (t, phi) in run.traj.t_s.iter().zip(&run.traj.phi_deg[0]) {
        if *t > drop_t {
            assert!(l.side * phi <= limit, "t {t}: {phi} deg beyond {limit}");
        }
    }
    assert!(run.traj.latch_s[0].is_some(), "switch closed at the end");
}

/// The largest peak torque [N·m] of the rebounds on the notch's wall, from
/// the undamped Hertz closed form (`physics.md` §10.4) at each contact
/// onset's measured speed: `δm^2.5 = 2.5 m v² / (2k)`, `T = k δm^1.5 r`.
fn rebound_peak_nm(m: &Mechanism, run: &LatchRun) -> f64 {
    let l = core_latch(m, 0);
    let p = &m.panels[0];
    let hinge = p.inertia_kgm2 + p.mass_kg * p.com_m * p.com_m;
    let r_mm = l.plunger.radius_m * 1000.0;
    let m_eff = hinge / (l.plunger.radius_m * l.plunger.radius_m) / 1000.0; // N·s²/mm
    let k = l.stop.stiffness_n_per_mm1_5;
    run.events
        .iter()
        .filter(|e| e.kind == LatchEventKind::Notch && e.rate_rad_s > 0.0)
        .filter(|e| (e.travel_rad - l.plunger.crest_rad).abs() < 1e-9)
        .map(|e| {
            let v = e.rate_rad_s * r_mm;
            let d = (2.5 * m_eff * v * v / (2.0 * k)).powf(1.0 / 2.5);
            k * d.powf(1.5) * l.plunger.radius_m
        })
        .fold(0.0, f64::max)
}

#[test]
fn a_pawl_weaker_than_the_rebound_breaks_and_the_run_says_when() {
    let strong = with_breaking_torque(1e7);
    let run = simulate(&strong, &[], &SimOptions::default()).expect("run");
    let peak = rebound_peak_nm(&strong, &run);
    let first_onset = run
        .events
        .iter()
        .find(|e| e.kind == LatchEventKind::Notch)
        .map(|e| e.t_s)
        .expect("the rebound reaches the pawl");
    println!("rebound peak on the pawl (closed form): {peak:.1} N·m");
    assert!(peak > 10.0, "{peak}");
    let holds = with_breaking_torque(2.0 * peak);
    let o = outcome(
        &holds,
        &simulate(&holds, &[], &SimOptions::default()).unwrap(),
        0,
    );
    assert_eq!(o.pawl_broke_s, None, "{o:?}");
    let weak = with_breaking_torque(0.5 * peak);
    let run = simulate(&weak, &[], &SimOptions::default()).expect("run");
    let o = outcome(&weak, &run, 0);
    println!("pawl of {:.1} N·m: {o:?}", 0.5 * peak);
    let t = o.pawl_broke_s.expect("the weak pawl breaks");
    assert_eq!(o.end, LatchEnd::Pawl(PawlEnd::Broken), "{o:?}");
    assert_eq!(o.end.to_string(), "free, its pawl broken");
    assert!(
        (first_onset..first_onset + 0.01).contains(&t),
        "breaks in the first rebound on it ({first_onset} s): {t}"
    );
    // Free of its pawl, the joint leaves the notch.
    let l = core_latch(&weak, 0);
    let out = run.traj.phi_deg[0]
        .iter()
        .map(|p| l.side * p)
        .fold(f64::MIN, f64::max);
    assert!(out > 1.0, "the rebound carries it out: {out} deg");
}

#[test]
fn the_ledger_closes_across_the_drop_and_the_break() {
    let strong = mechanism("one_panel_pawl.toml");
    let l = core_latch(&strong, 0);
    for (name, m) in [
        ("holds", strong.clone()),
        ("breaks", with_breaking_torque(300.0)),
    ] {
        let run = simulate(&m, &[], &tight()).expect("run");
        let e = run.energy;
        let rel = e.worst_drift_j / e.stored_j;
        println!(
            "{name}: stored {:.6} J, pawl {:.6} J (click {:.6} J), stops {:.6} J, drift {rel:.2e}",
            e.stored_j,
            e.pawl_j,
            l.click_energy(),
            e.contact_j
        );
        assert!(rel < 1e-6, "{name}: drift {rel:e}");
        let broke = outcome(&m, &run, 0).pawl_broke_s.is_some();
        assert_eq!(broke, name == "breaks");
        if broke {
            assert!(e.pawl_j > l.click_energy() + 1e-3, "the break's energy");
        } else {
            assert!((e.pawl_j - l.click_energy()).abs() < 1e-12, "the click");
        }
    }
}

#[test]
fn the_pawl_table_reads_back_and_its_mistakes_are_refused_with_the_key() {
    let m = mechanism("seed001_T01_pawl.toml");
    let back = Mechanism::from_toml_str(&m.to_toml_string(), "back.toml").expect("reads back");
    assert_eq!(back.latches, m.latches);
    assert!(m.latches.iter().flatten().all(|l| l.pawl.is_some()));
    let text = mechanism("one_panel_pawl.toml").to_toml_string();
    let bad = text.replace("breaking_torque_nm = 1500.0", "breaking_torque_nm = 0.0");
    let e = Mechanism::from_toml_str(&bad, "bad.toml").unwrap_err();
    assert!(
        e.to_string()
            .contains("joint[1].latch.pawl.breaking_torque_nm"),
        "{e}"
    );
    let plunger = "plunger = { preload_n = 1.0, stiffness_n_per_mm = 1.0, radius_mm = 40.0, \
                   stroke_mm = 0.5, crest_deg = 0.5, entry_ramp_deg = 30.0, hold_ramp_deg = 50.0 }\npawl = ";
    let both = text.replace("pawl = ", plunger);
    let e = Mechanism::from_toml_str(&both, "both.toml").unwrap_err();
    assert!(e.to_string().contains("not both"), "{e}");
    let neither: String = text
        .lines()
        .filter(|l| !l.starts_with("pawl = "))
        .map(|l| format!("{l}\n"))
        .collect();
    let e = Mechanism::from_toml_str(&neither, "neither.toml").unwrap_err();
    assert!(e.to_string().contains("pawl"), "{e}");
}

fn replay<const N: usize>(mech: &Mechanism, run: &LatchRun, seed: u64) -> Vec<Status<N>> {
    let measured = measure(&run.traj, &[], &SensorModel::REFERENCE, seed);
    let cfg = monitor_config::<N>(mech).expect("monitor config");
    let mut m = Monitor::new(&cfg).expect("monitor");
    samples::<N>(&measured)
        .expect("joint count")
        .iter()
        .map(|s| m.replay_step(s))
        .collect()
}

/// Every pawl joint: latched at the end, never escaped, no latch flag,
/// and latched at every sample once declared.
fn monitor_holds<const N: usize>(name: &str, seeds: u64) {
    let mech = mechanism(name);
    let run = simulate(&mech, &[], &SimOptions::default()).expect("run");
    for seed in 0..seeds {
        let st = replay::<N>(&mech, &run, seed);
        for j in 0..N {
            let o = outcome(&mech, &run, j);
            assert_eq!(
                (o.pawl_drops, o.pawl_broke_s),
                (1, None),
                "{name} joint {}",
                j + 1
            );
            let mut declared = false;
            for s in &st {
                let js = &s.joints[j];
                let at = format!("{name} seed {seed} joint {} t {}", j + 1, s.t_s);
                assert_ne!(js.latch, LatchState::Escaped, "{at}");
                for f in [
                    Fault::LatchDisagree,
                    Fault::SwitchChatter,
                    Fault::SwitchEarly,
                ] {
                    assert!(!js.faults.contains(f), "{at}: {f:?}");
                }
                if declared {
                    assert_eq!(js.latch, LatchState::Latched, "{at}: latched stays latched");
                }
                declared |= js.latch == LatchState::Latched;
            }
            assert!(
                declared,
                "{name} seed {seed} joint {}: never latched",
                j + 1
            );
        }
    }
}

#[test]
fn the_monitor_says_latched_and_never_escaped_on_simulated_pawl_runs() {
    monitor_holds::<1>("one_panel_pawl.toml", 5);
    monitor_holds::<3>("seed001_T01_pawl.toml", 3);
}

#[test]
fn the_monitor_flags_a_broken_pawl() {
    let mech = with_breaking_torque(300.0);
    let run = simulate(&mech, &[], &SimOptions::default()).expect("run");
    let broke = outcome(&mech, &run, 0).pawl_broke_s.expect("breaks");
    let st = replay::<1>(&mech, &run, 1);
    let flagged = st.iter().find(|s| {
        s.joints[0].latch == LatchState::Escaped
            && s.joints[0].faults.contains(Fault::LatchDisagree)
    });
    let t = flagged
        .map(|s| f64::from(s.t_s))
        .expect("escaped and flagged");
    assert!(t > broke, "{t} after the break at {broke}");
    assert!(
        st.iter()
            .all(|s| f64::from(s.t_s) > broke || s.joints[0].latch != LatchState::Escaped),
        "never escaped before the break"
    );
    // A broken pawl locks nothing: its spring brings the joint back onto
    // its stop, switch closed, and it is never latched again.
    let tr = &run.traj;
    let back = (0..tr.t_s.len())
        .any(|i| tr.t_s[i] > t + 0.5 && tr.phi_deg[0][i].abs() < 0.05 && tr.latched[0][i]);
    assert!(back, "the free joint is back on its stop, switch closed");
    for s in st.iter().filter(|s| f64::from(s.t_s) >= t) {
        let js = &s.joints[0];
        assert!(
            js.latch == LatchState::Escaped && js.faults.contains(Fault::LatchDisagree),
            "t {}: {:?} {:?}",
            s.t_s,
            js.latch,
            js.faults
        );
        // Predicted not to latch, certain, from the next refresh on.
        if f64::from(s.t_s) >= t + 0.1 {
            assert_eq!(
                (js.prediction, js.confidence, js.time_to_latch_s),
                (Prediction::Stall, 1.0, None),
                "t {}",
                s.t_s
            );
        }
    }
}

/// The monitor's statuses on `samples` of a pawl mechanism.
fn statuses<const N: usize>(mech: &Mechanism, samples: &[Sample<N>]) -> Vec<Status<N>> {
    let cfg = monitor_config::<N>(mech).expect("monitor config");
    let mut m = Monitor::new(&cfg).expect("monitor");
    samples.iter().map(|s| m.replay_step(s)).collect()
}

/// A latched pawl joint rebounds within its notch (0.2 to 0.8°
/// over a few samples, the switch opening with it) — motion the lock
/// allows, never `encoder_outlier`; a real spike of the encoder mid-swing
/// still is, and one at a latched joint beyond the pawl's reach is flagged
/// (`encoder_outlier` or `latch_disagree`). A spike within the reach of a
/// latched pawl joint is a rebound to the monitor: it cannot tell them apart.
#[test]
fn a_pawl_rebound_is_no_encoder_outlier_a_spike_still_is() {
    let mech = mechanism("seed001_T01_pawl.toml");
    let run = simulate(&mech, &[], &SimOptions::default()).expect("run");
    let mut rebounds = 0;
    for seed in 0..3 {
        let measured = measure(&run.traj, &[], &SensorModel::REFERENCE, seed);
        let mut samples = samples::<3>(&measured).expect("joint count");
        let st = statuses(&mech, &samples);
        let mut latched_at = [None; 3];
        for (k, s) in st.iter().enumerate() {
            for (j, js) in s.joints.iter().enumerate() {
                if latched_at[j].is_some() {
                    let at = format!("seed {seed} joint {} t {}", j + 1, s.t_s);
                    assert!(!js.faults.contains(Fault::EncoderOutlier), "{at}");
                    rebounds += usize::from(!samples[k].latch[j]);
                }
                if js.latch == LatchState::Latched && latched_at[j].is_none() {
                    latched_at[j] = Some(k);
                }
            }
        }
        // A spike 2° beyond the latch's reach (the farthest the pawl lets
        // the joint back: its notch and the contact's give under the
        // breaking torque) at each joint, 20 samples after its latch.
        let reach = monitor_config::<3>(&mech)
            .expect("monitor config")
            .joints
            .iter()
            .find_map(|j| j.physical)
            .expect("a pawl")
            .crest_deg;
        for (j, at) in latched_at.iter().enumerate() {
            let latched = at.expect("latched");
            // Mid-swing (the first reading within 45° of the latch): a
            // spike of 5°, flagged `encoder_outlier` as before.
            let k = samples
                .iter()
                .position(|x| x.phi_deg[j].abs() < 45.0)
                .expect("mid-swing");
            let mut spiked = samples.clone();
            spiked[k].phi_deg[j] += 5.0;
            let js = statuses(&mech, &spiked)[k].joints[j];
            let at = format!("seed {seed} joint {} sample {k}", j + 1);
            assert!(js.faults.contains(Fault::EncoderOutlier), "{at}: {js:?}");
            // Latched: beyond the reach it is no rebound, and flagged.
            let k = latched + 20;
            let mut spiked = samples.clone();
            spiked[k].phi_deg[j] = -(reach + 2.0) * spiked[k].phi_deg[j].signum();
            let js = statuses(&mech, &spiked)[k].joints[j];
            let at = format!("seed {seed} joint {} sample {k}", j + 1);
            assert!(
                js.faults.contains(Fault::EncoderOutlier)
                    || js.faults.contains(Fault::LatchDisagree),
                "{at}: {js:?}"
            );
        }
        samples.clear();
    }
    // The runs do rebound once latched: samples with the switch open.
    assert!(
        rebounds > 0,
        "no rebound after a latch: the test tests nothing"
    );
}

/// One named effect at a plausible value, or none.
fn effect(rng: &mut SplitMix, joints: usize) -> Option<Effect> {
    let j = 1 + (rng.next_f64() * joints as f64) as usize;
    let u = |rng: &mut SplitMix, a: f64, b: f64| a + (b - a) * rng.next_f64();
    let s = match (rng.next_f64() * 8.0) as usize {
        0 => return None,
        1 => format!("coulomb_friction:joint={j}:value={}", u(rng, 0.02, 0.6)),
        2 => format!("viscous_damping:joint={j}:value={}", u(rng, 0.02, 0.6)),
        3 => format!("harness_stiffness:joint={j}:value={}", u(rng, 0.02, 0.5)),
        4 => format!("spring_softening:joint={j}:value={}", u(rng, 0.02, 0.3)),
        5 => format!("air_drag:value={}", u(rng, 0.05, 1.5)),
        6 => format!(
            "rig_tilt:value={}:alpha_deg={}",
            u(rng, -0.3, 0.3),
            u(rng, 0.0, 360.0)
        ),
        _ => format!("encoder_offset:joint={j}:value={}", u(rng, -3.0, 3.0)),
    };
    Some(s.parse().unwrap_or_else(|e| panic!("{s}: {e}")))
}

fn draws() -> usize {
    std::env::var("DEPLOYWATCH_PAWL_DRAWS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(200)
}

#[test]
fn as_built_pawls_are_never_refused() {
    const NAMES: [&str; 2] = ["one_panel_pawl.toml", "seed001_T01_pawl.toml"];
    let drawings = NAMES.map(mechanism);
    let n = draws();
    let results: Vec<(usize, bool, Result<LatchRun, String>)> = (0..n)
        .into_par_iter()
        .map(|i| {
            let mut rng = SplitMix(0xBA71 + i as u64);
            let d = &drawings[i % NAMES.len()];
            let built = d.as_built(&LatchTolerance::default(), &mut || rng.next_f64());
            let effects: Vec<Effect> = effect(&mut rng, built.joint_count()).into_iter().collect();
            let label = format!("draw {i} {} {:?}", NAMES[i % NAMES.len()], effects);
            let r = simulate(&built, &effects, &SimOptions::default())
                .map_err(|e| format!("{label}: {e}"));
            (i, !effects.is_empty(), r)
        })
        .collect();
    let (mut refused, mut effects, mut broke, mut held) = (Vec::new(), 0, 0, 0);
    for (_, with, r) in &results {
        effects += usize::from(*with);
        match r {
            Ok(run) => {
                let breaks = run
                    .events
                    .iter()
                    .filter(|e| e.kind == LatchEventKind::PawlBreak);
                broke += breaks.count();
                held += run
                    .events
                    .iter()
                    .filter(|e| e.kind == LatchEventKind::PawlDrop)
                    .count();
            }
            Err(e) => refused.push(e.clone()),
        }
    }
    println!(
        "{n} as-built pawl draws ({effects} with a named effect): {} refused; {held} pawls dropped, {broke} broke",
        refused.len()
    );
    assert!(refused.is_empty(), "{refused:#?}");
    assert!(held > 0);
}
