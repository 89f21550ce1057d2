//! Particle collisions, as inequality constraints projected with the others
//! (compliance 0):
//!
//! - against the world's rigid colliders: each substep, every movable particle
//!   near a collider's box is projected onto the shape with parry
//!   (`C = n·(x − a) − r ≥ 0`, `a` the surface point and `n` its outward normal,
//!   both fixed in the body's frame so the contact follows the body). Dynamic
//!   bodies take their share through their generalized inverse mass. Friction is
//!   position-based (Müller et al. 2020): the tangential slip over the substep is
//!   removed while its multiplier stays within `μs λn`, and limited to `μk λn`
//!   beyond. A particle moving farther than its radius in a substep is swept
//!   along its motion (a ray from its previous position), so it cannot tunnel
//!   through a thin shape. A triangle mesh, which has no inside, is a thin
//!   two-sided shell whose outside is the side the particle comes from.
//! - between particles with a radius: pairs within reach are found each substep
//!   with a spatial hash; `C = |xᵢ − xⱼ| − (rᵢ + rⱼ) ≥ 0`, with the same
//!   position-based friction on their relative slip, `μ = √(μᵢ μⱼ)` static and
//!   dynamic. Pairs that already overlap where the particles were added
//!   (neighbours in a cloth or a soft body) never collide.

use nalgebra::Point3;
use parry3d_f64::query::Ray;

use super::body_point::{self, world_point};
use super::compliance::Substep;
use super::particles::Particles;
use super::spatial_hash::SpatialHash;
use crate::body::Bodies;
use crate::collide::broad_phase::Aabb;
use crate::collide::{Collider, Filter};
use crate::math::{quat, Vec3};

/// A particle touching (or about to touch) a rigid collider this substep.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct ColliderContact {
    pub particle: u32,
    pub body: u32,
    /// Surface point and outward normal in the body's principal frame (m, –).
    pub local_point: Vec3,
    pub local_normal: Vec3,
    /// Combined static and dynamic friction (–).
    pub static_friction: f64,
    pub friction: f64,
    /// Normal and tangential multipliers of this substep (kg·m).
    pub lambda_n: f64,
    pub lambda_t: f64,
}

/// Particles against rigid colliders.
#[derive(Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct ColliderCollisions {
    pub colliders: Vec<Collider>,
    boxes: Vec<Option<Aabb>>,
    pub contacts: Vec<ColliderContact>,
    /// Contacts are created this far (m) before the particle touches.
    margin: f64,
}

/// Normals shorter than this (m) are taken from the surface feature instead.
const ON_SURFACE: f64 = 1e-12;

impl ColliderCollisions {
    /// The colliders particles may touch: those whose filter allows some
    /// particle's.
    pub fn new(colliders: Vec<Collider>, margin: f64, particles: &Particles) -> Self {
        let mut filters: Vec<Filter> = particles.filter.clone();
        filters.sort_unstable_by_key(|f| (f.group, f.mask));
        filters.dedup();
        let colliders: Vec<Collider> = colliders.into_iter().filter(|c| filters.iter().any(|f| c.filter.allows(f))).collect();
        Self { boxes: vec![None; colliders.len()], colliders, contacts: Vec::new(), margin }
    }

    pub fn is_empty(&self) -> bool {
        self.colliders.is_empty()
    }

    /// Finds this substep's contacts of the movable particles.
    pub fn detect(&mut self, p: &Particles, b: &Bodies) {
        self.contacts.clear();
        for (k, c) in self.colliders.iter().enumerate() {
            self.boxes[k] = (!c.infinite).then(|| Aabb::from_parry(&c.shape.compute_aabb(&c.pose(b))));
        }
        for i in 0..p.len() {
            if p.inv_mass[i] == 0.0 {
                continue;
            }
            let reach = p.radius[i] + self.margin;
            let (x, x0) = (p.position[i], p.prev[i]);
            // The box around the particle's motion this substep.
            let near = Aabb {
                min: [0, 1, 2].map(|k| x[k].min(x0[k]) - reach),
                max: [0, 1, 2].map(|k| x[k].max(x0[k]) + reach),
            };
            for (k, c) in self.colliders.iter().enumerate() {
                if self.boxes[k].is_some_and(|a| !a.overlaps(&near)) || !c.filter.allows(&p.filter[i]) {
                    continue;
                }
                if let Some(ct) = contact(c, b, p, i, reach) {
                    self.contacts.push(ct);
                }
            }
        }
    }

    /// One pass over the contacts: normal, then friction.
    pub fn project(&mut self, p: &mut Particles, b: &mut Bodies, k: &Substep) {
        for ct in &mut self.contacts {
            project_contact(ct, p, b, k);
        }
    }
}

