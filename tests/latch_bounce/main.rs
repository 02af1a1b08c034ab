//! The latch-state estimator on physical latches (`docs/monitor.md` §4.1).
//!
//! Runs of the simulator with its ideal latches (seed001 T01, T02 and seed000
//! case 1, at 100 Hz and 1 kHz) are turned, joint by joint, into runs of a
//! latch as built, one of four cases drawn at random per joint:
//!
//! - **bounce**: damped rebounds off the stop, ballistic flights under a
//!   restoring acceleration (the first 0.2–1° high and 20–60 ms long, each
//!   next one a ratio 0.3–0.6 as high and √ratio as long, 1–2 ms of
//!   contact between two), then a settling tail within the switch travel;
//! - **escape and re-latch**: the first rebound carries the joint 2–6°
//!   beyond the crest; it comes back 0.2–1 s after the impact and bounces
//!   as above;
//! - **escape for good**: the same, but it stays out;
//! - **ramp stop**: the joint comes to rest 0.1–0.5° short of the latch.
//!
//! The switch reads closed while the joint is within the switch travel of
//! its stop. The runs are measured with the reference sensor and replayed
//! through the monitor configured with the physical latch; the monitor is
//! not told which case was drawn. Asserted over every joint: no fault flag;
//! a latch declared within 50 ms of the last return to the stop and never
//! at a sample where the joint is off its stop by more than the switch
//! travel; every escape reported as `escaped` while the joint is out; every
//! ramp stop reported as `stopped_short` at the end of the run.
//!
//! The sensor faults of the fault campaign that concern the switch (chatter,
//! stuck open, stuck closed) are still found with the physical latch
//! configured, on the ideal runs: every faulted run flagged, no latch
//! declared before the true one, no declared latch undone.
//!
//! Rerun: `cargo test --release -p deploywatch-tests --test latch_bounce --
//! --nocapture` (the counts are printed).

use deploywatch_core::monitor::LatchState;
use deploywatch_core::monitor::{LockKind, PhysicalLatch};
use deploywatch_core::monitor::{MonitorConfig, Status};
use deploywatch_sim::deployment::{simulate, SimOptions, Trajectory};
use deploywatch_sim::fault_injection::{apply, SensorFault};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::monitor_config::monitor_config;
use deploywatch_sim::run::Run;
use deploywatch_sim::sensor::{measure, SensorModel};
use deploywatch_tests::{data_dir, hold_at_rest, mechanism, replay, SplitMix};

mod bundled;
mod switch_faults;

/// Switch travel of the test latch \[deg\].
const TRAVEL_DEG: f64 = 0.02;
/// The latch the monitor is configured with: 0.02° switch travel, crest
/// 1.5° from the stop, ramp 0.6° short of it, 30 ms bounce window.
const LATCH: PhysicalLatch = PhysicalLatch {
    switch_travel_deg: TRAVEL_DEG as f32,
    crest_deg: 1.5,
    ramp_deg: 0.6,
    bounce_window_s: 0.03,
    lock: LockKind::Detent,
};
/// A latch must be declared within this of the last rebound \[s\].
const DECLARE_LIMIT_S: f64 = 0.05;
/// Monte-Carlo runs per mechanism and sample rate (three mechanisms: 210
/// runs per rate).
const RUNS_PER_MECHANISM: usize = 70;
/// Simulated ideal runs per mechanism and rate (each with its own friction
/// scale); the Monte-Carlo runs share them, each with its own latches and
/// sensor noise.
const SIMULATIONS: usize = 3;
/// Samples after the end of the simulation \[s\]: longer than the stall time
/// (1 s), so a ramp stop has come to rest.
const HOLD_S: f64 = 1.5;

/// One ballistic flight off the stop.
#[derive(Clone, Copy, Debug)]
struct Flight {
    start_s: f64,
    duration_s: f64,
    height_deg: f64,
}

impl Flight {
    fn off(&self, t: f64) -> Option<f64> {
        let x = (t - self.start_s) / self.duration_s;
        (0.0..=1.0)
            .contains(&x)
            .then_some(4.0 * self.height_deg * x * (1.0 - x))
    }
    /// The instant the joint comes back within the switch travel \[s\].
    fn back_within_travel(&self) -> f64 {
        let x = 0.5 * (1.0 + (1.0 - TRAVEL_DEG / self.height_deg).max(0.0).sqrt());
        self.start_s + x * self.duration_s
    }
}

/// A damped series of rebounds starting at `t0` \[s\]: flights while they
/// rise above a tenth of the travel, then the settling tail.
#[derive(Clone, Debug)]
struct Bounces {
    flights: Vec<Flight>,
    tail_start_s: f64,
}

