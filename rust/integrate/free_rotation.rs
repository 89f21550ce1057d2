//! Exact torque-free rotation, the drift of the splitting methods.
//!
//! With body-frame angular momentum `L` the kinetic energy splits as
//! `T = |L|²/(2 I_a) + Σ_j ½ c_j L_j²` (see [`Aniso`]). Each term has an exact flow:
//! the `|L|²` term turns the body about `L` at rate `|L|/I_a` and leaves `L` fixed
//! in the body; a `½ c_j L_j²` term turns the body about its axis `j` at rate
//! `c_j L_j` and turns `L` the other way. The `|L|²` flow commutes with the others,
//! so an isotropic body (no other term) and a symmetric one (one other term) rotate
//! exactly; an asymmetric one takes the Strang step `B(h/2) C(h) B(h/2)` of its two
//! remaining terms. Every flow is a rotation, so `|L|` is kept to round-off, and the
//! split is symplectic, so energy has no drift.

use super::Aniso;
use crate::body::Bodies;
use crate::math::{quat, Quat, Vec3};

/// Body-frame angular momentum from the stored world angular velocity.
#[inline(always)]
fn load(b: &Bodies, i: usize) -> (Quat, Vec3) {
    let q = b.q(i);
    let wb = quat::rotate_inv(&q, &Vec3::from(b.angular_velocity[i]));
    (q, wb.component_mul(&Vec3::from(b.inertia[i])))
}

/// Writes the orientation back (renormalised) and the world angular velocity.
#[inline(always)]
fn store(b: &mut Bodies, i: usize, q: Quat, lb: &Vec3) {
    let q = quat::normalize(&q);
    let w = quat::rotate(&q, &lb.component_mul(&Vec3::from(b.inv_inertia[i])));
    b.orientation[i] = quat::to_xyzw(&q);
    b.angular_velocity[i] = w.into();
}

/// Flow of `½ c L_j²` for time `h`: the body turns about axis `j` by `θ = h c L_j`.
#[inline(always)]
fn flow_axis(q: &mut Quat, lb: &mut Vec3, j: usize, hc: f64) {
    let theta = hc * lb[j];
    let (s, c) = (0.5 * theta).sin_cos();
    *q = quat::mul_axis(q, j, s, c);
    let (sin, cos) = (2.0 * s * c, c * c - s * s);
    let (k, l) = ((j + 1) % 3, (j + 2) % 3);
    let (lk, ll) = (lb[k], lb[l]);
    lb[k] = cos * lk + sin * ll;
    lb[l] = cos * ll - sin * lk;
}

/// Flow of `|L|²/(2 I_a)` for time `h`: the body turns about `L` by `h |L| / I_a`.
#[inline(always)]
fn flow_norm(q: &mut Quat, lb: &Vec3, hc: f64) {
    *q *= quat::exp(&(lb * hc));
}

/// Isotropic bodies: `ω` is constant, the orientation turns by `exp(h ω)`.
pub fn rotate_isotropic(b: &mut Bodies, list: &[u32], h: f64) {
    for &i in list {
        let i = i as usize;
        let w = Vec3::from(b.angular_velocity[i]);
        if w == Vec3::zeros() {
            continue;
        }
        let q = quat::exp(&(w * h)) * b.q(i);
        b.orientation[i] = quat::to_xyzw(&quat::normalize(&q));
    }
}

/// Symmetric bodies, in closed form:
/// `R(t) = exp(t L̂_w / I_t) R₀ exp(t (1/I_s − 1/I_t) L_s ê_s)`.
pub fn rotate_symmetric(b: &mut Bodies, list: &[Aniso], h: f64) {
    for a in list {
        let i = a.index as usize;
        let (mut q, mut lb) = load(b, i);
        flow_norm(&mut q, &lb, h * a.coef[0]);
        flow_axis(&mut q, &mut lb, a.axes[1] as usize, h * a.coef[1]);
        store(b, i, q, &lb);
    }
}

/// Asymmetric bodies: `A(h) B(h/2) C(h) B(h/2)`, second order, `|L|` exact.
pub fn rotate_asymmetric(b: &mut Bodies, list: &[Aniso], h: f64) {
    for a in list {
        let i = a.index as usize;
        let (mut q, mut lb) = load(b, i);
        let (jb, jc) = (a.axes[1] as usize, a.axes[2] as usize);
        flow_axis(&mut q, &mut lb, jb, 0.5 * h * a.coef[1]);
        flow_axis(&mut q, &mut lb, jc, h * a.coef[2]);
        flow_axis(&mut q, &mut lb, jb, 0.5 * h * a.coef[1]);
        flow_norm(&mut q, &lb, h * a.coef[0]);
        store(b, i, q, &lb);
    }
}
