//! `deploywatch simulate`: one deployment of a mechanism, written as a run CSV.

use super::simulate_args::measure;
pub use super::simulate_args::SimulateArgs;
use super::{check_outputs, outln, CliError, Console, Output};
use crate::model::mechanism::Mechanism;
use crate::report::files::Outputs;
use crate::report::run_plot::{plot_rig_run, plot_run};
use crate::simulate::deployment::{self, SimOptions, Stall};
use crate::simulate::fault_injection;
use crate::simulate::latch_deployment::{self, LatchEnd, LatchOutcome, LatchRun};

/// A simulation's error as the CLI's: a grid too long for the run is the
/// user's `--rate` or `duration_s` (exit 2), the rest the work's (exit 1).
fn sim_error(e: deployment::SimError) -> CliError {
    match e {
        deployment::SimError::TooManySamples { .. } => CliError::input(e.to_string()),
        _ => CliError::failed(e.to_string()),
    }
}

/// Runs `deploywatch simulate`.
pub fn run(args: &SimulateArgs) -> Result<(), CliError> {
    let mech = Mechanism::load(&args.mechanism).map_err(|e| CliError::input(e.to_string()))?;
    // `--flight`: the rig taken out, only what flies.
    let mech = if args.flight { mech.flight() } else { mech };
    let (args, found) = super::simulate_from::with_found(args, &mech)?;
    // Flexible panels a diagnosis named: the wing as it compared it.
    let mech = super::simulate_from::with_flexible(mech, found.as_ref(), args.quiet)?;
    let args = &args;
    check_args(args, &mech)?;
    if let Some(at) = &args.at {
        return super::simulate_from::run_at(args, &mech, found.as_ref(), at);
    }
    for w in crate::model::plausibility::warnings(&mech, &args.mechanism) {
        Console::new(args.quiet).warn(w);
    }
    if mech.truss.is_some() {
        return super::simulate_truss::run(args, &mech);
    }
    let console = Console::new(args.quiet);
    let opts = SimOptions {
        sample_hz: args.rate,
        stop_when_deployed: args.faults.is_empty(),
        ..SimOptions::default()
    };
    let (physical, traj) = deploy(&mech, &args.effects, &opts).map_err(sim_error)?;
    let mut run = measure(args, &mech, &traj);
    let cut = cut_at_two_turns(&mut run);
    let reports = fault_injection::apply(&mut run, &args.faults, args.seed)
        .map_err(|m| CliError::input(format!("--fault: {m}")))?;
    let mut outs = Outputs::new();
    let csv = run
        .checked_csv(&args.out.display().to_string())
        .map_err(|e| CliError::input(e.to_string()))?;
    outs.write(&args.out, csv)?;
    outln!(
        "{}: {} samples at {} Hz to {} ({} steps, {} evaluations)",
        mech.name,
        run.len(),
        opts.sample_hz.unwrap_or(mech.sample_hz),
        args.out.display(),
        traj.stats.steps,
        traj.stats.evaluations
    );
    print_latch_instants(&traj, &latch_ends(&mech, &args.effects, physical.as_ref()));
    for line in crept(&mech, &args.effects, &opts, &traj)
        .into_iter()
        .chain(cut)
    {
        outln!("  {line}");
    }
    if let Some(run) = &physical {
        print_latches(&mech, &args.effects, run);
    }
    for r in &reports {
        outln!("  fault {r}");
    }
    let rig = mech
        .active_rig()
        .map(|_| super::simulate_rig::report(&mech, &args.effects, &opts))
        .transpose()?;
    if let (Some(png), Some(rig)) = (&args.plot, &rig) {
        plot_rig_run(&outs.path(png)?, &mech.name, &run, rig)
            .map_err(|e| CliError::failed(e.to_string()))?;
    } else if let Some(png) = &args.plot {
        plot_run(&outs.path(png)?, &mech.name, &run, &traj.latch_s)
            .map_err(|e| CliError::failed(e.to_string()))?;
    }
    outs.commit()?;
    if let Some(png) = &args.plot {
        console.say(format_args!("  plot: {}", png.display()));
    }
    Ok(())
}

