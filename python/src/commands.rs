//! The CLI's commands run in this process (`diagnose`, `identify`,
//! `margin`, `replay`): the arguments parsed by the CLI's own parser, the
//! work done by the CLI's own `run` (same validation, same numbers, the
//! same files written), with the GIL released. The package's Python layer
//! builds the arguments from its keyword arguments and reads the JSON the
//! command wrote; errors name the Python arguments ([`crate::errors`]);
//! its warnings are raised as `UserWarning`s.

use crate::errors::Kind;
use clap::Parser;
use deploywatch_sim::cli::{self, Cli};
use pyo3::exceptions::PyUserWarning;
use pyo3::prelude::*;

/// The first line of clap's message without its `error: ` (what the
/// binary prints first), with what it lists below a line ending in `:`
/// (the required arguments not given) and the values clap lists as
/// possible, when it lists them.
fn clap_message(e: &clap::Error) -> String {
    let text = e.render().to_string();
    let first = text.lines().next().unwrap_or_default();
    let mut m = first.strip_prefix("error: ").unwrap_or(first).to_string();
    // A first line ending in `:` lists on the indented lines below it
    // (the required arguments not given).
    if m.ends_with(':') {
        let listed: Vec<&str> = text
            .lines()
            .skip(1)
            .take_while(|l| l.starts_with("  "))
            .map(str::trim)
            .collect();
        m.push(' ');
        m.push_str(&listed.join(", "));
    }
    if let Some(values) = text
        .lines()
        .find(|l| l.trim_start().starts_with("[possible values:"))
    {
        m.push(' ');
        m.push_str(values.trim());
    }
    m
}

/// `text` with each file of `names` (`(path, name)`) called by its name.
fn renamed(text: &str, names: &[(String, String)]) -> String {
    names
        .iter()
        .fold(text.to_string(), |t, (path, name)| t.replace(path, name))
}

/// Runs `deploywatch ARGS...` in this process: `InputError` for what the
/// binary exits 2 on (a bad argument, file or path), `DeploywatchError`
/// for what it exits 1 on (the work failed). The GIL is released while it
/// runs. `names` (`(path, name)`): files the package wrote for the call
/// (a mechanism given in memory), called in the errors and warnings by
/// the name the user knows them by, not by a path deleted after the call.
#[pyfunction]
#[pyo3(signature = (args, names=Vec::new()))]
pub(crate) fn run_command(
    py: Python<'_>,
    args: Vec<String>,
    names: Vec<(String, String)>,
) -> PyResult<()> {
    let argv = std::iter::once("deploywatch".to_string()).chain(args);
    let parsed = Cli::try_parse_from(argv)
        .map_err(|e| Kind::Input.raise(renamed(&clap_message(&e), &names), Vec::new()))?;
    let (done, warnings) =
        crate::threads::allow(py, || cli::capturing_warnings(|| cli::run(parsed)));
    // What the binary says on stderr as `warning: …`, each a `UserWarning`
    // (level 3: the user's call of the package's function, which calls
    // this through its `_run`), also when the command then failed.
    for w in &warnings {
        let text = std::ffi::CString::new(crate::errors::pythonic(&renamed(w, &names)))
            .map_err(|e| Kind::Other.raise(e.to_string(), Vec::new()))?;
        PyErr::warn(py, &py.get_type::<PyUserWarning>(), &text, 3)?;
    }
    done.map_err(|e| {
        let kind = if e.code == 2 {
            Kind::Input
        } else {
            Kind::Other
        };
        kind.raise(renamed(&e.message, &names), Vec::new())
    })
}
