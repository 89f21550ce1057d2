//! The particle side of a scene: particles, constraints and clusters as added,
//! each validated when added so that an error names the particle or constraint
//! and leaves the scene unchanged.
//!
//! Every constraint gets an index in the order it is added (all kinds share one
//! numbering): the index of its force in `World::constraint_forces`.

use std::ops::Range;

use super::attachment::Attachment;
use super::bending::{self, Bending};
use super::compliance::Compliance;
use super::distance::Distance;
use super::particles::{ParticleSpec, Particles};
use super::shape_matching::{Cluster, ClusterSpec};
use super::volume::{self, MeshVolume, TetVolume};
use crate::error::{non_negative, Error, Result};
use crate::math::{quat, Quat, Vec3};

/// The kind of each constraint, by index.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum ConstraintKind {
    Distance,
    Bending,
    TetVolume,
    MeshVolume,
    Attachment,
}

impl ConstraintKind {
    pub fn name(&self) -> &'static str {
        match self {
            ConstraintKind::Distance => "distance",
            ConstraintKind::Bending => "bending",
            ConstraintKind::TetVolume => "volume",
            ConstraintKind::MeshVolume => "mesh volume",
            ConstraintKind::Attachment => "attachment",
        }
    }
}

#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct XpbdModel {
    /// Particles in their initial state.
    pub particles: Particles,
    pub distance: Vec<Distance>,
    pub bending: Vec<Bending>,
    pub tets: Vec<TetVolume>,
    pub meshes: Vec<MeshVolume>,
    pub attachments: Vec<Attachment>,
    pub clusters: Vec<Cluster>,
    pub kinds: Vec<ConstraintKind>,
}

impl XpbdModel {
    pub fn is_empty(&self) -> bool {
        self.particles.is_empty()
    }

    pub fn constraint_count(&self) -> usize {
        self.kinds.len()
    }

    /// Validates and adds a particle; returns its index.
    pub fn add_particle(&mut self, spec: &ParticleSpec) -> Result<usize> {
        let index = self.particles.len();
        spec.validate().map_err(|e| e.context(format!("particle {index}")))?;
        self.particles.push(spec);
        Ok(index)
    }

    /// A particle index, checked against the particles added so far.
    pub fn particle(&self, i: i64) -> Result<u32> {
        let n = self.particles.len();
        if i < 0 || i as u64 >= n as u64 {
            return Err(Error::input(format!("particle index {i} is out of range: the scene has {n} particles")));
        }
        Ok(i as u32)
    }

    /// Distinct, valid particle indices.
    fn distinct<const N: usize>(&self, ids: [i64; N]) -> Result<[u32; N]> {
        let mut out = [0u32; N];
        for (k, &i) in ids.iter().enumerate() {
            out[k] = self.particle(i)?;
            if out[..k].contains(&out[k]) {
                return Err(Error::input(format!("particle {i} is constrained to itself (it appears twice in {ids:?})")));
            }
        }
        Ok(out)
    }

    fn position(&self, i: u32) -> Vec3 {
        Vec3::from(self.particles.initial[i as usize])
    }

    /// Runs `f` with the index of the next constraint, adding context to its error.
    fn next<T>(&self, kind: ConstraintKind, f: impl FnOnce(u32) -> Result<T>) -> Result<T> {
        let id = self.kinds.len();
        f(id as u32).map_err(|e| e.context(format!("constraint {id} ({})", kind.name())))
    }

    fn push_kind(&mut self, kind: ConstraintKind) -> usize {
        self.kinds.push(kind);
        self.kinds.len() - 1
    }

    /// Distance constraint between particles `i` and `j`; rest length `rest`
    /// (m, ≥ 0; default: their current distance). Returns the constraint index.
    pub fn add_distance(&mut self, i: i64, j: i64, k: Compliance, rest: Option<f64>) -> Result<usize> {
        let c = self.next(ConstraintKind::Distance, |id| {
            let [i, j] = self.distinct([i, j])?;
            let k = Compliance::new(k.alpha, k.damping)?;
            let rest = match rest {
                Some(r) => non_negative("rest_length", r)?,
                None => (self.position(i) - self.position(j)).norm(),
            };
            Ok(Distance { i, j, rest, compliance: k, id, lambda: 0.0 })
        })?;
        self.distance.push(c);
        Ok(self.push_kind(ConstraintKind::Distance))
    }

    /// Dihedral bending over the edge `p[0]`–`p[1]` of triangles (p0, p1, p2) and
    /// (p1, p0, p3); the rest angle is the current one.
    pub fn add_bending(&mut self, p: [i64; 4], k: Compliance) -> Result<usize> {
        let c = self.next(ConstraintKind::Bending, |id| {
            let p = self.distinct(p)?;
            let k = Compliance::new(k.alpha, k.damping)?;
            let (rest, _) = bending::angle_and_gradient(p.map(|i| self.position(i)))
                .ok_or_else(|| Error::shape(format!("the triangles of particles {p:?} are degenerate (no normal)")))?;
            Ok(Bending { p, rest, compliance: k, id, lambda: 0.0 })
        })?;
        self.bending.push(c);
        Ok(self.push_kind(ConstraintKind::Bending))
    }

