//! Shape classes. Each validates on construction (a bad shape never reaches a
//! scene) and holds the core [`crate::body::Shape`].

use pyo3::prelude::*;

use super::convert::{rows3, vec3};
use super::errors::IntoPy;
use super::mass::PyMassProperties;
use crate::body::shape::ShapeKind;
use crate::body::Shape;

/// Base class of every shape.
#[pyclass(name = "Shape", module = "rigidrs._core", subclass, frozen)]
pub struct PyShape {
    pub inner: Shape,
}

#[pymethods]
impl PyShape {
    /// Volume (m³); a `Plane` has none and raises.
    fn volume(&self) -> PyResult<f64> {
        self.inner.volume().py_err()
    }

    /// Mass properties for a uniform density (kg/m³), in this shape's frame.
    fn mass_properties(&self, density: f64) -> PyResult<PyMassProperties> {
        Ok(PyMassProperties { inner: self.inner.mass_properties(density).py_err()? })
    }

    fn __repr__(&self) -> String {
        match &self.inner.kind {
            ShapeKind::Sphere { radius } => format!("Sphere(radius={radius})"),
            ShapeKind::Box { half_extents } => format!("Box(half_extents={half_extents:?})"),
            ShapeKind::Capsule { radius, half_height } => format!("Capsule(radius={radius}, half_height={half_height})"),
            ShapeKind::Cylinder { radius, half_height } => format!("Cylinder(radius={radius}, half_height={half_height})"),
            ShapeKind::Cone { radius, half_height } => format!("Cone(radius={radius}, half_height={half_height})"),
            ShapeKind::ConvexHull { points } => format!("ConvexHull(<{} points>)", points.len()),
            ShapeKind::TriMesh { vertices, triangles } => {
                format!("TriMesh(<{} vertices, {} triangles>)", vertices.len(), triangles.len())
            }
            ShapeKind::Plane { normal, offset, .. } => format!("Plane(normal={normal:?}, offset={offset})"),
            ShapeKind::Compound { parts, .. } => format!("Compound(<{} parts>)", parts.len()),
        }
    }
}

fn base(shape: crate::Result<Shape>) -> PyResult<PyClassInitializer<PyShape>> {
    Ok(PyClassInitializer::from(PyShape { inner: shape.py_err()? }))
}

/// A ball. `radius` (m).
#[pyclass(name = "Sphere", module = "rigidrs._core", extends = PyShape, frozen)]
pub struct PySphere;

#[pymethods]
impl PySphere {
    #[new]
    fn new(radius: f64) -> PyResult<PyClassInitializer<Self>> {
        Ok(base(Shape::sphere(radius))?.add_subclass(Self))
    }
    #[getter]
    fn radius(slf: PyRef<'_, Self>) -> f64 {
        match slf.as_super().inner.kind {
            ShapeKind::Sphere { radius } => radius,
            _ => f64::NAN,
        }
    }
}

/// A box. `half_extents` (3,) along local x, y, z (m).
#[pyclass(name = "Box", module = "rigidrs._core", extends = PyShape, frozen)]
pub struct PyBox;

#[pymethods]
impl PyBox {
    #[new]
    fn new(half_extents: &Bound<'_, PyAny>) -> PyResult<PyClassInitializer<Self>> {
        Ok(base(Shape::cuboid(vec3(half_extents, "Box half_extents")?))?.add_subclass(Self))
    }
    #[getter]
    fn half_extents(slf: PyRef<'_, Self>) -> [f64; 3] {
        match slf.as_super().inner.kind {
            ShapeKind::Box { half_extents } => half_extents,
            _ => [f64::NAN; 3],
        }
    }
}

macro_rules! axial_shape {
    ($py:ident, $name:literal, $variant:ident, $ctor:ident, $doc:literal) => {
        #[doc = $doc]
        #[pyclass(name = $name, module = "rigidrs._core", extends = PyShape, frozen)]
        pub struct $py;

        #[pymethods]
        impl $py {
            #[new]
            fn new(radius: f64, half_height: f64) -> PyResult<PyClassInitializer<Self>> {
                Ok(base(Shape::$ctor(radius, half_height))?.add_subclass(Self))
            }
            #[getter]
            fn radius(slf: PyRef<'_, Self>) -> f64 {
                match slf.as_super().inner.kind {
                    ShapeKind::$variant { radius, .. } => radius,
                    _ => f64::NAN,
                }
            }
            #[getter]
            fn half_height(slf: PyRef<'_, Self>) -> f64 {
                match slf.as_super().inner.kind {
                    ShapeKind::$variant { half_height, .. } => half_height,
                    _ => f64::NAN,
                }
            }
        }
    };
}

axial_shape!(PyCapsule, "Capsule", Capsule, capsule, "A capsule along local z: segment of length 2·half_height (m) swept by radius (m).");
axial_shape!(PyCylinder, "Cylinder", Cylinder, cylinder, "A solid cylinder along local z: radius (m), length 2·half_height (m).");
axial_shape!(PyCone, "Cone", Cone, cone, "A solid cone along local z: base radius (m) at z = −half_height, apex at +half_height (m).");