/// The contact of particle `i` with collider `c`, if closer than `reach` (m).
fn contact(c: &Collider, b: &Bodies, p: &Particles, i: usize, reach: f64) -> Option<ColliderContact> {
    let pose = c.pose(b);
    let local = pose.inverse_transform_point(&Point3::from(Vec3::from(p.position[i])));
    let prev = pose.inverse_transform_point(&Point3::from(Vec3::from(p.prev[i])));
    let (point, normal) = match crossing(c, &prev, &local, p.radius[i]) {
        Some(hit) => hit,
        None => surface(c, &prev, &local, reach)?,
    };
    // Collider frame -> body principal frame (origin at the centre of mass).
    let local_point = (c.local * point).coords;
    let local_normal = c.local.rotation * normal;
    let m = c.material;
    let mu = p.friction[i];
    Some(ColliderContact {
        particle: i as u32,
        body: c.body,
        local_point,
        local_normal,
        static_friction: (mu * m.static_friction).sqrt(),
        friction: (mu * m.friction).sqrt(),
        lambda_n: 0.0,
        lambda_t: 0.0,
    })
}

/// Whether the collider's shape has no inside (a triangle mesh: a thin shell).
fn shell(c: &Collider) -> bool {
    c.shape.shape_type() == parry3d_f64::shape::ShapeType::TriMesh
}

/// The nearest surface point and outward normal (collider frame) if the particle
/// at `x` (from `prev` this substep) is within `reach`. A shell's outside is the
/// side the particle came from.
fn surface(c: &Collider, prev: &Point3<f64>, x: &Point3<f64>, reach: f64) -> Option<(Point3<f64>, Vec3)> {
    let proj = c.shape.project_local_point(x, false);
    let d = x - proj.point;
    let dist = d.norm();
    let mut normal = if dist > ON_SURFACE {
        if proj.is_inside { -d / dist } else { d / dist }
    } else {
        let (pr, feature) = c.shape.project_local_point_and_get_feature(x);
        c.shape.feature_normal_at_point(feature, &pr.point)?.into_inner()
    };
    let mut signed = if proj.is_inside { -dist } else { dist };
    if shell(c) {
        let mut side = (prev - proj.point).dot(&normal);
        if side.abs() <= ON_SURFACE {
            side = -(x - prev).dot(&normal);
        }
        if side < 0.0 {
            normal = -normal;
            signed = -signed;
        }
    }
    (signed <= reach).then_some((proj.point, normal))
}

/// A particle moving faster than its radius is swept from `prev` to `x`: if the
/// segment enters the shape, the contact is at the entry point, facing back
/// along the motion (no tunnelling through thin shapes).
fn crossing(c: &Collider, prev: &Point3<f64>, x: &Point3<f64>, radius: f64) -> Option<(Point3<f64>, Vec3)> {
    let travel = x - prev;
    if !(travel.norm() > radius.max(ON_SURFACE)) {
        return None;
    }
    let hit = c.shape.cast_local_ray_and_get_normal(&Ray::new(*prev, travel), 1.0, true)?;
    // Starting inside (time 0): the nearest-surface contact handles it.
    if !(hit.time_of_impact > 0.0) {
        return None;
    }
    let n = if hit.normal.dot(&travel) > 0.0 { -hit.normal } else { hit.normal };
    Some((prev + travel * hit.time_of_impact, n))
}

fn project_contact(ct: &mut ColliderContact, p: &mut Particles, b: &mut Bodies, k: &Substep) {
    let (i, body) = (ct.particle as usize, ct.body as usize);
    let wi = p.inv_mass[i];
    let (r, a) = world_point(b, body, &ct.local_point);
    let n = quat::rotate(&b.q(body), &ct.local_normal);
    let xi = Vec3::from(p.position[i]);
    let c = n.dot(&(xi - a)) - p.radius[i];
    if c < 0.0 {
        let dl = -c / (wi + body_point::inverse_mass(b, body, &r, &n));
        ct.lambda_n += dl;
        p.position[i] = (xi + n * (wi * dl)).into();
        body_point::apply(b, body, &r, &(-n * dl), k.h);
    }
    if ct.lambda_n > 0.0 && ct.static_friction > 0.0 {
        friction(ct, p, b, &r, &n, k);
    }
}

/// The friction multiplier to add (kg·m) against a slip that `full` would remove
/// whole: all of it while the total stays within the static cone `μs λn`, else up
/// to the dynamic one `μk λn`.
fn coulomb(full: f64, lambda_n: f64, lambda_t: f64, static_friction: f64, friction: f64) -> f64 {
    if lambda_t + full <= static_friction * lambda_n {
        full
    } else {
        (friction * lambda_n - lambda_t).min(full).max(0.0)
    }
}

