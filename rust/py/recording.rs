//! `World.record(every)`: a `Recording` attached to a world, fed by the step loop.
//!
//! The world keeps the recorders ([`Attached`]) and, only while one is attached,
//! steps one step at a time and copies the state after each k-th step; with none
//! attached `step(n)` is the plain `World::step(n)` (no cost). One step at a time
//! gives the same bits as `step(n)` (each call only re-checks the state), which
//! the tests check. The buffers are shared (`Arc<Mutex<..>>`) between the world
//! and the Python object, so either may outlive the other.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, MutexGuard};

use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::convert::{float_array, non_negative_int};
use super::world::PyWorld;
use crate::world::World;

/// Marker saved in every file, checked on load.
const FORMAT: &str = "rigidrs.Recording";
const VERSION: i64 = 1;

/// Frames captured so far, flat row-major buffers.
pub struct Frames {
    every: u64,
    /// Steps since the last captured frame.
    since: u64,
    attached: bool,
    bodies: usize,
    particles: usize,
    steps: Vec<i64>,
    times: Vec<f64>,
    position: Vec<f64>,
    orientation: Vec<f64>,
    particle_position: Vec<f64>,
}

impl Frames {
    fn capture(&mut self, w: &World) {
        self.steps.push(w.steps() as i64);
        self.times.push(w.time());
        for i in 0..self.bodies {
            self.position.extend_from_slice(&w.bodies.position[i]);
            self.orientation.extend_from_slice(&w.bodies.orientation[i]);
        }
        if let Some(x) = w.xpbd.as_ref() {
            for p in x.particles.position.iter().take(self.particles) {
                self.particle_position.extend_from_slice(p);
            }
        }
    }

    fn tick(&mut self, w: &World) {
        self.since += 1;
        if self.since >= self.every {
            self.since = 0;
            self.capture(w);
        }
    }

    fn len(&self) -> usize {
        self.times.len()
    }

    fn nbytes(&self) -> usize {
        8 * (self.steps.len() + self.times.len() + self.position.len() + self.orientation.len() + self.particle_position.len())
    }
}

fn lock(f: &Mutex<Frames>) -> MutexGuard<'_, Frames> {
    // A panic while capturing leaves whole frames behind (pushes of plain data);
    // the buffers stay usable.
    f.lock().unwrap_or_else(|e| e.into_inner())
}

/// The recorders attached to one world.
#[derive(Default)]
pub struct Attached(Vec<Arc<Mutex<Frames>>>);

impl Attached {
    /// `n` steps through `run(w, k)` (which steps `k` and returns how many it
    /// took: fewer when interrupted), capturing a frame after every k-th step for
    /// each attached recorder. With recorders the steps go one by one, and
    /// `interrupted` is asked between them.
    pub fn step(
        &mut self,
        w: &mut World,
        n: u64,
        run: &mut dyn FnMut(&mut World, u64) -> crate::Result<u64>,
        interrupted: &mut dyn FnMut() -> bool,
    ) -> crate::Result<()> {
        self.0.retain(|f| lock(f).attached);
        if self.0.is_empty() {
            return run(w, n).map(|_| ());
        }
        for k in 0..n {
            if (k > 0 && interrupted()) || run(w, 1)? == 0 {
                break;
            }
            for f in &self.0 {
                lock(f).tick(w);
            }
        }
        Ok(())
    }
}

/// Body and particle trajectories captured while stepping (`World.record`) or
/// loaded from a file (`Recording.load`).
///
/// Arrays (copies, made on each access): `times` (T,) (s), `steps` (T,) step
/// count, `position` (T, N, 3) (m) and `orientation` (T, N, 4) (x, y, z, w) as in
/// `world.bodies`, `particle_position` (T, P, 3) (m; P = 0 without particles).
/// Memory: 8·(2 + 7·N + 3·P) bytes per frame (`nbytes`); while recording the
/// buffers grow by doubling, so up to twice that may be reserved.
#[pyclass(name = "Recording", module = "rigidrs._core", frozen)]
pub struct PyRecording {
    frames: Arc<Mutex<Frames>>,
}

