//! `Snapshot`: a frozen copy of a world, to restore, copy or save; pickling
//! and copying of worlds and scenes; `World.save` and `load`.

use std::path::{Path, PathBuf};

use pyo3::exceptions::{PyFileNotFoundError, PyIsADirectoryError, PyOSError, PyPermissionError};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use super::errors::IntoPy;
use super::scene::PyScene;
use super::world::PyWorld;
use crate::world::{Scene, World};

/// Everything a step reads, frozen: `world.restore(snap)` makes the world
/// step on bit for bit as it would have from the moment of the snapshot.
#[pyclass(name = "Snapshot", module = "rigidrs._core", frozen)]
pub struct PySnapshot {
    pub world: World,
}

#[pymethods]
impl PySnapshot {
    /// Simulated time of the snapshot (s).
    #[getter]
    fn time(&self) -> f64 {
        self.world.time()
    }

    /// Steps the world had taken at the snapshot.
    #[getter]
    fn steps(&self) -> u64 {
        self.world.steps()
    }

    /// The snapshot as bytes: a header (magic, format and engine version,
    /// length, CRC-32) and the state.
    fn to_bytes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        Ok(PyBytes::new(py, &self.world.to_bytes().py_err()?))
    }

    /// The snapshot `data` holds. Foreign, truncated or corrupted data, or
    /// data of another rigidrs version, raises `RigidError` (a `ValueError`)
    /// saying which.
    #[staticmethod]
    fn from_bytes(data: &[u8]) -> PyResult<PySnapshot> {
        Ok(PySnapshot { world: World::from_bytes(data).py_err()? })
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyBytes>,))> {
        let data = slf.get().to_bytes(slf.py())?;
        Ok((slf.get_type().getattr("from_bytes")?, (data,)))
    }

    fn __repr__(&self) -> String {
        format!("Snapshot(bodies={}, time={})", self.world.bodies.len(), self.world.time())
    }
}

/// The OSError subclass of `e`, with the path in its message.
fn os_error(path: &Path, e: std::io::Error) -> PyErr {
    let msg = format!("{}: {e}", path.display());
    match e.kind() {
        std::io::ErrorKind::NotFound => PyFileNotFoundError::new_err(msg),
        std::io::ErrorKind::PermissionDenied => PyPermissionError::new_err(msg),
        std::io::ErrorKind::IsADirectory => PyIsADirectoryError::new_err(msg),
        _ => PyOSError::new_err(msg),
    }
}

/// Writes `data` to a temporary file beside `path`, then renames it over
/// `path`: a crash mid-write leaves the old file (or none), never half of one.
fn write_atomic(path: &Path, data: &[u8]) -> PyResult<()> {
    let name = path.file_name().ok_or_else(|| PyIsADirectoryError::new_err(format!("{}: not a file name", path.display())))?;
    let mut tmp_name = name.to_os_string();
    tmp_name.push(format!(".tmp-{}", std::process::id()));
    let tmp = path.with_file_name(tmp_name);
    let written = std::fs::File::create(&tmp).and_then(|mut f| {
        std::io::Write::write_all(&mut f, data)?;
        f.sync_all()
    });
    if let Err(e) = written.and_then(|_| std::fs::rename(&tmp, path)) {
        let _ = std::fs::remove_file(&tmp);
        return Err(os_error(path, e));
    }
    Ok(())
}

/// The world saved in the file `path` by `World.save`. A missing file raises
/// `FileNotFoundError`; a file that is not a snapshot of this rigidrs version,
/// or is truncated or corrupted, `RigidError` (a `ValueError`) saying which.
#[pyfunction]
pub fn load(py: Python<'_>, path: PathBuf) -> PyResult<PyWorld> {
    let data = std::fs::read(&path).map_err(|e| os_error(&path, e))?;
    let world = py.detach(|| World::from_bytes(&data)).map_err(|e| e.context(format!("{}", path.display()))).py_err()?;
    Ok(PyWorld::new(world))
}

#[pymethods]
impl PyWorld {
    /// A copy of everything a step reads (state, applied forces, time,
    /// contacts and warm starts, sleep, multipliers, plastic shapes).
    fn snapshot(&self) -> PySnapshot {
        PySnapshot { world: self.inner.clone() }
    }

    /// Makes this world `snap` again; views taken before stay valid and show
    /// the restored values. `snap` must have this world's numbers of bodies,
    /// particles and joints, else `RigidError` and nothing changes.
    fn restore(&mut self, snap: &PySnapshot) -> PyResult<()> {
        self.guard.invalidate();
        self.inner.restore(&snap.world).py_err()
    }

    /// Saves the world's snapshot to the file `path` (written to a temporary
    /// name beside it, then renamed); `rigidrs.load(path)` reads it back.
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let data = py.detach(|| self.inner.to_bytes()).py_err()?;
        write_atomic(&path, &data)
    }

    /// An independent world in the same state (also `copy.copy`).
    fn __copy__(&self) -> PyWorld {
        PyWorld::new(self.inner.clone())
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> PyWorld {
        PyWorld::new(self.inner.clone())
    }

    /// Pickles as its snapshot bytes.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyBytes>,))> {
        let data = slf.try_borrow()?.inner.to_bytes().py_err()?;
        Ok((slf.get_type().getattr("_from_bytes")?, (PyBytes::new(slf.py(), &data),)))
    }

    #[staticmethod]
    fn _from_bytes(data: &[u8]) -> PyResult<PyWorld> {
        Ok(PyWorld::new(World::from_bytes(data).py_err()?))
    }
}

#[pymethods]
impl PyScene {
    fn __copy__(&self, py: Python<'_>) -> PyScene {
        let import_report = self.import_report.as_ref().map(|r| r.clone_ref(py));
        PyScene { inner: self.inner.clone(), import_report }
    }

    fn __deepcopy__(&self, py: Python<'_>, memo: &Bound<'_, PyAny>) -> PyResult<PyScene> {
        let copy = py.import("copy")?.getattr("deepcopy")?;
        let import_report = match &self.import_report {
            Some(r) => Some(copy.call1((r.bind(py), memo))?.unbind()),
            None => None,
        };
        Ok(PyScene { inner: self.inner.clone(), import_report })
    }

    /// Pickles as bytes in the snapshot frame (and the import report, if any, as state).
    #[allow(clippy::type_complexity)]
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyBytes>,), Option<Py<PyAny>>)> {
        let this = slf.try_borrow()?;
        let data = this.inner.to_bytes().py_err()?;
        let state = this.import_report.as_ref().map(|r| r.clone_ref(slf.py()));
        Ok((slf.get_type().getattr("_from_bytes")?, (PyBytes::new(slf.py(), &data),), state))
    }

    fn __setstate__(&mut self, state: Option<Py<PyAny>>) {
        self.import_report = state;
    }

    #[staticmethod]
    fn _from_bytes(data: &[u8]) -> PyResult<PyScene> {
        Ok(PyScene { inner: Scene::from_bytes(data).py_err()?, import_report: None })
    }
}
