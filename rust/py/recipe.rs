//! `Scene._recipe()` and `Scene.build_settings`: the calls that filled a scene
//! (see `crate::world::recipe`) as plain Python data, keyed by the keyword names
//! of the methods that took them, for `rigidrs.io` to write and replay.

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use super::scene::PyScene;
use crate::articulation::DriveMode;
use crate::body::shape::ShapeKind;
use crate::body::{MassProps, Shape};
use crate::collide::{Filter, Material};
use crate::world::joints::{JointOptions, SolverChoice};
use crate::world::recipe::{ParticleCall, Setting, Source};
use crate::world::{BodySpec, Inertia};
use crate::xpbd::builders;
use crate::xpbd::joints::JointSpec;
use crate::xpbd::shape_matching::ClusterSpec;
use crate::xpbd::Compliance;

type Dict<'py> = Bound<'py, PyDict>;

fn shape<'py>(py: Python<'py>, s: &Shape) -> PyResult<Dict<'py>> {
    let d = PyDict::new(py);
    d.set_item("kind", s.name())?;
    match &s.kind {
        ShapeKind::Sphere { radius } => d.set_item("radius", radius)?,
        ShapeKind::Box { half_extents } => d.set_item("half_extents", half_extents.to_vec())?,
        ShapeKind::Capsule { radius, half_height }
        | ShapeKind::Cylinder { radius, half_height }
        | ShapeKind::Cone { radius, half_height } => {
            d.set_item("radius", radius)?;
            d.set_item("half_height", half_height)?;
        }
        ShapeKind::ConvexHull { points } => d.set_item("points", rows(points))?,
        ShapeKind::TriMesh { vertices, triangles } => {
            d.set_item("vertices", rows(vertices))?;
            d.set_item("triangles", triangles.iter().map(|t| t.to_vec()).collect::<Vec<_>>())?;
        }
        ShapeKind::Plane { offset, given, .. } => {
            d.set_item("normal", given.to_vec())?;
            d.set_item("offset", offset)?;
        }
        ShapeKind::Compound { parts, orientations } => {
            let list = PyList::empty(py);
            for ((pose, part), q) in parts.iter().zip(orientations.iter()) {
                let p = PyDict::new(py);
                p.set_item("shape", shape(py, part)?)?;
                p.set_item("position", pose.translation.vector.as_slice().to_vec())?;
                p.set_item("orientation", q.to_vec())?;
                list.append(p)?;
            }
            d.set_item("parts", list)?;
        }
    }
    Ok(d)
}

fn rows(v: &[[f64; 3]]) -> Vec<Vec<f64>> {
    v.iter().map(|r| r.to_vec()).collect()
}

fn mass_props<'py>(py: Python<'py>, m: &MassProps) -> PyResult<Dict<'py>> {
    let d = PyDict::new(py);
    d.set_item("mass", m.mass)?;
    d.set_item("center_of_mass", m.com.as_slice().to_vec())?;
    let rows: Vec<Vec<f64>> = (0..3).map(|r| (0..3).map(|c| m.inertia[(r, c)]).collect()).collect();
    d.set_item("inertia", rows)?;
    Ok(d)
}

fn material(d: &Dict<'_>, m: &Material) -> PyResult<()> {
    d.set_item("friction", m.friction)?;
    d.set_item("static_friction", m.static_friction)?;
    d.set_item("restitution", m.restitution)
}

fn filter(d: &Dict<'_>, f: &Filter) -> PyResult<()> {
    d.set_item("collision_group", f.group)?;
    d.set_item("collision_mask", f.mask)
}

