//! The native part of the `deploywatch` Python package
//! (`deploywatch._native`; the package's Python layer checks the arguments
//! and types the results): one deployment, a batch of deployments (the hot
//! loop in Rust on every core, the GIL released, Ctrl-C checked between
//! steps), and the reliability analysis with an optional Python batch
//! evaluator (the package's `executor=`). Mechanisms and identify results
//! are passed as text, so that remote workers need no files. Errors are
//! the package's exceptions (module `errors`).
#![deny(missing_docs)]

mod commands;
mod convert;
mod errors;
mod model;
mod monitor;
mod steps;
mod threads;

use deploywatch_sim::deployment::SimOptions;
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::progress;
use deploywatch_sim::reliability::auto::{estimate, Method};
use deploywatch_sim::reliability::correlation::Correlation;
use deploywatch_sim::reliability::criteria::{Criterion, Outcome};
use deploywatch_sim::reliability::identified;
use deploywatch_sim::reliability::params::{Target, Vary};
use deploywatch_sim::reliability::{warnings, Problem, ReliabilityError};
use errors::Kind;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray2};
use pyo3::exceptions::{PyUserWarning, PyValueError};
use pyo3::prelude::*;
use steps::Stop;

/// The mechanism of a TOML text; `MechanismError` naming the file, line and
/// key.
pub(crate) fn mechanism(text: &str, source: &str) -> PyResult<Mechanism> {
    Mechanism::from_toml_str(text, source).map_err(|e| Kind::Mechanism.of(&e))
}

/// Each string of argument `arg` parsed, an error naming `arg[i]`.
fn parse_all<T>(arg: &str, items: &[String]) -> PyResult<Vec<T>>
where
    T: std::str::FromStr,
    T::Err: std::error::Error + 'static,
{
    items
        .iter()
        .enumerate()
        .map(|(i, s)| {
            s.parse::<T>()
                .map_err(|e| Kind::Input.prefixed(&format!("{arg}[{i}]: "), &e))
        })
        .collect()
}

/// The problem of `reliability`/`simulate_batch` from their arguments, and
/// what `reliability` says of `from_` (`FromFindings::notes`, the CLI's
/// words of `--from`). `flight`: the flight unit, as `reliability
/// --flight` (the mechanism's `[rig]` taken out, the rig-only effects of
/// `from_` drawn in no deployment, the wing's losses the runs could not
/// tell from them drawn in their place).
fn problem(
    mech_toml: &str,
    source: &str,
    vary: &[String],
    fail: &[String],
    from_json: Option<&str>,
    corr: &[String],
    flight: bool,
) -> PyResult<(Problem, Vec<String>)> {
    let mech = mechanism(mech_toml, source)?;
    let mech = if flight { mech.flight() } else { mech };
    let mut vs: Vec<Vary> = parse_all("vary", vary)?;
    let (mut fixed, mut notes) = (Vec::new(), Vec::new());
    if let Some(text) = from_json {
        let given = vs.clone();
        let mut found = identified::from_findings_json(text, &mech)
            .map_err(|m| Kind::Input.raise(format!("from_: {m}"), Vec::new()))?;
        if let Some(why) = &found.no_effect {
            return Err(Kind::Input.raise(format!("from_: {why}"), Vec::new()));
        }
        let flown = if flight {
            found.take_out_the_rig_said("from_", "flight=True")
        } else {
            Vec::new()
        };
        notes = found.notes("from_", &mech.name);
        notes.extend(flown);
        vs.extend(
            found
                .vary
                .into_iter()
                .filter(|f| !given.iter().any(|g| g.label() == f.label())),
        );
        fixed = found.fixed;
        for f in &mut fixed {
            f.source = format!("from_: {}", f.source);
        }
    }
    let p = Problem {
        mech,
        vary: vs,
        fixed,
        fail: parse_all::<Criterion>("fail", fail)?,
        corr: parse_all::<Correlation>("corr", corr)?,
    };
    p.check().map_err(|e| errors::reliability(&e))?;
    Ok((p, notes))
}