impl Bounces {
    fn draw(t0: f64, rng: &mut SplitMix) -> Self {
        let mut height = rng.uniform(0.2, 1.0);
        let ratio = rng.uniform(0.3, 0.6);
        let mut duration = rng.uniform(0.02, 0.06);
        let mut t = t0 + rng.uniform(0.001, 0.002);
        let mut flights = Vec::new();
        while height > 0.1 * TRAVEL_DEG {
            flights.push(Flight {
                start_s: t,
                duration_s: duration,
                height_deg: height,
            });
            t += duration + rng.uniform(0.001, 0.002);
            height *= ratio;
            duration *= ratio.sqrt();
        }
        Bounces {
            flights,
            tail_start_s: t,
        }
    }
    /// Distance from the stop at `t` \[deg\] (`t` after the series started).
    fn off(&self, t: f64) -> f64 {
        if let Some(h) = self.flights.iter().find_map(|f| f.off(t)) {
            return h;
        }
        if t >= self.tail_start_s {
            // Settling tail: a decaying ring within the switch travel.
            let tau = t - self.tail_start_s;
            let ring = (2.0 * std::f64::consts::PI * tau / 0.01).sin().abs();
            return 0.8 * TRAVEL_DEG * ring * (-tau / 0.05).exp();
        }
        0.0
    }
    /// The last return to the stop from beyond the switch travel \[s\].
    fn last_return_s(&self) -> Option<f64> {
        self.flights
            .iter()
            .filter(|f| f.height_deg > TRAVEL_DEG)
            .map(Flight::back_within_travel)
            .next_back()
    }
}

/// What was drawn for one joint (the monitor never sees it).
#[derive(Clone, Debug)]
enum Case {
    /// The ideal simulation never latched this joint: unchanged.
    NoLatch,
    Bounce(Bounces),
    /// Out over the crest from `t0` to `t0 + out_s` (`None`: for good),
    /// `height_deg` at most; back in with `back` bounces.
    Escape {
        t0: f64,
        height_deg: f64,
        out_s: Option<f64>,
        back: Option<Bounces>,
    },
    /// At rest `rest_deg` short of the latch from about `t0`.
    Ramp {
        t0: f64,
        from_deg: f64,
        rest_deg: f64,
        tau_s: f64,
    },
}

impl Case {
    fn name(&self) -> &'static str {
        match self {
            Case::NoLatch => "no latch",
            Case::Bounce(_) => "bounce",
            Case::Escape { out_s: Some(_), .. } => "escape, re-latch",
            Case::Escape { .. } => "escape for good",
            Case::Ramp { .. } => "ramp stop",
        }
    }
    /// Distance from the stop at `t` \[deg\], `None` where the ideal run
    /// holds.
    fn off(&self, t: f64) -> Option<f64> {
        match self {
            Case::NoLatch => None,
            Case::Bounce(b) => (t >= b.flights.first()?.start_s - 0.002).then(|| b.off(t)),
            Case::Escape {
                t0,
                height_deg,
                out_s,
                back,
            } => {
                if t < *t0 {
                    return None;
                }
                let tau = t - t0;
                Some(match (out_s, back) {
                    (Some(out), Some(_)) if tau < *out => {
                        height_deg * (std::f64::consts::PI * tau / out).sin()
                    }
                    (Some(_), Some(b)) => b.off(t),
                    _ => height_deg * (std::f64::consts::FRAC_PI_2 * (tau / 0.2).min(1.0)).sin(),
                })
            }
            Case::Ramp {
                t0,
                from_deg,
                rest_deg,
                tau_s,
            } => (t >= *t0).then(|| rest_deg + (from_deg - rest_deg) * (-(t - t0) / tau_s).exp()),
        }
    }
    /// The last return to the stop before the latch holds \[s\], `None` when
    /// the joint does not latch.
    fn last_return_s(&self) -> Option<f64> {
        match self {
            Case::Bounce(b) => b.last_return_s().or(b.flights.first().map(|f| f.start_s)),
            Case::Escape { back: Some(b), .. } => {
                b.last_return_s().or(b.flights.first().map(|f| f.start_s))
            }
            _ => None,
        }
    }
    fn latches(&self) -> bool {
        matches!(self, Case::Bounce(_) | Case::Escape { back: Some(_), .. })
    }
}

