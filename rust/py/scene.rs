//! `Scene`: the description a world is built from.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use super::convert::{float_array, vec3, vec4};
use super::errors::IntoPy;
use super::mass::PyMassProperties;
use super::shapes::PyShape;
use super::world::PyWorld;
use crate::integrate::Integrator;
use crate::world::{BodySpec, Inertia, Scene, Settings};

/// A description of what to simulate. `gravity` (3,) in m/s², default (0, 0, −9.81).
#[pyclass(name = "Scene", module = "rigidrs._core")]
pub struct PyScene {
    inner: Scene,
}

fn inertia_arg(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Inertia> {
    let (v, shape) = float_array(obj, name)?;
    match shape.as_slice() {
        [3] => Ok(Inertia::Principal([v[0], v[1], v[2]])),
        [3, 3] => Ok(Inertia::Tensor([[v[0], v[1], v[2]], [v[3], v[4], v[5]], [v[6], v[7], v[8]]])),
        _ => Err(PyValueError::new_err(format!("{name} must have shape (3,) or (3, 3), got {shape:?}"))),
    }
}

#[pymethods]
impl PyScene {
    #[new]
    #[pyo3(signature = (gravity=None))]
    fn new(gravity: Option<&Bound<'_, PyAny>>) -> PyResult<Self> {
        let g = match gravity {
            Some(g) => vec3(g, "gravity")?,
            None => [0.0, 0.0, -9.81],
        };
        Ok(Self { inner: Scene::new(g).py_err()? })
    }

    /// Gravitational acceleration (3,) (m/s²).
    #[getter]
    fn gravity(&self) -> [f64; 3] {
        self.inner.gravity
    }

    fn __len__(&self) -> usize {
        self.inner.bodies().len()
    }

    /// Adds a body and returns its index. See the stub for the parameters.
    #[pyo3(signature = (shape=None, *, density=None, mass=None, inertia=None, mass_properties=None,
                        position=None, orientation=None, linear_velocity=None, angular_velocity=None,
                        fixed=false))]
    #[allow(clippy::too_many_arguments)]
    fn add_body(
        &mut self,
        shape: Option<PyRef<'_, PyShape>>,
        density: Option<f64>,
        mass: Option<f64>,
        inertia: Option<&Bound<'_, PyAny>>,
        mass_properties: Option<PyRef<'_, PyMassProperties>>,
        position: Option<&Bound<'_, PyAny>>,
        orientation: Option<&Bound<'_, PyAny>>,
        linear_velocity: Option<&Bound<'_, PyAny>>,
        angular_velocity: Option<&Bound<'_, PyAny>>,
        fixed: bool,
    ) -> PyResult<usize> {
        let index = self.inner.bodies().len();
        let field = |name: &str| format!("body {index}: {name}");
        let mut spec = BodySpec {
            shape: shape.map(|s| s.inner.clone()),
            density,
            mass,
            mass_properties: mass_properties.map(|m| m.inner.clone()),
            fixed,
            ..Default::default()
        };
        if let Some(i) = inertia {
            spec.inertia = Some(inertia_arg(i, &field("inertia"))?);
        }
        if let Some(p) = position {
            spec.position = vec3(p, &field("position"))?;
        }
        if let Some(q) = orientation {
            spec.orientation = vec4(q, &field("orientation"))?;
        }
        if let Some(v) = linear_velocity {
            spec.linear_velocity = vec3(v, &field("linear_velocity"))?;
        }
        if let Some(w) = angular_velocity {
            spec.angular_velocity = vec3(w, &field("angular_velocity"))?;
        }
        self.inner.add_body(spec).py_err()
    }

    /// Compiles the scene into a `World`. `dt` (s) per step; `integrator` one of
    /// `INTEGRATORS` (default "strang"); `substeps` per step (default 1).
    #[pyo3(signature = (dt, integrator="strang", substeps=1))]
    fn build(&self, dt: f64, integrator: &str, substeps: u32) -> PyResult<PyWorld> {
        let mut settings = Settings::new(dt);
        settings.integrator = Integrator::from_name(integrator).py_err()?;
        settings.substeps = substeps;
        Ok(PyWorld::new(self.inner.build(&settings).py_err()?))
    }
}