/// The deployment of `mech` with `effects`: the physical latches' run
/// when it has any, and the trajectory.
fn deploy(
    mech: &Mechanism,
    effects: &[crate::model::effect::Effect],
    opts: &SimOptions,
) -> Result<(Option<LatchRun>, deployment::Trajectory), deployment::SimError> {
    if mech.has_physical_latch() {
        let grid = deployment::sample_grid(mech, opts)?;
        let run = latch_deployment::simulate_physical(mech, effects, opts, grid)?;
        let traj = run.traj.clone();
        return Ok((Some(run), traj));
    }
    Ok((None, deployment::simulate(mech, effects, opts)?))
}

/// Where the deployment again with a stalled joint stuck ([`Stall::Hold`],
/// as a verdict runs it: `docs/spec/physics.md` §4a, "Creep") ends
/// otherwise than `traj`: the joints `traj` latched only by creeping (the
/// held deployment leaves them short of their latch), and those both
/// latch at instants apart; one line each. The second run is made for an
/// ideal-latch chain (a few milliseconds), and for a physical-latch or rig
/// wing only when a joint crept before its latch; nothing when it fails.
fn crept(
    mech: &Mechanism,
    effects: &[crate::model::effect::Effect],
    opts: &SimOptions,
    traj: &deployment::Trajectory,
) -> Vec<String> {
    let cheap = !mech.has_physical_latch() && mech.active_rig().is_none();
    if !cheap && !slow_before_latching(mech, traj) {
        return Vec::new();
    }
    let hold = SimOptions {
        stall: Stall::Hold,
        ..*opts
    };
    let Ok((_, held)) = deploy(mech, effects, &hold) else {
        return Vec::new();
    };
    let apart: Vec<String> = (0..traj.latch_s.len())
        .filter_map(|j| {
            let (here, there) = (traj.latch_s[j]?, (*held.latch_s.get(j)?)?);
            ((here - there).abs() > crate::analysis::nominal_deployment::SAME_LATCH_S)
                .then(|| format!("joint {} at {there:.3} s", j + 1))
        })
        .collect();
    let apart = (!apart.is_empty()).then(|| {
        format!(
            "a verdict's deployment (reliability, margin), which holds a joint while it \
             stalls where this run's regularised Coulomb law lets it creep, latches {} \
             (docs/spec/physics.md §4a, \"Creep\")",
            apart.join(", ")
        )
    });
    let short = (0..traj.latch_s.len())
        .filter(|&j| traj.latch_s[j].is_some() && held.latch_s.get(j).is_some_and(Option::is_none))
        .map(|j| {
            let at = held
                .phi_deg
                .get(j)
                .and_then(|p| p.last())
                .copied()
                .unwrap_or(f64::NAN);
            format!(
                "joint {}: latched only by creeping: with its friction holding it, it stalls \
                 {at:.2} deg from its latch and does not latch (as reliability and margin run \
                 the deployment); the Coulomb law's regularisation lets it creep on \
                 (docs/spec/physics.md §4a, \"Creep\")",
                j + 1
            )
        });
    short.chain(apart).collect()
}

/// Whether a joint of `traj` that latched was, at a sample between its
/// first swing faster than the creep rule's rate and its latch, slower
/// than it (`creep::rest_rate`, from the mechanism's largest `ω_coul`):
/// only then can a verdict's deployment end otherwise.
fn slow_before_latching(mech: &Mechanism, traj: &deployment::Trajectory) -> bool {
    let omega = mech
        .joints
        .iter()
        .map(|j| j.friction.coulomb_threshold_rad_s.abs())
        .fold(deploywatch_core::physics::COULOMB_THRESHOLD_RAD_S, f64::max);
    let rest = (crate::simulate::creep::CREEP_RATE_FACTOR * omega).to_degrees();
    traj.latch_s.iter().enumerate().any(|(j, latch)| {
        let (Some(tl), Some(rates)) = (latch, traj.rate_deg_s.get(j)) else {
            return false;
        };
        let before = traj.t_s.iter().zip(rates).filter(|(t, _)| *t < tl);
        let mut moving = before.skip_while(|(_, r)| r.abs() <= rest);
        moving.any(|(_, r)| r.abs() < rest)
    })
}

