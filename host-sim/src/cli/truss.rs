//! `deploywatch simulate` of a mechanism with a `[truss]`: the multibody
//! simulator ([`crate::simulate::multibody`]).
//!
//! Writes the two hinge angles and their latch switches as a normal run CSV
//! (`--out`), and beside it `<out stem>_truss.csv` with `t_s`, `psi_deg`
//! and every knee's interior angle and switch (`knee<P>_deg`, `knee<P>`;
//! `docs/spec/formats.md`, "Truss run: extra columns"). Prints the Gruebler
//! count with multi-link joints and the mobility from the constraint
//! Jacobian's rank after each lock.

use super::simulate::SimulateArgs;
use super::CliError;
use crate::data::run::Run;
use crate::model::kinematics::{planar_mobility, truss_bodies_and_joints};
use crate::model::mechanism::Mechanism;
use crate::simulate::deployment::{SimOptions, Trajectory};
use crate::simulate::multibody::{simulate_wing, wing_model, wing_options, WingRun};
use crate::simulate::sensor::{self, SensorModel};
use std::fmt::Write as _;
use std::path::Path;

/// Runs `deploywatch simulate` on a truss mechanism.
pub fn run(args: &SimulateArgs, mech: &Mechanism) -> Result<(), CliError> {
    let file = args.mechanism.display();
    if !args.effects.is_empty() || !args.faults.is_empty() || args.plot.is_some() {
        return Err(CliError::input(format!(
            "{file}: --effect, --fault and --plot are not supported for a mechanism with a [truss] yet; expected none of them"
        )));
    }
    let truss = mech
        .truss
        .as_ref()
        .ok_or_else(|| CliError::input("no truss"))?;
    let model = wing_model(mech).map_err(|e| CliError::input(format!("{file}: {e}")))?;
    let q0 = vec![0.0; model.n()];
    let free = model.mobility(&q0, &vec![false; model.sys.pins.len()]);
    let (bodies, joints) = truss_bodies_and_joints(truss, mech.panels.len());
    let gruebler = planar_mobility(bodies, joints, 0);
    if free == 0 {
        return Err(CliError::input(format!(
            "{file}: `truss`: the wing is locked up at the stowed pose (0 degrees of freedom by the constraint Jacobian, Gruebler {gruebler}); expected a truss that lets the panels move"
        )));
    }
    let side = args.out.with_file_name(format!(
        "{}_truss.csv",
        args.out.file_stem().unwrap_or_default().to_string_lossy()
    ));
    super::check_output("--out (truss columns)", &side)?;
    let opts = SimOptions {
        sample_hz: args.rate,
        ..wing_options()
    };
    let wing = simulate_wing(mech, &opts).map_err(|e| CliError::failed(e.to_string()))?;
    let sensor_model = if args.no_noise {
        SensorModel::IDEAL
    } else {
        SensorModel::REFERENCE
    };
    let mut out = sensor::measure(
        &hinges(&wing, mech.joints.len()),
        &[],
        &sensor_model,
        args.seed,
    );
    out.set_meta("mechanism", &mech.name);
    out.set_meta("source", "deploywatch simulate (multibody, truss)");
    out.set_meta("effects", "none");
    out.write(&args.out)
        .map_err(|e| CliError::input(e.to_string()))?;
    write_extra(&side, &wing, &out)?;
    if !args.quiet {
        report(mech, &wing, (bodies, joints, gruebler), &side);
    }
    Ok(())
}

/// The hinge series as a chain trajectory (the sensor model's input).
fn hinges(wing: &WingRun, n: usize) -> Trajectory {
    let mut t = Trajectory {
        t_s: wing.run.t_s.clone(),
        end_s: wing.run.end_s,
        stats: wing.run.stats,
        ..Trajectory::default()
    };
    for j in 0..n {
        let name = format!("hinge {}", j + 1);
        let (a, l) = wing.series(&name).unwrap_or((&[], &[]));
        t.phi_deg.push(a.to_vec());
        t.rate_deg_s.push(vec![0.0; a.len()]);
        t.latched.push(l.to_vec());
        t.latch_s.push(wing.lock_s(&name));
    }
    t
}

/// The knee and ψ columns (`<stem>_truss.csv`).
fn write_extra(path: &Path, wing: &WingRun, run: &Run) -> Result<(), CliError> {
    let knees: Vec<usize> = (0..wing.pins.len())
        .filter(|&p| !wing.pins[p].contains(':') && !wing.pins[p].starts_with("hinge"))
        .collect();
    let psi = wing.pins.iter().position(|n| n.ends_with(":3"));
    let mut text = String::new();
    for (k, v) in &run.metadata {
        let _ = writeln!(text, "# {k} = {v:?}");
    }
    text.push_str("t_s");
    if psi.is_some() {
        text.push_str(",psi_deg");
    }
    for &p in &knees {
        let _ = write!(text, ",knee{}_deg", wing.pins[p]);
    }
    for &p in &knees {
        let _ = write!(text, ",knee{}", wing.pins[p]);
    }
    text.push('\n');
    for (i, t) in wing.run.t_s.iter().enumerate() {
        let _ = write!(text, "{t:.6}");
        if let Some(p) = psi {
            let _ = write!(text, ",{:.6}", wing.run.angle_deg[p][i]);
        }
        for &p in &knees {
            let _ = write!(text, ",{:.6}", wing.run.angle_deg[p][i]);
        }
        for &p in &knees {
            let _ = write!(text, ",{}", u8::from(wing.run.locked[p][i]));
        }
        text.push('\n');
    }
    std::fs::write(path, text)
        .map_err(|e| CliError::input(format!("{}: cannot write: {e}", path.display())))
}

/// Prints the locks and the mobility.
fn report(mech: &Mechanism, wing: &WingRun, count: (u32, u32, i64), side: &Path) {
    let (bodies, joints, gruebler) = count;
    println!(
        "{}: {} samples to the run and {} ({} steps, {} evaluations)",
        mech.name,
        wing.run.t_s.len(),
        side.display(),
        wing.run.stats.steps,
        wing.run.stats.evaluations
    );
    let jacobian = wing.run.mobility.first().copied().unwrap_or(0);
    println!(
        "  mobility: Gruebler 3({bodies} - 1) - 2·{joints} = {gruebler}; constraint Jacobian n - rank = {jacobian} ({})",
        if jacobian as i64 == gruebler { "agree" } else { "DIFFER: redundant constraints" }
    );
    let seq: Vec<String> = wing.run.mobility.iter().map(|m| m.to_string()).collect();
    println!("  mobility as the locks close: {}", seq.join(" -> "));
    for (p, name) in wing.pins.iter().enumerate() {
        if let Some(t) = wing.run.lock_s[p] {
            println!("  {name}: locked at {t:.6} s");
        } else if wing.series(name).is_some() && !name.contains(':') {
            println!("  {name}: NOT locked by {:.3} s", wing.run.end_s);
        }
    }
}
