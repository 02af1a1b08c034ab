//! The papers' method: a response surface over a central composite design
//! (seed 000 §4, Table 9), fitted and minimised, in one or more rounds
//! (sequential response surface, each round re-centred with half the
//! half-ranges).

use super::*;
use crate::report::text::list_4;

/// The response of a scored design point.
fn responses(score: &CampaignScore, mse: f64, joints: &[usize]) -> Vec<f64> {
    let mut v: Vec<f64> = joints
        .iter()
        .map(|&j| score.mean_te_pct(j).unwrap_or(f64::NAN))
        .collect();
    v.push(mse);
    v
}

/// Identifies the EFT of `joints` (1-based) by the response-surface method
/// of seed 000 (section 4.3): a CCD ([`crate::analysis::identify::rsm::Ccd`]) around
/// `opts.centre_nm` with `opts.half_range_nm`, each design point simulated on
/// every run (design points in parallel), a full quadratic (Eq. 15) fitted
/// to each response (trajectory error of each joint, Eq. 14, mean over the
/// runs; and the mean squared residual), and the chosen response's surface
/// minimised in the box the design spans (`centre ± α·half_range`, clipped
/// at 0). The result is checked by one more simulation.
///
/// Default design: the centre is the per-joint best of the start scan
/// ([`super::SCAN_GRID_NM`], at least 0.025 N·m), the half-ranges half the centre (the
/// relative ranges of seed 000 Table 9), so that a rotatable design spans
/// `centre × (1 ± 0.84)`. A design point below 0 N·m is an error.
pub fn identify_rsm(
    campaign: &Campaign,
    joints: &[usize],
    opts: &RsmOptions,
    progress: Progress,
) -> Result<Identification, IdentifyError> {
    let t0 = Instant::now();
    check_rounds(opts.rounds)?;
    check_joints(campaign, joints)?;
    let model = Model::new(campaign, joints);
    let before = score_as_given(&model, progress)?;
    let mut plan = rsm_design(&model, opts, progress)?;
    let mut round = 1;
    let (points, surfaces, min, lo, hi, names) = loop {
        let coding = Coding::new(plan.centre.clone(), plan.half.clone())?;
        let points = design_points(&plan, &coding, joints)?;
        progress(&format!(
            "rsm round {round}/{}: {} design points ({} CCD, α = {:.3}) around {} ± {} N·m",
            opts.rounds,
            points.len(),
            opts.kind,
            plan.reach,
            list_4(&plan.centre),
            list_4(&plan.half)
        ));
        let table = simulate_design(&model, &points, progress)?;
        let names = response_names(&model.te_joints);
        let (surfaces, fits) = fit_surfaces(&plan.design.coded_points(), &table, &names)?;
        let k = model.te_joints.len();
        let (min, lo, hi) = minimise_surface(&fits, k, opts.response, &coding, plan.reach)?;
        progress(&format!(
            "rsm round {round}: surface minimum {:.4} at {} N·m",
            min.value,
            list(&min.x)
        ));
        if round >= opts.rounds {
            break (points, surfaces, min, lo, hi, names);
        }
        plan.next_round(&min.x, round);
        round += 1;
    };
    let k = model.te_joints.len();
    progress("rsm: checking the last minimum by simulation");
    let (after, _) = model.score(&min.x).ok_or_else(|| {
        IdentifyError::Simulation(format!("at the surface's minimum {} N·m", list(&min.x)))
    })?;
    let simulated = simulated_response(&after, &model.te_joints, opts.response);
    let mut id = Identification {
        joints: joints
            .iter()
            .zip(&min.x)
            .map(|(&j, &v)| JointEft {
                joint: j,
                coulomb_nm: v,
                ci95: None,
                sd_nm: None,
            })
            .collect(),
        rsm: Some(RsmDetails {
            centre_nm: plan.centre,
            half_range_nm: plan.half,
            design_rule: plan.rule.join("; "),
            alpha: plan.reach,
            points_nm: points,
            responses: surfaces,
            minimised: match opts.response {
                RsmResponse::TeSum => names[..k].join(" + "),
                RsmResponse::Mse => names[k].clone(),
            },
            box_nm: lo.iter().zip(&hi).map(|(l, h)| [*l, *h]).collect(),
            predicted: min.value,
            simulated,
            rounds: round,
            beyond_design: None,
        }),
        ..Identification::scored(Method::Rsm, &model, t0, before, after)
    };
    check_beyond_design(campaign, joints, &mut id, progress);
    Ok(id)
}

