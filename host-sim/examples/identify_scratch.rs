use deploywatch_sim::campaign::Campaign;
use deploywatch_sim::effect::{Effect, EffectKind};
use deploywatch_sim::identify::{self, identify_rsm, RsmOptions, RsmResponse};
use deploywatch_sim::mechanism::Mechanism;
use std::path::Path;

fn camp(names: &[&str], truth: &[f64]) -> Campaign {
    let d = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/mechanisms");
    let mechs: Vec<Mechanism> = names.iter().map(|n| Mechanism::load(&d.join(format!("{n}.toml"))).unwrap()).collect();
    let eff: Vec<Effect> = truth.iter().enumerate().map(|(j, &v)| Effect::joint(EffectKind::CoulombFriction, j + 1, v)).collect();
    let mut c = Campaign::default();
    for (i, m) in mechs.iter().enumerate() {
        let run = identify::synthetic_run(m, &eff, 1 + i as u64).unwrap();
        c.push(&mechs, run, Path::new(names[i])).unwrap();
    }
    c
}

fn main() {
    let c1 = camp(&["seed001_T01", "seed001_T02"], &[2.63, 1.7, 0.001]);
    let c0 = camp(&["seed000_case1", "seed000_case3"], &[0.54, 0.472]);
    let q = |_: &str| {};
    for (c, centre, half) in [
        (&c1, vec![2.26, 1.6, 0.025], None),
        (&c1, vec![2.63, 1.7, 0.001], None),
        (&c1, vec![2.63, 1.7, 0.01], Some(vec![0.25*2.63, 0.25*1.7, 0.005])),
        (&c0, vec![0.75, 0.6], Some(vec![0.25, 0.3])),
        (&c0, vec![0.54, 0.472], None),
    ] {
        for resp in [RsmResponse::TeSum, RsmResponse::Mse] {
            let o = RsmOptions { centre_nm: Some(centre.clone()), half_range_nm: half.clone(), response: resp, ..RsmOptions::default() };
            let j = identify::all_joints(c);
            let id = identify_rsm(c, &j, &o, &q).unwrap();
            let r = id.rsm.as_ref().unwrap();
            println!("{centre:?} {half:?} {resp:?}: {:?} rms {:.4} R2 {:?}", id.joints.iter().map(|j| (j.coulomb_nm * 1e4).round() / 1e4).collect::<Vec<_>>(), id.rms_deg_after, r.responses.iter().map(|s| (s.r2 * 1e3).round() / 1e3).collect::<Vec<_>>());
        }
    }
}
