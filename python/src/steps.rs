//! Long batches cut into steps with a look at Python's signals between two
//! steps, so that Ctrl-C stops a long call (`KeyboardInterrupt`) instead of
//! being seen only when it returns. Each row is a deterministic deployment,
//! so the steps change no bit of the result.

use deploywatch_sim::reliability::ReliabilityError;
use pyo3::prelude::*;

/// Why a batch stopped: Python (a signal, an error raised by Python code),
/// or the analysis.
pub(crate) enum Stop {
    /// A Python exception, raised as it is.
    Py(PyErr),
    /// The analysis' error, turned into the package's exception.
    Rel(ReliabilityError),
}

impl From<PyErr> for Stop {
    fn from(e: PyErr) -> Self {
        Stop::Py(e)
    }
}

impl From<ReliabilityError> for Stop {
    fn from(e: ReliabilityError) -> Self {
        Stop::Rel(e)
    }
}

impl Stop {
    /// The Python exception.
    pub(crate) fn into_py(self) -> PyErr {
        match self {
            Stop::Py(e) => e,
            Stop::Rel(e) => crate::errors::reliability(&e),
        }
    }
}

/// Rows per step: 256 per core, about 0.1 s of deployments on a core.
fn step_rows() -> usize {
    256 * std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// Python's pending signals (Ctrl-C), checked with the GIL taken for the
/// check only. Called with the GIL released; in a thread other than the
/// main one it finds nothing (Python handles signals in the main thread).
pub(crate) fn check_signals() -> PyResult<()> {
    Python::with_gil(|py| py.check_signals())
}

/// `f` over the rows of `xs`, step by step, with a check of the signals
/// before each step; call with the GIL released.
pub(crate) fn in_steps<T>(
    xs: &[Vec<f64>],
    f: impl Fn(&[Vec<f64>]) -> Result<Vec<T>, ReliabilityError>,
) -> Result<Vec<T>, Stop> {
    let mut out = Vec::with_capacity(xs.len());
    for step in xs.chunks(step_rows()) {
        check_signals()?;
        out.extend(f(step)?);
    }
    Ok(out)
}
