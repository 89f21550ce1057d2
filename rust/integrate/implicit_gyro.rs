//! Semi-implicit Euler with the gyroscopic term taken backward (Catto 2015, as in
//! Bullet, Box2D and Jolt): solve `I(ω − ω₀) + h ω × Iω = 0` in the body frame with
//! one Newton step from `ω₀`, Jacobian `J = I + h (ω̂₀ I − (Iω₀)^)`.
//!
//! First order and unconditionally stable, but it damps: a fast asymmetric spinner
//! loses most of its energy.

use super::{Gyroscopic, Rotation, Splitting};
use crate::body::Bodies;
use crate::math::{quat, so3::hat, Mat3, Vec3};

pub fn splitting() -> Splitting {
    Splitting {
        gyroscopic: Some(Gyroscopic::Implicit),
        kicks: vec![1.0, 0.0],
        drifts: vec![1.0],
        rotation: Rotation::Exp,
    }
}

pub fn gyroscopic_implicit(b: &mut Bodies, list: &[u32], h: f64) {
    for &i in list {
        let i = i as usize;
        let q = b.q(i);
        let w0 = quat::rotate_inv(&q, &Vec3::from(b.angular_velocity[i]));
        let inertia = Mat3::from_diagonal(&Vec3::from(b.inertia[i]));
        let iw = inertia * w0;
        let f = h * w0.cross(&iw);
        let j = inertia + h * (hat(&w0) * inertia - hat(&iw));
        // J is I plus a term of size h|ω|·I: invertible unless h|ω| is huge; then keep ω.
        let dw = j.lu().solve(&f).unwrap_or_else(Vec3::zeros);
        b.angular_velocity[i] = quat::rotate(&q, &(w0 - dw)).into();
    }
}
