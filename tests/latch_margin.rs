//! The physical latch's engagement in the margins (`docs/margin.md`, "The
//! latch's engagement"): `deploywatch margin` against a hand calculation
//! from the mechanism file's plunger, and the on-board prediction of a stop
//! on the plunger's entry ramp on the bundled latch runs.

use deploywatch_core::monitor::LatchState;
use deploywatch_core::monitor::{Monitor, MonitorConfig, Prediction, Sample, Status};
use deploywatch_sim::design_margin::{joint_margin, Standard};
use deploywatch_sim::joint_margins::latch_resistance;
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::monitor_config::{monitor_config, samples};
use deploywatch_sim::run::Run;
use deploywatch_tests::data_dir;

fn mechanism(name: &str) -> Mechanism {
    Mechanism::load(&data_dir().join("mechanisms").join(name)).expect("mechanism")
}

fn run(path: &str) -> Run {
    Run::load(&data_dir().join("examples").join(path)).expect("run")
}

fn replay<const N: usize>(cfg: &MonitorConfig<N>, samples: &[Sample<N>]) -> Vec<Status<N>> {
    let mut m = Monitor::new(cfg).expect("monitor config");
    samples.iter().map(|s| m.replay_step(s)).collect()
}

#[test]
fn margin_counts_the_engagement_as_the_hand_calculation() {
    // seed001_T01_physical_latch.toml, every joint: plunger preload_n = 20,
    // stiffness_n_per_mm = 10, stroke_mm = 0.8, radius_mm = 40,
    // entry_ramp_deg = 30. Joint 1: 3 x TS-1 (m_90 = 1.20 N·m each),
    // friction 2.63 N·m, stowed -90°.
    let (p0, kp, h, r_m) = (20.0f64, 10.0, 0.8, 0.040);
    let entry_torque = (p0 + kp * h) * r_m * 30f64.to_radians().tan(); // 0.6466 N·m
    let engagement = (p0 * h + 0.5 * kp * h * h) / 1000.0; // 0.0192 J
    let mech = mechanism("seed001_T01_physical_latch.toml");
    let latch = latch_resistance(&mech, 0);
    assert!((latch.entry_torque_nm - entry_torque).abs() < 1e-12);
    assert!((latch.engagement_energy_j - engagement).abs() < 1e-15);
    let spring = mech.joints[0].spring.to_spring().expect("spring");
    let stroke = mech.joints[0].stowed_deg.to_radians();
    for (standard, f) in [(Standard::None, 1.0), (Standard::NasaStd5017, 3.0)] {
        let m = joint_margin(&spring, stroke, 2.63, standard, None).with_latch(latch);
        let torque = (3.0 * 1.20 / (f * 2.63 + f * entry_torque) - 1.0) * 100.0;
        assert!(
            (m.torque_margin_pct() - torque).abs() < 1e-6,
            "{standard}: {} vs {torque}",
            m.torque_margin_pct()
        );
        let e_r = 2.63 * core::f64::consts::FRAC_PI_2;
        let energy = (m.driving_energy_j / (f * e_r + f * engagement) - 1.0) * 100.0;
        assert!((m.energy_margin_pct() - energy).abs() < 1e-9);
        // Without the latch the margins are higher: it is a resistance.
        let ideal = joint_margin(&spring, stroke, 2.63, standard, None);
        assert!(ideal.torque_margin_pct() > m.torque_margin_pct());
        assert!(ideal.energy_margin_pct() > m.energy_margin_pct());
    }
    // The ideal-latch mechanism has no engagement.
    let ideal = mechanism("seed001_T01.toml");
    assert_eq!(latch_resistance(&ideal, 0), Default::default());
}

/// The samples of `run` from the top of the rebound after the first
/// closing of joint 1's switch on (the panel's escape back over the
/// plunger; the latch tracker's handling of the bounce is not under test).
fn after_rebound(run: &Run) -> Vec<Sample<1>> {
    let all = samples::<1>(run).expect("one joint");
    let closed = all.iter().position(|s| s.latch[0]).expect("a closing");
    let rest = &all[closed..];
    let top = rest
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.phi_deg[0].abs().total_cmp(&b.1.phi_deg[0].abs()))
        .map(|(i, _)| closed + i)
        .expect("samples");
    all[top..].to_vec()
}

#[test]
fn ramp_stop_is_predicted_before_the_panel_reaches_the_ramp() {
    let mech = mechanism("one_panel_physical_latch.toml");
    let cfg = monitor_config::<1>(&mech).expect("config");
    let foot_deg = cfg.joints[0].latch.foot_rad().to_degrees();
    let s = after_rebound(&run("latch_ramp_stop/one_panel.csv"));
    let st = replay(&cfg, &s);
    // The panel comes back and enters the entry ramp (where it stops, switch
    // open to the end).
    let enters = s
        .iter()
        .position(|x| x.phi_deg[0].abs() < foot_deg)
        .expect("the panel reaches the ramp");
    assert!(s.iter().all(|x| !x.latch[0]), "never latches again");
    let first = st
        .iter()
        .position(|x| x.joints[0].prediction == Prediction::RampStop)
        .expect("a ramp stop is predicted");
    println!(
        "ramp stop predicted at {:.2} s, the panel enters the ramp ({foot_deg:.3}°) at {:.2} s",
        s[first].t_s, s[enters].t_s
    );
    assert!(first < enters, "predicted at {} s", s[first].t_s);
    // From the ramp on, the prediction is the ramp stop.
    assert!(st[enters..]
        .iter()
        .all(|x| x.joints[0].prediction == Prediction::RampStop));
    // With the same run and an ideal latch configured there is nothing to
    // climb, and no ramp stop.
    let mut ideal = mech.clone();
    ideal.latches.clear();
    let cfg = monitor_config::<1>(&ideal).expect("config");
    assert!(replay(&cfg, &s)
        .iter()
        .all(|x| x.joints[0].prediction != Prediction::RampStop));
}

