//! The native part of the `deploywatch` Python package: one deployment, a
//! batch of deployments (the hot loop in Rust on every core, the GIL
//! released), and the reliability analysis with a Python batch evaluator
//! (the package's `executor=`). Mechanisms and identify results are passed
//! as text, so that remote workers need no files.
#![deny(missing_docs)]

use deploywatch_sim::analysis::reliability::correlation::Correlation;
use deploywatch_sim::analysis::reliability::criteria::{Criterion, Outcome};
use deploywatch_sim::analysis::reliability::identified;
use deploywatch_sim::analysis::reliability::auto::{estimate, Method};
use deploywatch_sim::analysis::reliability::params::Vary;
use deploywatch_sim::analysis::reliability::{Evaluate, Problem, ReliabilityError};
use deploywatch_sim::model::effect::Effect;
use deploywatch_sim::model::mechanism::Mechanism;
use deploywatch_sim::report::progress;
use deploywatch_sim::simulate::deployment::{self, SimOptions};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray2};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

fn value_err(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

fn mechanism(text: &str, source: &str) -> PyResult<Mechanism> {
    Mechanism::from_toml_str(text, source).map_err(value_err)
}

/// The problem of `reliability`/`simulate_batch` from their arguments.
fn problem(
    mech_toml: &str,
    source: &str,
    vary: Vec<String>,
    fail: Vec<String>,
    from_json: Option<&str>,
    corr: &[String],
) -> PyResult<Problem> {
    let mech = mechanism(mech_toml, source)?;
    let mut vs: Vec<Vary> = vary
        .iter()
        .map(|v| v.parse::<Vary>().map_err(value_err))
        .collect::<PyResult<_>>()?;
    if let Some(text) = from_json {
        let given = vs.clone();
        let found = identified::from_identify_json(text).map_err(value_err)?;
        vs.extend(
            found
                .into_iter()
                .filter(|f| !given.iter().any(|g| g.label() == f.label())),
        );
    }
    let fail: Vec<Criterion> = fail
        .iter()
        .map(|c| c.parse::<Criterion>().map_err(value_err))
        .collect::<PyResult<_>>()?;
    let corr = corr
        .iter()
        .map(|c| c.parse::<Correlation>().map_err(value_err))
        .collect::<PyResult<_>>()?;
    let p = Problem {
        mech,
        vary: vs,
        fail,
        corr,
    };
    p.check().map_err(value_err)?;
    Ok(p)
}

/// The labels of the problem's parameters, in column order.
#[pyfunction]
#[pyo3(signature = (mechanism_toml, source, vary, fail, from_json=None))]
fn parameters(
    mechanism_toml: &str,
    source: &str,
    vary: Vec<String>,
    fail: Vec<String>,
    from_json: Option<&str>,
) -> PyResult<Vec<String>> {
    let p = problem(mechanism_toml, source, vary, fail, from_json, &[])?;
    Ok(p.vary.iter().map(|v| v.to_string()).collect())
}

/// One deployment: times, angles and rates (numpy) and latch instants.
#[pyfunction]
#[pyo3(signature = (mechanism_toml, source, effects, sample_hz=None))]
fn simulate<'py>(
    py: Python<'py>,
    mechanism_toml: &str,
    source: &str,
    effects: Vec<String>,
    sample_hz: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let mech = mechanism(mechanism_toml, source)?;
    let effects: Vec<Effect> = effects
        .iter()
        .map(|e| e.parse::<Effect>().map_err(value_err))
        .collect::<PyResult<_>>()?;
    let opts = SimOptions {
        sample_hz,
        ..SimOptions::default()
    };
    let traj = py
        .allow_threads(|| deployment::simulate(&mech, &effects, &opts))
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    let n = traj.t_s.len();
    let j = traj.joints();
    let cols = |v: &Vec<Vec<f64>>| -> Vec<f64> {
        (0..n).flat_map(|i| (0..j).map(move |k| v[k][i])).collect()
    };
    let d = PyDict::new(py);
    d.set_item("t_s", traj.t_s.clone().into_pyarray(py))?;
    let shape = |v: Vec<f64>| numpy::ndarray::Array2::from_shape_vec((n, j), v);
    d.set_item(
        "phi_deg",
        shape(cols(&traj.phi_deg))
            .map_err(value_err)?
            .into_pyarray(py),
    )?;
    d.set_item(
        "rate_deg_s",
        shape(cols(&traj.rate_deg_s))
            .map_err(value_err)?
            .into_pyarray(py),
    )?;
    d.set_item(
        "latch_s",
        traj.latch_s
            .iter()
            .map(|l| l.unwrap_or(f64::NAN))
            .collect::<Vec<_>>()
            .into_pyarray(py),
    )?;
    d.set_item("end_s", traj.end_s)?;
    Ok(d)
}

