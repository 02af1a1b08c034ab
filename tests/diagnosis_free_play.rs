//! Free-play held to one side (`docs/diagnosis.md`, "Free-play held to one
//! side"): an encoder reading off its panel within the hinge's declared
//! free-play is reported as that discrepancy, not claimed, and the hidden
//! effect beside it is found as without it; the same reading without a
//! declared play, or a reading beyond the play, stays a claim.
//!
//! The runs are our simulator's: a seed wing, one effect raised until it
//! moves the runs by ≥ 0.3° RMS, and at another joint the reading the
//! spring side of a hinge with free-play gives, the panel's angle plus
//! 0.06–0.18° of either sign (an `encoder_offset`), or 0.35–0.6°, beyond
//! the play; the reference sensor's noise and rounding. The diagnosis is
//! given the runs and the mechanisms, which declare `free_play_deg = 0.2`
//! at every joint (or none, for the control); it is not told which joint
//! reads off.
//!
//! - `a_reading_within_the_declared_play_is_not_claimed`: right in 85 % at
//!   least (the CI's 2 cases both): the hidden effect within 20 %, no
//!   other effect, the joint in `free_play` within 0.03°; a reading beyond
//!   the play is claimed as an `encoder_offset` within 0.03° (and how
//!   often the effect beside it is found alone is printed).
//!   `DEPLOYWATCH_FULL=1` runs 12 cases:
//!   `DEPLOYWATCH_FULL=1 cargo test --release -p deploywatch-tests --test diagnosis_free_play -- --nocapture`.
//! - `without_a_declared_play_the_offset_is_claimed`: the first case's
//!   runs with mechanisms that declare no play: the offset is claimed.
//! - `simulate_at_compares_as_the_diagnosis_did`: `deploywatch diagnose`
//!   writes the reading under `free_play`, not `effects`, and `simulate
//!   --from d.json --at run.csv` gives back the RMS the diagnosis reported.

use deploywatch_sim::diagnose::{diagnose, Outcome};
use deploywatch_sim::effect::{Effect, EffectKind};
use deploywatch_sim::findings::Findings;
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::progress::quiet;
use deploywatch_tests::cli_run::{angles, deploywatch};
use deploywatch_tests::data_dir;
use deploywatch_tests::hidden_effect::{moves_runs_deg, two_runs, SEED_WINGS, STROKE_KINDS};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::Path;

/// The free-play every joint of the test's mechanisms declares \[deg\].
const PLAY_DEG: f64 = 0.2;

/// `m` with `play` declared at every joint.
fn declaring(m: &Mechanism, play: f64) -> Mechanism {
    let mut m = m.clone();
    for j in &mut m.joints {
        j.free_play_deg = play;
    }
    m
}

/// Case `i`: a seed wing, one stroke effect at one joint raised until it
/// moves the runs by ≥ 0.3° RMS, and a reading off at another joint,
/// 0.06–0.18° of either sign (`within` the play) or 0.35–0.6°.
fn case(i: usize, within: bool) -> (Mechanism, Vec<Effect>) {
    let mut rng = ChaCha8Rng::seed_from_u64(5200 + i as u64);
    let m = Mechanism::load(&data_dir().join(format!("mechanisms/{}.toml", SEED_WINGS[i % 4])))
        .expect("bundled");
    let n = m.joint_count();
    let kind = STROKE_KINDS[(i / 4) % 3];
    let j = rng.gen_range(1..=n);
    let mut e = Effect::joint(kind, j, 0.01);
    for _ in 0..40 {
        if moves_runs_deg(&m, &[e]) >= 0.3 {
            break;
        }
        e = e.with_value(e.value() * 1.25);
    }
    let k = if n == 1 {
        1
    } else {
        1 + (j + rng.gen_range(0..n - 1)) % n
    };
    let sign = if rng.gen_bool(0.5) { 1.0 } else { -1.0 };
    let size = if within {
        rng.gen_range(0.06..0.18)
    } else {
        rng.gen_range(0.35..0.6)
    };
    let off = Effect::joint(EffectKind::EncoderOffset, k, sign * size);
    (declaring(&m, PLAY_DEG), vec![e, off])
}

fn names(o: &Outcome) -> String {
    let e: Vec<String> = o.extended.effects().iter().map(|e| e.to_string()).collect();
    let f: Vec<String> = o
        .free_play
        .iter()
        .map(|l| format!("free-play j{} {:+.4}", l.joint, l.offset_deg))
        .collect();
    format!("[{}] {}", e.join(" + "), f.join(", "))
}