    /// Volume of the tetrahedron `p`; the rest volume is the current one.
    pub fn add_tet_volume(&mut self, p: [i64; 4], k: Compliance) -> Result<usize> {
        let c = self.next(ConstraintKind::TetVolume, |id| {
            let p = self.distinct(p)?;
            let k = Compliance::new(k.alpha, k.damping)?;
            let rest = volume::tet_rest(p.map(|i| self.position(i)))?;
            Ok(TetVolume { p, rest, compliance: k, id, lambda: 0.0 })
        })?;
        self.tets.push(c);
        Ok(self.push_kind(ConstraintKind::TetVolume))
    }

    /// Volume enclosed by the closed particle mesh `triangles` (counter-clockwise
    /// from outside), kept at `pressure` (–, > 0) times its current volume.
    pub fn add_mesh_volume(&mut self, triangles: &[[i64; 3]], pressure: f64, k: Compliance) -> Result<usize> {
        let c = self.next(ConstraintKind::MeshVolume, |id| {
            let k = Compliance::new(k.alpha, k.damping)?;
            crate::error::positive("pressure", pressure)?;
            let tris = triangles
                .iter()
                .enumerate()
                .map(|(t, tri)| {
                    let mut out = [0u32; 3];
                    for a in 0..3 {
                        out[a] = self.particle(tri[a]).map_err(|e| e.context(format!("triangle {t}")))?;
                    }
                    Ok(out)
                })
                .collect::<Result<Vec<_>>>()?;
            MeshVolume::new(&tris, &self.particles.initial, pressure, k, id)
        })?;
        self.meshes.push(c);
        Ok(self.push_kind(ConstraintKind::MeshVolume))
    }

    /// Attaches particle `i` to body `body` (pose of its principal frame at the
    /// centre of mass: `body_position`, `body_orientation`) at the world point
    /// `point` (m; default: the particle's position), with rest length `rest`
    /// (m, default 0).
    #[allow(clippy::too_many_arguments)]
    pub fn add_attachment(
        &mut self,
        i: i64,
        body: usize,
        body_position: Vec3,
        body_orientation: Quat,
        point: Option<[f64; 3]>,
        rest: f64,
        k: Compliance,
    ) -> Result<usize> {
        let c = self.next(ConstraintKind::Attachment, |id| {
            let [i] = self.distinct([i])?;
            let k = Compliance::new(k.alpha, k.damping)?;
            non_negative("rest_length", rest)?;
            let a = match point {
                Some(p) => Vec3::from(crate::error::finite3("point", p)?),
                None => self.position(i),
            };
            let local = quat::rotate_inv(&body_orientation, &(a - body_position));
            Ok(Attachment { particle: i, body: body as u32, local, rest, compliance: k, id, lambda: 0.0 })
        })?;
        self.attachments.push(c);
        Ok(self.push_kind(ConstraintKind::Attachment))
    }

    /// A shape-matching cluster of `particles` (distinct); returns its index.
    pub fn add_cluster(&mut self, particles: &[i64], spec: ClusterSpec) -> Result<usize> {
        let index = self.clusters.len();
        let c = (|| {
            let ids = particles.iter().map(|&p| self.particle(p)).collect::<Result<Vec<_>>>()?;
            // Sorted, not searched: a body of a million particles is one cluster.
            let mut sorted = ids.clone();
            sorted.sort_unstable();
            if let Some(w) = sorted.windows(2).find(|w| w[0] == w[1]) {
                return Err(Error::input(format!("particle {} appears twice", w[0])));
            }
            let x: Vec<Vec3> = ids.iter().map(|&i| self.position(i)).collect();
            let m: Vec<f64> = ids.iter().map(|&i| self.particles.mass[i as usize]).collect();
            Cluster::new(ids, spec, &x, &m)
        })()
        .map_err(|e| e.context(format!("cluster {index}")))?;
        self.clusters.push(c);
        Ok(index)
    }

    /// Runs `f`, which adds to the model, and removes everything it added if it
    /// fails: builders leave the scene unchanged on error.
    pub fn atomically<T>(&mut self, f: impl FnOnce(&mut Self) -> Result<T>) -> Result<T> {
        let mark = [
            self.particles.len(),
            self.distance.len(),
            self.bending.len(),
            self.tets.len(),
            self.meshes.len(),
            self.attachments.len(),
            self.clusters.len(),
            self.kinds.len(),
        ];
        let r = f(self);
        if r.is_err() {
            self.particles.truncate(mark[0]);
            self.distance.truncate(mark[1]);
            self.bending.truncate(mark[2]);
            self.tets.truncate(mark[3]);
            self.meshes.truncate(mark[4]);
            self.attachments.truncate(mark[5]);
            self.clusters.truncate(mark[6]);
            self.kinds.truncate(mark[7]);
        }
        r
    }

    /// Indices `start..end` of particles added by a builder.
    pub fn range_from(&self, start: usize) -> Range<usize> {
        start..self.particles.len()
    }
}