/// A batch of deployments, one per row of `params` (columns: the `vary`
/// parameters, then those of `from_json`): the limit state `g` and, per
/// joint, latch instant, latch rate (NaN when not latched) and end angle.
#[pyfunction]
#[pyo3(signature = (mechanism_toml, source, vary, fail, params, from_json=None))]
fn simulate_batch<'py>(
    py: Python<'py>,
    mechanism_toml: &str,
    source: &str,
    vary: Vec<String>,
    fail: Vec<String>,
    params: PyReadonlyArray2<'py, f64>,
    from_json: Option<&str>,
) -> PyResult<Bound<'py, PyDict>> {
    let p = problem(mechanism_toml, source, vary, fail, from_json, &[])?;
    let a = params.as_array();
    if a.ncols() != p.vary.len() {
        return Err(value_err(format!(
            "params has {} columns; expected {} (one per parameter: {})",
            a.ncols(),
            p.vary.len(),
            p.vary
                .iter()
                .map(|v| v.label())
                .collect::<Vec<_>>()
                .join(", ")
        )));
    }
    let xs: Vec<Vec<f64>> = a.rows().into_iter().map(|r| r.to_vec()).collect();
    let outs = py
        .allow_threads(|| p.deploy_batch(&xs))
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    let n = outs.len();
    let j = p.mech.joint_count();
    let grid = |f: &dyn Fn(&Outcome, usize) -> f64| -> PyResult<Bound<'py, PyArray2<f64>>> {
        let v: Vec<f64> = outs
            .iter()
            .flat_map(|o| (0..j).map(move |k| f(o, k)))
            .collect();
        Ok(numpy::ndarray::Array2::from_shape_vec((n, j), v)
            .map_err(value_err)?
            .into_pyarray(py))
    };
    let d = PyDict::new(py);
    let g: Vec<f64> = outs.iter().map(|o| o.g(&p.fail)).collect();
    let g: Bound<'py, PyArray1<f64>> = g.into_pyarray(py);
    d.set_item("g", g)?;
    let modes = p.modes();
    let flat: Vec<f64> = outs.iter().flat_map(|o| o.margins(&modes)).collect();
    d.set_item(
        "margins",
        numpy::ndarray::Array2::from_shape_vec((n, modes.len()), flat)
            .map_err(value_err)?
            .into_pyarray(py),
    )?;
    d.set_item("latch_s", grid(&|o, k| o.latch_s[k].unwrap_or(f64::NAN))?)?;
    d.set_item(
        "latch_rate_deg_s",
        grid(&|o, k| o.latch_rate_deg_s[k].unwrap_or(f64::NAN))?,
    )?;
    d.set_item("end_deg", grid(&|o, k| o.end_deg[k])?)?;
    Ok(d)
}

/// The reliability analysis; returns the CLI's JSON as text. `evaluate`:
/// `None` for every local core, or a callable taking a float64 matrix (one
/// row per point) and returning the `g` of each row (the package sends the
/// rows to an executor).
#[allow(clippy::too_many_arguments)]
#[pyfunction]
#[pyo3(signature = (mechanism_toml, source, vary, fail, method, samples, target_cov, seed, from_json=None, evaluate=None, corr=Vec::new()))]
fn reliability(
    py: Python<'_>,
    mechanism_toml: &str,
    source: &str,
    vary: Vec<String>,
    fail: Vec<String>,
    method: &str,
    samples: Option<usize>,
    target_cov: Option<f64>,
    seed: u64,
    from_json: Option<&str>,
    evaluate: Option<PyObject>,
    corr: Vec<String>,
) -> PyResult<String> {
    let p = problem(mechanism_toml, source, vary, fail, from_json, &corr)?;
    let method: Method = method.parse().map_err(value_err)?;
    let run = |eval: Evaluate<'_>| {
        estimate(&p, method, samples, target_cov, seed, eval, &progress::quiet)
    };
    let est = match evaluate {
        None => py.allow_threads(|| run(&mut |xs: &[Vec<f64>]| p.margins_batch(xs))),
        Some(f) => {
            let d = p.vary.len();
            run(&mut |xs: &[Vec<f64>]| {
                let flat: Vec<f64> = xs.iter().flatten().copied().collect();
                let m = numpy::ndarray::Array2::from_shape_vec((xs.len(), d), flat)
                    .map_err(|e| ReliabilityError::Evaluator(e.to_string()))?;
                let out = f
                    .call1(py, (m.into_pyarray(py),))
                    .and_then(|g| g.extract::<Vec<Vec<f64>>>(py))
                    .map_err(|e| ReliabilityError::Evaluator(e.to_string()))?;
                Ok(out)
            })
        }
    }
    .map_err(|e| match e {
        ReliabilityError::Invalid(m) => PyValueError::new_err(m),
        other => PyRuntimeError::new_err(other.to_string()),
    })?;
    serde_json::to_string(&est.to_json(&p, seed)).map_err(value_err)
}

/// The extension module `deploywatch._native`.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_batch, m)?)?;
    m.add_function(wrap_pyfunction!(reliability, m)?)?;
    m.add_function(wrap_pyfunction!(parameters, m)?)?;
    Ok(())
}