/// Draws the case of a joint whose ideal latch is at `t_latch` \[s\]
/// (`i_latch` its first sample at or after it).
fn draw_case(traj: &Trajectory, j: usize, rng: &mut SplitMix) -> Case {
    let Some(t_latch) = traj.latch_s[j] else {
        return Case::NoLatch;
    };
    let u = rng.next_f64();
    if u < 0.55 {
        Case::Bounce(Bounces::draw(t_latch, rng))
    } else if u < 0.85 {
        let height = f64::from(LATCH.crest_deg) + rng.uniform(2.0, 6.0);
        let out = rng.uniform(0.2, 1.0);
        let for_good = u >= 0.75;
        Case::Escape {
            t0: t_latch,
            height_deg: height,
            out_s: (!for_good).then_some(out),
            back: (!for_good).then(|| Bounces::draw(t_latch + out, rng)),
        }
    } else {
        // The joint meets the ramp 0.5° out and comes to rest on it, at the
        // speed it had there.
        let rest = rng.uniform(0.1, 0.5);
        let from = rest + 0.5;
        let k = traj.phi_deg[j]
            .iter()
            .position(|p| p.abs() <= from)
            .unwrap_or(0);
        let speed = traj.rate_deg_s[j][k].abs().max(1.0);
        Case::Ramp {
            t0: traj.t_s[k],
            from_deg: traj.phi_deg[j][k].abs(),
            rest_deg: rest,
            tau_s: (traj.phi_deg[j][k].abs() - rest).max(0.01) / speed,
        }
    }
}

/// The physical run of `traj`: every joint's angle and switch from its
/// case, on the side of the stop it deploys from.
fn transform(traj: &Trajectory, stowed: &[f64], cases: &[Case]) -> Trajectory {
    let mut out = traj.clone();
    for (j, case) in cases.iter().enumerate() {
        let side = stowed[j].signum();
        for (i, &t) in traj.t_s.iter().enumerate() {
            if let Some(off) = case.off(t) {
                out.phi_deg[j][i] = side * off;
                out.latched[j][i] = off <= TRAVEL_DEG;
            }
        }
        out.latch_s[j] = None;
    }
    out
}

/// The ideal simulation of `mech` with every joint's friction scaled by
/// `scale` (the mechanism's own friction; the nominal files have none,
/// so the papers' is added).
fn simulate_ideal(mech: &Mechanism, scale: f64) -> Trajectory {
    let effects: Vec<_> = (0..mech.joint_count())
        .map(|j| {
            deploywatch_sim::effect::Effect::joint(
                deploywatch_sim::effect::EffectKind::CoulombFriction,
                j + 1,
                0.3 * scale,
            )
        })
        .collect();
    let opts = SimOptions {
        stop_when_deployed: false,
        ..SimOptions::default()
    };
    let mut traj = simulate(mech, &effects, &opts).expect("simulation");
    hold_at_rest(&mut traj, HOLD_S, 1.0 / mech.sample_hz);
    traj
}

fn physical_config<const N: usize>(mech: &Mechanism) -> MonitorConfig<N> {
    let mut cfg = monitor_config::<N>(mech).expect("monitor config");
    cfg.latch.physical = Some(LATCH);
    cfg
}

/// Counts over the Monte-Carlo runs.
#[derive(Default, Debug)]
struct Tally {
    runs: usize,
    bounces: usize,
    escapes_relatched: usize,
    escapes_for_good: usize,
    ramp_stops: usize,
    worst_declare_ms: f64,
    failures: Vec<String>,
}

