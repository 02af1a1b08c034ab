//! The physical latch's engagement in `deploywatch margin` (`docs/margin.md`,
//! "The latch's engagement"): the entry torque and engagement energy against
//! a hand calculation from the mechanism file's plunger.
//!
//! `cargo test -p deploywatch-tests --test latch_margin`

use deploywatch_sim::analysis::design_margin::{joint_margin, Standard};
use deploywatch_sim::cli::margin::latch_resistance;
use deploywatch_sim::model::mechanism::Mechanism;
use deploywatch_tests::data_dir;

fn mechanism(name: &str) -> Mechanism {
    Mechanism::load(&data_dir().join("mechanisms").join(name)).expect("mechanism")
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
