//! The particle side of a scene and of a world: `Scene` methods that add
//! particles, constraints, builders and shape-matching clusters (each validated
//! when added, naming the particle or constraint, and leaving the scene
//! unchanged on error), the compilation into the world's [`Xpbd`], and the
//! particle stages of a substep (see `pipeline` for where they run).

use std::ops::Range;

use super::{Scene, Settings, World};
use super::collision::collider_of;
use super::pipeline::StageKind;
use crate::error::{Error, Result};
use crate::xpbd::builders::{self, Material};
use crate::xpbd::shape_matching::ClusterSpec;
use crate::xpbd::{Compliance, ParticleSpec, Particles, Xpbd, XpbdModel};

impl Scene {
    /// The particles, constraints and clusters added so far.
    pub fn xpbd(&self) -> &XpbdModel {
        &self.xpbd
    }

    /// Adds a particle; returns its index.
    pub fn add_particle(&mut self, spec: &ParticleSpec) -> Result<usize> {
        self.xpbd.add_particle(spec)
    }

    /// Distance constraint between particles `i` and `j` (rest length `rest` in
    /// m, default their current distance); returns the constraint index.
    pub fn add_distance_constraint(&mut self, i: i64, j: i64, k: Compliance, rest: Option<f64>) -> Result<usize> {
        self.xpbd.add_distance(i, j, k, rest)
    }

    /// Dihedral bending over edge p0–p1 with tips p2, p3 (rest: current angle).
    pub fn add_bending_constraint(&mut self, p: [i64; 4], k: Compliance) -> Result<usize> {
        self.xpbd.add_bending(p, k)
    }

    /// Volume of the tetrahedron `p` (rest: current volume).
    pub fn add_volume_constraint(&mut self, p: [i64; 4], k: Compliance) -> Result<usize> {
        self.xpbd.add_tet_volume(p, k)
    }

    /// Volume of a closed particle mesh (counter-clockwise triangles from
    /// outside), kept at `pressure` times its current volume.
    pub fn add_mesh_volume_constraint(&mut self, triangles: &[[i64; 3]], pressure: f64, k: Compliance) -> Result<usize> {
        self.xpbd.add_mesh_volume(triangles, pressure, k)
    }

    /// Attaches particle `particle` to body `body` at the world point `point`
    /// (m, default the particle's position) with rest length `rest` (m).
    pub fn add_attachment(&mut self, particle: i64, body: i64, point: Option<[f64; 3]>, rest: f64, k: Compliance) -> Result<usize> {
        let n = self.bodies().len();
        let id = self.xpbd.constraint_count();
        let Some(d) = usize::try_from(body).ok().and_then(|b| self.bodies().get(b)) else {
            return Err(Error::input(format!("constraint {id} (attachment): body index {body} is out of range: the scene has {n} bodies")));
        };
        let (p, q) = (d.init.position, d.init.orientation);
        self.xpbd.add_attachment(particle, body as usize, p, q, point, rest, k)
    }

    /// A shape-matching cluster over `particles`; returns the cluster index.
    pub fn add_shape_matching(&mut self, particles: &[i64], spec: ClusterSpec) -> Result<usize> {
        self.xpbd.add_cluster(particles, spec)
    }

    /// See [`builders::rope`].
    pub fn add_rope(
        &mut self,
        start: [f64; 3],
        end: [f64; 3],
        segments: i64,
        mat: &Material,
        k: Compliance,
        pinned: &[usize],
    ) -> Result<Range<usize>> {
        builders::rope(&mut self.xpbd, start, end, segments, mat, k, pinned)
    }

    /// See [`builders::cloth`].
    #[allow(clippy::too_many_arguments)]
    pub fn add_cloth(
        &mut self,
        origin: [f64; 3],
        u: [f64; 3],
        v: [f64; 3],
        n: [i64; 2],
        mat: &Material,
        k: Compliance,
        bending: Option<Compliance>,
        pinned: &[usize],
    ) -> Result<Range<usize>> {
        builders::cloth(&mut self.xpbd, origin, u, v, n[0], n[1], mat, k, bending, pinned)
    }

    /// See [`builders::soft_box`].
    pub fn add_soft_box(
        &mut self,
        center: [f64; 3],
        half_extents: [f64; 3],
        cells: [i64; 3],
        mat: &Material,
        k: Compliance,
        volume: Option<Compliance>,
    ) -> Result<Range<usize>> {
        builders::soft_box(&mut self.xpbd, center, half_extents, cells, mat, k, volume)
    }