/// The `--vary` parser's verdict on one string, without a mechanism: the
/// law, the target's name, and its joint where no mechanism changes the
/// answer (`joint=J` missing for a per-joint effect or given to a global
/// one, `Effect::validate_joint`'s words; whether the mechanism has that
/// joint is [`Problem::check`]'s). `None` when it passes, else the words,
/// the CLI's flags named as the Python arguments. What the typed `Vary`
/// checks where it is written.
#[pyfunction]
fn check_vary(text: &str) -> Option<String> {
    let why = match text.parse::<Vary>() {
        Err(e) => e.to_string(),
        Ok(v) => match v.target {
            Target::Effect(e) if e.kind().per_joint() == e.joint.is_none() => {
                let refused = e.with_value(0.0).validate_joint(usize::MAX).err()?;
                format!("`{text}`: {refused}")
            }
            _ => return None,
        },
    };
    Some(errors::pythonic(&why))
}

/// The labels of the problem's parameters, in the column order of
/// `simulate_batch`'s `params`.
#[pyfunction]
#[pyo3(signature = (mechanism_toml, source, vary, fail, from_json=None, flight=false))]
fn parameters(
    mechanism_toml: &str,
    source: &str,
    vary: Vec<String>,
    fail: Vec<String>,
    from_json: Option<&str>,
    flight: bool,
) -> PyResult<Vec<String>> {
    let (p, _) = problem(mechanism_toml, source, &vary, &fail, from_json, &[], flight)?;
    // One name per column: a law given twice is numbered (`#2`) after its
    // label, as the JSON's parameters are.
    let labels = deploywatch_sim::reliability::params::unique_labels(&p.vary);
    Ok(labels
        .iter()
        .zip(&p.vary)
        .map(|(label, v)| format!("{label}:{}", v.dist))
        .collect())
}

/// An (n, j) matrix of `f(i, k)` as a numpy array.
fn grid<'py>(py: Python<'py>, n: usize, j: usize, f: impl Fn(usize, usize) -> f64) -> Matrix<'py> {
    Array2::from_shape_fn((n, j), |(i, k)| f(i, k)).into_pyarray(py)
}

/// A numpy vector of float64.
type Vector<'py> = Bound<'py, PyArray1<f64>>;
/// A numpy matrix of float64.
type Matrix<'py> = Bound<'py, PyArray2<f64>>;
/// What `simulate_batch` returns: `g`, the margins, latch instants, latch
/// rates, end angles.
type Outcomes<'py> = (
    Vector<'py>,
    Matrix<'py>,
    Matrix<'py>,
    Matrix<'py>,
    Matrix<'py>,
);

/// One deployment of a mechanism parsed once (`model`), as the CLI's
/// `simulate` runs it (the physical latches' contact model when it has
/// one): `(t_s, phi_deg, rate_deg_s, latch_s, end_s)`, numpy arrays of
/// shapes (n,), (n, joints), (n, joints), (joints,) (NaN where not latched)
/// and a float: `end_s` the time of the last sample, where the run ends
/// whichever simulator ran it (not `Trajectory::end_s`, where the
/// integration stopped: the last latch for the chain and the truss, whose
/// samples then hold the deployed state `settle_s` longer). The effect
/// strings are checked as the CLI checks `--effect` (the errors name
/// `effects[i]`). The GIL is released while it runs.
#[pyfunction]
#[pyo3(signature = (model, effects, sample_hz=None))]
fn simulate<'py>(
    py: Python<'py>,
    model: &model::Model,
    effects: Vec<String>,
    sample_hz: Option<f64>,
) -> PyResult<(Vector<'py>, Matrix<'py>, Matrix<'py>, Vector<'py>, f64)> {
    let mech = &model.mech;
    let effects = model::effects(mech, "effects", &effects)?;
    let opts = SimOptions {
        sample_hz,
        ..SimOptions::default()
    };
    let traj = threads::allow(py, || model::deploy(mech, &effects, &opts))
        .map_err(|e| errors::simulation(&e))?;
    let (n, j) = (traj.t_s.len(), traj.joints());
    let latch: Vec<f64> = traj.latch_s.iter().map(|l| l.unwrap_or(f64::NAN)).collect();
    // Where the integration stopped stands in only for a run without samples.
    let end_s = traj.t_s.last().copied().unwrap_or(traj.end_s);
    Ok((
        traj.t_s.clone().into_pyarray(py),
        grid(py, n, j, |i, k| traj.phi_deg[k][i]),
        grid(py, n, j, |i, k| traj.rate_deg_s[k][i]),
        latch.into_pyarray(py),
        end_s,
    ))
}

