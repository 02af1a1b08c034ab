//! `--method auto`: importance sampling around FORM's design points
//! ([`super::importance`]) and subset simulation ([`super::subset`]), two
//! estimators that fail differently (a design point FORM misses; a mode
//! whose chains stall), each with its own c.o.v.; the result is the first
//! that reached every mode (importance sampling first: its draws are
//! independent, so its c.o.v. is the one its spread shows), and says
//! whether the two agree: `|ln p₁ − ln p₂| ≤ 1.96 √(s₁² + s₂²)`, `s =
//! √ln(1 + c.o.v.²)` (their 95 % intervals as lognormal estimators).

use super::estimate::Estimate;
use super::importance::{self, IsSettings};
use super::mc::{self, McSettings};
use super::subset::{self, SubsetSettings};
use super::{Evaluate, Problem, ReliabilityError};
use crate::analysis::fit::Z_975;
use crate::report::progress::Progress;

/// Whether two estimates agree within their intervals (module doc): `None`
/// when neither found a failure (two zeros are no evidence of agreement:
/// nothing was estimated to compare); one that did and one that did not
/// do not agree.
pub fn agree(a: &Estimate, b: &Estimate) -> Option<bool> {
    match (a.p_fail > 0.0, b.p_fail > 0.0) {
        (false, false) => None,
        (true, true) => {
            let s = |c: f64| (1.0 + c * c).ln();
            let (sa, sb) = (s(a.cov), s(b.cov));
            if !(sa + sb).is_finite() {
                return Some(true);
            }
            Some((a.p_fail.ln() - b.p_fail.ln()).abs() <= Z_975 * (sa + sb).sqrt())
        }
        _ => Some(false),
    }
}

/// Runs both and compares them.
pub fn run(
    problem: &Problem,
    is: &IsSettings,
    ss: &SubsetSettings,
    eval: Evaluate<'_>,
    progress: Progress<'_>,
) -> Result<Estimate, ReliabilityError> {
    let a = importance::run(problem, is, eval, progress)?;
    let b = subset::run(problem, ss, eval, progress)?;
    let primary = if a.converged || !b.converged { &a } else { &b };
    Ok(Estimate {
        method: "auto",
        simulations: a.simulations + b.simulations,
        converged: a.converged || b.converged,
        agree: agree(&a, &b),
        modes: Vec::new(),
        design_points: Vec::new(),
        unreached: Vec::new(),
        checks: vec![a.clone(), b.clone()],
        ..primary.clone()
    })
}

/// The estimator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Importance sampling and subset simulation, compared.
    Auto,
    /// Importance sampling around FORM's design points.
    Is,
    /// Subset simulation (Au & Beck 2001), p0 = 0.1, one run per mode.
    Subset,
    /// Crude Monte-Carlo.
    Mc,
}

impl std::str::FromStr for Method {
    type Err = ReliabilityError;
    fn from_str(s: &str) -> Result<Method, ReliabilityError> {
        match s.trim() {
            "auto" => Ok(Method::Auto),
            "is" => Ok(Method::Is),
            "subset" => Ok(Method::Subset),
            "mc" => Ok(Method::Mc),
            other => Err(ReliabilityError::Invalid(format!(
                "method `{other}`: expected auto, is, subset or mc"
            ))),
        }
    }
}

/// Default `--samples`: mc's most deployments.
pub const MC_SAMPLES: usize = 100_000;
/// Default `--samples`: importance sampling's draws.
pub const IS_SAMPLES: usize = 8000;

/// Runs `method` on `problem` with the batch evaluator `eval` (`samples`:
/// mc its most deployments, subset its samples per level, is its draws,
/// auto both of the last two). The one dispatch of the CLI and the Python
/// package.
pub fn estimate(
    problem: &Problem,
    method: Method,
    samples: Option<usize>,
    target_cov: Option<f64>,
    seed: u64,
    eval: Evaluate<'_>,
    progress: Progress<'_>,
) -> Result<Estimate, ReliabilityError> {
    let ss = SubsetSettings {
        samples: samples.unwrap_or(SubsetSettings::default().samples),
        seed,
        ..SubsetSettings::default()
    };
    let is = IsSettings {
        samples: samples.unwrap_or(IS_SAMPLES),
        target_cov,
        seed,
    };
    match method {
        Method::Mc => mc::run(
            problem,
            &McSettings {
                samples: samples.unwrap_or(MC_SAMPLES),
                target_cov,
                seed,
            },
            eval,
            progress,
        ),
        Method::Subset => subset::run(problem, &ss, eval, progress),
        Method::Is => importance::run(problem, &is, eval, progress),
        Method::Auto => {
            // Subset's settings refused before importance sampling's
            // deployments, not after them.
            ss.check()?;
            run(problem, &is, &ss, eval, progress)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_estimates_without_a_failure_have_nothing_to_compare() {
        let zero = Estimate::plain("is", 0.0, f64::INFINITY, 100);
        let some = Estimate::plain("subset", 1e-3, 0.2, 100);
        assert_eq!(agree(&zero, &zero), None);
        assert_eq!(agree(&zero, &some), Some(false));
        assert_eq!(agree(&some, &some), Some(true));
        let far = Estimate::plain("is", 1e-6, 0.2, 100);
        assert_eq!(agree(&far, &some), Some(false));
    }
}
