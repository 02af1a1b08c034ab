//! `diagnose` on an effect that acts after the first latch contact, on
//! wings nobody drew, where the model follows the runs' latch history
//! (`docs/diagnosis.md`, "Runs of a physical latch", 5 and 6).
//!
//! Each campaign comes from `deploywatch_tests::after_contact`: a generated
//! wing of 4–6 joints with mixed latches and one named effect that moves
//! the runs by 0.3° RMS or more but by less than twice the sensor's noise
//! before the first latch contact, each switch closing as often with it as
//! without (the cases listed are the generator's, its seed and the kind
//! drawn, of the measured row's campaigns of the same latch history;
//! docs/measured.md gives the whole row). Two runs of the drawing with the
//! reference sensor noise. First the same wing without the effect: nothing
//! may be claimed. Then with it: the effect named at its joint within
//! 20 %, nothing else; `CASES`, whose runs the model follows to their end,
//! fitted whole; `TO_HORIZON`, whose runs it follows beyond their free
//! motion but not to their end (a switch parts, or the integration's
//! tolerance moves the model), fitted on each run up to there;
//! `SMALLEST`, effects of 0.01 at their joint, found. The
//! diagnosis sees only the runs and the drawing; the truth stays here until
//! it has answered.
//!
//! `DEPLOYWATCH_FULL=1` runs every case, the CI the first two of `CASES`,
//! the first of `TO_HORIZON` and the first of `SMALLEST`:
//!
//! ```text
//! DEPLOYWATCH_FULL=1 cargo test --release -p deploywatch-tests --test diagnosis_after_contact -- --nocapture
//! ```

use deploywatch_sim::diagnose::{diagnose, Outcome};
use deploywatch_sim::effect::EffectKind;
use deploywatch_sim::progress::quiet;
use deploywatch_tests::after_contact::case;
use deploywatch_tests::hidden_effect::two_runs;

/// The generator's seeds and the kind each hides.
const CASES: [(u64, EffectKind); 6] = [
    (9386, EffectKind::ViscousDamping),
    (9676, EffectKind::HarnessStiffness),
    (10436, EffectKind::HarnessStiffness),
    (14034, EffectKind::ViscousDamping),
    (14695, EffectKind::ViscousDamping),
    (16295, EffectKind::HarnessStiffness),
];

fn claims(o: &Outcome) -> Vec<String> {
    o.extended.effects().iter().map(|e| e.to_string()).collect()
}

/// The seeds and kinds whose runs the model follows beyond their free
/// motion but not to their end ("Runs of a physical latch", 6). Not
/// listed: seed 16327 (Coulomb 0.013 N·m at joint 1), which the fit on the
/// runs cut there, started from the scan's 0.01, takes to a local minimum
/// at 0.0103 (21 % off; a viscous damping and a softening at that joint
/// fit those runs better by a BIC of 460): a miss of the measured row.
const TO_HORIZON: [(u64, EffectKind); 2] = [
    (15261, EffectKind::ViscousDamping),
    (14948, EffectKind::CoulombFriction),
];

/// The seeds and kinds whose effect is the generator's smallest (0.01 at
/// its joint: N·m, N·m/rad; the coarse scan's first value, a third of the
/// next): found.
const SMALLEST: [(u64, EffectKind); 2] = [
    (14358, EffectKind::HarnessStiffness),
    (14408, EffectKind::CoulombFriction),
];

/// Case `seed` of `kind`: its clean runs claim nothing, then the effect is
/// named at its joint within 20 % and nothing else; the second diagnosis.
fn found_after_contact(seed: u64, kind: EffectKind) -> Outcome {
    let c = case(seed, kind).expect("the generator's case qualifies");
    assert!(
        c.same_history,
        "seed {seed}: the effect changes the latch history"
    );
    let clean = two_runs(&c.wing, &c.wing, &[], 1000 + seed);
    let o = diagnose(&clean, &deploywatch_tests::diagnose_options(), &quiet);
    assert!(
        o.extended.effects().is_empty() && o.unexplained.is_none(),
        "seed {seed}, clean runs: {:?}, unexplained {:?}",
        claims(&o),
        o.unexplained
    );
    let campaign = two_runs(&c.wing, &c.wing, &[c.truth], 1000 + seed);
    let o = diagnose(&campaign, &deploywatch_tests::diagnose_options(), &quiet);
    eprintln!(
        "seed {seed}: {} (before contact {:.3} deg) -> {:?}, fitted whole {}, fitted to {:?} ({:.1} s)",
        c.truth,
        c.before_deg,
        claims(&o),
        o.fitted_whole,
        o.fitted_to.as_ref().map(|w| w.iter().map(|w| w.kept).collect::<Vec<_>>()),
        o.wall_s
    );
    // Only now the truth.
    let found = o.extended.effects();
    assert!(
        found.len() == 1
            && found[0].kind() == c.truth.kind()
            && found[0].joint == c.truth.joint
            && (found[0].value() - c.truth.value()).abs() <= 0.2 * c.truth.value(),
        "seed {seed}: {} hidden, {:?} found",
        c.truth,
        claims(&o)
    );
    o
}

#[test]
fn an_effect_after_the_first_contact_is_found_on_the_whole_runs() {
    let full = std::env::var_os("DEPLOYWATCH_FULL").is_some();
    let n = if full { CASES.len() } else { 2 };
    for &(seed, kind) in &CASES[..n] {
        let o = found_after_contact(seed, kind);
        assert!(o.fitted_whole, "seed {seed}: not fitted on the whole runs");
        assert!(
            o.fitted_to.is_none(),
            "seed {seed}: also fitted to a window"
        );
    }
}

#[test]
fn an_effect_after_the_first_contact_is_found_up_to_where_the_model_follows_the_runs() {
    let full = std::env::var_os("DEPLOYWATCH_FULL").is_some();
    let n = if full { TO_HORIZON.len() } else { 1 };
    for &(seed, kind) in &TO_HORIZON[..n] {
        let o = found_after_contact(seed, kind);
        assert!(!o.fitted_whole, "seed {seed}: fitted whole");
        let (Some(to), Some(free)) = (&o.fitted_to, &o.free_window) else {
            panic!("seed {seed}: not fitted up to where the model follows the runs");
        };
        for (t, f) in to.iter().zip(free) {
            assert!(
                t.kept > f.kept && t.kept <= t.of,
                "seed {seed}: fitted to {} of {} samples, free motion {}",
                t.kept,
                t.of,
                f.kept
            );
        }
    }
}

#[test]
fn the_generators_smallest_effect_after_the_first_contact_is_found() {
    let full = std::env::var_os("DEPLOYWATCH_FULL").is_some();
    let n = if full { SMALLEST.len() } else { 1 };
    for &(seed, kind) in &SMALLEST[..n] {
        found_after_contact(seed, kind);
    }
}
