//! Why the random wings swing a joint back past its stowed angle
//! (`docs/simulator.md`, "The stowed side"): wings of seeds 0 to
//! `DEPLOYWATCH_WINGS − 1` (default 2000; rigs with a physical latch,
//! refused, left out) simulated with their drawn effects, and per joint the
//! run reports past its stowed angle: root or inner; kicked back by a
//! neighbour's ideal-latch impulse (its outward rate not positive at the
//! sample before the latch, positive at the one after, and its passage
//! before any other latch) or pushed back by the others' swing; its
//! spring's torque at the stowed angle weaker than some outboard joint's;
//! how far. Also the bundled mechanisms of `data/mechanisms` (chains) as
//! they are. Prints the table; records its section `stowed-census` of
//! `docs/measured.md` with `DEPLOYWATCH_FULL=1`:
//!
//! ```text
//! DEPLOYWATCH_FULL=1 cargo run --release -p deploywatch-tests --example stowed_census
//! ```

use deploywatch_core::Branch;
use deploywatch_sim::deployment::{self, SimOptions, Trajectory};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_tests::wing_gen::{wing_toml, PHYSICAL_SHARE};

fn main() {
    let n = std::env::var("DEPLOYWATCH_WINGS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(2000u64);
    let mut c = Census::default();
    for seed in 0..n {
        let w = wing_toml(seed, PHYSICAL_SHARE);
        if w.rig && !w.physical.is_empty() {
            continue;
        }
        let mech = Mechanism::from_toml_str(&w.toml, "random.toml").expect("wing");
        let traj = deployment::simulate(&mech, &w.effects, &SimOptions::default())
            .unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        c.wing(&mech, &traj);
    }
    c.seeds = n;
    let mut bundled = Vec::new();
    let dir = deploywatch_tests::data_dir().join("mechanisms");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("data/mechanisms")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    files.sort();
    for path in files {
        let mech = Mechanism::load(&path).expect("bundled mechanism");
        if mech.truss.is_some() {
            continue;
        }
        let traj = deployment::simulate(&mech, &[], &SimOptions::default()).expect("bundled run");
        let name = path.file_name().map(|f| f.to_string_lossy().into_owned());
        let said: Vec<String> = traj
            .past_stowed
            .iter()
            .map(|p| format!("joint {} {:.2}° past", p.joint, p.past_deg()))
            .collect();
        if !said.is_empty() {
            bundled.push(format!(
                "`{}`: {}",
                name.unwrap_or_default(),
                said.join(", ")
            ));
        }
    }
    let body = c.body(&bundled);
    println!("{body}");
    deploywatch_tests::record::record(
        "stowed-census",
        "DEPLOYWATCH_FULL=1 cargo run --release -p deploywatch-tests --example stowed_census",
        &body,
    )
    .expect("docs/measured.md written");
}

/// The counts of the census.
#[derive(Default)]
struct Census {
    seeds: u64,
    wings: usize,
    wings_past: usize,
    joints: usize,
    joints_weaker: usize,
    past: usize,
    root: usize,
    kicked: usize,
    weaker: usize,
    physical: usize,
    over: [usize; 3],
}

/// Degrees past the stowed angle counted in [`Census::over`].
const CENSUS_OVER_DEG: [f64; 3] = [1.0, 10.0, 180.0];

impl Census {
    fn wing(&mut self, mech: &Mechanism, traj: &Trajectory) {
        self.wings += 1;
        self.wings_past += usize::from(!traj.past_stowed.is_empty());
        let at_stowed: Vec<f64> = mech
            .joints
            .iter()
            .map(|j| {
                j.spring.to_spring::<f64>().map_or(0.0, |s| {
                    s.magnitude(j.stowed_deg.to_radians().abs(), Branch::Unfold)
                })
            })
            .collect();
        let weaker = |j: usize| at_stowed[j + 1..].iter().any(|&t| t > at_stowed[j]);
        self.joints += mech.joints.len();
        self.joints_weaker += (0..mech.joints.len()).filter(|&j| weaker(j)).count();
        for p in &traj.past_stowed {
            let j = p.joint - 1;
            self.past += 1;
            self.root += usize::from(j == 0);
            self.weaker += usize::from(weaker(j));
            self.physical += usize::from(mech.latches[j].is_some());
            self.kicked += usize::from(kicked(mech, traj, j, p.first_s));
            for (o, &deg) in self.over.iter_mut().zip(&CENSUS_OVER_DEG) {
                *o += usize::from(p.past_deg() > deg);
            }
        }
    }

    fn body(&self, bundled: &[String]) -> String {
        let share =
            |k: usize, of: usize| format!("{k} ({:.0} %)", 100.0 * k as f64 / of.max(1) as f64);
        let over: Vec<String> = self
            .over
            .iter()
            .zip(&CENSUS_OVER_DEG)
            .map(|(&k, d)| format!("more than {d}°: {}", share(k, self.past)))
            .collect();
        format!(
            "## Simulator: random wings past their stowed angle\n\n\
             The random wings of seeds 0 to {} (`tests/src/wing_gen.rs`; rigs with a physical \
             latch, refused, left out) and the joints each run reports past its stowed angle \
             by more than `STOWED_TOLERANCE_DEG` (`docs/simulator.md`, \"The stowed side\").\n\n\
             | quantity | measured |\n|---|---|\n\
             | wings simulated | {} |\n\
             | with a joint reported past its stowed angle | {} |\n\
             | joints reported | {} |\n\
             | of them the root (joint 1) | {} |\n\
             | kicked back by a neighbour's ideal-latch impulse | {} |\n\
             | pushed back by the others' swing | {} |\n\
             | with a spring weaker at its stowed angle than an outboard joint's | {} (of all joints drawn: {}) |\n\
             | with a physical latch | {} |\n\
             | how far | {} |\n\
             | bundled mechanisms (`data/mechanisms`, no effect) | {} |\n",
            self.seeds.max(1) - 1,
            self.wings,
            share(self.wings_past, self.wings),
            self.past,
            share(self.root, self.past),
            share(self.kicked, self.past),
            share(self.past - self.kicked, self.past),
            share(self.weaker, self.past),
            share(self.joints_weaker, self.joints),
            share(self.physical, self.past),
            over.join("; "),
            if bundled.is_empty() { "none".to_string() } else { bundled.join("; ") },
        )
    }
}

/// Whether joint `j`, first past its stowed angle at `first_s`, was kicked
/// back by another joint's ideal-latch impulse: the last latch of another
/// joint before `first_s`, with joint `j`'s outward rate not positive at
/// the sample before it and positive at the sample after.
fn kicked(mech: &Mechanism, traj: &Trajectory, j: usize, first_s: f64) -> bool {
    let side = mech.joints[j].stowed_deg.signum();
    let Some(tl) = traj
        .latch_s
        .iter()
        .enumerate()
        .filter(|&(k, _)| k != j && mech.latches[k].is_none())
        .filter_map(|(_, l)| *l)
        .filter(|&t| t <= first_s)
        .fold(None, |a: Option<f64>, t| Some(a.map_or(t, |a| a.max(t))))
    else {
        return false;
    };
    let Some(after) = traj.t_s.iter().position(|&t| t > tl) else {
        return false;
    };
    let outward = |i: usize| side * traj.rate_deg_s[j][i];
    after > 0 && outward(after - 1) <= 0.0 && outward(after) > 0.0
}
