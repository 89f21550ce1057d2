//! The particle side of the bindings: `Scene` methods that add particles,
//! constraints, builders and shape-matching clusters; `World.particles` (views),
//! `World.constraint_forces()` and `World.clusters()`. Thin: each method
//! converts its arguments and calls the Rust scene or world.

use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyRange};

use super::convert::{rows3, vec3, vec4};
use crate::collide::Filter;
use super::errors::IntoPy;
use super::scene::PyScene;
use super::shapes::PyShape;
use super::views::view;
use super::world::PyWorld;
use crate::math::{quat, Vec3};
use crate::world::scene::pose;
use crate::xpbd::builders::{self, Material};
use crate::xpbd::shape_matching::{plasticity, ClusterSpec, Mode};
use crate::world::recipe::{ParticleCall, Source};
use crate::xpbd::{Compliance, ParticleSpec};

/// Local particle indices of a builder (negative ones are out of range).
fn local_indices(v: &[i64], name: &str) -> PyResult<Vec<usize>> {
    v.iter()
        .map(|&i| usize::try_from(i).map_err(|_| PyValueError::new_err(format!("{name} index {i} is out of range"))))
        .collect()
}

fn range(py: Python<'_>, r: std::ops::Range<usize>) -> PyResult<Bound<'_, PyRange>> {
    PyRange::new(py, r.start as isize, r.end as isize)
}

/// Compliance and damping, the error naming the constraint about to be added.
fn compliance(scene: &PyScene, kind: &str, alpha: f64, damping: f64) -> PyResult<Compliance> {
    let id = scene.inner.xpbd().constraint_count();
    Compliance::new(alpha, damping).map_err(|e| e.context(format!("constraint {id} ({kind})"))).py_err()
}

/// Rows of `W` indices from a sequence of sequences or an integer array.
fn index_rows<const W: usize>(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<[i64; W]>> {
    let rows: Vec<Vec<i64>> = obj.extract().map_err(|e| PyValueError::new_err(format!("{name} must be rows of {W} particle indices: {e}")))?;
    rows.iter()
        .enumerate()
        .map(|(k, r)| {
            <[i64; W]>::try_from(r.as_slice())
                .map_err(|_| PyValueError::new_err(format!("{name}[{k}] must hold {W} particle indices, got {}", r.len())))
        })
        .collect()
}

fn cluster_spec(
    mode: &str,
    stiffness: f64,
    beta: f64,
    preserve_volume: bool,
    plastic_yield: Option<f64>,
    plastic_creep: f64,
    plastic_max: f64,
) -> crate::Result<ClusterSpec> {
    Ok(ClusterSpec {
        mode: Mode::from_name(mode)?,
        stiffness,
        beta,
        preserve_volume,
        plasticity: plasticity::from_parts(plastic_yield, plastic_creep, plastic_max)?,
    })
}

/// A particle collision filter from Python ints, naming the particle(s).
fn particle_filter(group: i64, mask: i64, whose: &str) -> PyResult<Filter> {
    Ok(Filter {
        group: super::scene::bits(group, &format!("{whose}: collision_group"))?,
        mask: super::scene::bits(mask, &format!("{whose}: collision_mask"))?,
    })
}

#[pymethods]
impl PyScene {
    /// Adds a particle and returns its index. See the stub for the parameters.
    #[pyo3(signature = (position, *, mass=1.0, radius=0.0, velocity=None, fixed=false, friction=0.5,
                        collision_group=1, collision_mask=4294967295))]
    #[allow(clippy::too_many_arguments)]
    fn add_particle(
        &mut self,
        position: &Bound<'_, PyAny>,
        mass: f64,
        radius: f64,
        velocity: Option<&Bound<'_, PyAny>>,
        fixed: bool,
        friction: f64,
        collision_group: i64,
        collision_mask: i64,
    ) -> PyResult<usize> {
        let n = self.inner.xpbd().particles.len();
        let filter = particle_filter(collision_group, collision_mask, &format!("particle {n}"))?;
        let mut spec = ParticleSpec::at(vec3(position, &format!("particle {n}: position"))?);
        if let Some(v) = velocity {
            spec.velocity = vec3(v, &format!("particle {n}: velocity"))?;
        }
        spec.mass = mass;
        spec.radius = radius;
        spec.fixed = fixed;
        spec.friction = friction;
        spec.filter = filter;
        let index = self.inner.add_particle(&spec).py_err()?;
        self.inner.recipe.particles.push(ParticleCall::Particle(spec));
        Ok(index)
    }

    /// Number of particles added so far.
    #[getter]
    fn particle_count(&self) -> usize {
        self.inner.xpbd().particles.len()
    }

    /// Number of constraints added so far (the length of `World.constraint_forces()`).
    #[getter]
    fn constraint_count(&self) -> usize {
        self.inner.xpbd().constraint_count()
    }

    /// Number of shape-matching clusters added so far.
    #[getter]
    fn cluster_count(&self) -> usize {
        self.inner.xpbd().clusters.len()
    }

    /// Distance constraint between particles `p` and `q`; returns its index.
    #[pyo3(signature = (p, q, *, compliance=0.0, damping=0.0, rest_length=None))]
    fn add_distance_constraint(&mut self, p: i64, q: i64, compliance: f64, damping: f64, rest_length: Option<f64>) -> PyResult<usize> {
        let k = self::compliance(self, "distance", compliance, damping)?;
        let index = self.inner.add_distance_constraint(p, q, k, rest_length).py_err()?;
        self.inner.recipe.particles.push(ParticleCall::Distance { p, q, k, rest_length });
        Ok(index)
    }

    /// Dihedral bending over the edge p0–p1 with tips p2 and p3; returns its index.
    #[pyo3(signature = (p0, p1, p2, p3, *, compliance=0.0, damping=0.0))]
    #[allow(clippy::too_many_arguments)]
    fn add_bending_constraint(&mut self, p0: i64, p1: i64, p2: i64, p3: i64, compliance: f64, damping: f64) -> PyResult<usize> {
        let k = self::compliance(self, "bending", compliance, damping)?;
        let index = self.inner.add_bending_constraint([p0, p1, p2, p3], k).py_err()?;
        self.inner.recipe.particles.push(ParticleCall::Bending { p: [p0, p1, p2, p3], k });
        Ok(index)
    }

    /// Volume of the tetrahedron of 4 particles; returns its index.
    #[pyo3(signature = (particles, *, compliance=0.0, damping=0.0))]
    fn add_volume_constraint(&mut self, particles: &Bound<'_, PyAny>, compliance: f64, damping: f64) -> PyResult<usize> {
        let k = self::compliance(self, "volume", compliance, damping)?;
        let p: Vec<i64> = particles.extract()?;
        let p = <[i64; 4]>::try_from(p.as_slice())
            .map_err(|_| PyValueError::new_err(format!("particles must hold 4 particle indices, got {}", p.len())))?;
        let index = self.inner.add_volume_constraint(p, k).py_err()?;
        self.inner.recipe.particles.push(ParticleCall::Volume { p, k });
        Ok(index)
    }

    /// Volume of a closed particle mesh; returns its index.
    #[pyo3(signature = (triangles, *, compliance=0.0, damping=0.0, pressure=1.0))]
    fn add_mesh_volume_constraint(&mut self, triangles: &Bound<'_, PyAny>, compliance: f64, damping: f64, pressure: f64) -> PyResult<usize> {
        let k = self::compliance(self, "mesh volume", compliance, damping)?;
        let t = index_rows::<3>(triangles, "triangles")?;
        let index = self.inner.add_mesh_volume_constraint(&t, pressure, k).py_err()?;
        self.inner.recipe.particles.push(ParticleCall::MeshVolume { triangles: t, pressure, k });
        Ok(index)
    }

    /// Attaches a particle to a body; returns the constraint index.
    #[pyo3(signature = (particle, body, *, point=None, rest_length=0.0, compliance=0.0, damping=0.0))]
    #[allow(clippy::too_many_arguments)]
    fn add_attachment(
        &mut self,
        particle: i64,
        body: i64,
        point: Option<&Bound<'_, PyAny>>,
        rest_length: f64,
        compliance: f64,
        damping: f64,
    ) -> PyResult<usize> {
        let k = self::compliance(self, "attachment", compliance, damping)?;
        let point = point.map(|p| vec3(p, "point")).transpose()?;
        let index = self.inner.add_attachment(particle, body, point, rest_length, k).py_err()?;
        self.inner.recipe.particles.push(ParticleCall::Attachment { particle, body, point, rest_length, k });
        Ok(index)
    }

    /// A shape-matching cluster over `particles`; returns the cluster index.
    #[pyo3(signature = (particles, *, mode="linear", stiffness=1.0, beta=0.5, preserve_volume=true,
                        plastic_yield=None, plastic_creep=0.0, plastic_max=f64::INFINITY))]
    #[allow(clippy::too_many_arguments)]
    fn add_shape_matching(
        &mut self,
        particles: Vec<i64>,
        mode: &str,
        stiffness: f64,
        beta: f64,
        preserve_volume: bool,
        plastic_yield: Option<f64>,
        plastic_creep: f64,
        plastic_max: f64,
    ) -> PyResult<usize> {
        let index = self.inner.xpbd().clusters.len();
        let spec = cluster_spec(mode, stiffness, beta, preserve_volume, plastic_yield, plastic_creep, plastic_max)
            .map_err(|e| e.context(format!("cluster {index}")))
            .py_err()?;
        let index = self.inner.add_shape_matching(&particles, spec).py_err()?;
        self.inner.recipe.particles.push(ParticleCall::ShapeMatching { particles, spec });
        Ok(index)
    }

    /// A rope of `segments` distance constraints; returns its particles' range.
    #[pyo3(signature = (start, end, segments, *, mass=1.0, radius=0.0, friction=0.5, compliance=0.0, damping=0.0, pinned=Vec::new(),
                        collision_group=1, collision_mask=4294967295))]
    #[allow(clippy::too_many_arguments)]
    fn add_rope<'py>(
        &mut self,
        py: Python<'py>,
        start: &Bound<'py, PyAny>,
        end: &Bound<'py, PyAny>,
        segments: i64,
        mass: f64,
        radius: f64,
        friction: f64,
        compliance: f64,
        damping: f64,
        pinned: Vec<i64>,
        collision_group: i64,
        collision_mask: i64,
    ) -> PyResult<Bound<'py, PyRange>> {
        let given = pinned.clone();
        let pinned = local_indices(&pinned, "pinned")?;
        let k = Compliance::new(compliance, damping).py_err()?;
        let filter = particle_filter(collision_group, collision_mask, "particles")?;
        let mat = Material { mass, radius, friction, filter };
        let (start, end) = (vec3(start, "start")?, vec3(end, "end")?);
        let r = self.inner.add_rope(start, end, segments, &mat, k, &pinned).py_err()?;
        self.inner.recipe.particles.push(ParticleCall::Rope { start, end, segments, mat, k, pinned: given });
        range(py, r)
    }

    /// A rectangular cloth of `resolution = (nu, nv)` particles; returns their range.
    #[pyo3(signature = (origin, u, v, resolution, *, mass=1.0, radius=0.0, friction=0.5, compliance=0.0, damping=0.0,
                        bending_compliance=None, bending_damping=None, pinned=Vec::new(), collision_group=1,
                        collision_mask=4294967295))]
    #[allow(clippy::too_many_arguments)]
    fn add_cloth<'py>(
        &mut self,
        py: Python<'py>,
        origin: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
        resolution: (i64, i64),
        mass: f64,
        radius: f64,
        friction: f64,
        compliance: f64,
        damping: f64,
        bending_compliance: Option<f64>,
        bending_damping: Option<f64>,
        pinned: Vec<i64>,
        collision_group: i64,
        collision_mask: i64,
    ) -> PyResult<Bound<'py, PyRange>> {
        let given = pinned.clone();
        let pinned = local_indices(&pinned, "pinned")?;
        let k = Compliance::new(compliance, damping).py_err()?;
        if bending_compliance.is_none() && bending_damping.is_some() {
            return Err(PyValueError::new_err("bending_damping needs bending_compliance: without it the cloth has no bending constraints"));
        }
        let kb = bending_compliance.map(|b| builders::cloth_bending(b, bending_damping)).transpose().py_err()?;
        let filter = particle_filter(collision_group, collision_mask, "particles")?;
        let mat = Material { mass, radius, friction, filter };
        let (o, u, v) = (vec3(origin, "origin")?, vec3(u, "u")?, vec3(v, "v")?);
        let resolution = [resolution.0, resolution.1];
        let r = self.inner.add_cloth(o, u, v, resolution, &mat, k, kb, &pinned).py_err()?;
        let call = ParticleCall::Cloth { origin: o, u, v, resolution, mat, k, bending: kb, pinned: given };
        self.inner.recipe.particles.push(call);
        range(py, r)
    }

    /// A soft box of tetrahedra; returns its particles' range.
    #[pyo3(signature = (center, half_extents, cells, *, mass=1.0, radius=0.0, friction=0.5, compliance=0.0, damping=0.0,
                        volume_compliance=None, collision_group=1, collision_mask=4294967295))]
    #[allow(clippy::too_many_arguments)]
    fn add_soft_box<'py>(
        &mut self,
        py: Python<'py>,
        center: &Bound<'py, PyAny>,
        half_extents: &Bound<'py, PyAny>,
        cells: (i64, i64, i64),
        mass: f64,
        radius: f64,
        friction: f64,
        compliance: f64,
        damping: f64,
        volume_compliance: Option<f64>,
        collision_group: i64,
        collision_mask: i64,
    ) -> PyResult<Bound<'py, PyRange>> {
        let k = Compliance::new(compliance, damping).py_err()?;
        let kv = volume_compliance.map(|b| Compliance::new(b, 0.0)).transpose().py_err()?;
        let filter = particle_filter(collision_group, collision_mask, "particles")?;
        let mat = Material { mass, radius, friction, filter };
        let (c, h) = (vec3(center, "center")?, vec3(half_extents, "half_extents")?);
        let cells = [cells.0, cells.1, cells.2];
        let r = self.inner.add_soft_box(c, h, cells, &mat, k, kv).py_err()?;
        let call = ParticleCall::SoftBox { center: c, half_extents: h, cells, mat, k, volume: kv };
        self.inner.recipe.particles.push(call);
        range(py, r)
    }

    /// A shape-matched body from a shape or a point set; returns (particle range,
    /// cluster indices).
    #[pyo3(signature = (source, *, spacing=None, position=None, orientation=None, mass=1.0, radius=0.0, friction=0.5,
                        mode="linear", stiffness=1.0, beta=0.5, preserve_volume=true, plastic_yield=None,
                        plastic_creep=0.0, plastic_max=f64::INFINITY, cluster_size=None, collision_group=1,
                        collision_mask=4294967295))]
    #[allow(clippy::too_many_arguments)]
    fn add_shape_matched_body<'py>(
        &mut self,
        py: Python<'py>,
        source: &Bound<'py, PyAny>,
        spacing: Option<f64>,
        position: Option<&Bound<'py, PyAny>>,
        orientation: Option<&Bound<'py, PyAny>>,
        mass: f64,
        radius: f64,
        friction: f64,
        mode: &str,
        stiffness: f64,
        beta: f64,
        preserve_volume: bool,
        plastic_yield: Option<f64>,
        plastic_creep: f64,
        plastic_max: f64,
        cluster_size: Option<f64>,
        collision_group: i64,
        collision_mask: i64,
    ) -> PyResult<(Bound<'py, PyRange>, Vec<usize>)> {
        let index = self.inner.xpbd().clusters.len();
        let spec = cluster_spec(mode, stiffness, beta, preserve_volume, plastic_yield, plastic_creep, plastic_max)
            .map_err(|e| e.context(format!("cluster {index}")))
            .py_err()?;
        let given;
        let local = match source.cast::<PyShape>() {
            Ok(shape) => {
                let s = spacing.ok_or_else(|| PyValueError::new_err("spacing (m) is required to fill a shape with particles"))?;
                given = Source::Shape(shape.get().inner.clone());
                builders::fill_shape(&shape.get().inner, s).py_err()?
            }
            Err(_) => {
                if spacing.is_some() {
                    return Err(PyValueError::new_err("spacing applies to a shape source, not to points"));
                }
                let points = rows3(source, "points")?;
                given = Source::Points(points.clone());
                points
            }
        };
        let position = position.map(|p| vec3(p, "position")).transpose()?;
        let orientation = orientation.map(|q| vec4(q, "orientation")).transpose()?;
        let p = position.unwrap_or([0.0; 3]);
        let q = orientation.unwrap_or([0.0, 0.0, 0.0, 1.0]);
        let iso = pose(p, q).py_err()?;
        let points: Vec<[f64; 3]> = local.iter().map(|x| (iso * nalgebra::Point3::from(Vec3::from(*x))).coords.into()).collect();
        let filter = particle_filter(collision_group, collision_mask, "particles")?;
        let mat = Material { mass, radius, friction, filter };
        let (r, ids) = self.inner.add_shape_matched_body(&points, &mat, spec, cluster_size).py_err()?;
        let call = ParticleCall::ShapeMatchedBody { source: given, spacing, position, orientation, mat, spec, cluster_size };
        self.inner.recipe.particles.push(call);
        Ok((range(py, r)?, ids))
    }
}

