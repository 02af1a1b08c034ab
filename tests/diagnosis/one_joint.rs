//! Two causes at one joint, named and measured.

use super::*;

/// The pairs of causes at one joint drawn by
/// [`two_causes_at_one_joint_are_named_and_measured`]: the second is at the
/// first's joint (rig tilt has none; its partner takes a drawn joint).
const ONE_JOINT_PAIRS: [[EffectKind; 2]; 4] = [
    [EffectKind::SpringSoftening, EffectKind::CoulombFriction],
    [EffectKind::SpringSoftening, EffectKind::HarnessStiffness],
    [EffectKind::ViscousDamping, EffectKind::CoulombFriction],
    [EffectKind::RigTilt, EffectKind::CoulombFriction],
];

/// Two causes at one joint, each moving the runs by 0.3° to 0.6° RMS on its
/// own (near the detectability bar): drawn like [`generate`]'s, then moved
/// to one joint. Noise seeds differ from the main suite's.
fn generate_one_joint(seed: u64, kinds: [EffectKind; 2], pair: usize) -> Case {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mechs = mechanisms(pair);
    let joints = mechs[0].joint_count();
    let mut truth: Vec<Effect> = kinds
        .iter()
        .map(|&k| draw_effect(&mut rng, k, joints))
        .collect();
    let joint = truth.iter().find_map(|e| e.joint);
    for e in truth.iter_mut().filter(|e| e.kind().per_joint()) {
        e.joint = joint;
    }
    // Near the detectability bar: each effect brought to 0.3–0.6° RMS.
    for i in 0..truth.len() {
        for _ in 0..20 {
            let size = effect_size(&mechs, &truth[i..=i]);
            if size < 0.3 {
                truth[i] = truth[i].with_value(truth[i].value() * 1.5);
            } else if size > 0.6 {
                truth[i] = truth[i].with_value(truth[i].value() / 1.5);
            } else {
                break;
            }
        }
    }
    let runs = simulate_runs(&mechs, &truth, seed);
    Case { pair, truth, runs }
}

/// Two causes at ONE joint (spring softening with Coulomb friction or with
/// a harness, viscous damping with Coulomb friction, rig tilt with Coulomb
/// friction): each pair twice, on both mechanism pairs, with the joint and
/// the values drawn by a seeded generator; the diagnosis sees only the runs
/// and the nominal mechanisms. A case is right when named exactly (names
/// and joints, nothing unexplained) with every value within 5 %. The
/// target (95 % named) is for the hidden sets together: with
/// [`hidden_effects_are_named_and_measured`]'s 61 it needs at least 5 of
/// these 8; the test asks for the 7 measured (`docs/diagnosis.md`, "Two
/// causes at one joint").
#[test]
fn two_causes_at_one_joint_are_named_and_measured() {
    let mut rng = ChaCha8Rng::seed_from_u64(4242);
    let (mut ok, mut total, mut worst) = (0usize, 0usize, 0.0f64);
    let mut misses = Vec::new();
    for rep in 0..2u64 {
        for (p, kinds) in ONE_JOINT_PAIRS.iter().enumerate() {
            let seed = 5200 + rng.gen_range(0..1000) + 1000 * rep;
            let case = generate_one_joint(seed, *kinds, (p + rep as usize) % 2);
            let outcome = diagnose(
                &campaign_of(&case, |_| true),
                &deploywatch_tests::diagnose_options(),
                trace_sink(),
            );
            // Only now the truth.
            let found = outcome.extended.effects();
            let mut want: Vec<_> = case.truth.iter().map(key).collect();
            let mut got: Vec<_> = found.iter().map(key).collect();
            want.sort();
            got.sort();
            let named = want == got && outcome.unexplained.is_none();
            let err = case
                .truth
                .iter()
                .filter_map(|t| {
                    let f = found.iter().find(|f| key(f) == key(t))?;
                    Some((f.value() - t.value()).abs() / t.value().abs())
                })
                .fold(0.0, f64::max);
            let right = named && err <= 0.05;
            println!(
                "seed {seed}: {} truth [{}] found [{}] RMS {:.3} -> {:.4}, worst value error {:.2} % ({:.1} s)",
                if right { "ok  " } else { "MISS" },
                case.truth.iter().map(|e| e.to_string()).collect::<Vec<_>>().join("; "),
                found.iter().map(|e| e.to_string()).collect::<Vec<_>>().join("; "),
                outcome.baseline.rms(),
                outcome.extended.rms(),
                100.0 * err,
                outcome.wall_s
            );
            total += 1;
            if right {
                ok += 1;
                worst = worst.max(err);
            } else {
                misses.push(seed);
            }
        }
    }
    println!(
        "two causes at one joint: {ok}/{total} named with values within 5 % (worst {:.2} %)",
        100.0 * worst
    );
    let body = format!(
        "## Diagnosis: two causes at one joint\n\n\
         {total} seeded campaigns of `two_causes_at_one_joint_are_named_and_measured` \
         (`docs/diagnosis.md`, \"How well it works\"): two causes at one drawn joint, \
         each near the detectability bar.\n\n\
         | criterion | required | measured |\n|---|---|---|\n\
         | exact names and joints, values within 5 % | ≥ 7/8 (test) | {ok}/{total} (worst value error {:.2} %) |\n\
         | misses (seeds) | (reported) | {} |\n",
        100.0 * worst,
        if misses.is_empty() {
            "none".to_string()
        } else {
            format!("{misses:?}")
        },
    );
    deploywatch_tests::record::record(
        "diagnosis-two-causes",
        "DEPLOYWATCH_FULL=1 cargo test -p deploywatch-tests --test diagnosis two_causes -- --nocapture",
        &body,
    )
    .expect("docs/measured.md written");
    assert!(ok * 8 >= total * 7, "{ok}/{total}; misses: {misses:?}");
}
