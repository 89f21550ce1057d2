//! Classical fourth-order Runge–Kutta on `(p, P, q, L)` with
//! `q̇ = ½ ω ⊗ q`, `ω = R(q) I0⁻¹ R(q)ᵀ L`, `L̇ = τ`, `Ṗ = F`; the quaternion is
//! renormalised at the end of the step. Forces and torques are constant over a
//! step, so position and momenta are exact; the rotation is fourth order.
//! Without torque the world `L` does not change, so `|L|` is kept to round-off.

use super::kick::KickSources;
use crate::body::Bodies;
use crate::math::{quat, Quat, Vec3};

#[inline(always)]
fn qdot(q: &Quat, l: &Vec3, inv_i: &Vec3) -> Quat {
    let u = q / q.norm();
    let w = quat::rotate(&u, &quat::rotate_inv(&u, l).component_mul(inv_i));
    Quat::from_parts(0.0, w) * q * 0.5
}

pub fn step(b: &mut Bodies, list: &[u32], h: f64, src: &KickSources) {
    for &i in list {
        let i = i as usize;
        let a = if src.force { src.gravity + Vec3::from(b.force[i]) * b.inv_mass[i] } else { src.gravity };
        let v = Vec3::from(b.linear_velocity[i]);
        b.position[i] = (Vec3::from(b.position[i]) + h * v + (0.5 * h * h) * a).into();
        b.linear_velocity[i] = (v + h * a).into();

        let inv_i = Vec3::from(b.inv_inertia[i]);
        let q = b.q(i);
        let wb = quat::rotate_inv(&q, &Vec3::from(b.angular_velocity[i]));
        let l0 = quat::rotate(&q, &wb.component_mul(&Vec3::from(b.inertia[i])));
        let tau = if src.torque { Vec3::from(b.torque[i]) } else { Vec3::zeros() };
        let l_half = l0 + 0.5 * h * tau;
        let l1 = l0 + h * tau;
        let k1 = qdot(&q, &l0, &inv_i);
        let k2 = qdot(&(q + k1 * (0.5 * h)), &l_half, &inv_i);
        let k3 = qdot(&(q + k2 * (0.5 * h)), &l_half, &inv_i);
        let k4 = qdot(&(q + k3 * h), &l1, &inv_i);
        let qn = q + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);
        let qn = quat::normalize(&qn);
        b.orientation[i] = quat::to_xyzw(&qn);
        let w = quat::rotate(&qn, &quat::rotate_inv(&qn, &l1).component_mul(&inv_i));
        b.angular_velocity[i] = w.into();
    }
}
