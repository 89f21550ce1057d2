//! Rotation vectors the angular constraints remove.

use crate::math::{quat, Quat, Vec3};

/// Below this sine two unit vectors count as parallel.
const PARALLEL: f64 = 1e-12;

/// The rotation vector (rad) of the shortest turn taking unit `from` to unit `to`:
/// axis `from × to`, angle `atan2(|from × to|, from · to)` (exact for every angle;
/// about any axis orthogonal to `from` when they are opposite).
pub fn turn_between(from: &Vec3, to: &Vec3) -> Vec3 {
    let cross = from.cross(to);
    let s = cross.norm();
    let c = from.dot(to);
    if s > PARALLEL {
        return cross * (s.atan2(c) / s);
    }
    if c > 0.0 {
        Vec3::zeros()
    } else {
        crate::solve::contact::orthonormal(from) * std::f64::consts::PI
    }
}

/// The rotation vector (world, rad, angle in [0, π]) of `q` relative to `target`:
/// `q = exp(v) target`.
pub fn turn_from(target: &Quat, q: &Quat) -> Vec3 {
    let d = q * target.conjugate();
    let d = if d.w < 0.0 { -d } else { d };
    let v = Vec3::new(d.i, d.j, d.k);
    let s = v.norm();
    if s > 0.0 {
        v * (2.0 * s.atan2(d.w) / s)
    } else {
        Vec3::zeros()
    }
}

/// The angle (rad, in (−π, π]) that turns `from` to `to` about the unit `axis`,
/// both taken in the plane orthogonal to `axis`.
pub fn signed_angle(from: &Vec3, to: &Vec3, axis: &Vec3) -> f64 {
    from.cross(to).dot(axis).atan2(from.dot(to) - from.dot(axis) * to.dot(axis))
}

/// Rotates a body-frame vector into the world.
pub fn world(q: &Quat, v: &Vec3) -> Vec3 {
    quat::rotate(q, v)
}
