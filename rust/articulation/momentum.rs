//! A floating base's linear momentum, kept to round-off.
//!
//! An integrator in joint coordinates is not variational: the joint forces are
//! internal, yet a kick at fixed `q` changes `P = Σ m v_c` by `−h Ȧ v` and a
//! drift at fixed `v` by `(A(q') − A(q)) v` (`P = A(q) v`), so a floating chain
//! that turns drifts by O(h²) (and a contact step, first order, by O(h): a box
//! hitting a three-link arm at 60 Hz left 2 % of its momentum unaccounted for).
//! What `P` must be after a substep is known exactly: what it was, plus the
//! impulses of gravity, the applied forces and the contacts. The difference is
//! given back to the root as a uniform translation of the whole articulation
//! (its free joint's linear velocity: `ΔP = M δv` exactly), an O(h²) change
//! that leaves the joints' motion alone. Angular momentum about a fixed point is
//! not known as exactly (gravity's moment moves with the centre of mass within
//! the substep) and keeps the integrator's own error.

use super::joint::JointModel;
use super::model::{Articulation, Parent};
use super::spatial::{ang, lin, Vec6};
use crate::body::Bodies;
use crate::math::Vec3;

/// Whether `art` has a floating root (a free joint to the world).
pub fn floating(art: &Articulation) -> bool {
    art.links.first().is_some_and(|l| l.model == JointModel::Free && l.parent == Parent::World)
}

/// `Σ m v_c` of the links for the joint velocities `v`, with the subspaces and
/// poses of the last pass 1. Leaves each link's spatial velocity in its work
/// record.
pub fn linear_momentum(art: &mut Articulation, v: &[f64]) -> Vec3 {
    let mut p = Vec3::zeros();
    for k in 0..art.links.len() {
        let l = &art.links[k];
        let mut vel = match l.parent {
            Parent::Link(parent) => art.work[parent].vel,
            _ => Vec6::zeros(),
        };
        for d in 0..l.model.nv() {
            vel += art.work[k].s[d] * v[l.v_at + d];
        }
        let w = &mut art.work[k];
        w.vel = vel;
        p += l.mass * (lin(&vel) + ang(&vel).cross(&w.pose.x));
    }
    p
}

/// The impulse (N·s) gravity and the links' applied forces give the
/// articulation over `h`.
pub fn external_impulse(art: &Articulation, bodies: &Bodies, gravity: &Vec3, h: f64) -> Vec3 {
    art.links.iter().map(|l| h * (l.mass * gravity + Vec3::from(bodies.force[l.body as usize]))).sum()
}

/// Gives the root's free joint the linear velocity that makes the momentum
/// `now` into `target`.
pub fn restore(art: &Articulation, v: &mut [f64], target: &Vec3, now: &Vec3) {
    let mass: f64 = art.links.iter().map(|l| l.mass).sum();
    if mass > 0.0 {
        let dv = (target - now) / mass;
        for k in 0..3 {
            v[3 + k] += dv[k];
        }
    }
}

/// The linear momentum at the articulation's state, after a pass 1 there.
pub fn measure(art: &mut Articulation, bodies: &Bodies) -> Vec3 {
    let (q, v) = (std::mem::take(&mut art.q), std::mem::take(&mut art.v));
    super::kinematics::forward(art, &q, &v, bodies, false);
    let p = linear_momentum(art, &v);
    art.q = q;
    art.v = v;
    p
}

/// After a substep: the momentum made `target` again (see the module docs).
pub fn settle(art: &mut Articulation, bodies: &Bodies, target: &Vec3) {
    let now = measure(art, bodies);
    let mut v = std::mem::take(&mut art.v);
    restore(art, &mut v, target, &now);
    art.v = v;
}
