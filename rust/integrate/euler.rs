//! The textbook explicit Euler on `(p, P, R, L)`:
//! `p += h P/m`, `R += h ω̂ R` (as `q += h/2 ω ⊗ q`, renormalised), then
//! `P += h F`, `L += h τ` and `ω = I(R)⁻¹ L` with the new `R`.
//!
//! First order. World `L` is untouched without torque, so `|L|` is kept, but `R`
//! leaves the true path and `ω = I⁻¹L` with it: the energy grows every step.
//! Kept to show what accuracy costs.

use super::{Rotation, Splitting};
use crate::body::Bodies;
use crate::math::{quat, Quat, Vec3};

pub fn splitting() -> Splitting {
    Splitting { gyroscopic: None, kicks: vec![0.0, 1.0], drifts: vec![1.0], rotation: Rotation::Euler }
}

#[inline(always)]
fn euler_quat(q: &Quat, w: &Vec3, h: f64) -> Quat {
    let dq = Quat::from_parts(0.0, *w) * q * (0.5 * h);
    let q = q + dq;
    q / q.norm()
}

/// Isotropic bodies: `ω` is constant; only the quaternion moves.
pub fn rotate_isotropic(b: &mut Bodies, list: &[u32], h: f64) {
    for &i in list {
        let i = i as usize;
        let q = euler_quat(&b.q(i), &Vec3::from(b.angular_velocity[i]), h);
        b.orientation[i] = quat::to_xyzw(&q);
    }
}

/// Other bodies: the quaternion moves with `ω`, then `ω = I(R_new)⁻¹ L` at fixed `L`.
pub fn rotate(b: &mut Bodies, list: &[u32], h: f64) {
    for &i in list {
        let i = i as usize;
        let q0 = b.q(i);
        let w = Vec3::from(b.angular_velocity[i]);
        let l = quat::rotate(&q0, &quat::rotate_inv(&q0, &w).component_mul(&Vec3::from(b.inertia[i])));
        let q = euler_quat(&q0, &w, h);
        b.orientation[i] = quat::to_xyzw(&q);
        b.angular_velocity[i] = b.inv_inertia_world_mul(i, &l).into();
    }
}
