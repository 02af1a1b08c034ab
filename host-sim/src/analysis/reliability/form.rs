//! FORM's design points (Hasofer & Lind 1974; Rackwitz & Fiessler 1978):
//! for each failure mode, the point of its failure boundary nearest the
//! origin of the standard normal space, `u* = β a`, `a` the unit direction
//! in which the margin falls fastest there (`u* ∥ −∇m(u*)`).
//!
//! The search is made for margins that are monotone but far from linear
//! (a latch time diverges as a joint nears its stall): a direction `a`
//! (first the steepest descent at the origin), the root of the margin on
//! the ray `β a` (a grid of [`RAY_STEP`] up to [`BETA_MAX`], then
//! bracketing refined by 7-point sections), the gradient there (forward
//! differences of [`FD_STEP`] in `u`), the new direction `−∇m/|∇m|`, until
//! the direction moves less than [`DIRECTION_TOL`]. Each stage evaluates
//! every mode's points in one batch (one row of margins answers every mode
//! at once). A mode whose ray reaches no failure within [`BETA_MAX`] is
//! *unreached*: its failure probability, if any, is not found this way.

use super::criteria::Mode;
use super::estimate::DesignPoint;
use super::mc::check_rows;
use super::{Evaluate, Problem, ReliabilityError};
use crate::report::progress::Progress;

/// Forward-difference step of the gradient [standard deviations].
pub const FD_STEP: f64 = 0.05;
/// Spacing of the first search along a ray [standard deviations].
pub const RAY_STEP: f64 = 0.5;
/// Farthest point searched along a ray: `Φ(−8) = 6e-16`.
pub const BETA_MAX: f64 = 8.0;
/// The direction has converged when it moves less than this.
pub const DIRECTION_TOL: f64 = 1e-3;
/// Most direction updates.
pub const MAX_ITERATIONS: usize = 12;
/// Sections of a bracket (each of 7 interior points: ×8 narrower).
const SECTIONS: usize = 4;

/// The design points found and the modes not reached.
#[derive(Clone, Debug, PartialEq)]
pub struct Form {
    /// One per mode reached, in the order of the modes.
    pub points: Vec<DesignPoint>,
    /// The modes whose boundary was not found within [`BETA_MAX`].
    pub unreached: Vec<Mode>,
    /// Deployments simulated.
    pub simulations: usize,
}

/// The search state of one mode.
#[derive(Clone, Debug)]
struct Search {
    dir: Vec<f64>,
    beta: f64,
    done: bool,
    /// The root nearest the origin found so far, `(u, β)`.
    best: Option<(Vec<f64>, f64)>,
    sims: usize,
}

/// Evaluates a batch and returns the rows.
fn rows(
    eval: Evaluate<'_>,
    problem: &Problem,
    us: &[Vec<f64>],
    width: usize,
) -> Result<Vec<Vec<f64>>, ReliabilityError> {
    if us.is_empty() {
        return Ok(Vec::new());
    }
    let xs: Vec<Vec<f64>> = us.iter().map(|u| problem.x_of(u)).collect();
    let r = eval(&xs)?;
    check_rows(&r, xs.len(), width)?;
    Ok(r)
}

fn unit(v: &[f64]) -> Option<Vec<f64>> {
    let n = v.iter().map(|a| a * a).sum::<f64>().sqrt();
    (n > 0.0 && n.is_finite()).then(|| v.iter().map(|a| a / n).collect())
}

fn scaled(dir: &[f64], beta: f64) -> Vec<f64> {
    dir.iter().map(|a| a * beta).collect()
}

/// The forward-difference points around `u` (`u` first).
fn stencil(u: &[f64]) -> Vec<Vec<f64>> {
    let mut pts = vec![u.to_vec()];
    for i in 0..u.len() {
        let mut p = u.to_vec();
        p[i] += FD_STEP;
        pts.push(p);
    }
    pts
}

/// The steepest-descent direction of mode `mi` from its stencil's rows.
fn descent(rows: &[Vec<f64>], mi: usize) -> Option<Vec<f64>> {
    let g0 = rows[0][mi];
    let grad: Vec<f64> = rows[1..].iter().map(|r| -(r[mi] - g0) / FD_STEP).collect();
    unit(&grad)
}

