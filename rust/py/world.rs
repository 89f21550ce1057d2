//! `World`: a compiled scene. `step` releases the GIL; state is seen through views.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::{Duration, Instant};

use numpy::{PyArray1, PyArrayDyn, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::convert::{non_negative_int, vec3};
use super::joints;
use super::errors::{IntoPy, RigidError};
use super::views::PyBodies;
use crate::collide::narrow_phase::ContactReport;
use crate::world::guard::{exposed, Guard};
use crate::world::World;

#[pyclass(name = "World", module = "rigidrs._core")]
pub struct PyWorld {
    pub inner: World,
    /// What puts the world back when a step fails (see `world::guard`).
    pub guard: Guard,
    /// Recordings fed by `step` (see `recording`).
    pub recorders: super::recording::Attached,
    /// The view-writable arrays set aside while a step runs (see `shadow`).
    pub shadow: super::shadow::Shadow,
}

impl PyWorld {
    pub fn new(inner: World) -> Self {
        Self { inner, guard: Guard::default(), recorders: Default::default(), shadow: Default::default() }
    }
}

/// How often a long `step(n)` takes the GIL to run Python's signal handlers
/// (Ctrl-C): a few microseconds each time, so every 20 ms costs nothing.
const SIGNAL_CHECK: Duration = Duration::from_millis(20);

fn vector<'py>(py: Python<'py>, v: crate::math::Vec3) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, v.as_slice())
}

#[pymethods]
impl PyWorld {
    /// Advances `n` steps of `dt` with the GIL released. The state is checked
    /// first; an invalid body (NaN, non-unit quaternion) raises `StateError`
    /// naming it, and nothing moves. A step that diverges or fails inside is
    /// undone and raises `SimulationError`; Ctrl-C stops at a step boundary
    /// (`KeyboardInterrupt`, the steps before it kept).
    #[pyo3(signature = (n=1))]
    fn step(&mut self, py: Python<'_>, n: i64) -> PyResult<()> {
        let n = non_negative_int(n, "n")?;
        let (w, guard, rec, shadow) = (&mut self.inner, &mut self.guard, &mut self.recorders, &mut self.shadow);
        // What other threads write through views while the GIL is released
        // never reaches these steps (`shadow`).
        shadow.enter(w, guard.exposed_bits());
        let mut signal: Option<PyErr> = None;
        let mut checked = Instant::now();
        let mut interrupted = || {
            if checked.elapsed() < SIGNAL_CHECK {
                return false;
            }
            checked = Instant::now();
            signal = Python::attach(|py| py.check_signals()).err();
            signal.is_some()
        };
        let r = py.detach(|| {
            catch_unwind(AssertUnwindSafe(|| {
                let interrupted = std::cell::RefCell::new(&mut interrupted);
                let mut run = |w: &mut World, k: u64| w.step_guarded(guard, k, &mut || (interrupted.borrow_mut())());
                let mut between = || (interrupted.borrow_mut())();
                rec.step(w, n, &mut run, &mut between)
            }))
        });
        shadow.leave(w);
        match r {
            Ok(result) => result.py_err()?,
            Err(_) => {
                self.guard.invalidate();
                return Err(RigidError::new_err("internal error in step (a bug in rigidrs: please report it)"));
            }
        };
        signal.map_or(Ok(()), Err)
    }

    /// The bodies, as NumPy views.
    #[getter]
    fn bodies(slf: Bound<'_, Self>) -> PyBodies {
        PyBodies { world: slf.unbind() }
    }

    /// The joints, as NumPy views (position, velocity, target, force, names).
    #[getter]
    fn joints(slf: Bound<'_, Self>) -> super::joint_views::PyJoints {
        super::joint_views::PyJoints { world: slf.unbind() }
    }

