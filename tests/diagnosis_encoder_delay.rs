//! Encoders late on their latch switches (`docs/diagnosis.md`, "An encoder
//! late on its switch"): the diagnosis names the delay by its signature at
//! the ideal latches, takes it out, and finds the hidden effect as if the
//! encoders were on time; runs without a delay name none.
//!
//! The delayed runs are our simulator's: each angle sampled at its stamp
//! minus the delay (the stowed rest before the release), each switch at its
//! stamp, then the reference sensor's noise and rounding. The diagnosis is
//! given the runs and the mechanisms only.
//!
//! - `latchings_bound_the_delay_on_random_wings`: over random ideal-latch
//!   wings (`tests/src/wing_gen.rs`, some with a named effect), on time the
//!   latchings never exclude zero, and delayed by 0.6 of a sample they
//!   always allow the delay. `DEPLOYWATCH_WINGS` wings (default 60).
//! - `a_joint_thrown_at_its_latch_by_its_spring_reads_no_delay`: a wing
//!   whose first joint creeps onto its latch (~70 °/s against 0.6 N·m)
//!   through its tape springs' peak, which throws it at the latch
//!   milliseconds before the approach's extrapolation says: on time the
//!   latchings allow zero and the diagnosis names no delay and finds the
//!   friction; 0.6 of a sample late they allow the delay.
//! - `a_delay_is_named_and_taken_out_and_the_effect_found`: seed wings with
//!   an effect hidden at the detectability bar and a delay of 0.3 to 1
//!   sample, beside the same campaigns on time: right in 85 % at least
//!   (the CI's 2 cases both). `DEPLOYWATCH_FULL=1` runs 12 cases:
//!   `DEPLOYWATCH_FULL=1 cargo test --release -p deploywatch-tests --test diagnosis_encoder_delay -- --nocapture`.
//! - `simulate_at_compares_as_the_diagnosis_did`: `deploywatch diagnose` on
//!   a delayed run names the delay in its JSON, and `simulate --from
//!   d.json --at run.csv` gives back the RMS the diagnosis reported, the
//!   model written at the run's own stamps.

use deploywatch_sim::campaign::Campaign;
use deploywatch_sim::deployment::{self, SimOptions, Trajectory};
use deploywatch_sim::diagnose::{diagnose, encoder_delay, Outcome};
use deploywatch_sim::effect::{self, Effect, EffectKind};
use deploywatch_sim::findings::Findings;
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::progress::quiet;
use deploywatch_sim::sensor::{self, SensorModel};
use deploywatch_tests::cli_run::{angles, deploywatch};
use deploywatch_tests::data_dir;
use deploywatch_tests::hidden_effect::{moves_runs_deg, SEED_WINGS, STROKE_KINDS};
use deploywatch_tests::wing_gen::wing_toml;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::Path;

/// The runs of `truth` on `m` as sensors with encoders `delay_s` late give
/// them: two runs, noise seeds `seed` and `seed + 1`.
fn campaign(m: &Mechanism, truth: &[Effect], delay_s: f64, seed: u64) -> Option<Campaign> {
    runs(m, truth, delay_s, seed, 2)
}

/// [`campaign`] of `count` runs.
fn runs(m: &Mechanism, truth: &[Effect], delay_s: f64, seed: u64, count: u64) -> Option<Campaign> {
    let opts = SimOptions::default();
    let on_time = deployment::simulate(m, truth, &opts).ok()?;
    let late: Vec<f64> = on_time
        .t_s
        .iter()
        .enumerate()
        .map(|(i, t)| (t - delay_s).max(i as f64 * 1e-9))
        .collect();
    let read = if delay_s > 0.0 {
        deployment::simulate_at(m, truth, &opts, &late).ok()?
    } else {
        on_time.clone()
    };
    let angles = Trajectory {
        latched: on_time.latched.clone(),
        t_s: on_time.t_s.clone(),
        ..read
    };
    let off = effect::encoder_offsets_deg(truth, m.joint_count());
    let mut c = Campaign::default();
    for r in 0..count {
        let mut run = sensor::measure(&angles, &off, &SensorModel::REFERENCE, seed + r);
        run.set_meta("mechanism", &m.name);
        c.push(
            std::slice::from_ref(m),
            run,
            Path::new(&format!("run{r}.csv")),
        )
        .ok()?;
    }
    Some(c)
}

