//! NumPy views of a world's arrays. Each view's base is the world object, so it
//! keeps the world (and the memory it shows) alive; the arrays never reallocate.

use numpy::ndarray::{ArrayView, IxDyn};
use numpy::PyArrayDyn;
use pyo3::prelude::*;

use super::world::PyWorld;

/// The bodies of a world, as views. Writable: `position`, `orientation`,
/// `linear_velocity`, `angular_velocity`, `force`, `torque`. Read-only: the rest.
#[pyclass(name = "Bodies", module = "rigidrs._core", frozen)]
pub struct PyBodies {
    pub world: Py<PyWorld>,
}

/// A view of `len` rows of `width` doubles starting at `ptr`, owned by `world`.
///
/// Safety: `ptr` must point into a `Vec` of the world that holds `len * width`
/// doubles and is never reallocated while the world lives.
pub(crate) unsafe fn view<'py>(
    world: &Bound<'py, PyWorld>,
    ptr: *const f64,
    shape: &[usize],
    writable: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let a = unsafe { ArrayView::from_shape_ptr(IxDyn(shape), ptr) };
    let arr = unsafe { PyArrayDyn::<f64>::borrow_from_array(&a, world.clone().into_any()) };
    if !writable {
        arr.call_method1("setflags", (false,))?;
    }
    Ok(arr.into_any())
}

#[derive(Clone, Copy)]
enum Field {
    Position,
    Orientation,
    LinearVelocity,
    AngularVelocity,
    Force,
    Torque,
    Mass,
    InverseMass,
    Inertia,
    InverseInertia,
    Rotation,
    InertiaWorld,
    AngularMomentum,
}

impl Field {
    /// The guard's bit of a writable field (0 for read-only ones): a step
    /// that fails is undone by a replay that needs what the user wrote.
    fn exposed(self) -> u16 {
        use crate::world::guard::exposed::*;
        match self {
            Field::Position => POSITION,
            Field::Orientation => ORIENTATION,
            Field::LinearVelocity => LINEAR_VELOCITY,
            Field::AngularVelocity => ANGULAR_VELOCITY,
            Field::Force => FORCE,
            Field::Torque => TORQUE,
            _ => 0,
        }
    }

    /// Pointer, shape of one row, writable, derived (refreshed on read).
    fn locate(self, b: &crate::body::Bodies) -> (*const f64, &'static [usize], bool, bool) {
        fn p<T>(v: &[T]) -> *const f64 {
            v.as_ptr() as *const f64
        }
        match self {
            Field::Position => (p(&b.position), &[3], true, false),
            Field::Orientation => (p(&b.orientation), &[4], true, false),
            Field::LinearVelocity => (p(&b.linear_velocity), &[3], true, false),
            Field::AngularVelocity => (p(&b.angular_velocity), &[3], true, false),
            Field::Force => (p(&b.force), &[3], true, false),
            Field::Torque => (p(&b.torque), &[3], true, false),
            Field::Mass => (p(&b.mass), &[], false, false),
            Field::InverseMass => (p(&b.inv_mass), &[], false, false),
            Field::Inertia => (p(&b.inertia), &[3], false, false),
            Field::InverseInertia => (p(&b.inv_inertia), &[3], false, false),
            Field::Rotation => (p(&b.rotation), &[3, 3], false, true),
            Field::InertiaWorld => (p(&b.inertia_world), &[3, 3], false, true),
            Field::AngularMomentum => (p(&b.angular_momentum), &[3], false, true),
        }
    }
}

impl PyBodies {
    fn field<'py>(&self, py: Python<'py>, field: Field) -> PyResult<Bound<'py, PyAny>> {
        let w = self.world.bind(py);
        let (ptr, row, writable, n) = {
            let mut g = w.try_borrow_mut()?;
            let derived = field.locate(&g.inner.bodies).3;
            if derived {
                g.inner.keep_derived = true;
                g.inner.bodies.update_derived();
            }
            let (ptr, row, writable, _) = field.locate(&g.inner.bodies);
            g.guard.expose(field.exposed());
            (ptr, row, writable, g.inner.bodies.len())
        };
        let shape: Vec<usize> = std::iter::once(n).chain(row.iter().copied()).collect();
        // Safety: every field is a Vec of the world allocated once at build and
        // never reallocated; the view's base is the world object.
        unsafe { view(w, ptr, &shape, writable) }
    }
}

#[pymethods]
impl PyBodies {
    fn __len__(&self, py: Python<'_>) -> PyResult<usize> {
        Ok(self.world.bind(py).try_borrow()?.inner.bodies.len())
    }

    /// The bodies' names (`add_body(name=...)`; "" where none was given).
    #[getter]
    fn names(&self, py: Python<'_>) -> PyResult<Vec<String>> {
        Ok(self.world.bind(py).try_borrow()?.inner.body_names.clone())
    }

    /// (N,) whether each body is asleep; read-only.
    #[getter]
    fn sleeping<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let w = self.world.bind(py);
        let (ptr, n) = {
            let g = w.try_borrow()?;
            (g.inner.bodies.sleeping.as_ptr(), g.inner.bodies.len())
        };
        // Safety: a Vec of the world allocated at build and never reallocated;
        // bool is one byte holding 0 or 1, as NumPy's bool.
        let a = unsafe { numpy::ndarray::ArrayView1::from_shape_ptr(n, ptr) };
        let arr = unsafe { numpy::PyArray1::<bool>::borrow_from_array(&a, w.clone().into_any()) };
        arr.call_method1("setflags", (false,))?;
        Ok(arr.into_any())
    }

    /// (N, 3) centre of mass, world (m); writable.
    #[getter]
    fn position<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::Position)
    }
    /// (N, 4) principal-frame orientation quaternion (x, y, z, w); writable.
    #[getter]
    fn orientation<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::Orientation)
    }
    /// (N, 3) centre-of-mass velocity, world (m/s); writable.
    #[getter]
    fn linear_velocity<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::LinearVelocity)
    }
    /// (N, 3) angular velocity, world (rad/s); writable.
    #[getter]
    fn angular_velocity<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::AngularVelocity)
    }
    /// (N, 3) applied force at the centre of mass, world (N); writable, persists.
    #[getter]
    fn force<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::Force)
    }
    /// (N, 3) applied torque, world (N·m); writable, persists.
    #[getter]
    fn torque<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::Torque)
    }
    /// (N,) mass (kg), inf for fixed bodies; read-only.
    #[getter]
    fn mass<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::Mass)
    }
    /// (N,) 1/mass (1/kg), 0 for fixed bodies; read-only.
    #[getter]
    fn inverse_mass<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::InverseMass)
    }
    /// (N, 3) principal moments of inertia, body frame (kg·m²); read-only.
    #[getter]
    fn inertia<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::Inertia)
    }
    /// (N, 3) inverse principal moments (1/(kg·m²)); read-only.
    #[getter]
    fn inverse_inertia<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::InverseInertia)
    }
    /// (N, 3, 3) rotation matrix R of each body; read-only, refreshed by each step.
    #[getter]
    fn rotation<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::Rotation)
    }
    /// (N, 3, 3) world inertia R I0 Rᵀ (kg·m²); read-only, refreshed by each step.
    #[getter]
    fn inertia_world<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::InertiaWorld)
    }
    /// (N, 3) spin angular momentum I ω about the centre of mass, world (kg·m²/s);
    /// read-only, refreshed by each step.
    #[getter]
    fn angular_momentum<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::AngularMomentum)
    }
}
