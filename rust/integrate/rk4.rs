//! Classical fourth-order Runge–Kutta on `(p, P, q, L)` with
//! `q̇ = ½ ω ⊗ q`, `ω = R(q) I0⁻¹ R(q)ᵀ L`, `L̇ = τ`, `Ṗ = F`; the quaternion is
//! renormalised at the end of the step. Forces and torques are constant over a
//! step, so position and momenta are exact; the rotation is fourth order.
//! Without torque the world `L` does not change, so `|L|` is kept to round-off.

use super::fast_rotation::Substeps;
use super::kick::KickSources;
use crate::body::Bodies;
use crate::math::{quat, Quat, Vec3};

#[inline(always)]
fn qdot(q: &Quat, l: &Vec3, inv_i: &Vec3) -> Quat {
    let u = q / q.norm();
    let w = quat::rotate(&u, &quat::rotate_inv(&u, l).component_mul(inv_i));
    Quat::from_parts(0.0, w) * q * 0.5
}

/// One step of `h` for the bodies of `list`; a body turning faster than
/// `sub.max_angle` a step at the fastest point of its torque-free orbit
/// ([`orbit_max_rate`]) has its rotation in `sub.count` equal substeps.
pub fn step(b: &mut Bodies, list: &[u32], h: f64, src: &KickSources, sub: Substeps) {
    for &i in list {
        let i = i as usize;
        let a = src.acceleration(b, i);
        let v = Vec3::from(b.linear_velocity[i]);
        b.position[i] = (Vec3::from(b.position[i]) + h * v + (0.5 * h * h) * a).into();
        b.linear_velocity[i] = (v + h * a).into();

        let inv_i = Vec3::from(b.inv_inertia[i]);
        let q = b.q(i);
        let wb = quat::rotate_inv(&q, &Vec3::from(b.angular_velocity[i]));
        let l0 = quat::rotate(&q, &wb.component_mul(&Vec3::from(b.inertia[i])));
        let tau = if src.torque { Vec3::from(b.torque[i]) } else { Vec3::zeros() };
        let n = sub.count(orbit_max_rate(&wb, &Vec3::from(b.inertia[i])), h);
        let hs = h / f64::from(n);
        let mut qn = q;
        let mut l = l0;
        for k in 1..=n {
            let l1 = if k == n { l0 + h * tau } else { l0 + (f64::from(k) * hs) * tau };
            qn = quarter(&qn, [&l, &(l + 0.5 * hs * tau), &l1], &inv_i, hs);
            l = l1;
        }
        b.orientation[i] = quat::to_xyzw(&qn);
        let w = quat::rotate(&qn, &quat::rotate_inv(&qn, &l).component_mul(&inv_i));
        b.angular_velocity[i] = w.into();
    }
}

/// The RK4 rotation over `h` from `q`, with the momentum at its start, middle
/// and end.
#[inline(always)]
fn quarter(q: &Quat, [l0, l_half, l1]: [&Vec3; 3], inv_i: &Vec3, h: f64) -> Quat {
    let k1 = qdot(q, l0, inv_i);
    let k2 = qdot(&(q + k1 * (0.5 * h)), l_half, inv_i);
    let k3 = qdot(&(q + k2 * (0.5 * h)), l_half, inv_i);
    let k4 = qdot(&(q + k3 * h), l1, inv_i);
    quat::normalize(&(q + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0)))
}

/// The largest `|ω|` (rad/s) of a torque-free body of principal moments `i0`
/// turning at `wb` (body frame). With `x_j = L_j²`, the orbit keeps
/// `Σ x_j = |L|²` and `Σ x_j / I_j = 2E`: a segment of the simplex, over which
/// `|ω|² = Σ x_j / I_j²` is linear, so its largest value is at an end, where
/// one `x_j` is zero. A body without distinct moments turns at `|ω|` always.
/// The same `W` as `free_rotation::orbit_max_omega`, which reads it from an
/// asymmetric body's split coefficients; RK4 has none, and takes every class.
pub fn orbit_max_rate(wb: &Vec3, i0: &Vec3) -> f64 {
    let x: [f64; 3] = std::array::from_fn(|j| (i0[j] * wb[j]).powi(2));
    let (l2, e2) = (x.iter().sum::<f64>(), (0..3).map(|j| x[j] / i0[j]).sum::<f64>());
    let mut top = wb.norm_squared();
    for zero in 0..3 {
        let (j, k) = ((zero + 1) % 3, (zero + 2) % 3);
        let d = 1.0 / i0[j] - 1.0 / i0[k];
        if d.abs() <= 1e-12 * (1.0 / i0[j]).abs() {
            continue;
        }
        let xj = (e2 - l2 / i0[k]) / d;
        let xk = l2 - xj;
        let slack = 1e-12 * l2;
        if xj >= -slack && xk >= -slack {
            top = top.max(xj.max(0.0) / (i0[j] * i0[j]) + xk.max(0.0) / (i0[k] * i0[k]));
        }
    }
    top.sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_orbit_rate_bounds_omega_and_is_reached_at_an_axis() {
        // A body turning about a principal axis stays there: its rate is |ω|.
        let (w, i) = (Vec3::new(0.0, 0.0, 3.0), Vec3::new(1.0, 2.0, 3.0));
        assert!((orbit_max_rate(&w, &i) - 3.0).abs() <= 1e-12 * 3.0);
        // Isotropic: |ω|.
        let w = Vec3::new(1.0, -2.0, 0.5);
        assert_eq!(orbit_max_rate(&w, &Vec3::new(2.0, 2.0, 2.0)), w.norm());
        // Near the intermediate axis of moments 1:2:3 the flip passes close
        // to the minor axis: the largest |ω| an integration of Euler's
        // equations (RK4, 40 s in steps of 0.1 ms, several flips) meets.
        let w0 = Vec3::new(0.01, 1.0, 0.01);
        let i = Vec3::new(1.0, 2.0, 3.0);
        let mut w = w0;
        let mut seen: f64 = w.norm();
        let h = 1e-4;
        for _ in 0..400_000 {
            let f = |w: &Vec3| Vec3::new((i[1] - i[2]) / i[0] * w[1] * w[2], (i[2] - i[0]) / i[1] * w[2] * w[0], (i[0] - i[1]) / i[2] * w[0] * w[1]);
            let k1 = f(&w);
            let k2 = f(&(w + k1 * (0.5 * h)));
            let k3 = f(&(w + k2 * (0.5 * h)));
            let k4 = f(&(w + k3 * h));
            w += (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);
            seen = seen.max(w.norm());
        }
        let bound = orbit_max_rate(&w0, &i);
        assert!(bound >= seen * (1.0 - 1e-9), "{bound} < {seen}");
        assert!(bound <= seen * (1.0 + 1e-6), "{bound} far above {seen}");
    }
}