fn wings() -> u64 {
    std::env::var("DEPLOYWATCH_WINGS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(60)
}

#[test]
fn latchings_bound_the_delay_on_random_wings() {
    let sigma = SensorModel::REFERENCE.noise_sigma_deg;
    let (mut read, mut named) = (0, 0);
    for seed in 0..wings() {
        let w = wing_toml(7000 + seed, 0.0);
        let m = Mechanism::from_toml_str(&w.toml, "random.toml").expect("a valid wing");
        let period = 1.0 / m.sample_hz;
        let Some(on_time) = campaign(&m, &w.effects, 0.0, seed) else {
            continue;
        };
        if let Some(d) = encoder_delay::estimate(&on_time, sigma) {
            assert!(
                d.allows_zero,
                "wing {seed}: on time, yet the latchings exclude zero: {:.3} .. {:.3} ms\n{}",
                d.lo_s * 1e3,
                d.hi_s * 1e3,
                w.toml
            );
        }
        let late = 0.6 * period;
        let Some(c) = campaign(&m, &w.effects, late, seed) else {
            continue;
        };
        if let Some(d) = encoder_delay::estimate(&c, sigma) {
            read += 1;
            named += usize::from(!d.allows_zero);
            assert!(
                d.lo_s <= late && late <= d.hi_s,
                "wing {seed}: {:.3} ms late, the latchings allow {:.3} .. {:.3} ms\n{}",
                late * 1e3,
                d.lo_s * 1e3,
                d.hi_s * 1e3,
                w.toml
            );
        }
    }
    println!(
        "{} wings: the latchings read on {read} delayed campaigns, clear of zero on {named}",
        wings()
    );
    assert!(read > 0, "no wing's latchings were read");
}

/// Three panels on tape springs; joint 1's friction (0.6 N·m) lets it
/// reach its latch at ~70 °/s, within the reach of its springs' peak.
const SLOW_WING: &str = r#"name = "slow-first-joint"
description = "joint 1 creeps onto its latch through its tape springs' peak"

[[panel]]
length_m = 0.6
mass_kg = 2.0
com_m = 0.3
inertia_kgm2 = 0.06000

[[panel]]
length_m = 0.5
mass_kg = 1.2
com_m = 0.25
inertia_kgm2 = 0.02500

[[panel]]
length_m = 0.4
mass_kg = 0.8
com_m = 0.2
inertia_kgm2 = 0.01067

[[joint]]
stowed_deg = -90
spring = { kind = "tape", type = "TS-1", count = 3 }
friction = { coulomb_nm = 0.6 }

[[joint]]
stowed_deg = 180
spring = { kind = "tape", type = "TS-2", count = 2 }
friction = { coulomb_nm = 0.4 }

[[joint]]
stowed_deg = -180
spring = { kind = "tape", type = "TS-3", count = 2 }
friction = { coulomb_nm = 0.2 }


[tape."TS-1"]
a = [1.10, 69.39]
b = [1.10, 1.50]
d = [0.52, 37.0]
m_90 = 1.20
c_180 = 2.32

[tape."TS-2"]
a = [1.26, 58.20]
b = [1.28, 0.86]
d = [0.65, 26.0]
m_90 = 0.80
c_180 = 1.46

[tape."TS-3"]
a = [1.08, 33.43]
b = [1.15, 0.46]
d = [0.29, 11.07]
m_90 = 0.385
c_180 = 0.74

[run]
duration_s = 12.0
sample_hz = 100.0
"#;

#[test]
fn a_joint_thrown_at_its_latch_by_its_spring_reads_no_delay() {
    let m = Mechanism::from_toml_str(SLOW_WING, "slow.toml").expect("a valid wing");
    let sigma = SensorModel::REFERENCE.noise_sigma_deg;
    let late = 0.6 / m.sample_hz;
    let mut read = 0;
    // One run each, as `deploywatch simulate --seed S` writes it; the
    // friction at joint 2 moves every latching's phase on the sample clock.
    for i in 0..24u64 {
        let truth = [Effect::joint(
            EffectKind::CoulombFriction,
            2,
            0.01 * (1 + i % 3) as f64,
        )];
        let on_time = runs(&m, &truth, 0.0, i, 1).expect("simulates");
        if let Some(d) = encoder_delay::estimate(&on_time, sigma) {
            read += 1;
            assert!(
                d.allows_zero,
                "{} seed {i}: on time, yet the latchings exclude zero: {:.3} .. {:.3} ms ({:?})",
                truth[0],
                d.lo_s * 1e3,
                d.hi_s * 1e3,
                d.latchings
            );
        }
        let c = runs(&m, &truth, late, i, 1).expect("simulates");
        if let Some(d) = encoder_delay::estimate(&c, sigma) {
            assert!(
                d.lo_s <= late && late <= d.hi_s,
                "{} seed {i}: {:.3} ms late, the latchings allow {:.3} .. {:.3} ms",
                truth[0],
                late * 1e3,
                d.lo_s * 1e3,
                d.hi_s * 1e3
            );
        }
    }
    assert!(read > 0, "no campaign's latchings were read");
    let truth = [Effect::joint(EffectKind::CoulombFriction, 2, 0.02)];
    let c = runs(&m, &truth, 0.0, 1, 1).expect("simulates");
    let o = diagnose(&c, &deploywatch_tests::diagnose_options(), &quiet);
    assert!(
        o.encoder_delay.as_ref().is_none_or(|d| !d.taken_out()),
        "on time, a delay taken out: {:?}",
        o.encoder_delay
    );
    assert!(found(&truth, &o), "{} found as [{}]", truth[0], names(&o));
}

/// Case `i`: a seed wing, one effect raised from a small value until it
/// moves the runs by ≥ 0.3° RMS, a delay of 0.3 to 1 sample.
fn case(i: usize) -> (Mechanism, Vec<Effect>, f64) {
    let mut rng = ChaCha8Rng::seed_from_u64(4100 + i as u64);
    let m = Mechanism::load(&data_dir().join(format!("mechanisms/{}.toml", SEED_WINGS[i % 4])))
        .expect("bundled");
    let kind = STROKE_KINDS[(i / 4) % 3];
    let j = rng.gen_range(1..=m.joint_count());
    let mut e = Effect::joint(kind, j, 0.01);
    for _ in 0..40 {
        if moves_runs_deg(&m, &[e]) >= 0.3 {
            break;
        }
        e = e.with_value(e.value() * 1.25);
    }
    let delay = rng.gen_range(0.3..1.0) / m.sample_hz;
    (m, vec![e], delay)
}

/// The outcome names exactly `truth`, values within 20 %, nothing
/// unexplained.
fn found(truth: &[Effect], o: &Outcome) -> bool {
    let e = o.extended.effects();
    o.unexplained.is_none()
        && e.len() == truth.len()
        && truth.iter().all(|t| {
            e.iter().any(|x| {
                x.kind() == t.kind()
                    && x.joint == t.joint
                    && (x.value() - t.value()).abs() <= 0.2 * t.value().abs()
            })
        })
}

fn names(o: &Outcome) -> String {
    let e: Vec<String> = o.extended.effects().iter().map(|e| e.to_string()).collect();
    e.join(" + ")
}

#[test]
fn a_delay_is_named_and_taken_out_and_the_effect_found() {
    let n = if std::env::var_os("DEPLOYWATCH_FULL").is_some() {
        12
    } else {
        2
    };
    let opts = deploywatch_tests::diagnose_options();
    let mut failed = Vec::new();
    for i in 0..n {
        let (m, truth, delay) = case(i);
        let period = 1.0 / m.sample_hz;
        let late = campaign(&m, &truth, delay, 10 * i as u64).expect("simulates");
        let o = diagnose(&late, &opts, &quiet);
        let got = o.encoder_delay.as_ref().map(|d| d.delay_s);
        let on_time = campaign(&m, &truth, 0.0, 10 * i as u64).expect("simulates");
        let c = diagnose(&on_time, &opts, &quiet);
        println!(
            "case {i} {}: {} with {:.2} ms late -> delay {} ms, found [{}]; on time -> delay {:?}, found [{}]",
            m.name,
            truth[0],
            delay * 1e3,
            got.map_or("none".into(), |d| format!("{:.2}", d * 1e3)),
            names(&o),
            c.encoder_delay.as_ref().map(|d| d.delay_s * 1e3),
            names(&c)
        );
        let delay_ok = got.is_some_and(|d| (d - delay).abs() <= 0.05 * period);
        if !delay_ok || !found(&truth, &o) || c.encoder_delay.is_some() || !found(&truth, &c) {
            failed.push(i);
        }
    }
    println!(
        "named within 5 % of a sample and the effect found, on time no delay named: {} of {n}",
        n - failed.len()
    );
    // The issue's bar, 85 %: every case of the CI's two.
    assert!(
        100 * failed.len() <= 15 * n,
        "cases {failed:?} (see the lines above)"
    );
}

#[test]
fn simulate_at_compares_as_the_diagnosis_did() {
    let (m, truth, delay) = case(0);
    let c = campaign(&m, &truth, delay, 77).expect("simulates");
    let dir = std::env::temp_dir().join(format!("dw-delay-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    let mech = data_dir().join(format!("mechanisms/{}.toml", SEED_WINGS[0]));
    let runs: Vec<std::path::PathBuf> = (0..2).map(|r| dir.join(format!("run{r}.csv"))).collect();
    for (cr, p) in c.runs.iter().zip(&runs) {
        cr.run.write(p).expect("writes");
    }
    let (json, model) = (dir.join("d.json"), dir.join("model.csv"));
    let s = |p: &Path| p.to_str().expect("UTF-8").to_string();
    let code = deploywatch(&[
        "diagnose",
        "--quiet",
        "--json",
        &s(&json),
        "--mechanism",
        &s(&mech),
        &s(&runs[0]),
    ]);
    assert_eq!(code, 0, "diagnose");
    let body = std::fs::read_to_string(&json).expect("the JSON");
    let Ok(Findings::Diagnosis(d)) = Findings::from_json_str(&body) else {
        panic!("not a diagnosis:\n{body}");
    };
    let named = d
        .encoder_delay
        .as_ref()
        .and_then(|e| e.delay_s)
        .expect("a delay named");
    assert!(
        (named - delay).abs() <= 0.05 / m.sample_hz,
        "{named} s, {delay} s late"
    );
    let code = deploywatch(&[
        "simulate",
        &s(&mech),
        "--from",
        &s(&json),
        "--at",
        &s(&runs[0]),
        "--out",
        &s(&model),
        "--quiet",
    ]);
    assert_eq!(code, 0, "simulate --from --at");
    let (a, b) = (
        angles(&model, m.joint_count()),
        angles(&runs[0], m.joint_count()),
    );
    let (mut sse, mut n) = (0.0, 0usize);
    for (x, y) in a.iter().zip(&b) {
        for (p, q) in x.iter().zip(y) {
            sse += (p - q) * (p - q);
            n += 1;
        }
    }
    let again = (sse / n as f64).sqrt();
    let said = d.extended.rms_deg.expect("an extended RMS");
    assert!(
        (again - said).abs() <= 1e-6,
        "re-simulated {again} deg, the diagnosis said {said}"
    );
    let head = std::fs::read_to_string(&model).expect("the model CSV");
    let first = head
        .lines()
        .find(|l| !l.starts_with('#') && !l.starts_with("t_s"))
        .expect("a sample");
    assert!(
        first.starts_with("0.0"),
        "the model written at the run's stamps: {first}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
