//! Python bindings (feature `python`): a thin layer that converts, validates at the
//! boundary, and maps [`crate::Error`] to Python exceptions.

mod batch;
mod convert;
mod drive;
mod joint_views;
mod errors;
mod joints;
mod mass;
mod polar;
mod recipe;
mod recording;
mod shape_readback;
mod particles;
mod scene;
mod shadow;
mod shapes;
mod snapshot;
mod threads;
mod views;
mod world;

use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::integrate::Integrator;

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    errors::register(m)?;
    shapes::register(m)?;
    m.add_class::<mass::PyMassProperties>()?;
    m.add_function(wrap_pyfunction!(mass::mass_properties, m)?)?;
    m.add_function(wrap_pyfunction!(polar::polar_decomposition, m)?)?;
    m.add_class::<scene::PyScene>()?;
    m.add_class::<world::PyWorld>()?;
    m.add_class::<views::PyBodies>()?;
    m.add_class::<particles::PyParticles>()?;
    m.add_class::<drive::PyDrive>()?;
    m.add_class::<joint_views::PyJoints>()?;
    m.add_class::<snapshot::PySnapshot>()?;
    m.add_function(wrap_pyfunction!(snapshot::load, m)?)?;
    m.add_class::<recording::PyRecording>()?;
    m.add_class::<batch::PyBatch>()?;
    m.add_class::<batch::PyBatchBodies>()?;
    let integrators = PyDict::new(py);
    for i in Integrator::ALL {
        integrators.set_item(i.name(), i.order())?;
    }
    m.add("INTEGRATORS", integrators)?;
    let art = PyDict::new(py);
    for i in crate::articulation::ArticulationIntegrator::ALL {
        art.set_item(i.name(), i.order())?;
    }
    m.add("ARTICULATION_INTEGRATORS", art)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
