//! `Scene`: the description a world is built from.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use super::convert::{float_array, vec3, vec4};
use super::drive::PyDrive;
use super::errors::IntoPy;
use super::joints::{self, JointArgs};
use super::mass::PyMassProperties;
use super::shapes::PyShape;
use super::world::PyWorld;
use crate::collide::{Filter, Material};
use crate::articulation::{ArticulationIntegrator, ArticulationSettings};
use crate::integrate::Integrator;
use crate::solve::islands::SleepSettings;
use crate::solve::SolverSettings;
use crate::world::{BodySpec, Inertia, Scene, Settings};

/// A description of what to simulate. `gravity` (3,) in m/s², default (0, 0, −9.81).
#[pyclass(name = "Scene", module = "rigidrs._core")]
pub struct PyScene {
    pub(crate) inner: Scene,
    /// What an importer (`Scene.from_urdf`, `from_mjcf`) dropped or approximated;
    /// `None` until one sets it (read as an empty report).
    pub(crate) import_report: Option<Py<PyAny>>,
}

/// A 32-bit collision filter word.
pub(crate) fn bits(x: i64, name: &str) -> PyResult<u32> {
    u32::try_from(x).map_err(|_| PyValueError::new_err(format!("{name} must be a 32-bit mask in [0, 2^32), got {x}")))
}

pub(crate) fn inertia_arg(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Inertia> {
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
        Ok(Self { inner: Scene::new(g).py_err()?, import_report: None })
    }

    /// Gravitational acceleration (3,) (m/s²).
    #[getter]
    fn gravity(&self) -> [f64; 3] {
        self.inner.gravity
    }

    fn __len__(&self) -> usize {
        self.inner.bodies().len()
    }

    /// What the file an importer read had that was dropped or approximated, and why
    /// (`rigidrs.io.ImportReport`, a list of entries); empty for a scene built by hand.
    #[getter]
    fn get_import_report(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        if let Some(r) = &self.import_report {
            return Ok(r.clone_ref(py));
        }
        let empty = py.import("rigidrs.io.report").and_then(|m| m.getattr("ImportReport")).and_then(|c| c.call0());
        match empty {
            Ok(r) => Ok(r.unbind()),
            Err(_) => Ok(pyo3::types::PyList::empty(py).into_any().unbind()),
        }
    }

    #[setter]
    fn set_import_report(&mut self, report: Option<Py<PyAny>>) {
        self.import_report = report;
    }

    /// Adds a body and returns its index. See the stub for the parameters.
    #[pyo3(signature = (shape=None, *, density=None, mass=None, inertia=None, mass_properties=None,
                        position=None, orientation=None, linear_velocity=None, angular_velocity=None,
                        fixed=false, kinematic=false, friction=0.5, static_friction=None, restitution=0.0,
                        ccd=false, collision_group=1, collision_mask=4294967295, name=None))]
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
        kinematic: bool,
        friction: f64,
        static_friction: Option<f64>,
        restitution: f64,
        ccd: bool,
        collision_group: i64,
        collision_mask: i64,
        name: Option<String>,
    ) -> PyResult<usize> {
        let index = self.inner.bodies().len();
        let field = |name: &str| format!("body {index}: {name}");
        let mut spec = BodySpec {
            shape: shape.map(|s| s.inner.clone()),
            density,
            mass,
            mass_properties: mass_properties.map(|m| m.inner.clone()),
            fixed,
            kinematic,
            material: Material::new(friction, static_friction, restitution)
                .map_err(|e| e.context(format!("body {index}")))
                .py_err()?,
            filter: Filter { group: bits(collision_group, &field("collision_group"))?, mask: bits(collision_mask, &field("collision_mask"))? },
            ccd,
            name,
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
        // The shape is kept once, by the compiled body (unchanged there): a mesh's
        // vertices and tree are not stored, pickled and saved twice.
        let given = BodySpec { shape: None, ..spec.clone() };
        let index = self.inner.add_body(spec).py_err()?;
        self.inner.recipe.bodies.push(given);
        Ok(index)
    }

    /// Adds a joint and returns its index. See the stub for the parameters.
    #[pyo3(signature = (kind, body_a, body_b=None, *, anchor=None, anchor_b=None, axis=None,
                        compliance=0.0, angular_compliance=0.0, limits=None, rest_length=None,
                        name=None, solver="auto", drive=None, damping=0.0, armature=0.0, friction=0.0,
                        cone_limit=None, twist_limits=None))]
    #[allow(clippy::too_many_arguments)]
    fn add_joint(
        &mut self,
        kind: &str,
        body_a: i64,
        body_b: Option<i64>,
        anchor: Option<&Bound<'_, PyAny>>,
        anchor_b: Option<&Bound<'_, PyAny>>,
        axis: Option<&Bound<'_, PyAny>>,
        compliance: f64,
        angular_compliance: f64,
        limits: Option<&Bound<'_, PyAny>>,
        rest_length: Option<f64>,
        name: Option<String>,
        solver: &str,
        drive: Option<PyRef<'_, PyDrive>>,
        damping: f64,
        armature: f64,
        friction: f64,
        cone_limit: Option<f64>,
        twist_limits: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<usize> {
        let drive = drive.map(|d| d.inner.clone());
        let args = JointArgs {
            kind,
            body_a,
            body_b,
            anchor,
            anchor_b,
            axis,
            compliance,
            angular_compliance,
            limits,
            rest_length,
            name,
            solver,
            drive,
            damping,
            armature,
            friction,
            cone_limit,
            twist_limits,
        };
        let index = self.inner.joints().len();
        let spec = joints::spec(&args, index)?;
        let options = joints::options(&args, index)?;
        let given = (spec.clone(), options.clone());
        let index = self.inner.add_joint_with(spec, options).py_err()?;
        self.inner.recipe.joints.push(given);
        Ok(index)
    }

    /// Number of joints added.
    #[getter]
    fn joint_count(&self) -> usize {
        self.inner.joints().len()
    }

    /// Compiles the scene into a `World`. See the stub for the parameters.
    #[pyo3(signature = (dt, integrator="strang", substeps=None, iterations=1, *, sleep=true,
                        restitution_threshold=None, slop=0.005, contact_hertz=None,
                        contact_damping_ratio=10.0, max_push_velocity=3.0,
                        sleep_linear=0.05, sleep_angular=0.05, sleep_time=0.5,
                        articulations=true, articulation_integrator="leapfrog", articulation_substeps=None,
                        max_rotation_angle=None, threads=None))]
    #[allow(clippy::too_many_arguments)]
    fn build(
        &self,
        py: Python<'_>,
        dt: f64,
        integrator: &str,
        substeps: Option<i64>,
        iterations: i64,
        sleep: bool,
        restitution_threshold: Option<f64>,
        slop: f64,
        contact_hertz: Option<f64>,
        contact_damping_ratio: f64,
        max_push_velocity: f64,
        sleep_linear: f64,
        sleep_angular: f64,
        sleep_time: f64,
        articulations: bool,
        articulation_integrator: &str,
        articulation_substeps: Option<i64>,
        max_rotation_angle: Option<f64>,
        threads: Option<i64>,
    ) -> PyResult<PyWorld> {
        let mut s = Settings::new(dt);
        s.integrator = Integrator::from_name(integrator).py_err()?;
        let small = |x: i64, name: &str| -> PyResult<u32> {
            u32::try_from(x).map_err(|_| PyValueError::new_err(format!("{name} must be an integer in [1, 2^32), got {x}")))
        };
        s.substeps = substeps.map(|n| small(n, "substeps")).transpose()?;
        s.iterations = small(iterations, "iterations")?;
        let asked = contact_hertz;
        let contact_hertz = contact_hertz.unwrap_or(SolverSettings::default().contact_hertz);
        s.solver = SolverSettings { contact_hertz, contact_damping_ratio, max_push_velocity, restitution_threshold, slop };
        s.sleep = SleepSettings { enabled: sleep, linear: sleep_linear, angular: sleep_angular, time: sleep_time };
        s.articulation = ArticulationSettings {
            enabled: articulations,
            integrator: ArticulationIntegrator::from_name(articulation_integrator).py_err()?,
            substeps: articulation_substeps.map(|n| small(n, "articulation_substeps")).transpose()?,
        };
        s.max_rotation_angle = max_rotation_angle;
        s.threads = threads.map(|n| small(n, "threads")).transpose()?;
        let world = self.inner.build(&s).py_err()?;
        if let (Some(hertz), true) = (asked, world.collision.is_some()) {
            warn_stiffness_capped(py, hertz, dt, world.substeps())?;
        }
        warn_behind_meshes(py, &world.behind_meshes())?;
        Ok(PyWorld::new(world))
    }
}