/// A joint that turned more than two turns, past what a run file holds
/// (`docs/spec/formats.md`, angles within ±720 deg): the run is written up
/// to the sample before, and the summary says where it was cut. (A joint
/// with no spring, flung by its neighbours, spins: the model has no stop
/// on the stowed side, `docs/simulator.md`.)
fn cut_at_two_turns(run: &mut crate::data::run::Run) -> Option<String> {
    let (k, joint) = run.first_past_two_turns().filter(|&(k, _)| k > 0)?;
    let at = run.t_s[k];
    let angle = run.phi_deg[joint - 1][k];
    run.truncate(k);
    Some(format!(
        "two turns: joint {joint} is at {angle:.2} deg at {at:.6} s, past the ±{} deg a run file \
         holds: the run is written to {:.6} s, the sample before",
        crate::data::run::MAX_ANGLE_DEG,
        run.t_s[k - 1]
    ))
}

/// When each joint latched (its switch closed for good), or where it is
/// at the end when it did not, with what its physical latch (`ends`) does
/// where the two disagree; then each joint that swung back past its stowed angle (never silent:
/// `docs/simulator.md`, "The stowed side").
fn print_latch_instants(traj: &deployment::Trajectory, ends: &[Option<LatchEnd>]) {
    for (j, l) in traj.latch_s.iter().enumerate() {
        // A physical latch's switch and its hold can disagree at the end:
        // said, so that "latched" (the switch, as the run's `latch` column
        // and `--fail not_latched` read it) is not taken for "held" (as
        // `--fail not_held` and `margin`'s nominal line read it).
        let hold = match (l, ends.get(j).copied().flatten()) {
            (None, Some(e)) if e.holds() => {
                format!(": its switch open at the end, though its latch holds it ({e})")
            }
            (Some(_), Some(e)) if !e.holds() => {
                format!(", its switch closed, though its latch does not hold it at the end ({e})")
            }
            _ => String::new(),
        };
        match l {
            Some(t) => outln!("  joint {}: latched at {t:.6} s{hold}", j + 1),
            None => outln!(
                "  joint {}: NOT latched by {:.3} s (at {:.2} deg){hold}",
                j + 1,
                traj.end_s,
                traj.phi_deg[j].last().copied().unwrap_or(f64::NAN)
            ),
        }
    }
    for p in &traj.past_stowed {
        outln!("  stowed side: {p}");
    }
}

/// What the physical latch of joint `joint` (1-based) did, in the words of
/// its kind: a ball plunger's engagements and escapes over its crest, a
/// pawl's drop into its notch (or its break).
fn latch_line(joint: usize, o: &LatchOutcome) -> String {
    let end = format!(
        "ends {} at {:.4} deg from the stop",
        o.end, o.end_travel_deg
    );
    match o.end {
        LatchEnd::Plunger(_) => format!(
            "joint {joint} ball plunger: {} impacts, {} engagements over the crest, {} escapes, \
             switch closed {} times; {end}",
            o.impacts, o.engagements, o.escapes, o.switch_closings
        ),
        LatchEnd::Pawl(_) => {
            let broke = o
                .pawl_broke_s
                .map(|t| format!(" (it BROKE at {t:.6} s)"))
                .unwrap_or_default();
            // The latch instant above is the switch's last closing; a
            // pawl locks its joint at the drop, which can be seconds
            // before where the switch chatters in the notch.
            let dropped = o
                .pawl_dropped_s
                .map(|t| format!(" (locked from {t:.6} s)"))
                .unwrap_or_default();
            format!(
                "joint {joint} pawl: {} impacts, dropped into its notch {} time(s){dropped}, \
                 switch closed {} times; {end}{broke}",
                o.impacts, o.pawl_drops, o.switch_closings
            )
        }
    }
}

