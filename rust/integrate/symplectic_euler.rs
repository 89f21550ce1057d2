//! Semi-implicit (symplectic) Euler as most game engines do it: the gyroscopic
//! term `−I⁻¹(ω × Iω)` taken explicitly, then `v += h a`, `ω += h I⁻¹τ`, then
//! `p += h v` and the orientation turned by `exp(h ω)`.
//!
//! First order. The explicit gyroscopic term feeds energy into fast-spinning
//! asymmetric bodies (the fast thin rod grows without bound).

use super::{Gyroscopic, Rotation, Splitting};
use crate::body::Bodies;
use crate::math::{quat, Vec3};

pub fn splitting() -> Splitting {
    Splitting {
        gyroscopic: Some(Gyroscopic::Explicit),
        kicks: vec![1.0, 0.0],
        drifts: vec![1.0],
        rotation: Rotation::Exp,
    }
}

/// `ω_b += −h I⁻¹ (ω_b × I ω_b)` in the body frame.
pub fn gyroscopic_explicit(b: &mut Bodies, list: &[u32], h: f64) {
    for &i in list {
        let i = i as usize;
        let q = b.q(i);
        let wb = quat::rotate_inv(&q, &Vec3::from(b.angular_velocity[i]));
        let iw = wb.component_mul(&Vec3::from(b.inertia[i]));
        let dw = -h * wb.cross(&iw).component_mul(&Vec3::from(b.inv_inertia[i]));
        b.angular_velocity[i] = quat::rotate(&q, &(wb + dw)).into();
    }
}

/// The orientation turned by `exp(h ω)` at fixed world `ω`.
pub fn rotate_exp(b: &mut Bodies, list: &[u32], h: f64) {
    for &i in list {
        let i = i as usize;
        let w = Vec3::from(b.angular_velocity[i]);
        let q = quat::exp(&(w * h)) * b.q(i);
        b.orientation[i] = quat::to_xyzw(&(q / q.norm()));
    }
}
