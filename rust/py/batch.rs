//! `Batch`: B worlds of one layout stepped in parallel with the GIL released,
//! seen through (B, N, ·) views. The views show one buffer per array owned by
//! the batch (allocated once, never reallocated, the view's base is the batch):
//! each `step` copies it into the worlds first and back after, O(B·N).
//!
//! The steps never read the buffers, so a thread writing through a view while
//! they run (the GIL released) cannot reach them. Its write is kept, as if
//! made after the call: a row that differs from what the buffers held when the
//! steps started is not overwritten by their result, and the next `step`'s
//! check of its inputs validates it (a NaN raises `StateError` naming the copy
//! and the body), as `World.step` does (`super::shadow`). Before, the copy
//! back overwrote it, and the write was lost.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::RecvTimeoutError;
use std::time::{Duration, Instant};

use numpy::ndarray::{ArrayView, IxDyn};
use numpy::PyArrayDyn;
use pyo3::exceptions::{PyIndexError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use super::convert::{float_array, non_negative_int};
use super::errors::{IntoPy, RigidError};
use super::scene::PyScene;
use super::world::PyWorld;
use crate::world::batch::{self, Batch};
use crate::world::{Scene, World};

/// How often a long `step(n)` takes the GIL to run Python's signal handlers.
const SIGNAL_CHECK: Duration = Duration::from_millis(20);

#[pyclass(name = "Batch", module = "rigidrs._core")]
pub struct PyBatch {
    core: Batch,
    bufs: Buffers,
    /// The buffers when the running steps started (see the module docs).
    before: Buffers,
}

/// What the views show: B·N rows per array, copy after copy.
struct Buffers {
    position: Vec<[f64; 3]>,
    orientation: Vec<[f64; 4]>,
    linear_velocity: Vec<[f64; 3]>,
    angular_velocity: Vec<[f64; 3]>,
}

/// The rows of one copy.
fn rows<T>(v: &[T], copy: usize, n: usize) -> &[T] {
    &v[copy * n..(copy + 1) * n]
}
fn rows_mut<T>(v: &mut [T], copy: usize, n: usize) -> &mut [T] {
    &mut v[copy * n..(copy + 1) * n]
}

impl Buffers {
    fn new(total: usize) -> Self {
        Self {
            position: vec![[0.0; 3]; total],
            orientation: vec![[0.0; 4]; total],
            linear_velocity: vec![[0.0; 3]; total],
            angular_velocity: vec![[0.0; 3]; total],
        }
    }

    /// Writes copy `c`'s rows into `w` (`n` bodies).
    fn write_into(&self, c: usize, n: usize, w: &mut World) {
        let b = &mut w.bodies;
        b.position.copy_from_slice(rows(&self.position, c, n));
        b.orientation.copy_from_slice(rows(&self.orientation, c, n));
        b.linear_velocity.copy_from_slice(rows(&self.linear_velocity, c, n));
        b.angular_velocity.copy_from_slice(rows(&self.angular_velocity, c, n));
    }

    /// Reads copy `c`'s rows from `w` (into the same memory: views stay valid).
    fn read_from(&mut self, c: usize, n: usize, w: &World) {
        let b = &w.bodies;
        rows_mut(&mut self.position, c, n).copy_from_slice(&b.position);
        rows_mut(&mut self.orientation, c, n).copy_from_slice(&b.orientation);
        rows_mut(&mut self.linear_velocity, c, n).copy_from_slice(&b.linear_velocity);
        rows_mut(&mut self.angular_velocity, c, n).copy_from_slice(&b.angular_velocity);
    }

    /// [`Self::read_from`], but a row that differs from `before`'s (written
    /// through a view since) keeps what was written.
    fn read_unwritten_from(&mut self, c: usize, n: usize, w: &World, before: &Buffers) {
        let b = &w.bodies;
        keep_writes(rows_mut(&mut self.position, c, n), &b.position, rows(&before.position, c, n));
        keep_writes(rows_mut(&mut self.orientation, c, n), &b.orientation, rows(&before.orientation, c, n));
        keep_writes(rows_mut(&mut self.linear_velocity, c, n), &b.linear_velocity, rows(&before.linear_velocity, c, n));
        keep_writes(rows_mut(&mut self.angular_velocity, c, n), &b.angular_velocity, rows(&before.angular_velocity, c, n));
    }

    /// `self = other`, same sizes (no allocation).
    fn set_to(&mut self, other: &Buffers) {
        self.position.copy_from_slice(&other.position);
        self.orientation.copy_from_slice(&other.orientation);
        self.linear_velocity.copy_from_slice(&other.linear_velocity);
        self.angular_velocity.copy_from_slice(&other.angular_velocity);
    }

    /// Whether every row holds the bits it holds in `other`.
    fn same_as(&self, other: &Buffers) -> bool {
        same_rows(&self.position, &other.position)
            && same_rows(&self.orientation, &other.orientation)
            && same_rows(&self.linear_velocity, &other.linear_velocity)
            && same_rows(&self.angular_velocity, &other.angular_velocity)
    }
}

/// Whether rows `a` and `b` hold the same bits (NaN equals NaN, −0 ≠ 0).
fn same_rows<const K: usize>(a: &[[f64; K]], b: &[[f64; K]]) -> bool {
    a.len() == b.len() && a.iter().flatten().zip(b.iter().flatten()).all(|(x, y)| x.to_bits() == y.to_bits())
}

/// `view = result` where `view` still holds `before`'s bits.
fn keep_writes<const K: usize>(view: &mut [[f64; K]], result: &[[f64; K]], before: &[[f64; K]]) {
    for ((v, r), b) in view.iter_mut().zip(result).zip(before) {
        if same_rows(std::slice::from_ref(v), std::slice::from_ref(b)) {
            *v = *r;
        }
    }
}

impl PyBatch {
    fn from_core(core: Batch) -> Self {
        let total = core.len() * core.bodies();
        let mut b = Self { core, bufs: Buffers::new(total), before: Buffers::new(total) };
        b.copy_out();
        b
    }

    /// Buffers → worlds (what the user wrote through the views).
    fn copy_in(&mut self) {
        let n = self.core.bodies();
        for (c, w) in self.core.worlds.iter_mut().enumerate() {
            self.bufs.write_into(c, n, w);
        }
    }

    /// Worlds → buffers.
    fn copy_out(&mut self) {
        let n = self.core.bodies();
        for (c, w) in self.core.worlds.iter().enumerate() {
            self.bufs.read_from(c, n, w);
        }
    }

    /// Worlds → buffers after steps that ran with the GIL released, keeping
    /// the rows written through the views meanwhile (see the module docs).
    fn copy_out_keeping_writes(&mut self) {
        if self.bufs.same_as(&self.before) {
            return self.copy_out();
        }
        let n = self.core.bodies();
        for (c, w) in self.core.worlds.iter().enumerate() {
            self.bufs.read_unwritten_from(c, n, w, &self.before);
        }
    }

    /// Steps every copy `n` steps on the pool while this thread (the one that
    /// holds Python's signal handlers) waits, looking for Ctrl-C every
    /// `SIGNAL_CHECK`; on one it sets `stop`.
    fn run(&mut self, n: u64, interrupted: &mut dyn FnMut() -> bool) -> crate::Result<()> {
        let stop = &AtomicBool::new(false);
        let pool = crate::world::threads::pool(self.core.threads())?;
        let core = &mut self.core;
        let (done, finished) = std::sync::mpsc::channel();
        // The copies go to the pool as one task (a pool thread runs `step`, whose
        // parallel loop spreads them); this thread waits for it, or for Ctrl-C.
        pool.in_place_scope(|s| {
            s.spawn(move |_| {
                let _ = done.send(catch_unwind(AssertUnwindSafe(|| core.step(n, stop))));
            });
            loop {
                match finished.recv_timeout(SIGNAL_CHECK) {
                    Ok(Ok(r)) => return r,
                    Ok(Err(p)) => std::panic::resume_unwind(p),
                    Err(RecvTimeoutError::Timeout) => {
                        if !stop.load(Ordering::Relaxed) && interrupted() {
                            stop.store(true, Ordering::Relaxed);
                        }
                    }
                    Err(RecvTimeoutError::Disconnected) => {
                        return Err(crate::Error::simulation("internal error: the batch's task ended without a result"))
                    }
                }
            }
        })
    }
}

/// The scenes of the first argument: one scene, or a list of them.
fn scenes_of(arg: &Bound<'_, PyAny>) -> PyResult<Option<Vec<Scene>>> {
    if arg.cast::<PyScene>().is_ok() {
        return Ok(None);
    }
    let list = arg.cast::<PyList>().map_err(|_| PyTypeError::new_err("Batch takes a Scene or a list of Scenes"))?;
    list.iter()
        .enumerate()
        .map(|(i, s)| {
            let s = s.cast::<PyScene>().map_err(|_| PyTypeError::new_err(format!("scenes[{i}] is not a Scene")))?;
            Ok(s.borrow().inner.clone())
        })
        .collect::<PyResult<Vec<_>>>()
        .map(Some)
}

#[pymethods]
impl PyBatch {
    #[new]
    #[pyo3(signature = (scene, copies=None, *, dt, **build))]
    fn new(
        py: Python<'_>,
        scene: &Bound<'_, PyAny>,
        copies: Option<i64>,
        dt: f64,
        build: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let list = scenes_of(scene)?;
        let first = match &list {
            None => scene.clone(),
            Some(v) if v.is_empty() => return Err(RigidError::new_err("a batch needs at least one scene")),
            Some(_) => scene.get_item(0)?,
        };
        // Scene.build checks and parses the build arguments (and warns as it does).
        let template = first.call_method("build", (dt,), build)?;
        let world = template.cast::<PyWorld>()?.borrow().inner.clone();
        let core = match list {
            None => {
                let copies = non_negative_int(copies.unwrap_or(1), "copies")? as usize;
                let scene = scene.cast::<PyScene>()?.borrow().inner.clone();
                Batch::copies(scene, world, copies).py_err()?
            }
            Some(scenes) => {
                if let Some(c) = copies {
                    if c as usize != scenes.len() || c < 0 {
                        return Err(PyValueError::new_err(format!(
                            "copies={c} with a list of {} scenes: give one or the other",
                            scenes.len()
                        )));
                    }
                }
                let settings = world.settings().clone();
                py.detach(|| Batch::new(scenes, settings)).py_err()?
            }
        };
        Ok(Self::from_core(core))
    }

    /// Advances every copy `n` steps of `dt`, in parallel with the GIL released.
    /// A state written through the views that no step can take raises
    /// `StateError` naming the copy and the body, and nothing moves. A copy that
    /// diverges raises `SimulationError` naming the copy, the body and the stage;
    /// every copy is put back as it was before that copy's failing step. Ctrl-C
    /// stops every copy at the same step boundary (`KeyboardInterrupt`). A
    /// state written through the views by another thread while the steps run
    /// is kept, as if written after the call, and checked by the next one.
    #[pyo3(signature = (n=1))]
    fn step(&mut self, py: Python<'_>, n: i64) -> PyResult<()> {
        let n = non_negative_int(n, "n")?;
        self.copy_in();
        self.core.check_inputs().py_err()?;
        self.before.set_to(&self.bufs);
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
        let r = py.detach(|| catch_unwind(AssertUnwindSafe(|| self.run(n, &mut interrupted))));
        self.copy_out_keeping_writes();
        match r {
            Ok(result) => result.py_err()?,
            Err(_) => {
                self.core.guards.iter_mut().for_each(|g| g.invalidate());
                return Err(RigidError::new_err("internal error in Batch.step (a bug in rigidrs: please report it)"));
            }
        }
        signal.map_or(Ok(()), Err)
    }

    /// Sets a per-copy parameter: `values` of shape (B,) (one per copy) or (B, N)
    /// (one per body); "gravity" (B, 3). Names: "friction" (dynamic and static),
    /// "static_friction", "restitution", "gravity" (m/s²), "mass" (kg, inertia
    /// scaled with it), "mass_scale"; fixed and kinematic bodies keep their
    /// (infinite) mass. Each copy is built again from its scene with the new
    /// value, keeping the state of the views and the time; what the world
    /// carried between steps (contact warm starts, sleep timers) starts afresh,
    /// so set parameters before stepping for a copy bitwise equal to a world
    /// built with them. On an error nothing changes.
    fn set(&mut self, py: Python<'_>, name: &str, values: &Bound<'_, PyAny>) -> PyResult<()> {
        if !batch::PARAMETERS.iter().any(|(known, _)| *known == name) {
            return Err(super::errors::to_py(batch::unknown(name)));
        }
        let (b, n) = (self.core.len(), self.core.bodies());
        let (v, shape) = float_array(values, name)?;
        let width = match (name, shape.as_slice()) {
            ("gravity", [rows, 3]) if *rows == b => 3,
            ("gravity", _) => {
                return Err(PyValueError::new_err(format!("gravity must have shape ({b}, 3), got {shape:?}")))
            }
            (_, [rows]) if *rows == b => 1,
            (_, [rows, cols]) if *rows == b && *cols == n => n,
            _ => {
                return Err(PyValueError::new_err(format!(
                    "{name} must have shape ({b},) or ({b}, {n}) (copies, bodies), got {shape:?}"
                )))
            }
        };
        let (core, bufs) = (&mut self.core, &self.bufs);
        py.detach(|| core.set(name, &v, width, &|c, w| bufs.write_into(c, n, w))).py_err()
    }

    /// Copy `i` as a world of its own (a copy: stepping it leaves the batch alone).
    fn world(&self, i: i64) -> PyResult<PyWorld> {
        let b = self.core.len();
        let c = usize::try_from(i).ok().filter(|&c| c < b).ok_or_else(|| {
            PyIndexError::new_err(format!("copy {i} is out of range: the batch has {b} copies"))
        })?;
        let mut w = self.core.worlds[c].clone();
        self.bufs.write_into(c, self.core.bodies(), &mut w);
        Ok(PyWorld::new(w))
    }

    /// The bodies of every copy, as (B, N, ·) views.
    #[getter]
    fn bodies(slf: Bound<'_, Self>) -> PyBatchBodies {
        PyBatchBodies { batch: slf.unbind() }
    }

    /// Number of copies B.
    #[getter]
    fn copies(&self) -> usize {
        self.core.len()
    }

    fn __len__(&self) -> usize {
        self.core.len()
    }

    /// Worker threads stepping the copies (the build argument `threads`).
    #[getter]
    fn threads(&self) -> usize {
        self.core.threads()
    }

    /// Simulated time of every copy (s).
    #[getter]
    fn time(&self) -> f64 {
        self.core.worlds.first().map_or(0.0, |w| w.time())
    }

    /// Steps every copy has taken.
    #[getter]
    fn steps(&self) -> u64 {
        self.core.worlds.first().map_or(0, |w| w.steps())
    }

    /// Time step (s).
    #[getter]
    fn dt(&self) -> f64 {
        self.core.settings.dt
    }

    fn __repr__(&self) -> String {
        format!(
            "Batch(copies={}, bodies={}, dt={}, time={})",
            self.core.len(),
            self.core.bodies(),
            self.core.settings.dt,
            self.time()
        )
    }
}

/// The bodies of a batch: (B, N, 3) and (B, N, 4) writable views.
#[pyclass(name = "BatchBodies", module = "rigidrs._core", frozen)]
pub struct PyBatchBodies {
    pub batch: Py<PyBatch>,
}

#[derive(Clone, Copy)]
enum Field {
    Position,
    Orientation,
    LinearVelocity,
    AngularVelocity,
}

impl PyBatchBodies {
    fn field<'py>(&self, py: Python<'py>, f: Field) -> PyResult<Bound<'py, PyAny>> {
        let b = self.batch.bind(py);
        let (ptr, width, shape) = {
            let g = b.try_borrow()?;
            let (ptr, width) = match f {
                Field::Position => (g.bufs.position.as_ptr() as *const f64, 3),
                Field::Orientation => (g.bufs.orientation.as_ptr() as *const f64, 4),
                Field::LinearVelocity => (g.bufs.linear_velocity.as_ptr() as *const f64, 3),
                Field::AngularVelocity => (g.bufs.angular_velocity.as_ptr() as *const f64, 3),
            };
            (ptr, width, [g.core.len(), g.core.bodies()])
        };
        // Safety: the buffers are Vecs of the batch holding B·N rows of `width`
        // doubles, allocated at construction and never reallocated (steps and
        // `set` copy into them); the view's base is the batch object.
        let a = unsafe { ArrayView::from_shape_ptr(IxDyn(&[shape[0], shape[1], width]), ptr) };
        let arr = unsafe { PyArrayDyn::<f64>::borrow_from_array(&a, b.clone().into_any()) };
        Ok(arr.into_any())
    }
}

#[pymethods]
impl PyBatchBodies {
    fn __len__(&self, py: Python<'_>) -> PyResult<usize> {
        Ok(self.batch.bind(py).try_borrow()?.core.bodies())
    }

    /// (B, N, 3) centre of mass of each body of each copy, world (m); writable.
    #[getter]
    fn position<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::Position)
    }
    /// (B, N, 4) orientation quaternion (x, y, z, w); writable.
    #[getter]
    fn orientation<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::Orientation)
    }
    /// (B, N, 3) centre-of-mass velocity, world (m/s); writable.
    #[getter]
    fn linear_velocity<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::LinearVelocity)
    }
    /// (B, N, 3) angular velocity, world (rad/s); writable.
    #[getter]
    fn angular_velocity<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::AngularVelocity)
    }
}