/// A batch of deployments, one per row of `params` (float64, C order;
/// columns: the `vary` parameters, then those of `from_json`):
/// `(g, margins, latch_s, latch_rate_deg_s, end_deg)`: the limit state
/// (n,), the margin of each failure mode (n, modes; the modes of
/// `Problem::modes`, each failed iff its margin ≤ 0, `g` their minimum),
/// and per joint latch instant, latch rate (NaN when not latched, or with
/// no `latch_rate>X` criterion: only that one has the rate sampled) and
/// end angle (n, joints). The GIL is released while it runs; Ctrl-C stops
/// it between steps. `flight`: the flight unit, as `reliability`'s.
#[allow(clippy::too_many_arguments)]
#[pyfunction]
#[pyo3(signature = (mechanism_toml, source, vary, fail, params, from_json=None, flight=false))]
fn simulate_batch<'py>(
    py: Python<'py>,
    mechanism_toml: &str,
    source: &str,
    vary: Vec<String>,
    fail: Vec<String>,
    params: PyReadonlyArray2<'py, f64>,
    from_json: Option<&str>,
    flight: bool,
) -> PyResult<Outcomes<'py>> {
    let (p, _) = problem(mechanism_toml, source, &vary, &fail, from_json, &[], flight)?;
    let a = params.as_array();
    if a.ncols() != p.vary.len() {
        let labels: Vec<String> = p.vary.iter().map(|v| v.label()).collect();
        return Err(Kind::Input.raise(
            format!(
                "params: expected {} columns (one per parameter: {}), got {}",
                p.vary.len(),
                labels.join(", "),
                a.ncols()
            ),
            Vec::new(),
        ));
    }
    let xs: Vec<Vec<f64>> = a.rows().into_iter().map(|r| r.to_vec()).collect();
    let outs: Vec<Outcome> =
        threads::allow(py, || steps::in_steps(&xs, |rows| p.deploy_batch(rows)))
            .map_err(Stop::into_py)?;
    let (n, j) = (outs.len(), p.mech.joint_count());
    let g: Vec<f64> = outs.iter().map(|o| o.g(&p.fail)).collect();
    let modes = p.modes();
    let margins: Vec<Vec<f64>> = outs.iter().map(|o| o.margins(&modes)).collect();
    let at = |v: Option<f64>| v.unwrap_or(f64::NAN);
    Ok((
        g.into_pyarray(py),
        grid(py, n, modes.len(), |i, m| margins[i][m]),
        grid(py, n, j, |i, k| at(outs[i].latch_s[k])),
        grid(py, n, j, |i, k| at(outs[i].latch_rate_deg_s[k])),
        grid(py, n, j, |i, k| outs[i].end_deg[k]),
    ))
}