/// The `--center` to give a new design around the EFTs least squares found
/// beyond this one ([`BeyondDesign::coulomb_nm`], each at least the least
/// default centre `SCAN_GRID_NM[1]`), or `None` when that is the centre
/// `used` to [`CENTRE_SAME_NM`] at every joint: a new design there would be
/// this one again, and least squares is the way to those EFTs.
pub fn centre_beyond(b: &BeyondDesign, used: &[f64]) -> Option<Vec<f64>> {
    let centre: Vec<f64> = b
        .coulomb_nm
        .iter()
        .map(|c| c.max(SCAN_GRID_NM[1]))
        .collect();
    let same = centre.len() == used.len()
        && centre
            .iter()
            .zip(used)
            .all(|(c, u)| (c - u).abs() < CENTRE_SAME_NM);
    (!same).then_some(centre)
}

/// Two design centres closer than this at every joint are the same design
/// [N·m]: half the last digit `--center` is printed with (0.001 N·m).
pub const CENTRE_SAME_NM: f64 = 5e-4;

/// When the surface's minimum leaves a joint's residual above
/// [`residual_check::RESIDUAL_WARN_FACTOR`] × the noise, least squares
/// ([`direct::identify_direct`]) started from it, then from the direct
/// method's own start (its scan) if that is not enough; the first that
/// explains every joint to that level is recorded in
/// [`RsmDetails::beyond_design`]: the design did not reach the friction
/// that explains the runs (a centre from the start scan far from it, a
/// box too narrow), which is not "friction alone does not explain them".
/// Its work is counted in `id`'s.
fn check_beyond_design(
    campaign: &Campaign,
    joints: &[usize],
    id: &mut Identification,
    progress: Progress,
) {
    if residual_check::residual_warnings(campaign, id).is_empty() {
        return;
    }
    progress("rsm: the minimum leaves residuals above the noise; least squares from it");
    let said = |m: &str| progress(&format!("rsm check: {m}"));
    let starts = [
        (
            Some(id.joints.iter().map(|j| j.coulomb_nm).collect()),
            "the surface's minimum",
        ),
        (None, "the direct method's start scan"),
    ];
    for (start_nm, start) in starts {
        let opts = DirectOptions {
            start_nm,
            ..DirectOptions::default()
        };
        let Ok(d) = direct::identify_direct(campaign, joints, &opts, &said) else {
            continue;
        };
        id.simulations += d.simulations;
        id.deployments += d.deployments;
        id.wall_s += d.wall_s;
        if !residual_check::residual_warnings(campaign, &d).is_empty() {
            continue;
        }
        if let Some(r) = id.rsm.as_mut() {
            r.beyond_design = Some(BeyondDesign {
                coulomb_nm: d.joints.iter().map(|j| j.coulomb_nm).collect(),
                rms_deg: d.rms_deg_after,
                simulations: d.simulations,
                start: start.to_string(),
            });
        }
        return;
    }
}

/// At least one round of the design.
fn check_rounds(rounds: usize) -> Result<(), IdentifyError> {
    if rounds == 0 {
        return Err(IdentifyError::BadOption(
            "rounds 0: expected at least 1 round of the design".into(),
        ));
    }
    Ok(())
}

impl RsmPlan {
    /// The design of the round after `round`: centred on that round's
    /// minimum `min_x`, half as wide, and no design point below 0 N·m.
    fn next_round(&mut self, min_x: &[f64], round: usize) {
        self.centre = min_x.iter().map(|c| c.max(RSM_MIN_CENTRE_NM)).collect();
        self.half = self
            .half
            .iter()
            .zip(&self.centre)
            .map(|(h, c)| (h * RSM_ROUND_SHRINK).min(RSM_REACH_MARGIN * c / self.reach))
            .collect();
        self.rule.push(format!(
            "round {}: re-centred on the round-{round} minimum, half-ranges × {RSM_ROUND_SHRINK}",
            round + 1
        ));
    }
}

