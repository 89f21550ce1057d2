//! Mass properties from Python: sampled density and the result object.

use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;

use super::convert::{rows3, scalar_or_vector, vec3};
use super::errors::IntoPy;
use crate::body::density::DensitySamples;
use crate::body::MassProps;
use crate::math::quat;

/// Mass, centre of mass and inertia of a body, and its principal form.
#[pyclass(name = "MassProperties", module = "rigidrs._core", frozen)]
#[derive(Clone)]
pub struct PyMassProperties {
    pub inner: MassProps,
}

#[pymethods]
impl PyMassProperties {
    /// Mass properties given directly: `mass` (kg), `center_of_mass` (3,) (m, default
    /// the origin) and `inertia` (3,) principal moments or (3, 3) tensor about the
    /// centre of mass (kg·m²). Checked: positive mass, finite centre, symmetric
    /// positive-definite inertia.
    #[new]
    #[pyo3(signature = (mass, center_of_mass=None, inertia=None))]
    fn new(mass: f64, center_of_mass: Option<&Bound<'_, PyAny>>, inertia: Option<&Bound<'_, PyAny>>) -> PyResult<Self> {
        let com = match center_of_mass {
            Some(c) => vec3(c, "center_of_mass")?,
            None => [0.0; 3],
        };
        let inertia = match inertia {
            Some(i) => super::scene::inertia_arg(i, "inertia")?,
            None => return Err(pyo3::exceptions::PyValueError::new_err("inertia is required: (3,) principal moments or a (3, 3) tensor (kg·m²)")),
        };
        let tensor = match inertia {
            crate::world::Inertia::Principal(m) => crate::math::Mat3::from_diagonal(&crate::math::Vec3::from(m)),
            crate::world::Inertia::Tensor(t) => crate::math::Mat3::from_fn(|r, c| t[r][c]),
        };
        let inner = MassProps { mass, com: crate::math::Vec3::from(com), inertia: tensor };
        inner.validate("MassProperties").py_err()?;
        Ok(Self { inner })
    }
    /// Mass (kg).
    #[getter]
    fn mass(&self) -> f64 {
        self.inner.mass
    }
    /// Centre of mass (3,) in the source frame (m).
    #[getter]
    fn center_of_mass<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, self.inner.com.as_slice())
    }
    /// Inertia tensor (3, 3) about the centre of mass, source-frame axes (kg·m²).
    #[getter]
    fn inertia<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix(py, &self.inner.inertia)
    }
    /// Principal moments (3,) (kg·m²), ascending unless the tensor was diagonal.
    #[getter]
    fn principal_moments<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.inner.principal().moments)
    }
    /// Principal axes (3, 3): column k is the axis of moment k (a rotation, det +1).
    #[getter]
    fn principal_axes<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix(py, &quat::to_matrix(&self.inner.principal().frame))
    }
    /// The principal axes as a quaternion (4,) (x, y, z, w).
    #[getter]
    fn principal_orientation<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &quat::to_xyzw(&self.inner.principal().frame))
    }
    fn __repr__(&self) -> String {
        format!("MassProperties(mass={}, center_of_mass={:?})", self.inner.mass, self.inner.com.as_slice())
    }
}

pub fn matrix<'py>(py: Python<'py>, m: &crate::math::Mat3) -> Bound<'py, PyArray2<f64>> {
    let rows: Vec<Vec<f64>> = (0..3).map(|r| (0..3).map(|c| m[(r, c)]).collect()).collect();
    // 3x3 rows of equal length: from_vec2 cannot fail here.
    PyArray2::from_vec2(py, &rows).unwrap_or_else(|_| PyArray2::zeros(py, [3, 3], false))
}

/// Mass properties of a body whose density varies: samples `points` (N, 3) (m),
/// the `volumes` (N,) or scalar (m³) they stand for and the `densities` (N,) or
/// scalar (kg/m³) there. Point quadrature of m = ∫ρ, c = ∫ρx/m,
/// I0 = ∫ρ(rᵀr·Id − r rᵀ).
#[pyfunction]
pub fn mass_properties(
    points: &Bound<'_, PyAny>,
    volumes: &Bound<'_, PyAny>,
    densities: &Bound<'_, PyAny>,
) -> PyResult<PyMassProperties> {
    let pts = rows3(points, "points")?;
    let n = pts.len();
    let vols = scalar_or_vector(volumes, "volumes", n)?;
    let rho = scalar_or_vector(densities, "densities", n)?;
    let samples = DensitySamples { points: &pts, volumes: &vols, densities: &rho };
    Ok(PyMassProperties { inner: samples.integrate().py_err()? })
}
