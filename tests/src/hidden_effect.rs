//! Hidden named effects, for the diagnosis tests (`tests/diagnosis/`,
//! `tests/diagnosis_physical_latch.rs`): which kinds a campaign draws and
//! how a kind's joint and value are drawn.

use deploywatch_sim::campaign::Campaign;
use deploywatch_sim::deployment::{self, SimOptions};
use deploywatch_sim::effect::{self, Effect, EffectKind, Law};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::sensor::{self, SensorModel};
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// The kinds drawn: the diagnosis's candidates ([`EffectKind::ALL`], in
/// its order) but `latch_detent`.
pub fn kinds() -> Vec<EffectKind> {
    EffectKind::ALL
        .into_iter()
        .filter(|&k| k != EffectKind::LatchDetent)
        .collect()
}

/// One effect of `kind` on a mechanism of `joints` joints: the joint
/// uniform, the value log-uniform over a range that the kind makes
/// visible but not absurd (an encoder offset of either sign). Kinds that
/// are never drawn ([`kinds`] leaves them out) get the value 0.
pub fn draw_effect(rng: &mut ChaCha8Rng, kind: EffectKind, joints: usize) -> Effect {
    let u = |rng: &mut ChaCha8Rng, lo: f64, hi: f64| lo * (hi / lo).powf(rng.gen::<f64>());
    let j = rng.gen_range(1..=joints);
    match kind {
        EffectKind::CoulombFriction => Effect::joint(kind, j, u(rng, 0.05, 1.0)),
        EffectKind::ViscousDamping => Effect::joint(kind, j, u(rng, 0.05, 1.5)),
        // Not candidates (not in `EffectKind::ALL`).
        EffectKind::QuadraticDamping | EffectKind::StribeckFriction => Effect::joint(kind, j, 0.0),
        EffectKind::SpringSoftening => Effect::joint(kind, j, u(rng, 0.05, 0.35)),
        EffectKind::HarnessStiffness => Effect::joint(kind, j, u(rng, 0.03, 0.5)),
        EffectKind::AirDrag => Effect::global(kind, u(rng, 0.05, 1.0)),
        EffectKind::RigTilt => {
            let alpha_deg = rng.gen_range(0.0..360.0);
            let g_m_s2 = u(rng, 0.01, 0.2);
            Effect {
                joint: None,
                law: Law::RigTilt { g_m_s2, alpha_deg },
            }
        }
        EffectKind::EncoderOffset => {
            let s = if rng.gen::<bool>() { 1.0 } else { -1.0 };
            Effect::joint(kind, j, s * u(rng, 0.3, 2.0))
        }
        EffectKind::LatchDetent => Effect::joint(kind, j, u(rng, 0.5, 2.0)),
        // Not drawn here: tests/unnamed_torque.rs draws its own tables.
        EffectKind::TorqueTable => Effect::joint(kind, j, 0.0),
        // Never drawn: they act only on a physical latch (`EffectKind::LATCH`).
        EffectKind::PlungerWeakening | EffectKind::MagnetWeakening => Effect::joint(kind, j, 0.0),
        // Never drawn here: they act only on a rig (tests/diagnosis_rig.rs).
        EffectKind::RigFriction | EffectKind::WireLength | EffectKind::FrameOffset => {
            Effect::global(kind, 0.0)
        }
    }
}

/// The seed wings of the single-effect diagnosis tests, by file stem in
/// `data/mechanisms/`.
pub const SEED_WINGS: [&str; 4] = [
    "seed001_T01",
    "seed000_case1",
    "seed001_T02",
    "seed000_case3",
];

/// The named effects that act over the whole stroke, drawn in turn by
/// those tests.
pub const STROKE_KINDS: [EffectKind; 3] = [
    EffectKind::CoulombFriction,
    EffectKind::ViscousDamping,
    EffectKind::SpringSoftening,
];

/// RMS \[deg\] by which the effects `e` move the runs of `m` (every joint,
/// over the samples both runs have; the runs not stopped when deployed);
/// 0 when either does not simulate.
pub fn moves_runs_deg(m: &Mechanism, e: &[Effect]) -> f64 {
    apart_deg(m, &[], e)
}

/// RMS \[deg\] between the runs of `m` with the effects `a` and with `b`
/// (every joint, over the samples both runs have; the runs not stopped
/// when deployed); 0 when either does not simulate.
pub fn apart_deg(m: &Mechanism, a: &[Effect], b: &[Effect]) -> f64 {
    let opts = SimOptions {
        stop_when_deployed: false,
        ..SimOptions::default()
    };
    let (Ok(x), Ok(y)) = (
        deployment::simulate(m, a, &opts),
        deployment::simulate(m, b, &opts),
    ) else {
        return 0.0;
    };
    let (mut sse, mut n) = (0.0, 0usize);
    for j in 0..m.joint_count() {
        for i in 0..x.t_s.len().min(y.t_s.len()) {
            sse += (y.phi_deg[j][i] - x.phi_deg[j][i]).powi(2);
            n += 1;
        }
    }
    (sse / n.max(1) as f64).sqrt()
}

/// Two runs of `truth` made on `built` (the reference sensor, noise seeds
/// `seed` and `seed + 1`), paired with the drawing `drawn` the diagnosis
/// is given (`built` itself when the wing is as drawn).
pub fn two_runs(drawn: &Mechanism, built: &Mechanism, truth: &[Effect], seed: u64) -> Campaign {
    let traj = deployment::simulate(built, truth, &SimOptions::default()).expect("simulates");
    let off = effect::encoder_offsets_deg(truth, built.joint_count());
    let mut c = Campaign::default();
    for r in 0..2 {
        let mut run = sensor::measure(&traj, &off, &SensorModel::REFERENCE, seed + r);
        run.set_meta("mechanism", &drawn.name);
        c.push(
            std::slice::from_ref(drawn),
            run,
            std::path::Path::new(&format!("run{r}.csv")),
        )
        .expect("a campaign");
    }
    c
}