    /// See [`builders::shape_matched_body`].
    pub fn add_shape_matched_body(
        &mut self,
        points: &[[f64; 3]],
        mat: &Material,
        spec: ClusterSpec,
        cluster_size: Option<f64>,
    ) -> Result<(Range<usize>, Vec<usize>)> {
        builders::shape_matched_body(&mut self.xpbd, points, mat, spec, cluster_size)
    }
}

/// The world's particle system, or `None` for a scene without particles.
pub(crate) fn compile(scene: &Scene, settings: &Settings) -> Result<Option<Xpbd>> {
    if scene.xpbd.is_empty() {
        return Ok(None);
    }
    let colliders = scene.bodies().iter().enumerate().filter_map(|(i, d)| collider_of(i, d)).collect();
    let g = crate::math::Vec3::from(scene.gravity);
    Xpbd::new(&scene.xpbd, g, settings.iterations, colliders, settings.solver.slop).map(Some)
}

impl World {
    /// The particles (state arrays), if the world has any.
    pub fn particles(&self) -> Option<&Particles> {
        self.xpbd.as_ref().map(|x| &x.particles)
    }

    /// `λ/h²` of every constraint at the last substep, by constraint index (see
    /// [`Xpbd::forces`]); empty without particles.
    pub fn constraint_forces(&self) -> Vec<f64> {
        self.xpbd.as_ref().map_or_else(Vec::new, |x| x.forces())
    }

    /// Particle state written through views must be finite before a step.
    pub(crate) fn check_particles(&self) -> Result<()> {
        self.xpbd.as_ref().map_or(Ok(()), |x| x.particles.check())
    }

    pub(crate) fn particle_stage(&mut self, kind: StageKind, h: f64) {
        let Some(x) = self.xpbd.as_mut() else { return };
        match kind {
            StageKind::ParticlePredict => x.predict(h),
            StageKind::ShapeMatching => x.shape_match(h),
            _ => {
                x.project(&mut self.bodies, h);
                self.wake_pulled_bodies();
            }
        }
    }

    /// Sleeping bodies that a particle moving faster than the sleep threshold is
    /// attached to or touches wake up (particles see sleeping bodies as fixed).
    fn wake_pulled_bodies(&mut self) {
        let (Some(x), Some(c)) = (self.xpbd.as_ref(), self.collision.as_mut()) else { return };
        let limit = self.settings.sleep.linear;
        let p = &x.particles;
        let moving = |i: u32| crate::math::Vec3::from(p.velocity[i as usize]).norm() > limit;
        let pulled = x.attachments.iter().map(|a| (a.body, a.particle)).chain(x.colliders.contacts.iter().map(|t| (t.body, t.particle)));
        let mut woke = false;
        for (b, i) in pulled {
            if self.bodies.sleeping[b as usize] && moving(i) {
                woke |= c.islands.wake(&mut self.bodies, b as usize);
            }
        }
        if woke {
            self.relist();
        }
    }
}

/// Energy and momentum of the movable particles (pinned ones are like fixed
/// bodies: they carry none).
#[derive(Clone, Copy, Debug, Default, serde::Serialize, serde::Deserialize)]
pub(crate) struct ParticleSums {
    /// `Σ ½ m v²` (J), `−Σ m g·x` (J), `Σ m v` (kg·m/s), `Σ x × m v` (kg·m²/s).
    pub kinetic: f64,
    pub potential: f64,
    pub linear: crate::math::Vec3,
    pub angular: crate::math::Vec3,
}

impl World {
    pub(crate) fn particle_sums(&self) -> ParticleSums {
        use crate::math::Vec3;
        let mut s = ParticleSums::default();
        let Some(p) = self.particles() else { return s };
        for i in 0..p.len() {
            if p.inv_mass[i] == 0.0 {
                continue;
            }
            let (m, x, v) = (p.mass[i], Vec3::from(p.position[i]), Vec3::from(p.velocity[i]));
            s.kinetic += 0.5 * m * v.norm_squared();
            s.potential -= m * self.gravity.dot(&x);
            s.linear += v * m;
            s.angular += x.cross(&(v * m));
        }
        s
    }
}
