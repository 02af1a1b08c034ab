//! The direct method: the EFTs fitted to the runs through the simulator by
//! Levenberg–Marquardt on the free joints, with an active set for the
//! bound at 0 and 95 % intervals from the Jacobian.

use super::*;

/// Identifies the EFT of `joints` (1-based) by least squares over every run
/// of `campaign` at once (the direct method, see the module docs).
///
/// The parameters are the Coulomb EFT `T_C` [N·m] of each joint
/// (`physics.md` 4), common to all runs, with the bound `T_C ≥ 0` enforced
/// by an active set: the solver works unbounded (a negative `T_C` is
/// simulated as it is, a driving torque), and a joint that ends below 0 is
/// fixed at 0 and the others refitted, until none is negative. (The
/// projection of the bounds inside [`crate::analysis::fit::least_squares`] can stall a
/// parameter at its bound, so it is not used here.) The start is
/// `opts.start_nm`, or the per-joint best of the start scan ([`super::SCAN_GRID_NM`]),
/// or the scan's best uniform value where the per-joint one fits worse. The
/// 95 % intervals come from the Jacobian at the solution ([`crate::analysis::fit`]);
/// a joint fixed at 0 gets `[0, upper end of its interval when last free]`.
pub fn identify_direct(
    campaign: &Campaign,
    joints: &[usize],
    opts: &DirectOptions,
    progress: Progress,
) -> Result<Identification, IdentifyError> {
    let t0 = Instant::now();
    check_joints(campaign, joints)?;
    let model = Model::new(campaign, joints);
    let before = score_as_given(&model, progress)?;
    let (start, start_rule) = direct_start(&model, opts, progress)?;
    let fit = active_set_fit(&model, &start, opts, progress)?;
    let (fit, start, start_rule) =
        restarted_if_short(&model, fit, (start, start_rule), opts, progress)?;
    let p = &fit.params;
    let (after, _) = model
        .score(p)
        .ok_or_else(|| IdentifyError::Simulation(format!("at the solution {} N·m", list(p))))?;
    let scored = Identification::scored(Method::Direct, &model, t0, before, after);
    Ok(Identification {
        joints: joints
            .iter()
            .enumerate()
            .map(|(i, &j)| JointEft {
                joint: j,
                coulomb_nm: p[i],
                ci95: Some(if fit.free[i] {
                    fit.ci[i]
                } else {
                    // At the bound: from 0 up to the last free fit's upper
                    // end, or its half-width `t·sd` where that end is below
                    // 0 (the precision the runs give it, not none).
                    let [lo, hi] = fit.ci[i];
                    [0.0, hi.max(0.5 * (hi - lo)).max(0.0)]
                }),
                sd_nm: Some(fit.sd[i]),
            })
            .collect(),
        direct: Some(DirectDetails {
            start_nm: start,
            start_rule,
            sse_deg2: fit.sse,
            residuals: fit.residuals,
            termination: fit.termination,
            fixed_at_zero: joints
                .iter()
                .zip(&fit.free)
                .filter(|(_, f)| !**f)
                .map(|(j, _)| *j)
                .collect(),
            clearly_below_zero: joints
                .iter()
                .enumerate()
                .filter(|&(i, _)| !fit.free[i] && fit.ci[i][1] < 0.0)
                .map(|(_, j)| *j)
                .collect(),
        }),
        ..scored
    })
}