/// Scores joint `j` of one replay against its case.
fn score<const N: usize>(
    label: &str,
    traj: &Trajectory,
    case: &Case,
    st: &[Status<N>],
    j: usize,
    tally: &mut Tally,
) {
    let mut fail = |what: String| {
        tally
            .failures
            .push(format!("{label} joint {} ({}): {what}", j + 1, case.name()))
    };
    if let Some((k, s)) = st
        .iter()
        .enumerate()
        .find(|(_, s)| !s.joints[j].faults.is_empty())
    {
        fail(format!(
            "flag {} at {:.3} s (true off {:.3}°)",
            s.joints[j].faults,
            s.t_s,
            traj.phi_deg[j][k].abs()
        ));
    }
    for (i, s) in st.iter().enumerate() {
        let off = traj.phi_deg[j][i].abs();
        if s.joints[j].latch == LatchState::Latched && off > TRAVEL_DEG + 1e-9 {
            fail(format!(
                "latched at {:.3} s while {off:.3}° off the stop",
                s.t_s
            ));
            break;
        }
    }
    let declared = st
        .iter()
        .position(|s| s.joints[j].latch == LatchState::Latched);
    let last = st.last().map(|s| s.joints[j].latch);
    match case {
        Case::NoLatch => {}
        Case::Bounce(_) | Case::Escape { .. } if case.latches() => {
            let ret = case.last_return_s().unwrap_or(0.0);
            // The first declaration after the last return (an escape may
            // not be declared before it either: checked above).
            let after = st.iter().find(|s| {
                s.joints[j].latch == LatchState::Latched && f64::from(s.t_s) >= ret - 1e-6
            });
            match after {
                Some(s) => {
                    let ms = 1e3 * (f64::from(s.t_s) - ret);
                    tally.worst_declare_ms = tally.worst_declare_ms.max(ms);
                    if ms > 1e3 * DECLARE_LIMIT_S + 1e-3 {
                        fail(format!("declared {ms:.1} ms after the last rebound"));
                    }
                }
                None => fail(format!("never declared (final {last:?})")),
            }
            if last != Some(LatchState::Latched) {
                fail(format!("final state {last:?}"));
            }
        }
        _ => {}
    }
    match case {
        Case::Bounce(_) => tally.bounces += 1,
        Case::Escape { t0, out_s, .. } => {
            if out_s.is_some() {
                tally.escapes_relatched += 1;
            } else {
                tally.escapes_for_good += 1;
                if last != Some(LatchState::Escaped) || declared.is_some() {
                    fail(format!("final state {last:?}, declared at {declared:?}"));
                }
            }
            let end = t0 + out_s.unwrap_or(f64::INFINITY);
            let reported = st.iter().any(|s| {
                let t = f64::from(s.t_s);
                t >= *t0 && t <= end && s.joints[j].latch == LatchState::Escaped
            });
            if !reported {
                fail("escape never reported".into());
            }
        }
        Case::Ramp { .. } => {
            tally.ramp_stops += 1;
            if last != Some(LatchState::StoppedShort) || declared.is_some() {
                fail(format!("final state {last:?}, declared at {declared:?}"));
            }
        }
        Case::NoLatch => {}
    }
}

fn monte_carlo<const N: usize>(name: &str, sample_hz: f64, seed: u64, tally: &mut Tally) {
    let mut mech = mechanism(name);
    mech.sample_hz = sample_hz;
    let cfg = physical_config::<N>(&mech);
    let stowed: Vec<f64> = mech.joints.iter().map(|j| j.stowed_deg).collect();
    let mut rng = SplitMix(seed);
    let ideal: Vec<Trajectory> = (0..SIMULATIONS)
        .map(|k| simulate_ideal(&mech, 0.5 + k as f64 / SIMULATIONS as f64))
        .collect();
    for r in 0..RUNS_PER_MECHANISM {
        let traj = &ideal[r % SIMULATIONS];
        let cases: Vec<Case> = (0..N).map(|j| draw_case(traj, j, &mut rng)).collect();
        let phys = transform(traj, &stowed, &cases);
        let sensor_seed = seed.wrapping_mul(1000) + r as u64;
        let run = measure(&phys, &[], &SensorModel::REFERENCE, sensor_seed);
        let st = replay(&cfg, &run);
        tally.runs += 1;
        let label = format!("{name} {sample_hz} Hz run {r} (sensor seed {sensor_seed})");
        for (j, case) in cases.iter().enumerate() {
            score(&label, &phys, case, &st, j, tally);
        }
    }
}

fn physical_latch_monte_carlo(sample_hz: f64, seed: u64) {
    let mut tally = Tally::default();
    monte_carlo::<3>("seed001_T01", sample_hz, seed, &mut tally);
    monte_carlo::<3>("seed001_T02", sample_hz, seed + 1, &mut tally);
    monte_carlo::<2>("seed000_case1", sample_hz, seed + 2, &mut tally);
    println!(
        "{sample_hz} Hz: {} runs; {} bouncing latches, {} escapes re-latched, {} escapes for good, {} ramp stops; latest declaration {:.1} ms after the last rebound; {} failures",
        tally.runs,
        tally.bounces,
        tally.escapes_relatched,
        tally.escapes_for_good,
        tally.ramp_stops,
        tally.worst_declare_ms,
        tally.failures.len()
    );
    for f in &tally.failures {
        println!("FAIL {f}");
    }
    assert!(tally.runs >= 200);
    assert!(
        tally.bounces > 0
            && tally.escapes_relatched > 0
            && tally.escapes_for_good > 0
            && tally.ramp_stops > 0
    );
    assert!(
        tally.failures.is_empty(),
        "{} failures",
        tally.failures.len()
    );
}

/// 210 Monte-Carlo runs at 100 Hz.
#[test]
fn physical_latches_at_100_hz() {
    physical_latch_monte_carlo(100.0, 22);
}

/// 210 Monte-Carlo runs at 1 kHz.
#[test]
fn physical_latches_at_1_khz() {
    physical_latch_monte_carlo(1000.0, 2222);
}
