//! The Python exceptions: every `crate::Error` becomes a `RigidError` (a
//! `ValueError`) or one of its subclasses, with the message naming the body/field.

use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::error::{Error, ErrorKind};

create_exception!(rigidrs, RigidError, PyValueError, "Invalid input to rigidrs; the message names the body or field.");
create_exception!(rigidrs, ShapeError, RigidError, "A degenerate shape: no volume, an open mesh, too few points.");
create_exception!(rigidrs, StateError, RigidError, "A world's state (written through a view) is invalid at step.");

pub fn to_py(e: Error) -> PyErr {
    match e.kind {
        ErrorKind::Input => RigidError::new_err(e.message),
        ErrorKind::Shape => ShapeError::new_err(e.message),
        ErrorKind::State => StateError::new_err(e.message),
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
    Ok(())
}