/// The start of the direct method and how it was chosen: the given one,
/// the per-joint best of the start scan, or the scan's best uniform value
/// where the per-joint best fits the runs worse.
fn direct_start(
    model: &Model,
    opts: &DirectOptions,
    progress: Progress,
) -> Result<(Vec<f64>, String), IdentifyError> {
    match &opts.start_nm {
        Some(s) => {
            check_vector("start", s, model.joints.len(), true)?;
            Ok((s.clone(), "given".to_string()))
        }
        None => {
            let sc = scan_with(model, progress)?;
            let top = SCAN_GRID_NM[SCAN_GRID_NM.len() - 1];
            // Each joint's best value of the scan was found with the
            // others at the same value; together they can fit worse than
            // the best uniform value (joints that drag one another).
            let per_joint_rms = model.score(&sc.per_joint_best_nm).map(|(s, _)| s.rms_deg);
            match per_joint_rms {
                Some(rms) if rms <= sc.uniform_best_rms_deg => Ok((
                    sc.per_joint_best_nm,
                    format!("per-joint best of a scan of uniform EFTs from 0 to {top} N·m"),
                )),
                _ => {
                    progress(&format!(
                        "direct: the per-joint best fits worse ({}) than the best uniform EFT \
                         ({:.4} deg): starting from the uniform one",
                        per_joint_rms
                            .map_or("not evaluable".to_string(), |r| format!("RMS {r:.4} deg")),
                        sc.uniform_best_rms_deg
                    ));
                    Ok((
                        vec![sc.uniform_best_nm; model.joints.len()],
                        format!(
                            "best uniform EFT of a scan from 0 to {top} N·m (the per-joint \
                             bests together fitted worse)"
                        ),
                    ))
                }
            }
        }
    }
}

/// The factors the start of a direct fit is scaled by for its restarts,
/// where the fit from it leaves more than
/// [`super::residual_check::RESIDUAL_WARN_FACTOR`] times the runs' noise:
/// two steps of the start scan's grid up and down (×2, ×½). Levenberg–
/// Marquardt on finite differences of simulated runs can stop where a
/// latch instant jumps by a sample, short of the optimum (a subset of
/// joints started at 0.4 N·m stopped at 0.466 with 0.89° RMS where 0.5
/// fits to the noise).
const RESTART_SCALES: [f64; 2] = [2.0, 0.5];

/// `fit` (from `start`), or, where it leaves more than
/// [`super::residual_check::RESIDUAL_WARN_FACTOR`] times the runs' noise
/// RMS, the best of it and the fits from the start scaled by each of
/// [`RESTART_SCALES`] (smallest sum of squares), with its start and the
/// rule that gave it.
fn restarted_if_short(
    model: &Model,
    fit: ActiveSetFit,
    (start, rule): (Vec<f64>, String),
    opts: &DirectOptions,
    progress: Progress,
) -> Result<(ActiveSetFit, Vec<f64>, String), IdentifyError> {
    let rms = |f: &ActiveSetFit| (f.sse / f.residuals.max(1) as f64).sqrt();
    let noise = crate::analysis::evidence::noise_sigma_estimate(model.campaign);
    let short = noise.is_some_and(|n| rms(&fit) > super::residual_check::RESIDUAL_WARN_FACTOR * n);
    if !short || opts.start_nm.is_some() {
        return Ok((fit, start, rule));
    }
    let origin = (start.clone(), rule.clone());
    let mut best = (fit, start, rule);
    for scale in RESTART_SCALES {
        let from: Vec<f64> = origin.0.iter().map(|v| v * scale).collect();
        if from.iter().all(|v| *v == 0.0) {
            continue;
        }
        progress(&format!(
            "direct: RMS {:.4} deg, over {} times the noise: restarting from {} N·m",
            rms(&best.0),
            super::residual_check::RESIDUAL_WARN_FACTOR,
            list(&from)
        ));
        let again = active_set_fit(model, &from, opts, progress)?;
        if again.sse < best.0.sse {
            let rule = format!(
                "{} × {scale} (the fit from it left over {} times the noise; this one fits \
                 better)",
                origin.1,
                super::residual_check::RESIDUAL_WARN_FACTOR
            );
            best = (again, from, rule);
        }
    }
    Ok(best)
}

/// The outcome of the bounded least squares of the direct method.
struct ActiveSetFit {
    /// The EFT of every identified joint [N·m] (0 where fixed).
    params: Vec<f64>,
    /// False where the joint was fixed at the bound 0.
    free: Vec<bool>,
    /// 95 % intervals [N·m] (of the last fit where the joint was free).
    ci: Vec<[f64; 2]>,
    /// Standard deviations [N·m].
    sd: Vec<f64>,
    /// Sum of squared residuals \[deg²\].
    sse: f64,
    /// Number of residuals.
    residuals: usize,
    /// The solver's verdict, in words.
    termination: String,
}