/// The stroke effect of `truth` within 20 % is the only effect found.
fn effect_alone(truth: &Effect, o: &Outcome, also: Option<&Effect>) -> bool {
    let e = o.extended.effects();
    let near = |x: &Effect, t: &Effect, tol: f64| {
        x.kind() == t.kind() && x.joint == t.joint && (x.value() - t.value()).abs() <= tol
    };
    e.len() == 1 + usize::from(also.is_some())
        && e.iter().any(|x| near(x, truth, 0.2 * truth.value().abs()))
        && also.is_none_or(|a| e.iter().any(|x| near(x, a, 0.03)))
}

#[test]
fn a_reading_within_the_declared_play_is_not_claimed() {
    let n = if std::env::var_os("DEPLOYWATCH_FULL").is_some() {
        12
    } else {
        2
    };
    let opts = deploywatch_tests::diagnose_options();
    let mut failed = Vec::new();
    let mut beside_large = 0;
    for i in 0..n {
        let within = i % 2 == 0;
        let (m, truth) = case(i, within);
        let o = diagnose(&two_runs(&m, &m, &truth, 10 * i as u64), &opts, &quiet);
        let off = &truth[1];
        let ok = if within {
            let lag = o.free_play.iter().find(|l| Some(l.joint) == off.joint);
            effect_alone(&truth[0], &o, None)
                && o.free_play.len() == 1
                && lag.is_some_and(|l| (l.offset_deg - off.value()).abs() <= 0.03)
        } else {
            // Beyond the play: the offset is claimed, whatever the search
            // makes of the effect beside it (printed, not asked).
            let claimed = o.extended.effects().iter().any(|x| {
                x.kind() == EffectKind::EncoderOffset
                    && x.joint == off.joint
                    && (x.value() - off.value()).abs() <= 0.03
            });
            beside_large += usize::from(effect_alone(&truth[0], &o, Some(off)));
            claimed && o.free_play.is_empty()
        };
        println!(
            "case {i} {}: {} + {} ({}) -> {}: {}",
            m.name,
            truth[0],
            off,
            if within {
                "within the play"
            } else {
                "beyond it"
            },
            names(&o),
            if ok { "right" } else { "WRONG" }
        );
        if !ok {
            failed.push(i);
        }
    }
    println!(
        "right: {} of {n}; beyond the play, the effect found alone beside the offset in {beside_large} of {}",
        n - failed.len(),
        n / 2
    );
    assert!(
        100 * failed.len() <= 15 * n,
        "cases {failed:?} (see the lines above)"
    );
}

#[test]
fn without_a_declared_play_the_offset_is_claimed() {
    let (m, truth) = case(0, true);
    let m = declaring(&m, 0.0);
    let o = diagnose(
        &two_runs(&m, &m, &truth, 0),
        &deploywatch_tests::diagnose_options(),
        &quiet,
    );
    println!("{}", names(&o));
    assert!(o.free_play.is_empty(), "{}", names(&o));
    assert!(
        effect_alone(&truth[0], &o, Some(&truth[1])),
        "{}",
        names(&o)
    );
}

#[test]
fn simulate_at_compares_as_the_diagnosis_did() {
    let (m, truth) = case(0, true);
    let c = two_runs(&m, &m, &truth, 77);
    let dir = std::env::temp_dir().join(format!("dw-free-play-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    let mech = dir.join("wing.toml");
    std::fs::write(&mech, m.to_toml_string()).expect("writes the mechanism");
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
    let off = &truth[1];
    assert!(
        d.effects.iter().all(|e| e.name != "encoder_offset"),
        "an offset within the play claimed:\n{body}"
    );
    let lag = d
        .free_play
        .iter()
        .find(|f| Some(f.joint) == off.joint)
        .unwrap_or_else(|| panic!("no free-play at joint {:?}:\n{body}", off.joint));
    let b = lag.offset_deg.expect("an offset");
    assert!((b - off.value()).abs() <= 0.03, "{b} deg, {off}");
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
    // The model is written as true angles; the run's readings at the
    // joint with free-play are off by the offset the diagnosis took out.
    let (a, mut r) = (
        angles(&model, m.joint_count()),
        angles(&runs[0], m.joint_count()),
    );
    for f in &d.free_play {
        for x in &mut r[f.joint - 1] {
            *x -= f.offset_deg.expect("an offset");
        }
    }
    let (mut sse, mut n) = (0.0, 0usize);
    for (x, y) in a.iter().zip(&r) {
        for (p, q) in x.iter().zip(y) {
            sse += (p - q) * (p - q);
            n += 1;
        }
    }
    let again = (sse / n as f64).sqrt();
    let said = d.extended.rms_deg.expect("an extended RMS");
    // The model CSV's angles have 6 decimals: within their rounding.
    assert!(
        (again - said).abs() <= 1e-5,
        "re-simulated {again} deg, the diagnosis said {said}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
