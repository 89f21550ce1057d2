//! The XPBD step of a world's particles (Müller et al. 2007; Macklin et al.
//! 2016; Macklin et al. 2019, "Small steps in physics simulation"). Each substep
//! of length `h`:
//!
//! 1. predict ([`Xpbd::predict`]): `prev = x`, `v += h g`, `x += h v` for every
//!    movable particle;
//! 2. shape matching, when the scene has clusters (its own stage, see
//!    [`super::shape_matching`]);
//! 3. project ([`Xpbd::project`]): find this substep's collisions, reset every
//!    `λ` to 0, then `iterations` symmetric Gauss–Seidel passes: the constraints
//!    in the order distance, bending, tetrahedral volume, mesh volume,
//!    attachments, then the same in reverse, then particle–particle and
//!    particle–collider contacts (collisions last, so they win); then
//!    `v = (x − prev) / h`.
//!
//! Why both ways. With one forward sweep, a substep maps the deviation `z` of the
//! positions and the step `u = h v` as `z' = Π(z + u)`, `u' = z' − z`, with `Π` the
//! product of the constraints' (mass-weighted orthogonal) projections. An
//! eigenvalue `π` of `Π` gives the substep the factors `μ = π ± √(π² − π)`: for
//! real `π` in [0, 1], `|μ|² = π ≤ 1`, but a forward sweep's `Π` is not
//! self-adjoint and has complex eigenvalues, and near 1 those give `|μ| > 1`. On a
//! cloth of 20 × 20 or finer the slowest in-plane modes of the stretch links do
//! (`|μ| = 1.0082` per substep for 20 × 20, where the engine's Jacobian and the
//! linear model agree, 1.0083 for 30 × 30): a flat cloth lying on a frictionless floor grew
//! from 1e-4 to 5.6 m/s in 2 s, and with bending (which stops it buckling out of
//! the plane, where the growth would otherwise crumple away) the README's cloth
//! over a sphere blew up. The forward-then-backward sweep's `Π = AᵀA` (in the
//! mass metric) is self-adjoint with eigenvalues in [0, 1], so no mode grows; a
//! compliant constraint's update is the same symmetric Gauss–Seidel on
//! `(∇CᵀW∇C + α̃) λ = −C`, and keeps that property.
//!
//! Forces are readable after a step as `λ / h²` of its last substep.

use super::attachment::{self, Attachment};
use super::bending::{self, Bending};
use super::collision::{ColliderCollisions, ParticlePairs};
use super::compliance::Substep;
use super::distance::{self, Distance};
use super::model::{ConstraintKind, XpbdModel};
use super::particles::Particles;
use super::shape_matching::ShapeMatching;
use super::volume::{self, MeshVolume, TetVolume};
use crate::body::Bodies;
use crate::collide::Collider;
use crate::error::Result;
use crate::math::Vec3;

#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub struct Xpbd {
    pub particles: Particles,
    pub distance: Vec<Distance>,
    pub bending: Vec<Bending>,
    pub tets: Vec<TetVolume>,
    pub meshes: Vec<MeshVolume>,
    pub attachments: Vec<Attachment>,
    pub shape_matching: ShapeMatching,
    pub colliders: ColliderCollisions,
    pub pairs: ParticlePairs,
    pub kinds: Vec<ConstraintKind>,
    gravity: Vec3,
    /// Constraint passes per substep (≥ 1).
    pub iterations: u32,
    /// The last substep (s), for reading forces.
    last_h: f64,
}

impl Xpbd {
    /// Compiles the particle side of a scene. `colliders` are the rigid
    /// colliders of the world, `margin` (m) how far ahead contacts are made.
    pub fn new(m: &XpbdModel, gravity: Vec3, iterations: u32, colliders: Vec<Collider>, margin: f64) -> Result<Self> {
        Ok(Self {
            shape_matching: ShapeMatching::new(m.clusters.clone(), &m.particles)?,
            colliders: ColliderCollisions::new(colliders, margin, &m.particles),
            pairs: ParticlePairs::new(&m.particles),
            particles: m.particles.clone(),
            distance: m.distance.clone(),
            bending: m.bending.clone(),
            tets: m.tets.clone(),
            meshes: m.meshes.clone(),
            attachments: m.attachments.clone(),
            kinds: m.kinds.clone(),
            gravity,
            iterations: iterations.max(1),
            last_h: 0.0,
        })
    }