/// A body's inputs; `given_shape`: its shape, kept by the compiled body.
fn body<'py>(py: Python<'py>, b: &BodySpec, given_shape: Option<&Shape>) -> PyResult<Dict<'py>> {
    let d = PyDict::new(py);
    d.set_item("shape", given_shape.map(|s| shape(py, s)).transpose()?)?;
    d.set_item("density", b.density)?;
    d.set_item("mass", b.mass)?;
    match &b.inertia {
        Some(Inertia::Principal(m)) => d.set_item("inertia", m.to_vec())?,
        Some(Inertia::Tensor(t)) => d.set_item("inertia", t.iter().map(|r| r.to_vec()).collect::<Vec<_>>())?,
        None => d.set_item("inertia", py.None())?,
    }
    d.set_item("mass_properties", b.mass_properties.as_ref().map(|m| mass_props(py, m)).transpose()?)?;
    d.set_item("position", b.position.to_vec())?;
    d.set_item("orientation", b.orientation.to_vec())?;
    d.set_item("linear_velocity", b.linear_velocity.to_vec())?;
    d.set_item("angular_velocity", b.angular_velocity.to_vec())?;
    d.set_item("fixed", b.fixed)?;
    d.set_item("kinematic", b.kinematic)?;
    material(&d, &b.material)?;
    d.set_item("ccd", b.ccd)?;
    filter(&d, &b.filter)?;
    d.set_item("name", b.name.clone())?;
    Ok(d)
}

fn joint<'py>(py: Python<'py>, (s, o): &(JointSpec, JointOptions)) -> PyResult<Dict<'py>> {
    let d = PyDict::new(py);
    d.set_item("kind", s.kind.name())?;
    d.set_item("body_a", s.body_a)?;
    d.set_item("body_b", s.body_b)?;
    d.set_item("anchor", s.anchor.map(|p| p.to_vec()))?;
    d.set_item("anchor_b", s.anchor_b.map(|p| p.to_vec()))?;
    d.set_item("axis", s.axis.to_vec())?;
    d.set_item("compliance", s.compliance)?;
    d.set_item("angular_compliance", s.angular_compliance)?;
    d.set_item("limits", s.limits.map(|l| l.to_vec()))?;
    d.set_item("rest_length", s.rest_length)?;
    d.set_item("name", o.name.clone())?;
    let solver = match o.solver {
        SolverChoice::Auto => "auto",
        SolverChoice::Xpbd => "xpbd",
        SolverChoice::Articulation => "articulation",
    };
    d.set_item("solver", solver)?;
    let c = &o.control;
    let drive = match &c.drive {
        Some(dr) => {
            let x = PyDict::new(py);
            x.set_item("mode", if dr.mode == DriveMode::Position { "position" } else { "velocity" })?;
            x.set_item("target", dr.target.clone())?;
            x.set_item("stiffness", dr.stiffness)?;
            x.set_item("damping", dr.damping)?;
            x.set_item("max_force", dr.max_force)?;
            Some(x)
        }
        None => None,
    };
    d.set_item("drive", drive)?;
    d.set_item("damping", c.damping)?;
    d.set_item("armature", c.armature)?;
    d.set_item("friction", c.friction)?;
    d.set_item("cone_limit", c.cone)?;
    d.set_item("twist_limits", c.twist.map(|l| l.to_vec()))?;
    Ok(d)
}

fn compliance(d: &Dict<'_>, k: &Compliance) -> PyResult<()> {
    d.set_item("compliance", k.alpha)?;
    d.set_item("damping", k.damping)
}

/// The material of a builder's particles (`add_rope`, `add_cloth`, ...).
fn particles_material(d: &Dict<'_>, m: &builders::Material) -> PyResult<()> {
    d.set_item("mass", m.mass)?;
    d.set_item("radius", m.radius)?;
    d.set_item("friction", m.friction)?;
    filter(d, &m.filter)
}

fn cluster(d: &Dict<'_>, s: &ClusterSpec) -> PyResult<()> {
    d.set_item("mode", s.mode.name())?;
    d.set_item("stiffness", s.stiffness)?;
    d.set_item("beta", s.beta)?;
    d.set_item("preserve_volume", s.preserve_volume)?;
    match &s.plasticity {
        Some(p) => {
            d.set_item("plastic_yield", p.yield_strain)?;
            d.set_item("plastic_creep", p.creep)?;
            d.set_item("plastic_max", p.max)
        }
        None => {
            d.set_item("plastic_yield", None::<f64>)?;
            d.set_item("plastic_creep", 0.0)?;
            d.set_item("plastic_max", f64::INFINITY)
        }
    }
}

