//! Rust errors as the package's exceptions (`deploywatch._errors`): the
//! class says the kind of failure, the message is the Rust error's
//! `Display` (the CLI's words), `__cause__` and `causes` its `source()`
//! chain. The classes are plain Python classes, so they pickle and cross a
//! Dask worker's boundary as themselves.

use deploywatch_sim::deployment::SimError;
use deploywatch_sim::reliability::{Param, ReliabilityError};
use pyo3::prelude::*;
use std::error::Error;

/// Which exception class of `deploywatch` an error becomes.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Kind {
    /// `InputError` (a `ValueError`): an argument is not usable.
    Input,
    /// `MechanismError` (an `InputError`): the mechanism file is not valid.
    Mechanism,
    /// `SimulationError` (a `RuntimeError`): a deployment failed.
    Simulation,
    /// `EvaluatorError` (a `RuntimeError`): the executor's answer is unusable.
    Evaluator,
    /// `DeploywatchError`: none of the above.
    Other,
}

impl Kind {
    /// The key of the class in `deploywatch._errors._KINDS`.
    fn key(self) -> &'static str {
        match self {
            Kind::Input => "input",
            Kind::Mechanism => "mechanism",
            Kind::Simulation => "simulation",
            Kind::Evaluator => "evaluator",
            Kind::Other => "error",
        }
    }

    /// The exception for a message with the given causes (outermost first),
    /// the CLI's flags in them named as the Python arguments ([`pythonic`]).
    pub(crate) fn raise(self, message: String, causes: Vec<String>) -> PyErr {
        let message = pythonic(&message);
        let causes: Vec<String> = causes.iter().map(|c| pythonic(c)).collect();
        Python::with_gil(|py| {
            let made = py
                .import("deploywatch._errors")
                .and_then(|m| m.getattr("_from_rust"))
                .and_then(|f| f.call1((self.key(), message, causes)));
            match made {
                Ok(obj) => PyErr::from_value(obj),
                Err(e) => e,
            }
        })
    }

    /// The exception for a Rust error: its message, its source chain.
    pub(crate) fn of(self, e: &(dyn Error + 'static)) -> PyErr {
        self.prefixed("", e)
    }

    /// The exception for a Rust error about an argument: `"{arg}: {e}"`.
    pub(crate) fn prefixed(self, arg: &str, e: &(dyn Error + 'static)) -> PyErr {
        let mut causes = Vec::new();
        let mut next = e.source();
        while let Some(c) = next {
            causes.push(c.to_string());
            next = c.source();
        }
        self.raise(format!("{arg}{e}"), causes)
    }
}

/// The CLI's option names and the Python arguments that take their values
/// (the library's messages name the CLI's options).
const ARGUMENTS: [(&str, &str); 35] = [
    ("--effect", "effects"),
    ("--vary", "vary"),
    ("--fail", "fail"),
    ("--corr", "corr"),
    ("--method", "method"),
    ("--samples", "samples"),
    ("--target-cov", "target_cov"),
    ("--from", "from_"),
    ("--rate", "sample_hz"),
    ("--friction", "friction"),
    ("--standard", "standard"),
    ("--factor", "factors"),
    ("--data-source", "data_source"),
    ("--spring-tolerance", "spring_tolerance_pct"),
    ("--end-of-life", "end_of_life_pct"),
    ("--deploy-time", "deploy_time_s"),
    ("--plot", "plot"),
    ("--flight", "flight"),
    ("--json", "json"),
    ("--out", "out"),
    ("--mechanism", "mechanism"),
    ("--max-effects", "max_effects"),
    ("--max-seconds", "max_seconds"),
    ("--elf", "elf"),
    ("--port", "port"),
    ("--baud", "baud"),
    ("--duration", "duration"),
    ("--every", "every"),
    ("--drop", "drop"),
    ("--corrupt", "corrupt"),
    ("--delay", "delay"),
    ("--seed", "seed"),
    ("--icount", "icount"),
    ("--latency", "latency"),
    ("--require-deadlines", "require_deadlines"),
];

/// A message of the library with each CLI option (`--vary`, clap's
/// `--vary <VARY>`) named as the Python argument (`vary`): the words are
/// the CLI's, the names Python's.
pub(crate) fn pythonic(message: &str) -> String {
    let mut out = String::with_capacity(message.len());
    let mut rest = message;
    'scan: while let Some(at) = rest.find("--") {
        let (head, tail) = rest.split_at(at);
        out.push_str(head);
        for (flag, arg) in ARGUMENTS {
            let end = tail.as_bytes().get(flag.len()).copied();
            let whole =
                !matches!(end, Some(b) if b.is_ascii_alphanumeric() || b == b'-' || b == b'_');
            if tail.starts_with(flag) && whole {
                out.push_str(arg);
                rest = &tail[flag.len()..];
                // clap's value name after the flag: ` <VARY>`.
                if let Some(after) = rest.strip_prefix(" <") {
                    if let Some(close) = after.find('>') {
                        rest = &after[close + 1..];
                    }
                }
                continue 'scan;
            }
        }
        out.push_str("--");
        rest = &tail[2..];
    }
    out.push_str(rest);
    out
}

/// The Python argument that sets the library's parameter `p`.
pub(crate) fn argument(p: Param) -> &'static str {
    match p {
        Param::Vary => "vary",
        Param::Fixed => "from_",
        Param::Fail => "fail",
        Param::Corr => "corr",
        Param::Samples => "samples",
        other => other.name(),
    }
}

/// The exception of a reliability error: the user's input
/// ([`ReliabilityError::is_input`], each parameter named as its Python
/// argument), `Simulation` a deployment, `Evaluator` the executor's answer.
pub(crate) fn reliability(e: &ReliabilityError) -> PyErr {
    if e.is_input() {
        return Kind::Input.raise(e.words(&|p| argument(p).to_string()), Vec::new());
    }
    let kind = match e {
        ReliabilityError::Simulation { .. } => Kind::Simulation,
        ReliabilityError::Evaluator(_) => Kind::Evaluator,
        _ => Kind::Other,
    };
    kind.of(e)
}

/// The exception of a simulation error: `Invalid` (an effect the mechanism
/// cannot take) is the user's input, the rest the integration's failure.
pub(crate) fn simulation(e: &SimError) -> PyErr {
    match e {
        SimError::Invalid(_) => Kind::Input.of(e),
        _ => Kind::Simulation.of(e),
    }
}