/// Least squares with `T_C ≥ 0` by an active set: fit the free joints
/// unbounded; fix any that ends below 0 at 0 and refit the others, until
/// none is negative.
fn active_set_fit(
    model: &Model,
    start: &[f64],
    opts: &DirectOptions,
    progress: Progress,
) -> Result<ActiveSetFit, IdentifyError> {
    let k = model.joints.len();
    let mut out = ActiveSetFit {
        params: start.to_vec(),
        free: vec![true; k],
        ci: vec![[f64::NEG_INFINITY, f64::INFINITY]; k],
        sd: vec![f64::INFINITY; k],
        sse: 0.0,
        residuals: 0,
        termination: String::new(),
    };
    let best = Mutex::new(f64::INFINITY);
    loop {
        let idx: Vec<usize> = (0..k).filter(|&i| out.free[i]).collect();
        if idx.is_empty() {
            let r = model
                .residuals(&out.params)
                .ok_or_else(|| IdentifyError::Simulation("with every EFT at 0".into()))?;
            out.sse = r.iter().map(|x| x * x).sum::<f64>();
            out.residuals = r.len();
            out.termination = "every EFT at 0".to_string();
            return Ok(out);
        }
        let fit = fit_free_joints(model, &out.params, &idx, opts, &best, progress)?;
        for (r, &i) in idx.iter().enumerate() {
            out.params[i] = fit.params[r];
            out.ci[i] = fit.ci95[r];
            out.sd[i] = fit.sd[r];
        }
        let negative: Vec<usize> = idx
            .iter()
            .copied()
            .filter(|&i| out.params[i] < 0.0)
            .collect();
        if negative.is_empty() {
            out.sse = fit.sse;
            out.residuals = fit.residuals;
            out.termination = fit.termination;
            return Ok(out);
        }
        for i in negative {
            progress(&format!(
                "direct: joint {} ends at {:.5} N·m < 0: fixed at 0, refitting the others",
                model.joints[i], out.params[i]
            ));
            out.free[i] = false;
            out.params[i] = 0.0;
        }
    }
}

/// One Levenberg–Marquardt fit of the joints `idx` (indices into the
/// identified joints), the others held at `p`; reports each better RMS
/// (`best` \[deg\], shared by the rounds) as progress.
fn fit_free_joints(
    model: &Model,
    p: &[f64],
    idx: &[usize],
    opts: &DirectOptions,
    best: &Mutex<f64>,
    progress: Progress,
) -> Result<fit::FitResult, IdentifyError> {
    let full = |q: &[f64]| -> Vec<f64> {
        let mut x = p.to_vec();
        for (&i, &v) in idx.iter().zip(q) {
            x[i] = v;
        }
        x
    };
    let q0: Vec<f64> = idx.iter().map(|&i| p[i]).collect();
    progress(&format!(
        "direct: Levenberg–Marquardt over joints {} from {} N·m",
        list(&idx.iter().map(|&i| model.joints[i]).collect::<Vec<_>>()),
        list(&q0)
    ));
    let f = |q: &[f64]| -> Option<Vec<f64>> {
        let x = full(q);
        let r = model.residuals(&x)?;
        let rms = (r.iter().map(|v| v * v).sum::<f64>() / r.len().max(1) as f64).sqrt();
        if let Ok(mut b) = best.lock() {
            if rms < *b {
                *b = rms;
                let ps: Vec<String> = x.iter().map(|v| format!("{v:.5}")).collect();
                progress(&format!(
                    "direct: {} simulations, best RMS {rms:.5} deg at {} N·m",
                    model.count(),
                    ps.join(", ")
                ));
            }
        }
        Some(r)
    };
    let m = idx.len();
    let mut fo = FitOptions::new(vec![f64::NEG_INFINITY; m], vec![opts.min_step_nm; m]);
    fo.upper = vec![opts.upper_nm; m];
    fo.patience = opts.patience;
    Ok(fit::least_squares(&f, &q0, &fo)?)
}
