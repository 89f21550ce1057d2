//! Spatial vectors (Featherstone) in world coordinates about the world origin:
//! a motion `(ω, v_O)` is the angular velocity and the velocity of the body point
//! passing through the origin; a force `(n_O, f)` is the couple about the origin
//! and the force. One frame for every link means no transforms between links:
//! each step pays for the world poses once, the recursions are plain sums.

use crate::math::{so3::hat, Mat3, Vec3};

pub type Vec6 = nalgebra::Vector6<f64>;
pub type Mat6 = nalgebra::Matrix6<f64>;

#[inline(always)]
pub fn ang(m: &Vec6) -> Vec3 {
    Vec3::new(m[0], m[1], m[2])
}

#[inline(always)]
pub fn lin(m: &Vec6) -> Vec3 {
    Vec3::new(m[3], m[4], m[5])
}

#[inline(always)]
pub fn join(a: &Vec3, l: &Vec3) -> Vec6 {
    Vec6::new(a.x, a.y, a.z, l.x, l.y, l.z)
}

/// `m1 × m2` (motion cross motion).
#[inline(always)]
pub fn cross_motion(m1: &Vec6, m2: &Vec6) -> Vec6 {
    let (w1, v1, w2, v2) = (ang(m1), lin(m1), ang(m2), lin(m2));
    join(&w1.cross(&w2), &(w1.cross(&v2) + v1.cross(&w2)))
}

/// `m ×* f` (motion cross force).
#[inline(always)]
pub fn cross_force(m: &Vec6, f: &Vec6) -> Vec6 {
    let (w, v, n, fl) = (ang(m), lin(m), ang(f), lin(f));
    join(&(w.cross(&n) + v.cross(&fl)), &w.cross(&fl))
}

/// The spatial inertia about the origin of a body of mass `m`, centre of mass
/// `c` and world inertia `ic` about its centre of mass.
pub fn inertia(m: f64, c: &Vec3, ic: &Mat3) -> Mat6 {
    let cx = hat(c);
    let mut out = Mat6::zeros();
    let top = ic + m * cx * cx.transpose();
    let off = m * cx;
    out.fixed_view_mut::<3, 3>(0, 0).copy_from(&top);
    out.fixed_view_mut::<3, 3>(0, 3).copy_from(&off);
    out.fixed_view_mut::<3, 3>(3, 0).copy_from(&off.transpose());
    out.fixed_view_mut::<3, 3>(3, 3).copy_from(&Mat3::from_diagonal_element(m));
    out
}

/// The motion of a rotation about the unit axis `a` through the point `p`.
#[inline(always)]
pub fn rotation_about(a: &Vec3, p: &Vec3) -> Vec6 {
    join(a, &p.cross(a))
}

/// The motion of a translation along `a`.
#[inline(always)]
pub fn translation_along(a: &Vec3) -> Vec6 {
    join(&Vec3::zeros(), a)
}

/// Velocity of the point `x` of a body moving with `m`.
#[inline(always)]
pub fn point_velocity(m: &Vec6, x: &Vec3) -> Vec3 {
    lin(m) + ang(m).cross(x)
}

/// The force `f` applied at the point `x`, as a spatial force about the origin.
#[inline(always)]
pub fn force_at(f: &Vec3, x: &Vec3) -> Vec6 {
    join(&x.cross(f), f)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inertia_gives_momentum_and_energy_of_a_body() {
        let (m, c) = (2.0, Vec3::new(0.3, -0.2, 0.5));
        let ic = Mat3::new(0.4, 0.01, 0.0, 0.01, 0.3, 0.02, 0.0, 0.02, 0.2);
        let (w, vc) = (Vec3::new(0.1, 2.0, -0.5), Vec3::new(1.0, 0.0, 3.0));
        let motion = join(&w, &(vc - w.cross(&c)));
        let h = inertia(m, &c, &ic) * motion;
        assert!((lin(&h) - m * vc).norm() < 1e-14);
        assert!((ang(&h) - (ic * w + c.cross(&(m * vc)))).norm() < 1e-13);
        let t = 0.5 * motion.dot(&h);
        assert!((t - 0.5 * (m * vc.norm_squared() + w.dot(&(ic * w)))).abs() < 1e-13);
    }

    #[test]
    fn cross_force_is_minus_the_transpose_of_cross_motion() {
        let m = Vec6::new(0.1, -0.4, 2.0, 0.3, 0.7, -1.1);
        let (a, b) = (Vec6::new(1.0, 2.0, 3.0, -1.0, 0.5, 0.25), Vec6::new(-0.3, 0.2, 0.9, 1.5, -2.0, 0.1));
        assert!((cross_force(&m, &a).dot(&b) + a.dot(&cross_motion(&m, &b))).abs() < 1e-13);
    }
}
