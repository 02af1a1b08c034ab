//! Issue 44: every effect kind survives the diagnosis JSON. For each kind
//! of the vocabulary (an exhaustive match: a kind added to `EffectKind`
//! does not compile here until it has a generator), an effect with
//! generated parameters is written as `deploywatch diagnose --json` writes
//! it ([`FoundEffect::of_effect`]), read back as `margin --from`,
//! `reliability --from` and `simulate --from` read it
//! ([`Findings::from_json_str`], [`Diagnosis::extended_effects`]), and
//! must be the same effect (every parameter within the JSON's rounding, 6
//! decimals). Every key the entry carries is named in `docs/spec/formats.md`'s
//! "Diagnosis: JSON" section.

use deploywatch_sim::effect::{Effect, EffectKind};
use deploywatch_sim::findings::{Diagnosis, Findings, FoundEffect};
use deploywatch_sim::torque_table::TablePoints;
use proptest::prelude::*;

/// Every kind the effect syntax knows.
fn kinds() -> Vec<EffectKind> {
    let mut k: Vec<EffectKind> = EffectKind::ALL
        .iter()
        .chain(EffectKind::LATCH.iter())
        .chain(EffectKind::RIG.iter())
        .copied()
        .chain([
            EffectKind::TorqueTable,
            EffectKind::StribeckFriction,
            EffectKind::QuadraticDamping,
        ])
        .collect();
    k.sort();
    k.dedup();
    k
}

/// An effect of `kind` from generated numbers `u` (each in 0..1).
fn sample(kind: EffectKind, joint: usize, u: [f64; 4]) -> Effect {
    let mut e = if kind.per_joint() {
        Effect::joint(kind, joint, 0.0)
    } else {
        Effect::global(kind, 0.0)
    };
    e.value = match kind {
        EffectKind::CoulombFriction
        | EffectKind::ViscousDamping
        | EffectKind::QuadraticDamping
        | EffectKind::HarnessStiffness
        | EffectKind::LatchDetent
        | EffectKind::AirDrag
        | EffectKind::RigFriction => 2.0 * u[0],
        EffectKind::SpringSoftening
        | EffectKind::PlungerWeakening
        | EffectKind::MagnetWeakening => 0.9 * u[0],
        EffectKind::RigTilt | EffectKind::EncoderOffset => 4.0 * u[0] - 2.0,
        EffectKind::WireLength | EffectKind::FrameOffset => 0.02 * u[0] - 0.01,
        EffectKind::StribeckFriction => {
            e.excess_nm = u[1];
            e.stribeck_rad_s = 0.01 + u[2];
            u[0]
        }
        EffectKind::TorqueTable => {
            let points = TablePoints {
                angle_deg: Some(vec![0.0, 45.0 + 40.0 * u[1], 180.0]),
                torque_nm: Some(vec![u[0], -u[2], 0.5 * u[3]]),
                rate_deg_s: Some(vec![0.0, 10.0 + u[3]]),
                rate_torque_nm: Some(vec![0.0, u[1]]),
            };
            e.table = points.build().expect("increasing knots");
            0.0
        }
    };
    if kind == EffectKind::RigTilt {
        e.alpha_deg = 360.0 * u[3] - 180.0;
    }
    if kind == EffectKind::TorqueTable {
        // The syntax's value of a table is its largest absolute torque.
        e = e.to_string().parse().expect("a table effect reparses");
    }
    e
}

/// The diagnosis JSON of one effect, as `diagnose --json` writes it.
fn json_of(e: &Effect) -> String {
    let d = Diagnosis {
        effects: vec![FoundEffect::of_effect(e)],
        ..Diagnosis::default()
    };
    serde_json::to_string_pretty(&d).expect("serialises")
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-6 * (1.0 + a.abs())
}

fn same_tables(a: &Effect, b: &Effect) -> bool {
    let t = |x: &Option<deploywatch_core::Table<f64>>, y: &Option<deploywatch_core::Table<f64>>| {
        match (x, y) {
            (None, None) => true,
            (Some(x), Some(y)) => {
                x.xs().len() == y.xs().len()
                    && x.xs().iter().zip(y.xs()).all(|(p, q)| close(*p, *q))
                    && x.ys().iter().zip(y.ys()).all(|(p, q)| close(*p, *q))
            }
            _ => false,
        }
    };
    t(&a.table.angle, &b.table.angle) && t(&a.table.rate, &b.table.rate)
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 64,
        failure_persistence: None,
        rng_seed: proptest::test_runner::RngSeed::Fixed(20_261_129),
        ..ProptestConfig::default()
    })]

    /// Every kind, generated parameters: the effect read back from the JSON
    /// alone is the effect written.
    #[test]
    fn every_kind_survives_its_json(joint in 1usize..4, u in proptest::array::uniform4(0.0f64..1.0)) {
        for kind in kinds() {
            let e = sample(kind, joint, u);
            let text = json_of(&e);
            let Ok(Findings::Diagnosis(d)) = Findings::from_json_str(&text) else {
                panic!("{kind}: not read back as a diagnosis:\n{text}");
            };
            let back = d.extended_effects().map_err(|x| TestCaseError::fail(format!("{kind}: {x}")))?;
            prop_assert_eq!(back.len(), 1, "{}: {}", kind, text);
            let b = &back[0];
            prop_assert_eq!(b.kind, e.kind);
            prop_assert_eq!(b.joint, e.joint);
            prop_assert!(close(b.value, e.value), "{}: value {} vs {}", kind, b.value, e.value);
            prop_assert!(close(b.alpha_deg, e.alpha_deg), "{}: alpha_deg", kind);
            prop_assert!(close(b.excess_nm, e.excess_nm), "{}: excess_nm", kind);
            prop_assert!(close(b.stribeck_rad_s, e.stribeck_rad_s), "{}: stribeck_rad_s", kind);
            prop_assert!(same_tables(b, &e), "{}: tables", kind);
        }
    }
}

/// The "Diagnosis: JSON" section of formats.md.
fn formats_diagnosis_section() -> String {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/spec/formats.md");
    let text = std::fs::read_to_string(path).expect("docs/spec/formats.md");
    let start = text
        .find("## Diagnosis: JSON")
        .expect("a Diagnosis: JSON section");
    let rest = &text[start + 3..];
    let end = rest.find("\n## ").unwrap_or(rest.len());
    rest[..end].to_string()
}

/// Every key an effect entry carries, for every kind, is named in
/// formats.md's diagnosis section (as `"key"` or in the JSON example).
#[test]
fn formats_md_names_every_key_of_every_kind() {
    let doc = formats_diagnosis_section();
    for kind in kinds() {
        let e = sample(kind, 1, [0.3, 0.4, 0.5, 0.6]);
        let v: serde_json::Value = serde_json::from_str(&json_of(&e)).expect("JSON");
        let entry = v["effects"][0].as_object().expect("an effect entry");
        for key in entry.keys() {
            assert!(
                doc.contains(&format!("\"{key}\"")),
                "{kind}: key \"{key}\" of its JSON entry is not in formats.md's Diagnosis: JSON section"
            );
        }
        assert!(
            doc.contains(&format!("`{}", kind.name()))
                || kind == EffectKind::CoulombFriction
                || doc.contains(&format!("\"{}\"", kind.name())),
            "{kind} is not named in formats.md's Diagnosis: JSON section"
        );
    }
}