/// The margins of a batch (one per failure mode per row) from the Python
/// evaluator, called with the GIL taken for the call (and a look at the
/// signals before it).
fn call_evaluator(f: &PyObject, xs: &[Vec<f64>], d: usize) -> Result<Vec<Vec<f64>>, Stop> {
    Python::with_gil(|py| {
        py.check_signals()?;
        let m = Array2::from_shape_fn((xs.len(), d), |(i, k)| xs[i][k]);
        let out = f.call1(py, (m.into_pyarray(py),))?;
        out.extract::<Vec<Vec<f64>>>(py).map_err(|e| {
            Stop::Rel(ReliabilityError::Evaluator(format!(
                "the executor's answer: expected a list of rows of floats, one margin per failure mode ({e})"
            )))
        })
    })
}

/// The reliability analysis; returns the CLI's JSON object as Python
/// objects (a dict, no text in between). `evaluate`: `None` for every
/// local core, or a callable taking a float64 matrix (one row per point)
/// and returning the margins of each row, one per failure mode (the
/// `margins` of `simulate_batch`; the package sends the rows to an
/// executor); an exception it raises is raised here as it is. The GIL is
/// released while the analysis runs (taken back for each call of
/// `evaluate`); Ctrl-C stops it between batches (`KeyboardInterrupt`).
#[allow(clippy::too_many_arguments)]
#[pyfunction]
#[pyo3(signature = (mechanism_toml, source, vary, fail, method, samples, target_cov, seed, from_json=None, evaluate=None, corr=Vec::new(), flight=false))]
fn reliability<'py>(
    py: Python<'py>,
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
    flight: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let (p, notes) = problem(
        mechanism_toml,
        source,
        &vary,
        &fail,
        from_json,
        &corr,
        flight,
    )?;
    let method: Method = method.parse().map_err(|e| errors::reliability(&e))?;
    // A Python exception (Ctrl-C, an executor's task) stops the run through
    // the analysis' error path and is kept here to be raised as it is.
    let mut stopped: Option<PyErr> = None;
    let est = threads::allow(py, || {
        let d = p.vary.len();
        let mut eval = |xs: &[Vec<f64>]| -> Result<Vec<Vec<f64>>, ReliabilityError> {
            let got = match &evaluate {
                None => steps::in_steps(xs, |rows| p.margins_batch(rows)),
                Some(f) => call_evaluator(f, xs, d),
            };
            got.map_err(|stop| match stop {
                Stop::Rel(e) => e,
                Stop::Py(e) => {
                    stopped = Some(e);
                    ReliabilityError::Evaluator("stopped by a Python exception".into())
                }
            })
        };
        let quiet = &progress::quiet;
        estimate(&p, method, samples, target_cov, seed, &mut eval, quiet)
    });
    let est = match (est, stopped) {
        (_, Some(e)) => return Err(e),
        (Err(e), None) => return Err(errors::reliability(&e)),
        (Ok(est), None) => est,
    };
    // What the CLI says on stderr and writes in its JSON's `warnings`, in
    // the result's `warnings` and each as a `UserWarning`; a check that
    // cannot run costs nothing of the result either.
    let mut said = notes;
    said.extend(threads::allow(py, || {
        warnings(&p, &est, target_cov, &|q| errors::argument(q).to_string())
    }));
    for w in &said {
        let text =
            std::ffi::CString::new(w.as_str()).map_err(|e| PyValueError::new_err(e.to_string()))?;
        // Level 2: the warning points at the user's call of
        // `deploywatch.reliability`, not at the package's call of this.
        PyErr::warn(py, &py.get_type::<PyUserWarning>(), &text, 2)?;
    }
    let mut json = est.to_json(&p, seed);
    json["warnings"] = serde_json::json!(said);
    convert::to_py(py, &json)
}

/// The extension module `deploywatch._native`.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    threads::imported();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<model::Model>()?;
    m.add_class::<monitor::Monitor>()?;
    m.add_function(wrap_pyfunction!(commands::run_command, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_batch, m)?)?;
    m.add_function(wrap_pyfunction!(reliability, m)?)?;
    m.add_function(wrap_pyfunction!(parameters, m)?)?;
    m.add_function(wrap_pyfunction!(check_vary, m)?)?;
    Ok(())
}