/// The design of a response-surface identification: where and how wide.
struct RsmPlan {
    /// The CCD in coded units.
    design: rsm::Ccd,
    /// Its coded extent: α (circumscribed) or 1.
    reach: f64,
    /// Design centre [N·m].
    centre: Vec<f64>,
    /// Half-ranges [N·m] (coded ±1).
    half: Vec<f64>,
    /// How the centre and half-ranges were chosen.
    rule: Vec<String>,
}

/// Chooses the design: the given centre or the start scan's, the given
/// half-ranges or `half_range_fraction × centre`.
fn rsm_design(
    model: &Model,
    opts: &RsmOptions,
    progress: Progress,
) -> Result<RsmPlan, IdentifyError> {
    let k = model.joints.len();
    let design = rsm::Ccd::new(k, opts.kind, opts.centre_runs)?;
    let reach = design
        .coded_points()
        .iter()
        .flat_map(|p| p.iter().map(|v| v.abs()))
        .fold(0.0, f64::max);
    let mut rule = Vec::new();
    let centre = match &opts.centre_nm {
        Some(c) => {
            check_vector("centre", c, k, true)?;
            rule.push("centre given".to_string());
            c.clone()
        }
        None => {
            let sc = scan_with(model, progress)?;
            rule.push(format!(
                "centre = per-joint best of the uniform-EFT scan, {} N·m (at least {} N·m)",
                list(&sc.per_joint_best_nm),
                SCAN_GRID_NM[1]
            ));
            sc.per_joint_best_nm
                .iter()
                .map(|c| c.max(SCAN_GRID_NM[1]))
                .collect()
        }
    };
    let half = match &opts.half_range_nm {
        Some(h) => {
            check_vector("range", h, k, true)?;
            rule.push("half-ranges given".to_string());
            h.clone()
        }
        None => {
            if !(opts.half_range_fraction > 0.0 && opts.half_range_fraction.is_finite()) {
                return Err(IdentifyError::BadOption(format!(
                    "half-range fraction {}: expected a positive number",
                    opts.half_range_fraction
                )));
            }
            let fraction = default_fraction(opts.half_range_fraction, reach);
            if fraction < opts.half_range_fraction {
                rule.push(format!(
                    "half-range = 1/α = {fraction:.3} × centre: {} × centre would reach below \
                     0 N·m at α = {reach:.3}; the axial points reach 0 N·m",
                    opts.half_range_fraction
                ));
            } else {
                rule.push(format!(
                    "half-range = {fraction} × centre (design spans centre × (1 ± {:.3}))",
                    fraction * reach
                ));
            }
            centre.iter().map(|c| c * fraction).collect()
        }
    };
    Ok(RsmPlan {
        design,
        reach,
        centre,
        half,
        rule,
    })
}

/// The default half-range as a fraction of the centre \[1\]: `fraction`,
/// or `1/reach` where `fraction × reach` would take the axial points below
/// 0 N·m (a rotatable CCD of 5 or more factors, α = (2^k)^(1/4) ≥ 2.378,
/// with the default 0.5), so a default design is always one the plan accepts.
fn default_fraction(fraction: f64, reach: f64) -> f64 {
    if fraction * reach > 1.0 {
        1.0 / reach
    } else {
        fraction
    }
}

/// The design points [N·m]; a point below 0 (beyond rounding) is an error.
fn design_points(
    plan: &RsmPlan,
    coding: &Coding,
    joints: &[usize],
) -> Result<Vec<Vec<f64>>, IdentifyError> {
    let mut points = plan.design.natural_points(coding)?;
    for p in points.iter_mut() {
        for (i, v) in p.iter_mut().enumerate() {
            if *v >= 0.0 {
                continue;
            }
            if *v > -RSM_ZERO_SLACK * plan.half[i] {
                *v = 0.0;
            } else {
                // The point's coded level: 1 at a factorial point, the
                // axial reach at an axial one.
                let level = (plan.centre[i] - *v) / plan.half[i];
                return Err(IdentifyError::BadOption(format!(
                    "the design reaches EFT {v:.4} N·m < 0 at joint {}: centre {} − {level:.3} × half-range {} is negative; \
                     raise the centre or narrow the range",
                    joints[i], plan.centre[i], plan.half[i]
                )));
            }
        }
    }
    Ok(points)
}