    /// `prev = x`, `v += h g`, `x += h v` for movable particles; pinned ones keep
    /// their position and have no velocity.
    pub fn predict(&mut self, h: f64) {
        let g = self.gravity;
        let p = &mut self.particles;
        for i in 0..p.len() {
            p.prev[i] = p.position[i];
            if p.inv_mass[i] == 0.0 {
                p.velocity[i] = [0.0; 3];
                continue;
            }
            let v = Vec3::from(p.velocity[i]) + g * h;
            p.velocity[i] = v.into();
            p.position[i] = (Vec3::from(p.position[i]) + v * h).into();
        }
    }

    /// The shape-matching stage of a substep of `h` seconds.
    pub fn shape_match(&mut self, h: f64) {
        self.shape_matching.apply(&mut self.particles, h);
    }

    /// Collisions, `iterations` constraint passes, and the velocities.
    pub fn project(&mut self, bodies: &mut Bodies, h: f64) {
        let k = Substep::new(h);
        self.last_h = h;
        if !self.colliders.is_empty() {
            self.colliders.detect(&self.particles, bodies);
        }
        self.pairs.detect(&self.particles);
        self.pairs.reset();
        self.reset_multipliers();
        for _ in 0..self.iterations {
            self.pass(bodies, &k);
        }
        let p = &mut self.particles;
        for i in 0..p.len() {
            let v = (Vec3::from(p.position[i]) - Vec3::from(p.prev[i])) * k.inv_h;
            p.velocity[i] = v.into();
        }
    }

    fn reset_multipliers(&mut self) {
        self.distance.iter_mut().for_each(|c| c.lambda = 0.0);
        self.bending.iter_mut().for_each(|c| c.lambda = 0.0);
        self.tets.iter_mut().for_each(|c| c.lambda = 0.0);
        self.meshes.iter_mut().for_each(|c| c.lambda = 0.0);
        self.attachments.iter_mut().for_each(|c| c.lambda = 0.0);
    }

    /// One symmetric Gauss–Seidel pass: the particle constraints forward, then
    /// backward, then the contacts (see the module docs for why both ways).
    fn pass(&mut self, bodies: &mut Bodies, k: &Substep) {
        self.sweep(bodies, k, false);
        self.sweep(bodies, k, true);
        self.pairs.project(&mut self.particles);
        self.colliders.project(&mut self.particles, bodies, k);
    }

    /// One Gauss–Seidel sweep over the particle constraints (not the contacts), in
    /// the order distance, bending, volume, mesh volume, attachment, or the reverse.
    fn sweep(&mut self, bodies: &mut Bodies, k: &Substep, reverse: bool) {
        let Particles { position: x, prev, inv_mass: w, .. } = &mut self.particles;
        let order: [usize; 5] = if reverse { [4, 3, 2, 1, 0] } else { [0, 1, 2, 3, 4] };
        for kind in order {
            match kind {
                0 => each(&mut self.distance, reverse, |c| distance::project(c, x, prev, w, k)),
                1 => each(&mut self.bending, reverse, |c| bending::project(c, x, prev, w, k)),
                2 => each(&mut self.tets, reverse, |c| volume::project_tet(c, x, prev, w, k)),
                3 => each(&mut self.meshes, reverse, |c| c.project(x, prev, w, k)),
                _ => each(&mut self.attachments, reverse, |c| attachment::project(c, x, prev, w, bodies, k)),
            }
        }
    }

    /// `λ / h²` of every constraint at the last substep, by constraint index: the
    /// generalized force (N, N·m or Pa; see each constraint's docs). Zero before
    /// the first step.
    pub fn forces(&self) -> Vec<f64> {
        let mut out = vec![0.0; self.kinds.len()];
        if self.last_h == 0.0 {
            return out;
        }
        let s = 1.0 / (self.last_h * self.last_h);
        let mut put = |id: u32, l: f64| out[id as usize] = l * s;
        self.distance.iter().for_each(|c| put(c.id, c.lambda));
        self.bending.iter().for_each(|c| put(c.id, c.lambda));
        self.tets.iter().for_each(|c| put(c.id, c.lambda));
        self.meshes.iter().for_each(|c| put(c.id, c.lambda));
        self.attachments.iter().for_each(|c| put(c.id, c.lambda));
        out
    }
}

/// `f` on every item of `list`, last to first if `reverse`.
#[inline(always)]
fn each<T>(list: &mut [T], reverse: bool, f: impl FnMut(&mut T)) {
    if reverse {
        list.iter_mut().rev().for_each(f)
    } else {
        list.iter_mut().for_each(f)
    }
}