fn particle_call<'py>(py: Python<'py>, call: &ParticleCall) -> PyResult<Dict<'py>> {
    let d = PyDict::new(py);
    match call {
        ParticleCall::Particle(p) => {
            d.set_item("op", "particle")?;
            d.set_item("position", p.position.to_vec())?;
            d.set_item("velocity", p.velocity.to_vec())?;
            d.set_item("mass", p.mass)?;
            d.set_item("radius", p.radius)?;
            d.set_item("fixed", p.fixed)?;
            d.set_item("friction", p.friction)?;
            filter(&d, &p.filter)?;
        }
        ParticleCall::Distance { p, q, k, rest_length } => {
            d.set_item("op", "distance")?;
            d.set_item("particles", vec![*p, *q])?;
            compliance(&d, k)?;
            d.set_item("rest_length", *rest_length)?;
        }
        ParticleCall::Bending { p, k } => {
            d.set_item("op", "bending")?;
            d.set_item("particles", p.to_vec())?;
            compliance(&d, k)?;
        }
        ParticleCall::Volume { p, k } => {
            d.set_item("op", "volume")?;
            d.set_item("particles", p.to_vec())?;
            compliance(&d, k)?;
        }
        ParticleCall::MeshVolume { triangles, pressure, k } => {
            d.set_item("op", "mesh_volume")?;
            d.set_item("triangles", triangles.iter().map(|t| t.to_vec()).collect::<Vec<_>>())?;
            d.set_item("pressure", pressure)?;
            compliance(&d, k)?;
        }
        ParticleCall::Attachment { particle, body, point, rest_length, k } => {
            d.set_item("op", "attachment")?;
            d.set_item("particle", particle)?;
            d.set_item("body", body)?;
            d.set_item("point", point.map(|p| p.to_vec()))?;
            d.set_item("rest_length", rest_length)?;
            compliance(&d, k)?;
        }
        ParticleCall::ShapeMatching { particles, spec } => {
            d.set_item("op", "shape_matching")?;
            d.set_item("particles", particles.clone())?;
            cluster(&d, spec)?;
        }
        ParticleCall::Rope { start, end, segments, mat, k, pinned } => {
            d.set_item("op", "rope")?;
            d.set_item("start", start.to_vec())?;
            d.set_item("end", end.to_vec())?;
            d.set_item("segments", segments)?;
            particles_material(&d, mat)?;
            compliance(&d, k)?;
            d.set_item("pinned", pinned.clone())?;
        }
        ParticleCall::Cloth { origin, u, v, resolution, mat, k, bending, pinned } => {
            d.set_item("op", "cloth")?;
            d.set_item("origin", origin.to_vec())?;
            d.set_item("u", u.to_vec())?;
            d.set_item("v", v.to_vec())?;
            d.set_item("resolution", resolution.to_vec())?;
            particles_material(&d, mat)?;
            compliance(&d, k)?;
            d.set_item("bending_compliance", bending.map(|b| b.alpha))?;
            d.set_item("bending_damping", bending.map(|b| b.damping))?;
            d.set_item("pinned", pinned.clone())?;
        }
        ParticleCall::SoftBox { center, half_extents, cells, mat, k, volume } => {
            d.set_item("op", "soft_box")?;
            d.set_item("center", center.to_vec())?;
            d.set_item("half_extents", half_extents.to_vec())?;
            d.set_item("cells", cells.to_vec())?;
            particles_material(&d, mat)?;
            compliance(&d, k)?;
            d.set_item("volume_compliance", volume.map(|b| b.alpha))?;
        }
        ParticleCall::ShapeMatchedBody { source, spacing, position, orientation, mat, spec, cluster_size } => {
            d.set_item("op", "shape_matched_body")?;
            match source {
                Source::Shape(s) => d.set_item("shape", shape(py, s)?)?,
                Source::Points(p) => d.set_item("points", rows(p))?,
            }
            d.set_item("spacing", *spacing)?;
            d.set_item("position", position.map(|p| p.to_vec()))?;
            d.set_item("orientation", orientation.map(|q| q.to_vec()))?;
            particles_material(&d, mat)?;
            cluster(&d, spec)?;
            d.set_item("cluster_size", *cluster_size)?;
        }
    }
    Ok(d)
}