fn rows<'py>(py: Python<'py>, data: &[f64], shape: [usize; 3]) -> PyResult<Bound<'py, PyAny>> {
    Ok(PyArray1::from_slice(py, data).reshape(shape)?.into_any())
}

/// A temporary name next to `path` (same file system, so the rename is atomic),
/// unique to this process and call (two saves at once never share one), ending in
/// .npz because `np.savez` appends that otherwise.
fn temp_name(path: &Path) -> PathBuf {
    static COUNT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let k = COUNT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let name = path.file_name().map_or("recording".into(), |n| n.to_string_lossy().into_owned());
    path.with_file_name(format!(".{name}.{}-{k}.tmp.npz", std::process::id()))
}

#[pymethods]
impl PyRecording {
    /// Number of frames T.
    fn __len__(&self) -> usize {
        lock(&self.frames).len()
    }

    /// (T,) simulated time of each frame (s).
    #[getter]
    fn times<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &lock(&self.frames).times)
    }

    /// (T,) the world's step count at each frame.
    #[getter]
    fn steps<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        PyArray1::from_slice(py, &lock(&self.frames).steps)
    }

    /// (T, N, 3) body positions (centre of mass, world, m).
    #[getter]
    fn position<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let f = lock(&self.frames);
        rows(py, &f.position, [f.len(), f.bodies, 3])
    }

    /// (T, N, 4) body orientations (x, y, z, w), as `world.bodies.orientation`.
    #[getter]
    fn orientation<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let f = lock(&self.frames);
        rows(py, &f.orientation, [f.len(), f.bodies, 4])
    }

    /// (T, P, 3) particle positions (world, m); P = 0 without particles.
    #[getter]
    fn particle_position<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let f = lock(&self.frames);
        rows(py, &f.particle_position, [f.len(), f.particles, 3])
    }

    /// Steps between frames (the `every` given to `World.record`).
    #[getter]
    fn every(&self) -> u64 {
        lock(&self.frames).every
    }

    /// Whether steps of the world are still being captured.
    #[getter]
    fn attached(&self) -> bool {
        lock(&self.frames).attached
    }

    /// Bytes held by the frames: 8·T·(2 + 7·N + 3·P).
    #[getter]
    fn nbytes(&self) -> usize {
        lock(&self.frames).nbytes()
    }

    /// Stops capturing; the frames so far stay. Idempotent.
    fn detach(&self) {
        lock(&self.frames).attached = false;
    }

    /// Writes the frames to `path` (str or path-like; the name is kept as given)
    /// with `numpy.savez`, or `numpy.savez_compressed` with `compress=True`
    /// (default False; smaller when bodies rest, slower): written to a temporary
    /// file next to it, then renamed, so a failure (missing directory, no
    /// permission) raises `OSError` and leaves no file behind.
    #[pyo3(signature = (path, compress=false))]
    fn save(&self, py: Python<'_>, path: PathBuf, compress: bool) -> PyResult<()> {
        let d = PyDict::new(py);
        {
            let f = lock(&self.frames);
            d.set_item("format", FORMAT)?;
            d.set_item("version", VERSION)?;
            d.set_item("every", f.every)?;
            d.set_item("times", PyArray1::from_slice(py, &f.times))?;
            d.set_item("steps", PyArray1::from_slice(py, &f.steps))?;
            d.set_item("position", rows(py, &f.position, [f.len(), f.bodies, 3])?)?;
            d.set_item("orientation", rows(py, &f.orientation, [f.len(), f.bodies, 4])?)?;
            d.set_item("particle_position", rows(py, &f.particle_position, [f.len(), f.particles, 3])?)?;
        }
        let tmp = temp_name(&path);
        let written = py
            .import("numpy")?
            .getattr(if compress { "savez_compressed" } else { "savez" })?
            .call((tmp.clone(),), Some(&d))
            .map(|_| ())
            .and_then(|_| std::fs::rename(&tmp, &path).map_err(PyErr::from));
        if let Err(e) = written {
            // Nothing half-written stays behind; the temp file may not exist.
            let _ = std::fs::remove_file(&tmp);
            return Err(PyOSError::new_err(format!("cannot write the recording to {}: {e}", path.display())));
        }
        Ok(())
    }

    /// Reads a file written by `save`. Raises `FileNotFoundError` if there is none
    /// and `ValueError` if it is not a recording (or is damaged).
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        if !path.exists() {
            return Err(pyo3::exceptions::PyFileNotFoundError::new_err(format!("no recording at {}", path.display())));
        }
        let bad = |why: String| PyValueError::new_err(format!("{} is not a rigidrs recording: {why}", path.display()));
        let kw = PyDict::new(py);
        kw.set_item("allow_pickle", false)?;
        let npz = py.import("numpy")?.getattr("load")?.call((path.clone(),), Some(&kw)).map_err(|e| bad(e.to_string()))?;
        let read = || -> PyResult<Frames> {
            let get = |k: &str| npz.get_item(k).map_err(|_| bad(format!("no array {k:?}")));
            let format: String = get("format")?.call_method0("item")?.extract().map_err(|_| bad("no format marker".into()))?;
            if format != FORMAT {
                return Err(bad(format!("format {format:?}")));
            }
            let version: i64 = get("version")?.call_method0("item")?.extract()?;
            if version != VERSION {
                return Err(bad(format!("version {version} (this rigidrs reads {VERSION})")));
            }
            let every: i64 = get("every")?.call_method0("item")?.extract()?;
            let (times, ts) = float_array(&get("times")?, "times")?;
            let (steps, ss) = float_array(&get("steps")?, "steps")?;
            let (position, ps) = float_array(&get("position")?, "position")?;
            let (orientation, os) = float_array(&get("orientation")?, "orientation")?;
            let (particle_position, qs) = float_array(&get("particle_position")?, "particle_position")?;
            let t = ts.first().copied().unwrap_or(0);
            let ok = ts.len() == 1
                && ss == [t]
                && ps.len() == 3 && ps[0] == t && ps[2] == 3
                && os == [t, ps[1], 4]
                && qs.len() == 3 && qs[0] == t && qs[2] == 3
                && every >= 1;
            if !ok {
                return Err(bad(format!(
                    "array shapes do not match: times {ts:?}, steps {ss:?}, position {ps:?}, orientation {os:?}, particle_position {qs:?}"
                )));
            }
            Ok(Frames {
                every: every as u64,
                since: 0,
                attached: false,
                bodies: ps[1],
                particles: qs[1],
                steps: steps.iter().map(|&s| s as i64).collect(),
                times,
                position,
                orientation,
                particle_position,
            })
        };
        let frames = read();
        let _ = npz.call_method0("close");
        Ok(Self { frames: Arc::new(Mutex::new(frames?)) })
    }

    fn __repr__(&self) -> String {
        let f = lock(&self.frames);
        format!(
            "Recording(frames={}, bodies={}, particles={}, every={}, attached={}, nbytes={})",
            f.len(),
            f.bodies,
            f.particles,
            f.every,
            if f.attached { "True" } else { "False" },
            f.nbytes()
        )
    }
}

#[pymethods]
impl PyWorld {
    /// Attaches a new `Recording` and returns it: the current state is its first
    /// frame, then every `every`-th step (default 1; each step of a `step(n)` call
    /// counts) adds one, until `rec.detach()`. Several may be attached at once.
    /// While any is attached, `step(n)` runs its steps one by one (same results).
    #[pyo3(signature = (every=1))]
    fn record(&mut self, every: i64) -> PyResult<PyRecording> {
        let every = non_negative_int(every, "every")?;
        if every == 0 {
            return Err(PyValueError::new_err("every must be at least 1, got 0"));
        }
        let w = &self.inner;
        let mut f = Frames {
            every,
            since: 0,
            attached: true,
            bodies: w.bodies.len(),
            particles: w.xpbd.as_ref().map_or(0, |x| x.particles.len()),
            steps: Vec::new(),
            times: Vec::new(),
            position: Vec::new(),
            orientation: Vec::new(),
            particle_position: Vec::new(),
        };
        f.capture(w);
        let frames = Arc::new(Mutex::new(f));
        self.recorders.0.push(frames.clone());
        Ok(PyRecording { frames })
    }
}
