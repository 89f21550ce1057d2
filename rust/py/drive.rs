//! `rigidrs.Drive`: a joint drive's description, given to `Scene.add_joint`.

use pyo3::prelude::*;

use super::convert::float_array;
use crate::articulation::{Drive, DriveMode};

/// A joint drive. `mode`: "position" (force `stiffness·(target − q) − damping·q̇`)
/// or "velocity" (force `damping·(target − q̇)`); `target`: rad or m (hinge,
/// prismatic; position) or rad/s, m/s (velocity); for a spherical joint a
/// quaternion (x, y, z, w) of body a relative to its build pose (position) or an
/// angular velocity (3,) in a's frame (velocity). `stiffness` N·m/rad or N/m,
/// `damping` N·m·s/rad or N·s/m (defaults 0), `max_force` N·m or N (default inf).
#[pyclass(name = "Drive", module = "rigidrs._core", frozen)]
#[derive(Clone)]
pub struct PyDrive {
    pub inner: Drive,
}

#[pymethods]
impl PyDrive {
    #[new]
    #[pyo3(signature = (mode="position", target=None, stiffness=0.0, damping=0.0, max_force=f64::INFINITY))]
    fn new(mode: &str, target: Option<&Bound<'_, PyAny>>, stiffness: f64, damping: f64, max_force: f64) -> PyResult<Self> {
        let mode = match mode {
            "position" => DriveMode::Position,
            "velocity" => DriveMode::Velocity,
            _ => {
                return Err(super::errors::RigidError::new_err(format!(
                    "Drive mode: unknown mode {mode:?}; choose \"position\" or \"velocity\""
                )))
            }
        };
        let target = match target {
            Some(t) => float_array(t, "Drive target")?.0,
            None => vec![0.0],
        };
        Ok(Self { inner: Drive { mode, target, stiffness, damping, max_force } })
    }

    #[getter]
    fn mode(&self) -> &'static str {
        match self.inner.mode {
            DriveMode::Position => "position",
            DriveMode::Velocity => "velocity",
        }
    }

    #[getter]
    fn target(&self) -> Vec<f64> {
        self.inner.target.clone()
    }

    #[getter]
    fn stiffness(&self) -> f64 {
        self.inner.stiffness
    }

    #[getter]
    fn damping(&self) -> f64 {
        self.inner.damping
    }

    #[getter]
    fn max_force(&self) -> f64 {
        self.inner.max_force
    }

    fn __repr__(&self) -> String {
        format!(
            "Drive(mode={:?}, target={:?}, stiffness={}, damping={}, max_force={})",
            self.mode(),
            self.inner.target,
            self.inner.stiffness,
            self.inner.damping,
            self.inner.max_force
        )
    }
}
