//! `deploywatch simulate` of a mechanism with a `[truss]`: the multibody
//! simulator ([`crate::simulate::multibody`]) through the deployment
//! dispatch ([`crate::simulate::truss_deployment`]), with `--effect`s on its
//! pins.
//!
//! Writes one run CSV (`--out`): the hinge angles and latch switches as in
//! every run, then the documented extra columns `psi_deg`, every knee's
//! interior angle `knee<P>_deg` and its switch `knee<P>`
//! (`docs/spec/formats.md`, "Run: extra columns"). Prints the Gruebler count
//! with multi-link joints and the mobility from the constraint Jacobian's
//! rank after each lock.

use super::simulate_args::{measure, SimulateArgs};
use super::{outln, CliError};
use crate::data::run::{ExtraColumn, ExtraKind, Run};
use crate::model::kinematics::{planar_mobility, truss_bodies_and_joints};
use crate::model::mechanism::Mechanism;
use crate::simulate::deployment::{Samples, SimOptions};
use crate::simulate::multibody::{wing_model, wing_options, WingRun};
use crate::simulate::truss_deployment::simulate_truss;

/// Runs `deploywatch simulate` on a truss mechanism.
pub fn run(args: &SimulateArgs, mech: &Mechanism) -> Result<(), CliError> {
    let file = args.mechanism.display();
    if !args.faults.is_empty() || args.plot.is_some() {
        return Err(CliError::input(format!(
            "{file}: --fault and --plot are not supported for a mechanism with a [truss] yet; expected neither"
        )));
    }
    if let Some(e) = args
        .effects
        .iter()
        .find(|e| !crate::simulate::truss_deployment::models(e.kind()))
    {
        return Err(CliError::input(format!(
            "--effect {e}: {} is not modelled on a wing with a truss; expected coulomb_friction, viscous_damping, spring_softening or encoder_offset",
            e.kind()
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
    let opts = SimOptions {
        sample_hz: args.rate,
        ..wing_options()
    };
    let rate = args.rate.unwrap_or(mech.sample_hz);
    let times = Samples::grid(mech.duration_s, rate);
    let (traj, wing) = simulate_truss(mech, &args.effects, &opts, times)
        .map_err(|e| CliError::failed(e.to_string()))?;
    let mut out = measure(args, mech, &traj);
    out.set_meta("source", "deploywatch simulate (multibody, truss)");
    add_extra(&mut out, &wing);
    let mut outs = crate::report::files::Outputs::new();
    let csv = out
        .checked_csv(&args.out.display().to_string())
        .map_err(|e| CliError::input(e.to_string()))?;
    outs.write(&args.out, csv)?;
    outs.commit()?;
    report(mech, &wing, (bodies, joints, gruebler), args);
    Ok(())
}

/// The truss's extra columns: `psi_deg` (link 3 against its carrier at C,
/// `truss-link.md`), then `knee<P>_deg` and `knee<P>` of every knee, in the
/// points' file order (true values: the sensor model reads the hinges only).
pub fn add_extra(run: &mut Run, wing: &WingRun) {
    let n = run.len();
    let knees: Vec<usize> = (0..wing.pins.len())
        .filter(|&p| !wing.pins[p].contains(':') && !wing.pins[p].starts_with("hinge"))
        .collect();
    let column = |name: String, kind, values: Vec<f64>| ExtraColumn {
        name,
        kind,
        values: values.into_iter().take(n).collect(),
    };
    if let Some(p) = wing.pins.iter().position(|n| n.ends_with(":3")) {
        let values = wing.run.angle_deg[p].clone();
        run.extra
            .push(column("psi_deg".into(), ExtraKind::Psi, values));
    }
    for &p in &knees {
        let values = wing.run.angle_deg[p].clone();
        let name = format!("knee{}_deg", wing.pins[p]);
        run.extra.push(column(name, ExtraKind::KneeAngle, values));
    }
    for &p in &knees {
        let values = wing.run.locked[p]
            .iter()
            .map(|&l| f64::from(u8::from(l)))
            .collect();
        let name = format!("knee{}", wing.pins[p]);
        run.extra.push(column(name, ExtraKind::KneeSwitch, values));
    }
}

/// Prints the locks and the mobility (the summary and the locks even with
/// `--quiet`, as the chain's `simulate` does).
fn report(mech: &Mechanism, wing: &WingRun, count: (u32, u32, i64), args: &SimulateArgs) {
    let (bodies, joints, gruebler) = count;
    outln!(
        "{}: {} samples to {} ({} steps, {} evaluations)",
        mech.name,
        wing.run.t_s.len(),
        args.out.display(),
        wing.run.stats.steps,
        wing.run.stats.evaluations
    );
    let jacobian = wing.run.mobility.first().copied().unwrap_or(0);
    outln!(
        "  mobility: Gruebler 3({bodies} - 1) - 2·{joints} = {gruebler}; constraint Jacobian n - rank = {jacobian} ({})",
        if jacobian as i64 == gruebler { "agree" } else { "DIFFER: redundant constraints" }
    );
    let seq: Vec<String> = wing.run.mobility.iter().map(|m| m.to_string()).collect();
    outln!("  mobility as the locks close: {}", seq.join(" -> "));
    for (p, name) in wing.pins.iter().enumerate() {
        if let Some(t) = wing.run.lock_s[p] {
            outln!("  {name}: locked at {t:.6} s");
        } else if wing.series(name).is_some() && !name.contains(':') {
            outln!("  {name}: NOT locked by {:.3} s", wing.run.end_s);
        }
    }
}