/// Where each joint's physical latch ended in `run` (`None`: an ideal
/// latch; empty without a run of a physical latch).
fn latch_ends(
    mech: &Mechanism,
    effects: &[crate::model::effect::Effect],
    run: Option<&LatchRun>,
) -> Vec<Option<LatchEnd>> {
    let Some(run) = run else {
        return Vec::new();
    };
    let w = latch_deployment::weakenings(effects, mech.joint_count());
    (0..mech.joint_count())
        .map(|j| {
            let spec = mech.latches.get(j)?.as_ref()?;
            let joint = mech.joints.get(j)?;
            let (p, m) = w.get(j).copied().unwrap_or((1.0, 1.0));
            run.outcome(j + 1, &spec.to_core(joint.stowed_deg, p, m))
                .map(|o| o.end)
        })
        .collect()
}

/// What each physical latch did, and the run's energy ledger.
fn print_latches(mech: &Mechanism, effects: &[crate::model::effect::Effect], run: &LatchRun) {
    let w = latch_deployment::weakenings(effects, mech.joint_count());
    for (j, spec) in mech.latches.iter().enumerate() {
        let (Some(spec), Some(joint)) = (spec, mech.joints.get(j)) else {
            continue;
        };
        let (p, m) = w.get(j).copied().unwrap_or((1.0, 1.0));
        let latch = spec.to_core(joint.stowed_deg, p, m);
        if let Some(o) = run.outcome(j + 1, &latch) {
            outln!("  {}", latch_line(j + 1, &o));
        }
    }
    let e = &run.energy;
    outln!(
        "  energy [J]: stored {:.6}; at the end kinetic {:.6}, springs {:.6}, latches {:.6}; \
         dissipated by friction/hysteresis {:.6}, by the stops {:.6}, by ideal impacts and pawls {:.6}; \
         worst drift {:.3e} ({:.2e} of stored)",
        e.stored_j,
        e.kinetic_j,
        e.spring_j,
        e.latch_j,
        e.friction_j,
        e.contact_j,
        e.impact_j,
        e.worst_drift_j,
        e.worst_drift_j / e.stored_j.abs().max(f64::MIN_POSITIVE)
    );
}

/// Checks the arguments against the mechanism, and that the outputs can be
/// written, before anything is simulated.
fn check_args(args: &SimulateArgs, mech: &Mechanism) -> Result<(), CliError> {
    for e in &args.effects {
        e.validate(mech.effect_joints())
            .map_err(|m| CliError::input(format!("--effect {e}: {m}")))?;
    }
    latch_deployment::check_latch_effects(mech, &args.effects)
        .map_err(|m| CliError::input(format!("--effect {m}")))?;
    for f in &args.faults {
        f.validate(mech.joint_count())
            .map_err(|m| CliError::input(format!("--fault {f}: {m}")))?;
    }
    if let Some(r) = args.rate {
        if !(r > 0.0 && r.is_finite()) {
            return Err(CliError::input(format!(
                "--rate {r}: expected a positive sample rate in Hz"
            )));
        }
    }
    let inputs: Vec<&std::path::Path> = std::iter::once(&args.mechanism)
        .chain(&args.from)
        .chain(&args.at)
        .map(|p| p.as_path())
        .collect();
    let mut outputs = vec![Output::file("--out", &args.out)];
    outputs.extend(args.plot.as_deref().map(|p| Output::plot("--plot", p)));
    check_outputs(&outputs, &inputs)
}