/// Simulates every design point (in parallel): one row of responses each.
fn simulate_design(
    model: &Model,
    points: &[Vec<f64>],
    progress: Progress,
) -> Result<Vec<Vec<f64>>, IdentifyError> {
    let done = AtomicUsize::new(0);
    let results: Vec<Option<Vec<f64>>> = points
        .par_iter()
        .map(|p| {
            let (s, _) = model.score(p)?;
            let mse = s.rms_deg * s.rms_deg;
            let r = responses(&s, mse, &model.te_joints);
            let n = done.fetch_add(1, Ordering::Relaxed) + 1;
            progress(&format!("rsm: design point {n}/{} simulated", points.len()));
            Some(r)
        })
        .collect();
    points
        .iter()
        .zip(results)
        .map(|(p, r)| {
            r.ok_or_else(|| {
                IdentifyError::Simulation(format!("at the design point {} N·m", list(p)))
            })
        })
        .collect()
}

/// The names of the responses: `te<j>_pct` per joint, then `mse_deg2`.
fn response_names(joints: &[usize]) -> Vec<String> {
    joints
        .iter()
        .map(|j| format!("te{j}_pct"))
        .chain(std::iter::once("mse_deg2".to_string()))
        .collect()
}

/// A full quadratic (seed 000 Eq. 15) fitted to every response column.
fn fit_surfaces(
    coded: &[Vec<f64>],
    table: &[Vec<f64>],
    names: &[String],
) -> Result<(Vec<ResponseSurface>, Vec<rsm::Fit>), IdentifyError> {
    let mut surfaces = Vec::with_capacity(names.len());
    let mut fits = Vec::with_capacity(names.len());
    for (c, name) in names.iter().enumerate() {
        let y: Vec<f64> = table.iter().map(|r| r[c]).collect();
        if y.iter().any(|v| !v.is_finite()) {
            return Err(IdentifyError::Simulation(format!(
                "with a defined {name} at every design point (a joint without samples for Eq. 14?)"
            )));
        }
        let f = rsm::fit_quadratic(coded, &y)?;
        surfaces.push(ResponseSurface {
            name: name.clone(),
            values: y,
            r2: f.r2,
            adj_r2: f.adj_r2,
            coded_coefficients: f.model.coefficients().to_vec(),
        });
        fits.push(f);
    }
    Ok((surfaces, fits))
}

/// Minimises the chosen response's surface in the box the design spans
/// (clipped at 0 N·m): the minimum and the box `(lower, upper)` [N·m].
fn minimise_surface(
    fits: &[rsm::Fit],
    k: usize,
    response: RsmResponse,
    coding: &Coding,
    reach: f64,
) -> Result<(rsm_box::BoxMinimum, Vec<f64>, Vec<f64>), IdentifyError> {
    let target: Quadratic = match response {
        RsmResponse::TeSum => {
            let parts: Vec<(f64, &Quadratic)> = fits[..k].iter().map(|f| (1.0, &f.model)).collect();
            Quadratic::weighted_sum(&parts)?
        }
        RsmResponse::Mse => fits[k].model.clone(),
    };
    let natural = target.to_natural(coding)?;
    let (lo, hi) = coding.natural_box(reach);
    let lo: Vec<f64> = lo.iter().map(|v| v.max(0.0)).collect();
    let min = rsm_box::minimize_in_box(&natural, &lo, &hi)?;
    Ok((min, lo, hi))
}

/// The minimised response, simulated (the check of the surface's minimum).
fn simulated_response(after: &CampaignScore, joints: &[usize], response: RsmResponse) -> f64 {
    match response {
        RsmResponse::TeSum => joints
            .iter()
            .map(|&j| after.mean_te_pct(j).unwrap_or(f64::NAN))
            .sum(),
        RsmResponse::Mse => after.rms_deg * after.rms_deg,
    }
}
