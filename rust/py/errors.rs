//! The Python exceptions: every `crate::Error` becomes a `RigidError` (a
//! `ValueError`) or one of its subclasses, with the message naming the body/field.

use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyType};

use crate::error::{Error, ErrorKind};

create_exception!(rigidrs, RigidError, PyValueError, "Invalid input to rigidrs; the message names the body or field.");
create_exception!(rigidrs, ShapeError, RigidError, "A degenerate shape: no volume, an open mesh, too few points.");
create_exception!(rigidrs, StateError, RigidError, "A world's state (written through a view) is invalid at step.");

/// `SimulationError(StateError, RuntimeError)`: a step diverged or failed
/// inside and was undone. A `StateError` (what a blow-up raised before), and a
/// `RuntimeError` (what it is); made at import, as a class of two bases.
static SIMULATION_ERROR: PyOnceLock<Py<PyType>> = PyOnceLock::new();

const SIMULATION_DOC: &str = "A step diverged (a body or particle not finite) or failed inside; the message names the \
body or particle, the stage and the time. The world is as it was before that step and can step on.";

fn simulation_error(py: Python<'_>) -> PyResult<&Py<PyType>> {
    SIMULATION_ERROR.get_or_try_init(py, || {
        let builtins = py.import("builtins")?;
        let bases = (py.get_type::<StateError>(), builtins.getattr("RuntimeError")?);
        let ns = PyDict::new(py);
        ns.set_item("__module__", "rigidrs")?;
        ns.set_item("__doc__", SIMULATION_DOC)?;
        let t = builtins.getattr("type")?.call1(("SimulationError", bases, ns))?;
        Ok(t.cast_into::<PyType>()?.unbind())
    })
}

pub fn to_py(e: Error) -> PyErr {
    match e.kind {
        ErrorKind::Input => RigidError::new_err(e.message),
        ErrorKind::Shape => ShapeError::new_err(e.message),
        ErrorKind::State => StateError::new_err(e.message),
        ErrorKind::Simulation => Python::attach(|py| match simulation_error(py) {
            Ok(t) => PyErr::from_type(t.bind(py).clone(), e.message),
            Err(err) => err,
        }),
    }
}

/// `Result<T, Error>` → `PyResult<T>`.
pub trait IntoPy<T> {
    fn py_err(self) -> PyResult<T>;
}

impl<T> IntoPy<T> for crate::Result<T> {
    fn py_err(self) -> PyResult<T> {
        self.map_err(to_py)
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("RigidError", py.get_type::<RigidError>())?;
    m.add("ShapeError", py.get_type::<ShapeError>())?;
    m.add("StateError", py.get_type::<StateError>())?;
    m.add("SimulationError", simulation_error(py)?.bind(py))?;
    Ok(())
}