/// The particles of a world, as views. Writable: `position`, `velocity`.
/// Read-only: `inverse_mass`, `mass`, `radius`.
#[pyclass(name = "Particles", module = "rigidrs._core", frozen)]
pub struct PyParticles {
    pub world: Py<PyWorld>,
}

#[derive(Clone, Copy)]
enum Field {
    Position,
    Velocity,
    InverseMass,
    Mass,
    Radius,
}

impl PyParticles {
    fn field<'py>(&self, py: Python<'py>, field: Field) -> PyResult<Bound<'py, PyAny>> {
        let w = self.world.bind(py);
        let located = {
            let g = w.try_borrow()?;
            use crate::world::guard::exposed::{PARTICLE_POSITION, PARTICLE_VELOCITY};
            g.guard.expose(match field {
                Field::Position => PARTICLE_POSITION,
                Field::Velocity => PARTICLE_VELOCITY,
                _ => 0,
            });
            g.inner.particles().map(|p| {
                fn ptr<T>(v: &[T]) -> *const f64 {
                    v.as_ptr() as *const f64
                }
                let (ptr, row, writable): (_, &[usize], _) = match field {
                    Field::Position => (ptr(&p.position), &[3], true),
                    Field::Velocity => (ptr(&p.velocity), &[3], true),
                    Field::InverseMass => (ptr(&p.inv_mass), &[], false),
                    Field::Mass => (ptr(&p.mass), &[], false),
                    Field::Radius => (ptr(&p.radius), &[], false),
                };
                (ptr, row, writable, p.len())
            })
        };
        let Some((ptr, row, writable, n)) = located else {
            // No particles: an empty array (there is no memory to share).
            let np = py.import("numpy")?;
            let shape: Vec<usize> = match field {
                Field::Position | Field::Velocity => vec![0, 3],
                _ => vec![0],
            };
            return np.call_method1("zeros", (shape,));
        };
        let shape: Vec<usize> = std::iter::once(n).chain(row.iter().copied()).collect();
        // Safety: the particle arrays are Vecs of the world allocated once at build
        // and never reallocated; the view's base is the world object.
        unsafe { view(w, ptr, &shape, writable) }
    }
}

