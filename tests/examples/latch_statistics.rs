//! The experiment behind `docs/diagnosis.md`'s weakened-latch paragraph:
//! what a plunger or magnet at 30 % of its drawing (a weakening of 0.7) does
//! to a joint's latch statistics, against the spread of 12 as-built draws
//! of the drawing (mean ± standard deviation of each, per family and joint,
//! with the reference sensor noise). Prints a line per family, joint and
//! latch:
//!
//! ```text
//! cargo run --release -p deploywatch-tests --example latch_statistics
//! ```

use deploywatch_sim::deployment::{self, SimOptions};
use deploywatch_sim::effect::{Effect, EffectKind};
use deploywatch_sim::latch::LatchTolerance;
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::sensor::{self, SensorModel};
use deploywatch_tests::{mechanism as load, PHYSICAL_LATCH_FAMILIES as FAMILIES};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn main() {
    let tol = LatchTolerance::default();
    for (family, drawn) in FAMILIES.iter().enumerate() {
        let drawings: Vec<Mechanism> = drawn.iter().map(|(d, _)| load(d)).collect();
        for j in 0..drawings[0].joint_count() {
            for (kind, w) in [
                (EffectKind::PlungerWeakening, 0.0),
                (EffectKind::PlungerWeakening, 0.7),
                (EffectKind::MagnetWeakening, 0.7),
            ] {
                let mut rows: Vec<[f64; 12]> = Vec::new();
                for k in 0..12u64 {
                    let mut rng = ChaCha8Rng::seed_from_u64(900 + k);
                    let mut uniform = || rng.gen::<f64>();
                    let eff = vec![Effect::joint(kind, j + 1, w)];
                    let mut st = [0.0; 12];
                    for d in &drawings {
                        let m = d.as_built(&tol, &mut uniform);
                        let traj = deployment::simulate(&m, &eff, &SimOptions::default()).unwrap();
                        let run = sensor::measure(
                            &traj,
                            &vec![0.0; m.joint_count()],
                            &SensorModel::REFERENCE,
                            k,
                        );
                        let s = m.joints[j].stowed_deg.signum();
                        let u: Vec<f64> = run.phi_deg[j].iter().map(|p| s * p).collect();
                        if let Some(x) = latch_statistics(&run.t_s, &u, &run.latch[j]) {
                            for (a, b) in st.iter_mut().zip(x) {
                                *a += b;
                            }
                        }
                    }
                    rows.push(st);
                }
                let names = [
                    "imp",
                    "cross",
                    "hold",
                    "mean1",
                    "mean05",
                    "open1",
                    "max1",
                    "mean_in",
                    "n_in",
                    "out_s",
                    "rest_mdeg",
                    "t0",
                ];
                let mut line = format!("fam {family} j{} {kind:?} {w}:", j + 1);
                for (c, nm) in names.iter().enumerate() {
                    let v: Vec<f64> = rows.iter().map(|r| r[c]).collect();
                    let m = v.iter().sum::<f64>() / v.len() as f64;
                    let sd = (v.iter().map(|x| (x - m).powi(2)).sum::<f64>()
                        / (v.len() - 1) as f64)
                        .sqrt();
                    line += &format!(" {nm} {m:.3}±{sd:.3}");
                }
                println!("{line}");
            }
        }
    }
}

/// A joint's latch statistics in one run (times `t`, travel from the stop
/// `u` \[deg\], switch `sw`; crest 0.6°): impacts, crest crossings, time
/// from first impact to hold \[s\], mean travel in the first 1 s and 0.5 s
/// after it, time open in the first second \[s\], deepest excursion in it,
/// mean travel of the open samples within the crest, their count, time
/// out of the crest \[s\], mean travel at rest after the hold [millidegrees],
/// first impact \[s\]. `None` when the switch never closes.
fn latch_statistics(t: &[f64], u: &[f64], sw: &[bool]) -> Option<[f64; 12]> {
    let i0 = sw.iter().position(|&b| b)?;
    let crest = 0.6;
    let n = t.len();
    let (mut imp, mut cross) = (0.0, 0.0);
    for i in i0.max(1)..n {
        imp += f64::from(u8::from(sw[i] && !sw[i - 1]));
        cross += f64::from(u8::from((u[i] > crest) != (u[i - 1] > crest)));
    }
    let hold_i = (0..n).rev().take_while(|&i| sw[i]).last();
    let hold = hold_i.map_or(f64::NAN, |i| t[i] - t[i0]);
    let mean = |to: usize| {
        let to = to.min(n);
        u[i0..to].iter().map(|x| x.clamp(0.0, 3.0)).sum::<f64>() / (to - i0) as f64
    };
    let w1 = (i0 + 100).min(n);
    let open1 = sw[i0..w1].iter().filter(|&&b| !b).count() as f64 / (w1 - i0) as f64;
    let max1 = u[i0..w1].iter().copied().fold(0.0, f64::max);
    let increst: Vec<f64> = (i0..n)
        .filter(|&i| !sw[i] && u[i] < crest)
        .map(|i| u[i])
        .collect();
    let mean_in = increst.iter().sum::<f64>() / increst.len().max(1) as f64;
    let out_s = (i0..n).filter(|&i| u[i] > crest).count() as f64 * 0.01;
    let rest_from = hold_i.unwrap_or(n) + 20;
    let rest = if rest_from + 50 < n {
        u[rest_from..].iter().sum::<f64>() / (n - rest_from) as f64 * 1000.0
    } else {
        f64::NAN
    };
    Some([
        imp,
        cross,
        hold,
        mean(i0 + 100),
        mean(i0 + 50),
        open1,
        max1,
        mean_in,
        increst.len() as f64,
        out_s,
        rest,
        t[i0],
    ])
}