/// Joints whose switch is closed at the end of `path`: they latched.
fn latching_joints<const N: usize>(mech: &str, path: &str) -> (Vec<Status<N>>, Vec<usize>) {
    let mech = mechanism(mech);
    let cfg = monitor_config::<N>(&mech).expect("config");
    let run = run(path);
    let s = samples::<N>(&run).expect("joint count");
    let last = s.last().expect("samples");
    let latched = (0..N).filter(|&j| last.latch[j]).collect();
    (replay(&cfg, &s), latched)
}

/// Largest |margin| [%] at which a joint that latches may be predicted
/// `ramp_stop` on its way in: the ramp's work is a small share of the
/// stroke's (0.0192 J against joules for the seed 001 plungers), so the
/// balance calls a ramp stop only when it is within that share of zero,
/// where a stall or a latch is equally open.
const BORDERLINE_PCT: f32 = 1.0;

/// Every `ramp_stop` prediction of joint `j` is a borderline one; returns
/// how many samples had it.
fn borderline_only<const N: usize>(st: &[Status<N>], j: usize, what: &str) -> usize {
    let calls: Vec<_> = st
        .iter()
        .filter(|x| x.joints[j].prediction == Prediction::RampStop)
        .collect();
    for x in &calls {
        let m = x.joints[j].margin_pct.unwrap_or(f32::NAN);
        assert!(
            m.abs() <= BORDERLINE_PCT,
            "{what} joint {}: ramp_stop at {} s with margin {m} %",
            j + 1,
            x.t_s
        );
    }
    // Never at the end: the joint latched.
    assert_ne!(
        st.last().map(|x| x.joints[j].prediction),
        Some(Prediction::RampStop)
    );
    println!(
        "{what} joint {}: {} samples predicted ramp_stop (borderline margins)",
        j + 1,
        calls.len()
    );
    calls.len()
}

#[test]
fn latching_joints_are_never_firmly_predicted_to_stop_on_the_ramp() {
    let (st, t02) = latching_joints::<3>(
        "seed001_T02_physical_latch.toml",
        "latch_clean_bounce/seed001_T02.csv",
    );
    assert_eq!(t02, [1, 2]);
    for j in t02 {
        borderline_only(&st, j, "latch_clean_bounce");
    }
    let (st, t01) = latching_joints::<3>(
        "seed001_T01_physical_latch.toml",
        "latch_escape_never/seed001_T01.csv",
    );
    assert_eq!(t01, [0, 2]);
    for j in t01 {
        borderline_only(&st, j, "latch_escape_never");
    }
    // The first approach of the ramp-stop run carries plenty of energy: the
    // panel passes the crest, and no ramp stop is predicted before.
    let mech = mechanism("one_panel_physical_latch.toml");
    let cfg = monitor_config::<1>(&mech).expect("config");
    let s = samples::<1>(&run("latch_ramp_stop/one_panel.csv")).expect("one joint");
    let closed = s.iter().position(|x| x.latch[0]).expect("a closing");
    let st = replay(&cfg, &s[..closed]);
    assert!(st
        .iter()
        .all(|x| x.joints[0].prediction != Prediction::RampStop));
    assert_eq!(
        st.last().map(|x| x.joints[0].prediction),
        Some(Prediction::Latch)
    );
}

#[test]
fn whole_ramp_stop_run_ends_stopped_short_with_a_ramp_stop_predicted() {
    // The whole run, the latch tracker included: the panel latches,
    // escapes back over the plunger and comes to rest on the entry ramp.
    let mech = mechanism("one_panel_physical_latch.toml");
    let cfg = monitor_config::<1>(&mech).expect("config");
    let s = samples::<1>(&run("latch_ramp_stop/one_panel.csv")).expect("one joint");
    let st = replay(&cfg, &s);
    let last = st.last().expect("statuses").joints[0];
    assert_eq!(last.latch, LatchState::StoppedShort);
    assert_eq!(last.prediction, Prediction::RampStop);
    let escaped = st
        .iter()
        .position(|x| x.joints[0].latch == LatchState::Escaped)
        .expect("the escape is reported");
    let foot_deg = cfg.joints[0].latch.foot_rad().to_degrees();
    let top = (escaped..s.len())
        .max_by(|&a, &b| s[a].phi_deg[0].abs().total_cmp(&s[b].phi_deg[0].abs()))
        .expect("samples");
    let enters = (top..s.len())
        .find(|&k| s[k].phi_deg[0].abs() < foot_deg)
        .expect("the panel comes back to the ramp");
    let from = (top..st.len())
        .find(|&k| st[k].joints[0].prediction == Prediction::RampStop)
        .expect("a ramp stop is predicted on the way back");
    let at_rest = st
        .iter()
        .position(|x| x.joints[0].latch == LatchState::StoppedShort)
        .expect("stopped short");
    println!(
        "escape reported at {:.2} s; on the way back a ramp stop predicted first at {:.2} s, the panel enters the ramp at {:.2} s, reported stopped_short from {:.2} s",
        st[escaped].t_s, st[from].t_s, s[enters].t_s, st[at_rest].t_s
    );
    assert!(from < enters);
    // Once the tracker sees it at rest on the ramp, the prediction is the
    // ramp stop.
    assert!(st[at_rest..]
        .iter()
        .all(|x| x.joints[0].prediction == Prediction::RampStop));
}
