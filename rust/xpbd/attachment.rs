//! A particle attached to a point of a rigid body: `C = |x − a| − L`, with `a`
//! the body point (fixed in the body frame) and `L` the rest length (m, default
//! 0). The body takes its share of every correction through its generalized
//! inverse mass (see [`super::body_point`]), so it feels the pull: momentum
//! passes between particle and body. `λ/h²` is the force on the particle along
//! `x − a` (N): negative when it is pulled towards the body.

use super::body_point::{self, world_point};
use super::compliance::{delta_lambda, Compliance, Substep};
use crate::body::Bodies;
use crate::math::Vec3;

#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct Attachment {
    pub particle: u32,
    pub body: u32,
    /// The point in the body's principal frame, from its centre of mass (m).
    pub local: Vec3,
    /// Rest length L (m) ≥ 0.
    pub rest: f64,
    pub compliance: Compliance,
    pub id: u32,
    pub lambda: f64,
}

/// Shortest `|x − a|` (m) along which a correction is still applied.
const COINCIDENT: f64 = 1e-14;

#[inline]
pub fn project(c: &mut Attachment, x: &mut [[f64; 3]], prev: &[[f64; 3]], w: &[f64], b: &mut Bodies, k: &Substep) {
    let (i, body) = (c.particle as usize, c.body as usize);
    let (r, a) = world_point(b, body, &c.local);
    let xi = Vec3::from(x[i]);
    let d = xi - a;
    let len = d.norm();
    if !(len > COINCIDENT) {
        return;
    }
    let n = d / len;
    let wsum = w[i] + body_point::inverse_mass(b, body, &r, &n);
    let (alpha_t, gamma) = k.factors(&c.compliance);
    let grad_dx = if gamma > 0.0 {
        n.dot(&((xi - Vec3::from(prev[i])) - body_point::point_velocity(b, body, &r) * k.h))
    } else {
        0.0
    };
    let dl = delta_lambda(len - c.rest, c.lambda, wsum, alpha_t, gamma, grad_dx);
    if dl == 0.0 {
        return;
    }
    c.lambda += dl;
    x[i] = (xi + n * (w[i] * dl)).into();
    body_point::apply(b, body, &r, &(-n * dl), k.h);
}