/// Bodies that start behind a fixed mesh pass through it (a mesh collides on
/// the side its triangles run counter-clockwise from): say which, and how to
/// turn the mesh round.
fn warn_behind_meshes(py: Python<'_>, found: &[(u32, u32)]) -> PyResult<()> {
    let Some(&(body, mesh)) = found.first() else { return Ok(()) };
    let others = if found.len() > 1 { format!(" (and {} more such bodies)", found.len() - 1) } else { String::new() };
    let msg = format!(
        "body {body} starts behind the mesh of body {mesh}{others}: a mesh collides only on the side its \
         triangles run counter-clockwise from, so it will pass through; if it should rest on the mesh, \
         reverse the triangles' winding (triangles[:, ::-1])"
    );
    user_warning(py, msg)
}

/// Emits `msg` as a Python `UserWarning`.
fn user_warning(py: Python<'_>, msg: String) -> PyResult<()> {
    let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
    let msg = std::ffi::CString::new(msg).map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
    PyErr::warn(py, &category, &msg, 1)
}

/// A `contact_hertz` the substep cannot resolve is capped at a quarter of the
/// substep rate (a stiffer contact would overshoot within one substep): say so
/// rather than let a user believe the contacts are as stiff as asked.
fn warn_stiffness_capped(py: Python<'_>, hertz: f64, dt: f64, substeps: u32) -> PyResult<()> {
    let cap = 0.25 * f64::from(substeps.max(1)) / dt;
    if hertz <= cap {
        return Ok(());
    }
    let msg = format!(
        "contact_hertz={hertz} Hz is above a quarter of the substep rate ({substeps} substeps of dt={dt} s): \
         contacts use {cap:.4} Hz; raise substeps or lower contact_hertz"
    );
    user_warning(py, msg)
}