/// Removes the tangential slip of the particle relative to the body point over
/// the substep, within the friction cone of the normal multiplier.
fn friction(ct: &mut ColliderContact, p: &mut Particles, b: &mut Bodies, r: &Vec3, n: &Vec3, k: &Substep) {
    let (i, body) = (ct.particle as usize, ct.body as usize);
    let xi = Vec3::from(p.position[i]);
    let slip = (xi - Vec3::from(p.prev[i])) - body_point::point_velocity(b, body, r) * k.h;
    let tangential = slip - n * n.dot(&slip);
    let t = tangential.norm();
    if !(t > 1e-15) {
        return;
    }
    let dir = tangential / t;
    let wi = p.inv_mass[i];
    let full = t / (wi + body_point::inverse_mass(b, body, r, &dir));
    let dl = coulomb(full, ct.lambda_n, ct.lambda_t, ct.static_friction, ct.friction);
    if dl == 0.0 {
        return;
    }
    ct.lambda_t += dl;
    p.position[i] = (xi - dir * (wi * dl)).into();
    body_point::apply(b, body, r, &(dir * dl), k.h);
}

/// Particles with a radius against each other.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct ParticlePairs {
    /// Particles with a radius > 0.
    ids: Vec<u32>,
    max_radius: f64,
    hash: SpatialHash,
    pub pairs: Vec<(u32, u32)>,
    /// Normal and friction multipliers of each pair over the substep (kg·m).
    lambda: Vec<[f64; 2]>,
}

impl ParticlePairs {
    pub fn new(p: &Particles) -> Self {
        let ids: Vec<u32> = (0..p.len() as u32).filter(|&i| p.radius[i as usize] > 0.0).collect();
        let max_radius = ids.iter().map(|&i| p.radius[i as usize]).fold(0.0, f64::max);
        Self { ids, max_radius, ..Default::default() }
    }

    /// Whether two particles can collide at all.
    pub fn active(&self) -> bool {
        self.ids.len() >= 2
    }

    /// This substep's pairs within reach: closer than `rᵢ + rⱼ + margin`, with
    /// `margin` the largest radius.
    pub fn detect(&mut self, p: &Particles) {
        self.pairs.clear();
        if !self.active() {
            return;
        }
        let margin = self.max_radius;
        self.hash.build(&p.position, &self.ids, 2.0 * self.max_radius + margin);
        for &i in &self.ids {
            let iu = i as usize;
            let xi = Vec3::from(p.position[iu]);
            let (hash, pairs) = (&self.hash, &mut self.pairs);
            hash.for_neighbours(&p.position[iu], |j| {
                let ju = j as usize;
                if j <= i || p.inv_mass[iu] + p.inv_mass[ju] == 0.0 || !p.filter[iu].allows(&p.filter[ju]) {
                    return;
                }
                let touch = p.radius[iu] + p.radius[ju];
                if (xi - Vec3::from(p.position[ju])).norm() >= touch + margin {
                    return;
                }
                if (Vec3::from(p.initial[iu]) - Vec3::from(p.initial[ju])).norm() < touch {
                    return;
                }
                pairs.push((i, j));
            });
        }
    }

    /// Zeroes the multipliers: each substep starts its own.
    pub fn reset(&mut self) {
        self.lambda.clear();
        self.lambda.resize(self.pairs.len(), [0.0; 2]);
    }

    /// One pass over the pairs: normal, then friction.
    pub fn project(&mut self, p: &mut Particles) {
        for (&(i, j), lambda) in self.pairs.iter().zip(self.lambda.iter_mut()) {
            let (i, j) = (i as usize, j as usize);
            let (xi, xj) = (Vec3::from(p.position[i]), Vec3::from(p.position[j]));
            let d = xi - xj;
            let len = d.norm();
            if !(len > 0.0) {
                continue;
            }
            let (wi, wj) = (p.inv_mass[i], p.inv_mass[j]);
            let n = d / len;
            let c = len - (p.radius[i] + p.radius[j]);
            if c < 0.0 {
                let dl = -c / (wi + wj);
                lambda[0] += dl;
                p.position[i] = (xi + n * (wi * dl)).into();
                p.position[j] = (xj - n * (wj * dl)).into();
            }
            let mu = (p.friction[i] * p.friction[j]).sqrt();
            if lambda[0] > 0.0 && mu > 0.0 {
                pair_friction(p, (i, j), &n, mu, lambda);
            }
        }
    }
}

/// Removes the relative tangential slip of two touching particles over the
/// substep while its multiplier stays within `μ λn`, and limits it to `μ λn`
/// beyond (one coefficient, static and dynamic alike).
fn pair_friction(p: &mut Particles, (i, j): (usize, usize), n: &Vec3, mu: f64, lambda: &mut [f64; 2]) {
    let (xi, xj) = (Vec3::from(p.position[i]), Vec3::from(p.position[j]));
    let slip = (xi - Vec3::from(p.prev[i])) - (xj - Vec3::from(p.prev[j]));
    let tangential = slip - n * n.dot(&slip);
    let t = tangential.norm();
    if !(t > 1e-15) {
        return;
    }
    let (wi, wj) = (p.inv_mass[i], p.inv_mass[j]);
    let dl = coulomb(t / (wi + wj), lambda[0], lambda[1], mu, mu);
    if dl == 0.0 {
        return;
    }
    lambda[1] += dl;
    let dir = tangential / t;
    p.position[i] = (xi - dir * (wi * dl)).into();
    p.position[j] = (xj + dir * (wj * dl)).into();
}
