//! Why no energy bound ends a T01 physical-latch run early: the tape
//! springs' folding knee lies under their unfolding curve near the stop, so
//! a joint that rattles there (out on the folding branch, back on the
//! unfolding one) is given energy on every loop.
//!
//! For each joint of seed 001 T01 (the springs of both its physical-latch
//! files), at a few angles up to the pawl wing's switch travel (0.35°), the
//! spring's torque on its unfolding and folding branches [N·m], and the
//! energy one loop from the stop out to `A` and back gives the joint,
//! `∫₀^A (T_unfold − T_fold) dφ` \[J\] (positive: the law gives energy),
//! for `A` = the plunger wing's switch travel (0.05°), the pawl's notch
//! (0.3°) and the pawl wing's switch travel (0.35°); beside it the elastic
//! energy of the notch's side compressed by the 0.05° between notch and
//! switch (what a locked joint needs to open its switch).
//!
//! `cargo run --release -p deploywatch-sim --example tape_small_loops`

use deploywatch_core::Branch;
use deploywatch_sim::effect::to_core;
use deploywatch_sim::mechanism::Mechanism;
use std::path::PathBuf;

/// Midpoint-rule intervals of each loop's integral.
const INTERVALS: usize = 10_000;

fn main() -> Result<(), String> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../data/mechanisms");
    let mech = Mechanism::load(&root.join("seed001_T01_pawl.toml")).map_err(|e| e.to_string())?;
    let (je, g) = to_core(&[], 3);
    let chain = mech
        .chain::<3>(&je, g)
        .ok_or("seed 001 T01 cannot be built")?;
    // The notch's wall: the stop's Hertz law (37,000 N/mm^1.5) at the
    // pawl's 40 mm, compressed by 0.05°: k δ^2.5 / 2.5 [N·mm → J].
    let delta_mm = 0.05_f64.to_radians() * 40.0;
    let notch_j = 37_000.0 * delta_mm.powf(2.5) / 2.5 / 1000.0;
    println!("| joint | angle [deg] | unfolding [N·m] | folding [N·m] |");
    println!("|---|---|---|---|");
    for (j, jt) in chain.joints().iter().enumerate() {
        for deg in [0.05, 0.1, 0.2, 0.3, 0.35] {
            let phi = f64::to_radians(deg);
            println!(
                "| {} | {deg} | {:.2} | {:.2} |",
                j + 1,
                jt.spring.magnitude(phi, Branch::Unfold),
                jt.spring.magnitude(phi, Branch::Fold)
            );
        }
    }
    println!(
        "\n| joint | energy a loop gives, to 0.05° [J] | to 0.3° [J] | to 0.35° [J] | the notch's wall compressed 0.05° [J] |"
    );
    println!("|---|---|---|---|---|");
    for (j, jt) in chain.joints().iter().enumerate() {
        let gain = |top_deg: f64| {
            let top = top_deg.to_radians();
            let h = top / INTERVALS as f64;
            (0..INTERVALS)
                .map(|i| {
                    let phi = (i as f64 + 0.5) * h;
                    (jt.spring.magnitude(phi, Branch::Unfold)
                        - jt.spring.magnitude(phi, Branch::Fold))
                        * h
                })
                .sum::<f64>()
        };
        println!(
            "| {} | {:.2e} | {:.2e} | {:.2e} | {notch_j:.2e} |",
            j + 1,
            gain(0.05),
            gain(0.3),
            gain(0.35)
        );
    }
    Ok(())
}
