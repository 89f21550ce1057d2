//! `world.joints`: NumPy views of the joints' read-back and control arrays.
//! Like the body views, each is the world's own memory (its base is the world,
//! so it keeps the world alive); `target` is writable, the rest read-only.

use pyo3::prelude::*;

use super::views::view;
use super::world::PyWorld;

/// The joints of a world, as views of (J,) arrays, J = the scene's joints.
#[pyclass(name = "Joints", module = "rigidrs._core", frozen)]
pub struct PyJoints {
    pub world: Py<PyWorld>,
}

#[derive(Clone, Copy)]
enum Field {
    Position,
    Velocity,
    Target,
    Force,
}

impl PyJoints {
    fn field<'py>(&self, py: Python<'py>, field: Field) -> PyResult<Bound<'py, PyAny>> {
        let w = self.world.bind(py);
        let (ptr, n, writable) = {
            let g = w.try_borrow()?;
            let inner = &g.inner;
            let (v, writable) = match field {
                Field::Position => (&inner.joint_position, false),
                Field::Velocity => (&inner.joint_velocity, false),
                Field::Target => (&inner.joint_target, true),
                Field::Force => (&inner.joint_force, false),
            };
            if writable {
                g.guard.expose(crate::world::guard::exposed::TARGET);
            }
            (v.as_ptr(), v.len(), writable)
        };
        // Safety: a Vec of the world allocated at build and never reallocated;
        // the view's base is the world object.
        unsafe { view(w, ptr, &[n], writable) }
    }
}

#[pymethods]
impl PyJoints {
    fn __len__(&self, py: Python<'_>) -> PyResult<usize> {
        Ok(self.world.bind(py).try_borrow()?.inner.joint_position.len())
    }

    /// (J,) hinge angle (rad) or prismatic slide (m) of body a relative to body b
    /// since build; NaN for other kinds. Read-only, refreshed by each step.
    #[getter]
    fn position<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::Position)
    }

    /// (J,) its rate (rad/s or m/s); NaN for other kinds. Read-only.
    #[getter]
    fn velocity<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::Velocity)
    }

    /// (J,) drive target of 1-dof drives (rad, m, rad/s or m/s by the drive's
    /// mode); writable, read at the next step. Ignored for joints without one.
    #[getter]
    fn target<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::Target)
    }

    /// (J,) generalized force the joint's drive, damping, friction and limits
    /// applied to body a over the last step, averaged (N·m or N; XPBD hinges and
    /// slides: the constraint couple or force along the axis); NaN for joints
    /// without a single coordinate. Read-only.
    #[getter]
    fn force<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::Force)
    }

    /// The joints' names (`add_joint(name=...)`; "" where none was given).
    #[getter]
    fn names(&self, py: Python<'_>) -> PyResult<Vec<String>> {
        Ok(self.world.bind(py).try_borrow()?.inner.joint_names.clone())
    }
}
