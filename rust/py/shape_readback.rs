//! `World.shapes()` and `Scene.shapes()`: each body's geometry as plain data,
//! for drawing and exporting (the renderer tessellates from this).

use nalgebra::Isometry3;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::scene::PyScene;
use super::world::PyWorld;
use crate::body::shape::ShapeKind;
use crate::body::Shape;

fn points<'py>(py: Python<'py>, p: impl Iterator<Item = [f64; 3]>) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f64> = p.flatten().collect();
    let n = flat.len() / 3;
    Ok(PyArray1::from_vec(py, flat).reshape([n, 3])?.into_any())
}

fn triangles<'py>(py: Python<'py>, t: &[[u32; 3]]) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<i64> = t.iter().flat_map(|x| x.map(i64::from)).collect();
    Ok(PyArray1::from_vec(py, flat).reshape([t.len(), 3])?.into_any())
}

/// One shape as a dict: "kind", its dimensions, and "position" (3,) (m) and
/// "orientation" (4,) (x, y, z, w) of its frame in the frame given by `pose`.
fn describe<'py>(py: Python<'py>, shape: &Shape, pose: &Isometry3<f64>) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("kind", shape.name())?;
    d.set_item("position", PyArray1::from_slice(py, pose.translation.vector.as_slice()))?;
    d.set_item("orientation", PyArray1::from_slice(py, pose.rotation.coords.as_slice()))?;
    match &shape.kind {
        ShapeKind::Sphere { radius } => d.set_item("radius", radius)?,
        ShapeKind::Box { half_extents } => d.set_item("half_extents", PyArray1::from_slice(py, half_extents))?,
        ShapeKind::Capsule { radius, half_height }
        | ShapeKind::Cylinder { radius, half_height }
        | ShapeKind::Cone { radius, half_height } => {
            d.set_item("radius", radius)?;
            d.set_item("half_height", half_height)?;
        }
        ShapeKind::ConvexHull { points: p } => {
            d.set_item("points", points(py, p.iter().copied())?)?;
            // The hull's own faces, as parry built them, so a drawing needs no hull code.
            if let Some((v, t)) = shape.parry.as_convex_polyhedron().map(|c| c.to_trimesh()) {
                d.set_item("vertices", points(py, v.iter().map(|p| [p.x, p.y, p.z]))?)?;
                d.set_item("triangles", triangles(py, &t)?)?;
            }
        }
        ShapeKind::TriMesh { vertices, triangles: t } => {
            d.set_item("vertices", points(py, vertices.iter().copied())?)?;
            d.set_item("triangles", triangles(py, t)?)?;
        }
        ShapeKind::Plane { normal, offset, .. } => {
            d.set_item("normal", PyArray1::from_slice(py, normal))?;
            d.set_item("offset", offset)?;
        }
        ShapeKind::Compound { parts, .. } => {
            let list = parts.iter().map(|(p, s)| describe(py, s, p)).collect::<PyResult<Vec<_>>>()?;
            d.set_item("parts", list)?;
        }
    }
    Ok(d)
}

#[pymethods]
impl PyWorld {
    /// Per body (N items, None for a body without a shape): a dict with "kind"
    /// ("Sphere", "Box", "Capsule", "Cylinder", "Cone", "ConvexHull", "TriMesh",
    /// "Plane", "Compound"), "position" (3,) (m) and "orientation" (4,) (x, y, z, w)
    /// of the shape's frame in the body frame of `bodies.position/orientation`
    /// (the principal frame at the centre of mass), and its dimensions in its own
    /// frame (m): "radius", "half_height" (axial shapes, axis z), "half_extents"
    /// (3,), "points" (K, 3) plus the hull's "vertices" (V, 3) and "triangles"
    /// (F, 3) (ConvexHull), "vertices" and "triangles" (TriMesh), "normal" (3,) and
    /// "offset" (Plane, the half-space normal·x ≤ offset), "parts" (Compound: dicts
    /// like these, posed in the compound's frame).
    fn shapes<'py>(&self, py: Python<'py>) -> PyResult<Vec<Option<Bound<'py, PyDict>>>> {
        self.inner.shapes.iter().map(|s| s.as_ref().map(|(s, p)| describe(py, s, p)).transpose()).collect()
    }
}

#[pymethods]
impl PyScene {
    /// The bodies' shapes as `World.shapes()` gives them (body frames as they
    /// will be built: the principal frame at the centre of mass).
    fn shapes<'py>(&self, py: Python<'py>) -> PyResult<Vec<Option<Bound<'py, PyDict>>>> {
        self.inner
            .bodies()
            .iter()
            .map(|d| d.shape.as_ref().map(|s| describe(py, s, &d.shape_pose)).transpose())
            .collect()
    }
}