/// Finds the design point of every mode.
pub fn run(
    problem: &Problem,
    eval: Evaluate<'_>,
    progress: Progress<'_>,
) -> Result<Form, ReliabilityError> {
    let modes = problem.modes();
    let (k, d) = (modes.len(), problem.vary.len());
    let origin = rows(eval, problem, &stencil(&vec![0.0; d]), k)?;
    let mut sims = d + 1;
    let mut s: Vec<Search> = (0..k)
        .map(|mi| {
            let failed = origin[0][mi] <= 0.0;
            let dir = descent(&origin, mi);
            Search {
                dir: dir.clone().unwrap_or(vec![0.0; d]),
                beta: 0.0,
                done: failed || dir.is_none(),
                best: failed.then(|| (vec![0.0; d], 0.0)),
                sims: 0,
            }
        })
        .collect();
    for it in 0..MAX_ITERATIONS {
        if s.iter().all(|m| m.done) {
            break;
        }
        ray_roots(problem, eval, &mut s, k)?;
        let active: Vec<usize> = (0..k).filter(|&i| !s[i].done).collect();
        let pts: Vec<Vec<f64>> = active
            .iter()
            .flat_map(|&i| stencil(&scaled(&s[i].dir, s[i].beta)))
            .collect();
        let r = rows(eval, problem, &pts, k)?;
        for (n, &i) in active.iter().enumerate() {
            s[i].sims += d + 1;
            let at = &r[n * (d + 1)..(n + 1) * (d + 1)];
            let Some(new) = descent(at, i) else {
                s[i].done = true;
                continue;
            };
            let moved = new.iter().zip(&s[i].dir).map(|(a, b)| (a - b).powi(2));
            if moved.sum::<f64>().sqrt() < DIRECTION_TOL {
                s[i].done = true;
            }
            // Past a few updates, damp a direction that swings.
            let w = if it >= 4 { 0.5 } else { 1.0 };
            let mixed: Vec<f64> = new
                .iter()
                .zip(&s[i].dir)
                .map(|(a, b)| w * a + (1.0 - w) * b)
                .collect();
            s[i].dir = unit(&mixed).unwrap_or(new);
        }
        progress(&format!(
            "form: iteration {it}: {} of {k} modes still moving",
            s.iter().filter(|m| !m.done).count()
        ));
    }
    // The last direction's root (a direction moved since its root).
    for m in s
        .iter_mut()
        .filter(|m| m.best.as_ref().is_some_and(|b| b.1 > 0.0))
    {
        m.done = false;
    }
    ray_roots(problem, eval, &mut s, k)?;
    sims += s.iter().map(|m| m.sims).sum::<usize>();
    Ok(finish(problem, &modes, &s, sims))
}

/// The design points of the searches, and the modes not reached.
fn finish(problem: &Problem, modes: &[Mode], s: &[Search], sims: usize) -> Form {
    let mut points = Vec::new();
    let mut unreached = Vec::new();
    for (mi, m) in s.iter().enumerate() {
        let Some((u, beta)) = m.best.clone() else {
            unreached.push(modes[mi]);
            continue;
        };
        points.push(DesignPoint {
            mode: modes[mi],
            x: problem.x_of(&u),
            beta,
            u,
            simulations: m.sims,
        });
    }
    Form {
        points,
        unreached,
        simulations: sims,
    }
}

/// For every mode still searching: the first root of its margin along its
/// ray, to `RAY_STEP / 8^SECTIONS`, on the failure side (kept when nearer
/// the origin than the best so far); a mode with none within
/// [`BETA_MAX`] is done.
fn ray_roots(
    problem: &Problem,
    eval: Evaluate<'_>,
    s: &mut [Search],
    k: usize,
) -> Result<(), ReliabilityError> {
    let active: Vec<usize> = (0..k).filter(|&i| !s[i].done).collect();
    let steps = (BETA_MAX / RAY_STEP).round() as usize;
    let grid: Vec<f64> = (1..=steps).map(|j| j as f64 * RAY_STEP).collect();
    let pts: Vec<Vec<f64>> = active
        .iter()
        .flat_map(|&i| grid.iter().map(move |&b| (i, b)))
        .map(|(i, b)| scaled(&s[i].dir, b))
        .collect();
    let r = rows(eval, problem, &pts, k)?;
    let mut brackets: Vec<(usize, f64, f64)> = Vec::new();
    for (n, &i) in active.iter().enumerate() {
        s[i].sims += steps;
        let hit = (0..steps).find(|&j| r[n * steps + j][i] <= 0.0);
        match hit {
            Some(j) => brackets.push((i, grid[j] - RAY_STEP, grid[j])),
            None => s[i].done = true,
        }
    }
    for _ in 0..SECTIONS {
        let pts: Vec<Vec<f64>> = brackets
            .iter()
            .flat_map(|&(i, lo, hi)| (1..8).map(move |q| (i, lo + (hi - lo) * q as f64 / 8.0)))
            .map(|(i, b)| scaled(&s[i].dir, b))
            .collect();
        let r = rows(eval, problem, &pts, k)?;
        for (n, br) in brackets.iter_mut().enumerate() {
            let (i, lo, hi) = *br;
            s[i].sims += 7;
            let w = (hi - lo) / 8.0;
            let first = (0..7).find(|&q| r[n * 7 + q][i] <= 0.0);
            *br = match first {
                Some(q) => (i, lo + w * q as f64, lo + w * (q + 1) as f64),
                None => (i, hi - w, hi),
            };
        }
    }
    for (i, _, hi) in brackets {
        s[i].beta = hi;
        if s[i].best.as_ref().is_none_or(|b| hi < b.1) {
            s[i].best = Some((scaled(&s[i].dir, hi), hi));
        }
    }
    Ok(())
}