/// The convex hull of `points` (N, 3) (m); at least 4 points spanning a volume.
#[pyclass(name = "ConvexHull", module = "rigidrs._core", extends = PyShape, frozen)]
pub struct PyConvexHull;

#[pymethods]
impl PyConvexHull {
    #[new]
    fn new(points: &Bound<'_, PyAny>) -> PyResult<PyClassInitializer<Self>> {
        Ok(base(Shape::convex_hull(rows3(points, "ConvexHull points")?))?.add_subclass(Self))
    }
}

/// A triangle mesh: `vertices` (V, 3) (m), `triangles` (T, 3) vertex indices,
/// counter-clockwise seen from outside. Must be closed to carry mass. It collides
/// only on the side its triangles run counter-clockwise from (see
/// `collide::mesh_side`): an open mesh must face the bodies.
#[pyclass(name = "TriMesh", module = "rigidrs._core", extends = PyShape, frozen)]
pub struct PyTriMesh;

#[pymethods]
impl PyTriMesh {
    #[new]
    fn new(vertices: &Bound<'_, PyAny>, triangles: &Bound<'_, PyAny>) -> PyResult<PyClassInitializer<Self>> {
        let v = rows3(vertices, "TriMesh vertices")?;
        let t = super::convert::triangles(triangles, "TriMesh triangles")?;
        Ok(base(Shape::trimesh(v, t))?.add_subclass(Self))
    }
}

/// The half-space `normal · x ≤ offset` (unit normal, offset in m). Only for
/// fixed bodies.
#[pyclass(name = "Plane", module = "rigidrs._core", extends = PyShape, frozen)]
pub struct PyPlane;

#[pymethods]
impl PyPlane {
    #[new]
    #[pyo3(signature = (normal=None, offset=0.0))]
    fn new(normal: Option<&Bound<'_, PyAny>>, offset: f64) -> PyResult<PyClassInitializer<Self>> {
        let n = match normal {
            Some(n) => vec3(n, "Plane normal")?,
            None => [0.0, 0.0, 1.0],
        };
        Ok(base(Shape::plane(n, offset))?.add_subclass(Self))
    }
}

/// A union of convex parts: `parts` is a list of `(shape, position)` or
/// `(shape, position, orientation)` in this shape's frame (m; x, y, z, w).
#[pyclass(name = "Compound", module = "rigidrs._core", extends = PyShape, frozen)]
pub struct PyCompound;

#[pymethods]
impl PyCompound {
    #[new]
    fn new(parts: &Bound<'_, PyAny>) -> PyResult<PyClassInitializer<Self>> {
        let mut out = Vec::new();
        let mut given = Vec::new();
        let items = parts.try_iter().map_err(|_| {
            pyo3::exceptions::PyTypeError::new_err("Compound parts must be a sequence of (shape, position[, orientation]) tuples")
        })?;
        for (k, item) in items.enumerate() {
            let item = item?;
            let name = format!("Compound part {k}");
            let tuple = item.cast::<pyo3::types::PyTuple>().map_err(|_| {
                pyo3::exceptions::PyTypeError::new_err(format!("{name} must be a tuple (shape, position[, orientation])"))
            })?;
            if !(2..=3).contains(&tuple.len()) {
                return Err(pyo3::exceptions::PyValueError::new_err(format!(
                    "{name} must be (shape, position) or (shape, position, orientation), got {} items",
                    tuple.len()
                )));
            }
            let shape = tuple.get_item(0)?;
            let shape = shape.cast::<PyShape>().map_err(|_| {
                pyo3::exceptions::PyTypeError::new_err(format!("{name}: the first item must be a rigidrs Shape"))
            })?;
            let p = vec3(&tuple.get_item(1)?, &format!("{name} position"))?;
            let q = match tuple.len() {
                3 => super::convert::vec4(&tuple.get_item(2)?, &format!("{name} orientation"))?,
                _ => [0.0, 0.0, 0.0, 1.0],
            };
            let pose = crate::world::scene::pose(p, q).map_err(|e| e.context(&name)).py_err()?;
            out.push((pose, shape.get().inner.clone()));
            given.push(q);
        }
        Ok(base(Shape::compound_as_given(out, given))?.add_subclass(Self))
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyCompound>()?;
    m.add_class::<PyShape>()?;
    m.add_class::<PySphere>()?;
    m.add_class::<PyBox>()?;
    m.add_class::<PyCapsule>()?;
    m.add_class::<PyCylinder>()?;
    m.add_class::<PyCone>()?;
    m.add_class::<PyConvexHull>()?;
    m.add_class::<PyTriMesh>()?;
    m.add_class::<PyPlane>()?;
    Ok(())
}
