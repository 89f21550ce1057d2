//! `Snapshot`: a frozen copy of a world, to restore, copy or save.

use pyo3::prelude::*;

use super::errors::IntoPy;
use super::world::PyWorld;
use crate::world::World;

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

    fn __repr__(&self) -> String {
        format!("Snapshot(bodies={}, time={})", self.world.bodies.len(), self.world.time())
    }
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
        self.inner.restore(&snap.world).py_err()
    }

    /// An independent world in the same state (also `copy.copy`).
    fn __copy__(&self) -> PyWorld {
        PyWorld::new(self.inner.clone())
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> PyWorld {
        PyWorld::new(self.inner.clone())
    }
}
