//! A mechanism parsed once (`deploywatch._native.Model`, wrapped by the
//! package's `Mechanism`): its parts as plain values for the typed
//! attributes, one deployment of it, and the validation of effect strings
//! that the CLI's `simulate` does (`Effect::validate` against the
//! mechanism's joints, then `check_latch_effects`), with the argument's
//! name where the CLI names its flag.

use crate::errors::Kind;
use deploywatch_sim::deployment::{self, SimOptions, Trajectory};
use deploywatch_sim::effect::Effect;
use deploywatch_sim::latch_deployment::{check_latch_effects, simulate_physical};
use deploywatch_sim::mechanism::{Mechanism, SpringSpec};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The effects of argument `arg`, parsed and checked against the mechanism
/// by the CLI's own checks: `"{arg}[i]: {parse error}"`, `"{arg}[i] {effect}:
/// {what is wrong}"` where the CLI says `--effect {effect}: {what is
/// wrong}` (a latch effect on a joint without a physical latch too).
pub(crate) fn effects(mech: &Mechanism, arg: &str, items: &[String]) -> PyResult<Vec<Effect>> {
    let mut out = Vec::with_capacity(items.len());
    for (i, s) in items.iter().enumerate() {
        let e: Effect = s
            .parse()
            .map_err(|e| Kind::Input.prefixed(&format!("{arg}[{i}]: "), &e))?;
        e.validate(mech.effect_joints())
            .map_err(|m| Kind::Input.prefixed(&format!("{arg}[{i}] {e}: "), &m))?;
        check_latch_effects(mech, std::slice::from_ref(&e))
            .map_err(|m| Kind::Input.prefixed(&format!("{arg}[{i}] "), &m))?;
        if e.kind().is_sensor() {
            return Err(Kind::Input.raise(
                format!(
                    "{arg}[{i}] {e}: acts on the encoder's reading, not on the motion \
                     `simulate` returns (`deploywatch simulate` writes the reading to its run CSV)"
                ),
                Vec::new(),
            ));
        }
        out.push(e);
    }
    Ok(out)
}

/// One deployment as the CLI's `simulate` runs it: the physical latches'
/// contact model when the mechanism has one, the chain's otherwise. Call
/// with the GIL released.
pub(crate) fn deploy(
    mech: &Mechanism,
    effects: &[Effect],
    opts: &SimOptions,
) -> Result<Trajectory, deployment::SimError> {
    if mech.has_physical_latch() {
        let grid = deployment::sample_grid(mech, opts)?;
        Ok(simulate_physical(mech, effects, opts, grid)?.traj)
    } else {
        deployment::simulate(mech, effects, opts)
    }
}

/// A mechanism file parsed once.
#[pyclass(frozen, module = "deploywatch._native")]
pub(crate) struct Model {
    /// The mechanism.
    pub(crate) mech: Mechanism,
    /// The file's text (what a remote worker is sent).
    #[pyo3(get)]
    text: String,
    /// The file's name, in error messages.
    #[pyo3(get)]
    source: String,
}

#[pymethods]
impl Model {
    /// The mechanism of TOML `text` read from `source` (a file name, for the
    /// messages); `MechanismError` naming the file, line and key.
    #[new]
    fn new(text: String, source: String) -> PyResult<Self> {
        let mech = crate::mechanism(&text, &source)?;
        Ok(Model { mech, text, source })
    }

    /// The effect strings checked against this mechanism, as the CLI
    /// checks `--effect`; returns them in the canonical syntax.
    fn check_effects(&self, arg: &str, items: Vec<String>) -> PyResult<Vec<String>> {
        Ok(effects(&self.mech, arg, &items)?
            .iter()
            .map(|e| e.to_string())
            .collect())
    }

    /// The values of the mechanism that are valid but unlikely (a mass in
    /// grams, angles in radians, a spring that cannot deploy), as the CLI
    /// warns of them: `file:line: key: message`.
    fn implausible(&self) -> Vec<String> {
        deploywatch_sim::plausibility::warnings_in(&self.mech, Some(&self.text), &self.source)
    }

    /// The mechanism's parts as dicts of plain values (the package makes
    /// them dataclasses): `name`, `description`, `duration_s`, `sample_hz`,
    /// `settle_s`, `panels`, `joints`, `latches` (one per joint, `None` for
    /// the ideal latch), `rig` (`None` without one), `truss` (bool).
    fn describe<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        describe(py, &self.mech)
    }
}

/// The dict of [`Model::describe`].
fn describe<'py>(py: Python<'py>, m: &Mechanism) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("name", &m.name)?;
    d.set_item("description", &m.description)?;
    d.set_item("duration_s", m.duration_s)?;
    d.set_item("sample_hz", m.sample_hz)?;
    d.set_item("settle_s", m.settle_s)?;
    d.set_item("truss", m.truss.is_some())?;
    let mut panels = Vec::new();
    for (i, p) in m.panels.iter().enumerate() {
        let x = PyDict::new(py);
        x.set_item("length_m", p.length_m)?;
        x.set_item("mass_kg", p.mass_kg)?;
        x.set_item("com_m", p.com_m)?;
        x.set_item("inertia_kgm2", p.inertia_kgm2)?;
        let tol = m.mass_tolerance(i);
        x.set_item("mass_tolerance_pct", tol.mass_pct)?;
        x.set_item("inertia_tolerance_pct", tol.inertia_pct)?;
        panels.push(x);
    }
    d.set_item("panels", panels)?;
    let mut joints = Vec::new();
    for j in &m.joints {
        let x = PyDict::new(py);
        x.set_item("stowed_deg", j.stowed_deg)?;
        let (kind, count) = match &j.spring {
            SpringSpec::Linear { count, .. } => ("linear", *count),
            SpringSpec::Tape { count, .. } => ("tape", *count),
            SpringSpec::Curve { count, .. } => ("curve", *count),
        };
        x.set_item("spring", kind)?;
        x.set_item("spring_count", count)?;
        x.set_item("coulomb_nm", j.friction.coulomb_nm)?;
        x.set_item("viscous_nms", j.friction.viscous_nms)?;
        x.set_item("free_play_deg", j.free_play_deg)?;
        x.set_item("spring_tolerance_pct", j.spring_tolerance_pct)?;
        joints.push(x);
    }
    d.set_item("joints", joints)?;
    let mut latches = Vec::new();
    for j in 0..m.joint_count() {
        latches.push(match m.latch(j) {
            None => None,
            Some(l) => {
                let x = PyDict::new(py);
                x.set_item("switch_travel_deg", l.switch_travel_deg)?;
                x.set_item("magnet", l.magnet.is_some())?;
                x.set_item(
                    "pawl_breaking_torque_nm",
                    l.pawl.map(|p| p.breaking_torque_nm),
                )?;
                Some(x)
            }
        });
    }
    d.set_item("latches", latches)?;
    let rig = match &m.rig {
        None => None,
        Some(r) => {
            let x = PyDict::new(py);
            x.set_item("enabled", r.enabled)?;
            x.set_item("gravity_m_s2", r.gravity_m_s2)?;
            x.set_item("static_mu", r.static_mu)?;
            x.set_item("dynamic_mu", r.dynamic_mu)?;
            let ts: Vec<(usize, f64, f64, f64)> = r
                .trolleys
                .iter()
                .map(|t| (t.panel, t.offload_m, t.mass_kg, t.wire_m))
                .collect();
            x.set_item("trolleys", ts)?;
            Some(x)
        }
    };
    d.set_item("rig", rig)?;
    Ok(d)
}