fn setting_to_py<'py>(py: Python<'py>, s: &Setting) -> PyResult<Bound<'py, PyAny>> {
    Ok(match s {
        Setting::None => py.None().into_bound(py),
        Setting::Bool(b) => pyo3::types::PyBool::new(py, *b).to_owned().into_any(),
        Setting::Int(i) => i.into_pyobject(py)?.into_any(),
        Setting::Float(x) => x.into_pyobject(py)?.into_any(),
        Setting::Str(t) => t.into_pyobject(py)?.into_any(),
    })
}

fn setting_from_py(key: &str, v: &Bound<'_, PyAny>) -> PyResult<Setting> {
    use pyo3::types::{PyBool, PyFloat, PyInt, PyString};
    if v.is_none() {
        Ok(Setting::None)
    } else if v.is_instance_of::<PyBool>() {
        Ok(Setting::Bool(v.extract()?))
    } else if v.is_instance_of::<PyInt>() {
        let i: i64 = v.extract().map_err(|_| PyValueError::new_err(format!("build_settings[{key:?}]: integer out of range")))?;
        Ok(Setting::Int(i))
    } else if v.is_instance_of::<PyFloat>() {
        Ok(Setting::Float(v.extract()?))
    } else if v.is_instance_of::<PyString>() {
        Ok(Setting::Str(v.extract()?))
    } else {
        let t = v.get_type().name()?;
        Err(PyTypeError::new_err(format!("build_settings[{key:?}] must be None, a bool, int, float or str, got {t}")))
    }
}

#[pymethods]
impl PyScene {
    /// The calls that filled this scene, as given: {"gravity", "bodies", "joints",
    /// "particles"}, keyed by the methods' keyword names. Used by `rigidrs.io`.
    fn _recipe<'py>(&self, py: Python<'py>) -> PyResult<Dict<'py>> {
        let r = &self.inner.recipe;
        let d = PyDict::new(py);
        d.set_item("gravity", self.inner.gravity.to_vec())?;
        let bodies = r.bodies.iter().zip(self.inner.bodies()).map(|(b, desc)| body(py, b, desc.shape.as_ref()));
        d.set_item("bodies", bodies.collect::<PyResult<Vec<_>>>()?)?;
        d.set_item("joints", r.joints.iter().map(|j| joint(py, j)).collect::<PyResult<Vec<_>>>()?)?;
        d.set_item("particles", r.particles.iter().map(|c| particle_call(py, c)).collect::<PyResult<Vec<_>>>()?)?;
        Ok(d)
    }

    /// `Scene.build` keyword arguments kept with the scene (written to and read from
    /// scene files): a dict of None, bool, int, float or str values, default empty.
    #[getter]
    fn build_settings<'py>(&self, py: Python<'py>) -> PyResult<Dict<'py>> {
        let d = PyDict::new(py);
        for (k, v) in &self.inner.recipe.build {
            d.set_item(k, setting_to_py(py, v)?)?;
        }
        Ok(d)
    }

    #[setter]
    fn set_build_settings(&mut self, settings: &Bound<'_, PyDict>) -> PyResult<()> {
        let mut out = Vec::with_capacity(settings.len());
        for (k, v) in settings.iter() {
            let key: String = k.extract().map_err(|_| PyTypeError::new_err("build_settings keys must be str"))?;
            let value = setting_from_py(&key, &v)?;
            out.push((key, value));
        }
        self.inner.recipe.build = out;
        Ok(())
    }
}
