//! Claims within the discrepancy (`docs/diagnosis.md`, "Claims within the
//! discrepancy"): runs that hold something the named effects do not — here
//! a flexible wing's ringing after each latch shock — leave a residual
//! above the noise; the diagnosis claims only what accounts for more of the
//! runs than that discrepancy, and sets the rest aside.
//!
//! The runs are our simulator's, with every joint's angle ringing after
//! the release and after each latching of the wing (a damped sinusoid at the wing's first mode,
//! 4–15 Hz, 1–3 % of critical, its RMS over the run 0.15–0.4°, drawn per
//! case), then the reference sensor's noise and rounding. Half the cases
//! hide nothing; the others one named effect that moves the runs by at
//! least twice the ringing. The diagnosis is given the runs and the
//! mechanisms only.
//!
//! - `a_ringing_wing_is_not_given_claims`: nothing claimed where nothing
//!   was hidden, the hidden effect alone (within 20 %) where one was; an
//!   `unexplained` residual allowed beside. Right in 85 % at least (the
//!   CI's 2 cases both); `DEPLOYWATCH_FULL=1` runs 12:
//!   `DEPLOYWATCH_FULL=1 cargo test -p deploywatch-tests --test diagnosis_discrepancy -- --nocapture`.
//!   Every claim set aside must be one the truth does not hold. A ringing
//!   is zero-mean and projects little onto the named effects: on these
//!   cases the search itself rarely makes a claim for the rule to set
//!   aside, so the test guards the answer, not the rule's every branch;
//!   the rule's work shows on another engine's campaigns
//!   (`python/examples/outside_engine.py`, docs/measured.md).

use deploywatch_sim::campaign::Campaign;
use deploywatch_sim::deployment::{self, SimOptions, Trajectory};
use deploywatch_sim::diagnose::{diagnose, Outcome};
use deploywatch_sim::effect::{self, Effect};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::progress::quiet;
use deploywatch_sim::sensor::{self, SensorModel};
use deploywatch_tests::data_dir;
use deploywatch_tests::hidden_effect::{moves_runs_deg, SEED_WINGS, STROKE_KINDS};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;
use std::path::Path;

/// The wing's first mode and how hard it rings.
#[derive(Clone, Copy, Debug)]
struct Ringing {
    /// Natural frequency \[Hz\].
    hz: f64,
    /// Damping ratio \[1\].
    zeta: f64,
    /// RMS over the run of the ringing of the joint that rings most \[deg\].
    rms_deg: f64,
}

/// `tr`'s angles with every joint ringing after the release and after each
/// latching of the wing: a shock at `t_L` adds `a_j e^(−ζω(t−t_L)) sin(ω_d (t−t_L))` to
/// joint `j`, with a share of the amplitude per joint drawn from `rng`,
/// scaled so the largest joint's ringing has `r.rms_deg` RMS over the run.
fn ring(tr: &Trajectory, r: Ringing, rng: &mut ChaCha8Rng) -> Trajectory {
    let w = 2.0 * PI * r.hz;
    let wd = w * (1.0 - r.zeta * r.zeta).sqrt();
    // The release (the first sample any joint has left its stowed angle)
    // and each latching shock the wing.
    let release = tr.t_s.iter().enumerate().find_map(|(i, &t)| {
        tr.phi_deg
            .iter()
            .any(|phi| (phi[i] - phi[0]).abs() > 1e-6)
            .then_some(t)
    });
    let shocks: Vec<f64> = release
        .into_iter()
        .chain(tr.latch_s.iter().flatten().copied())
        .collect();
    let shape: Vec<f64> = tr
        .t_s
        .iter()
        .map(|&t| {
            shocks
                .iter()
                .filter(|&&s| t > s)
                .map(|&s| (-r.zeta * w * (t - s)).exp() * (wd * (t - s)).sin())
                .sum()
        })
        .collect();
    let rms = (shape.iter().map(|x| x * x).sum::<f64>() / shape.len().max(1) as f64).sqrt();
    let mut out = tr.clone();
    if rms <= 0.0 {
        return out;
    }
    let share: Vec<f64> = (0..tr.phi_deg.len())
        .map(|j| if j == 0 { 1.0 } else { rng.gen_range(0.3..1.0) })
        .collect();
    for (phi, s) in out.phi_deg.iter_mut().zip(share) {
        for (p, x) in phi.iter_mut().zip(&shape) {
            *p += s * r.rms_deg / rms * x;
        }
    }
    out
}