#[pymethods]
impl PyParticles {
    fn __len__(&self, py: Python<'_>) -> PyResult<usize> {
        Ok(self.world.bind(py).try_borrow()?.inner.particles().map_or(0, |p| p.len()))
    }

    /// (M, 3) positions, world (m); writable.
    #[getter]
    fn position<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::Position)
    }
    /// (M, 3) velocities, world (m/s); writable.
    #[getter]
    fn velocity<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::Velocity)
    }
    /// (M,) 1/mass (1/kg), 0 for pinned particles; read-only.
    #[getter]
    fn inverse_mass<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::InverseMass)
    }
    /// (M,) mass (kg), also of pinned particles; read-only.
    #[getter]
    fn mass<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::Mass)
    }
    /// (M,) collision radius (m); read-only.
    #[getter]
    fn radius<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.field(py, Field::Radius)
    }
}

#[pymethods]
impl PyWorld {
    /// The particles, as NumPy views.
    #[getter]
    fn particles(slf: Bound<'_, Self>) -> PyParticles {
        PyParticles { world: slf.unbind() }
    }

    /// (C,) `λ/h²` of every constraint at the last substep, by constraint index.
    fn constraint_forces<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_vec(py, self.inner.constraint_forces())
    }

    /// The shape-matching clusters at the last substep: `center` (K, 3) (m),
    /// `rotation` (K, 3, 3), `plastic` (K, 3, 3) plastic deformation Sp.
    fn clusters<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let clusters = self.inner.xpbd.as_ref().map_or(&[][..], |x| &x.shape_matching.clusters[..]);
        let k = clusters.len();
        let center: Vec<f64> = clusters.iter().flat_map(|c| c.center.iter().copied().collect::<Vec<_>>()).collect();
        let rows = |m: &crate::math::Mat3| (0..3).flat_map(|r| (0..3).map(move |c| m[(r, c)])).collect::<Vec<_>>();
        let rotation: Vec<f64> = clusters.iter().flat_map(|c| rows(&quat::to_matrix(c.rotation.quaternion()))).collect();
        let plastic: Vec<f64> = clusters.iter().flat_map(|c| rows(&c.plastic)).collect();
        let d = PyDict::new(py);
        d.set_item("center", PyArray1::from_vec(py, center).reshape([k, 3])?)?;
        d.set_item("rotation", PyArray1::from_vec(py, rotation).reshape([k, 3, 3])?)?;
        d.set_item("plastic", PyArray1::from_vec(py, plastic).reshape([k, 3, 3])?)?;
        Ok(d)
    }
}
