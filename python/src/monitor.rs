//! The on-board monitor from Python (`deploywatch._native.Monitor`): the
//! core's `Monitor<N>` configured from a parsed mechanism as `replay`
//! configures it (`monitor_config`), fed one sample at a time
//! (`replay_step`, what `replay` calls), each status returned as
//! the dict of its serde form (the fields of `deploywatch_core::monitor::Status`).

use crate::errors::Kind;
use deploywatch_core::monitor::{Monitor as CoreMonitor, Sample};
use deploywatch_sim::monitor_config::monitor_config;
use pyo3::prelude::*;

/// A monitor of `N` joints, boxed (the core's monitor is large).
macro_rules! sized {
    ($($v:ident = $n:literal),*) => {
        /// The monitor for the mechanism's joint count.
        enum Sized { $($v(Box<CoreMonitor<$n>>)),* }

        impl Sized {
            /// The monitor of a mechanism of 1 to 8 joints.
            fn of(mech: &deploywatch_sim::mechanism::Mechanism) -> PyResult<Sized> {
                let bad = |m: String| Kind::Input.raise(m, Vec::new());
                match mech.joint_count() {
                    $($n => {
                        let cfg = monitor_config::<$n>(mech).map_err(|e| bad(e.to_string()))?;
                        let m = CoreMonitor::<$n>::new(&cfg).map_err(|e| bad(e.to_string()))?;
                        Ok(Sized::$v(Box::new(m)))
                    })*
                    n => Err(bad(format!("the monitor takes 1 to 8 joints (the core's predictor holds at most 8), the mechanism has {n}"))),
                }
            }

            /// The joint count.
            fn joints(&self) -> usize {
                match self { $(Sized::$v(_) => $n),* }
            }

            /// One sample in, the status out as JSON.
            fn update(&mut self, t_s: f32, phi: &[f32], latch: &[bool]) -> serde_json::Result<serde_json::Value> {
                match self {
                    $(Sized::$v(m) => {
                        let s = Sample::new(
                            t_s,
                            core::array::from_fn(|j| phi[j]),
                            core::array::from_fn(|j| latch[j]),
                        );
                        serde_json::to_value(m.replay_step(&s))
                    })*
                }
            }
        }
    };
}

// The core's predictor holds at most 8 joints (`ROLLOUT_MAX_JOINTS`).
sized!(
    One = 1,
    Two = 2,
    Three = 3,
    Four = 4,
    Five = 5,
    Six = 6,
    Seven = 7,
    Eight = 8
);

/// The core's monitor of a parsed mechanism.
#[pyclass(module = "deploywatch._native")]
pub(crate) struct Monitor {
    /// The monitor.
    inner: Sized,
}

#[pymethods]
impl Monitor {
    /// The monitor of `model`, configured as `replay` configures it.
    #[new]
    fn new(model: &crate::model::Model) -> PyResult<Self> {
        Ok(Monitor {
            inner: Sized::of(&model.mech)?,
        })
    }

    /// The joint count.
    #[getter]
    fn joints(&self) -> usize {
        self.inner.joints()
    }

    /// One sample: time \[s\], the encoder angle of each joint \[deg\] (NaN
    /// for a missing reading), each latch switch (closed = true); returns
    /// the status as a dict (the fields of the core's `Status`).
    fn update<'py>(
        &mut self,
        py: Python<'py>,
        t_s: f32,
        phi_deg: Vec<f32>,
        latch: Vec<bool>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let n = self.inner.joints();
        if phi_deg.len() != n || latch.len() != n {
            return Err(Kind::Input.raise(
                format!(
                    "sample: expected {n} angles and {n} latch switches (one per joint), got {} and {}",
                    phi_deg.len(),
                    latch.len()
                ),
                Vec::new(),
            ));
        }
        let v = self
            .inner
            .update(t_s, &phi_deg, &latch)
            .map_err(|e| Kind::Other.raise(e.to_string(), Vec::new()))?;
        crate::convert::to_py(py, &v)
    }
}