/// Two runs of `truth` on `m`, ringing as `r`, the reference sensor's
/// noise seeds `seed` and `seed + 1`.
fn campaign(m: &Mechanism, truth: &[Effect], r: Ringing, seed: u64) -> Option<Campaign> {
    let tr = deployment::simulate(m, truth, &SimOptions::default()).ok()?;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let angles = ring(&tr, r, &mut rng);
    let off = effect::encoder_offsets_deg(truth, m.joint_count());
    let mut c = Campaign::default();
    for k in 0..2 {
        let mut run = sensor::measure(&angles, &off, &SensorModel::REFERENCE, seed + k);
        run.set_meta("mechanism", &m.name);
        c.push(
            std::slice::from_ref(m),
            run,
            Path::new(&format!("run{k}.csv")),
        )
        .ok()?;
    }
    Some(c)
}

/// Case `i`: a seed wing and its ringing; the odd cases one effect raised
/// from a small value until it moves the runs by twice the ringing.
fn case(i: usize) -> (Mechanism, Vec<Effect>, Ringing) {
    let mut rng = ChaCha8Rng::seed_from_u64(5200 + i as u64);
    let m = Mechanism::load(&data_dir().join(format!("mechanisms/{}.toml", SEED_WINGS[i % 4])))
        .expect("bundled");
    let r = Ringing {
        hz: rng.gen_range(4.0..15.0),
        zeta: rng.gen_range(0.01..0.03),
        rms_deg: rng.gen_range(0.15..0.4),
    };
    if i % 2 == 0 {
        return (m, Vec::new(), r);
    }
    let kind = STROKE_KINDS[(i / 2) % 3];
    let j = rng.gen_range(1..=m.joint_count());
    let mut e = Effect::joint(kind, j, 0.01);
    for _ in 0..60 {
        if moves_runs_deg(&m, &[e]) >= 2.0 * r.rms_deg {
            break;
        }
        e = e.with_value(e.value() * 1.25);
    }
    (m, vec![e], r)
}

/// The outcome claims exactly `truth`, values within 20 % (an
/// `unexplained` residual allowed beside).
fn right(truth: &[Effect], o: &Outcome) -> bool {
    let e = o.extended.effects();
    e.len() == truth.len()
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
fn a_ringing_wing_is_not_given_claims() {
    let n = if std::env::var_os("DEPLOYWATCH_FULL").is_some() {
        12
    } else {
        2
    };
    let opts = deploywatch_tests::diagnose_options();
    let mut failed = Vec::new();
    for i in 0..n {
        let (m, truth, r) = case(i);
        let c = campaign(&m, &truth, r, 10 * i as u64).expect("simulates");
        let o = diagnose(&c, &opts, &quiet);
        let aside: Vec<String> = o
            .set_aside
            .iter()
            .map(|s| {
                format!(
                    "{} ({:.3} of {:.3} deg)",
                    s.effect.candidate.words(),
                    s.explained_deg,
                    s.discrepancy_deg
                )
            })
            .collect();
        println!(
            "case {i} {}: [{}] ringing {:.1} Hz, {:.1} %, {:.2} deg -> [{}]{}; set aside [{}]",
            m.name,
            truth
                .iter()
                .map(|e| e.to_string())
                .collect::<Vec<_>>()
                .join(", "),
            r.hz,
            100.0 * r.zeta,
            r.rms_deg,
            names(&o),
            if o.unexplained.is_some() {
                " + unexplained"
            } else {
                ""
            },
            aside.join(", ")
        );
        // What is set aside is never the truth.
        for s in &o.set_aside {
            let e = s.effect.candidate.effect(&s.effect.params);
            assert!(
                !truth
                    .iter()
                    .any(|t| t.kind() == e.kind() && t.joint == e.joint),
                "case {i}: the hidden {} set aside",
                e
            );
        }
        if !right(&truth, &o) {
            failed.push(i);
        }
    }
    println!(
        "the truth claimed and nothing else: {} of {n}",
        n - failed.len()
    );
    // The bar, 85 %: every case of the CI's two.
    assert!(
        100 * failed.len() <= 15 * n,
        "cases {failed:?} (see the lines above)"
    );
}
