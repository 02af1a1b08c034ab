//! `diagnose` on an effect that acts after the first latch contact, on
//! wings nobody drew, where the model follows the runs' latch history
//! (`docs/diagnosis.md`, "Runs of a physical latch", 5).
//!
//! Each campaign comes from `deploywatch_tests::after_contact`: a generated
//! wing of 4–6 joints with mixed latches and one named effect that moves
//! the runs by 0.3° RMS or more but by less than twice the sensor's noise
//! before the first latch contact, each switch closing as often with it as
//! without (the cases listed are the generator's, its seed and the kind
//! drawn: six of the measured row's campaigns of the same latch history
//! whose runs the model follows to their end; docs/measured.md gives the
//! whole row). Two runs of the drawing with the reference sensor noise. First
//! the same wing without the effect: nothing may be claimed. Then with it:
//! the effect named at its joint within 20 %, nothing else, the runs fitted
//! whole. The diagnosis sees only the runs and the drawing; the truth stays
//! here until it has answered.
//!
//! `DEPLOYWATCH_FULL=1` runs six campaigns, the CI the first two:
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

#[test]
fn an_effect_after_the_first_contact_is_found_on_the_whole_runs() {
    let full = std::env::var_os("DEPLOYWATCH_FULL").is_some();
    let n = if full { CASES.len() } else { 2 };
    for &(seed, kind) in &CASES[..n] {
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
            "seed {seed}: {} (before contact {:.3} deg) -> {:?}, fitted whole {} ({:.1} s)",
            c.truth,
            c.before_deg,
            claims(&o),
            o.fitted_whole,
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
        assert!(o.fitted_whole, "seed {seed}: not fitted on the whole runs");
    }
}