    /// Poses articulated hinges and slides by their coordinates: `positions`
    /// (J,) angle (rad) or slide (m) per joint, NaN to keep a joint as it is;
    /// `velocities` (J,) likewise (rad/s, m/s), default: 0 for every joint given
    /// a position. Raises naming the joint (not articulated, not 1-dof, outside
    /// its limits, not finite) and leaves the world unchanged.
    #[pyo3(signature = (positions, velocities=None))]
    fn set_joint_positions(&mut self, positions: &Bound<'_, PyAny>, velocities: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        let n = self.inner.joint_position.len();
        let q = super::convert::scalar_or_vector(positions, "positions", n)?;
        let v = velocities.map(|v| super::convert::scalar_or_vector(v, "velocities", n)).transpose()?;
        self.guard.invalidate();
        self.inner.set_joint_positions(&q, v.as_deref()).py_err()
    }

    /// Per articulation: its bodies (links, root first), its joints (the free
    /// root of a floating base is -1) and the substeps its last step took (the
    /// contact substeps when one of its links was in contact).
    fn articulations<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        let mut out = Vec::new();
        for a in &self.inner.articulations.list {
            let d = PyDict::new(py);
            d.set_item("bodies", a.links.iter().map(|l| l.body as i64).collect::<Vec<_>>())?;
            d.set_item("joints", a.links.iter().map(|l| l.joint.map_or(-1, |j| j as i64)).collect::<Vec<_>>())?;
            d.set_item("substeps", a.last_substeps)?;
            d.set_item("dofs", a.nv)?;
            out.push(d);
        }
        Ok(out)
    }

    /// Simulated time (s).
    #[getter]
    fn time(&self) -> f64 {
        self.inner.time()
    }

    /// Steps taken.
    #[getter]
    fn steps(&self) -> u64 {
        self.inner.steps()
    }

    /// Time step (s).
    #[getter]
    fn dt(&self) -> f64 {
        self.inner.dt()
    }

    /// The integrator's name.
    #[getter]
    fn integrator(&self) -> &'static str {
        self.inner.integrator().name()
    }

    /// Names of the stages one (sub)step runs now, in order.
    #[getter]
    fn stages(&mut self) -> Vec<&'static str> {
        self.inner.stage_names()
    }

    /// Seconds spent in each stage since the last reset, by stage name, and under
    /// "steps" the number of steps that covers; `reset` (default True) starts a new
    /// window.
    #[pyo3(signature = (reset=true))]
    fn profile<'py>(&mut self, py: Python<'py>, reset: bool) -> PyResult<Bound<'py, PyDict>> {
        let (rows, steps) = self.inner.profile.report();
        let d = PyDict::new(py);
        for (name, s) in rows {
            d.set_item(name, s)?;
        }
        d.set_item("steps", steps)?;
        if reset {
            self.inner.profile.reset();
        }
        Ok(d)
    }

    /// Whether stages are timed (default True; costs two clock reads per stage).
    #[getter]
    fn profiling(&self) -> bool {
        self.inner.profile.enabled
    }

    #[setter]
    fn set_profiling(&mut self, on: bool) {
        self.inner.profile.enabled = on;
    }

    /// Kinetic energy, translational plus rotational (J).
    fn kinetic_energy(&self) -> f64 {
        self.inner.kinetic_energy()
    }

    /// Gravitational potential energy −Σ m g·p (J).
    fn potential_energy(&self) -> f64 {
        self.inner.potential_energy()
    }

    /// Total linear momentum (3,) (kg·m/s).
    fn linear_momentum<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.inner.linear_momentum())
    }

    /// Total angular momentum about the origin (3,) (kg·m²/s).
    fn angular_momentum<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.inner.angular_momentum())
    }

    /// Adds `force` (3,) (N, world) to body `body`; with `point` (3,) (m, world) also
    /// the torque (point − p) × force at the body's current position. Persists
    /// until changed or `clear_forces()`.
    #[pyo3(signature = (body, force, point=None))]
    fn apply_force(&mut self, body: i64, force: &Bound<'_, PyAny>, point: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        let body = non_negative_int(body, "body")? as usize;
        let f = vec3(force, "force")?;
        let p = point.map(|p| vec3(p, "point")).transpose()?;
        self.guard.expose(exposed::FORCE | exposed::TORQUE);
        self.inner.apply_force(body, f, p).py_err()
    }

    /// Adds `torque` (3,) (N·m, world) to body `body`; persists until cleared.
    fn apply_torque(&mut self, body: i64, torque: &Bound<'_, PyAny>) -> PyResult<()> {
        let body = non_negative_int(body, "body")? as usize;
        let t = vec3(torque, "torque")?;
        self.guard.expose(exposed::TORQUE);
        self.inner.apply_torque(body, t).py_err()
    }

    /// This step's contact points as arrays (K contacts): `body_a`, `body_b` (K,)
    /// int64; `point` (K, 3) world (m), midway between the surfaces; `normal` (K, 3)
    /// from a to b; `depth` (K,) penetration (m, negative: predicted, not yet
    /// touching); `normal_impulse` (K,) and `friction_impulse` (K, 3) over the step
    /// (N·s; divide by dt for forces).
    fn contacts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let rows = self.inner.contacts();
        let d = PyDict::new(py);
        let ints = |f: fn(&ContactReport) -> u32| rows.iter().map(|r| f(r) as i64).collect::<Vec<_>>();
        let flat3 = |f: fn(&ContactReport) -> [f64; 3]| rows.iter().flat_map(f).collect::<Vec<_>>();
        let scalars = |f: fn(&ContactReport) -> f64| rows.iter().map(f).collect::<Vec<_>>();
        let k = rows.len();
        d.set_item("body_a", PyArray1::from_vec(py, ints(|r| r.body_a)))?;
        d.set_item("body_b", PyArray1::from_vec(py, ints(|r| r.body_b)))?;
        d.set_item("point", PyArray1::from_vec(py, flat3(|r| r.point)).reshape([k, 3])?)?;
        d.set_item("normal", PyArray1::from_vec(py, flat3(|r| r.normal)).reshape([k, 3])?)?;
        d.set_item("depth", PyArray1::from_vec(py, scalars(|r| r.depth)))?;
        d.set_item("normal_impulse", PyArray1::from_vec(py, scalars(|r| r.normal_impulse)))?;
        d.set_item("friction_impulse", PyArray1::from_vec(py, flat3(|r| r.friction_impulse)).reshape([k, 3])?)?;
        Ok(d)
    }

    /// Force (J, 3) (N, world) each joint applied to its body a over the last
    /// substep; body b received the opposite.
    fn joint_forces<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        joints::rows(py, self.inner.joint_forces())
    }

    /// Couple (J, 3) (N·m, world) each joint's angular constraints applied to
    /// body a over the last substep (with the force: the wrench about a's anchor).
    fn joint_torques<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        joints::rows(py, self.inner.joint_torques())
    }

    /// Substeps per step (resolved: 1 without contacts, 4 with them, unless given).
    #[getter]
    fn substeps(&self) -> u32 {
        self.inner.substeps()
    }

    /// Contact substeps the last step took: `substeps`, or enough for substeps
    /// of at most 1/960 s (16 at 60 Hz) while a slow body rocks on its
    /// supports and for 0.5 s after (unless `substeps` was given),
    /// or more if an articulation in contact asked for them.
    #[getter]
    fn last_substeps(&self) -> u32 {
        self.inner.last_substeps()
    }

    /// Sets every applied force and torque to zero.
    fn clear_forces(&mut self) {
        self.guard.expose(exposed::FORCE | exposed::TORQUE);
        self.inner.clear_forces();
    }

    fn __repr__(&self) -> String {
        format!(
            "World(bodies={}, dt={}, integrator={:?}, time={})",
            self.inner.bodies.len(),
            self.inner.dt(),
            self.inner.integrator().name(),
            self.inner.time()
        )
    }
}
