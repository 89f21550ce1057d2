//! `World.threads`: the worker threads a world's own parallel work may use.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use super::world::PyWorld;

#[pymethods]
impl PyWorld {
    /// Worker threads the world's parallel stages use (≥ 1; the build argument
    /// `threads`, all cores by default). Settable; every count gives the same bits.
    /// Parallel today: the free rotation of 4096 or more bodies of one class; the
    /// contact solve, island by island and group by group, when the last step
    /// had two islands of support blocks or more with 128 blocks between them;
    /// in such a step, or after 8192 contact pairs or more, the narrow phase and
    /// contact-constraint build.
    #[getter]
    fn threads(&self) -> usize {
        crate::world::threads::resolve(self.inner.settings().threads)
    }

    #[setter]
    fn set_threads(&mut self, n: i64) -> PyResult<()> {
        let n = u32::try_from(n)
            .ok()
            .filter(|&n| n >= 1)
            .ok_or_else(|| PyValueError::new_err(format!("threads must be an integer in [1, 2^32), got {n}")))?;
        self.inner.set_threads(n);
        Ok(())
    }
}
