//! Dihedral bending between two triangles sharing an edge: `C = θ − θ₀`, with
//! `θ` the signed angle between the triangles' normals about their common edge
//! and `θ₀` its rest value (rad). `λ/h²` is the bending moment (N·m).
//!
//! Particles `p0`, `p1` span the shared edge; `p2` is the tip of triangle
//! (p0, p1, p2) and `p3` the tip of triangle (p1, p0, p3). The gradient is the
//! exact one of Bridson, Marino and Fedkiw (2003), valid at any angle (no acos):
//! with `E = p1 − p0`, `N1 = (p2 − p0) × (p2 − p1)`, `N2 = (p3 − p1) × (p3 − p0)`,
//! ```text
//! ∇₂θ = |E| N1/|N1|²,  ∇₃θ = |E| N2/|N2|²,
//! ∇₀θ = ((p2 − p1)·E/|E|) N1/|N1|² + ((p3 − p1)·E/|E|) N2/|N2|²,
//! ∇₁θ = −((p2 − p0)·E/|E|) N1/|N1|² − ((p3 − p0)·E/|E|) N2/|N2|²,
//! ```
//! up to the sign fixed by `θ = atan2((n1 × n2)·Ê, n1·n2)` (checked against finite
//! differences in the tests).

use std::f64::consts::PI;

use super::compliance::{delta_lambda, Compliance, Substep};
use crate::math::Vec3;

#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct Bending {
    /// Edge p0–p1, tips p2 and p3.
    pub p: [u32; 4],
    /// Rest angle θ₀ (rad) in (−π, π].
    pub rest: f64,
    pub compliance: Compliance,
    pub id: u32,
    pub lambda: f64,
}

/// Smallest |N|² (m⁴) of a triangle that still has a normal.
const DEGENERATE: f64 = 1e-30;

/// The dihedral angle (rad) and its gradient with respect to the four particles;
/// `None` for a degenerate triangle or edge.
pub fn angle_and_gradient(x: [Vec3; 4]) -> Option<(f64, [Vec3; 4])> {
    let [p0, p1, p2, p3] = x;
    let e = p1 - p0;
    let elen = e.norm();
    let n1 = (p2 - p0).cross(&(p2 - p1));
    let n2 = (p3 - p1).cross(&(p3 - p0));
    let (q1, q2) = (n1.norm_squared(), n2.norm_squared());
    if !(elen > 0.0 && q1 > DEGENERATE && q2 > DEGENERATE) {
        return None;
    }
    let (m1, m2) = (n1 / q1, n2 / q2);
    let eh = e / elen;
    let theta = (n1.cross(&n2).dot(&eh)).atan2(n1.dot(&n2));
    let g2 = m1 * elen;
    let g3 = m2 * elen;
    let g0 = m1 * (p2 - p1).dot(&eh) + m2 * (p3 - p1).dot(&eh);
    let g1 = -(m1 * (p2 - p0).dot(&eh)) - m2 * (p3 - p0).dot(&eh);
    // Bridson's vectors point along −∇θ for this sign of θ.
    Some((theta, [-g0, -g1, -g2, -g3]))
}

/// Wraps an angle difference into (−π, π] (branches only for the usual |a| < 3π).
#[inline]
pub fn wrap(a: f64) -> f64 {
    let a = if a.abs() < 3.0 * PI { a } else { a % (2.0 * PI) };
    if a > PI {
        a - 2.0 * PI
    } else if a <= -PI {
        a + 2.0 * PI
    } else {
        a
    }
}

#[inline]
pub fn project(c: &mut Bending, x: &mut [[f64; 3]], prev: &[[f64; 3]], w: &[f64], k: &Substep) {
    let idx = c.p.map(|i| i as usize);
    let ws = idx.map(|i| w[i]);
    let pos = idx.map(|i| Vec3::from(x[i]));
    let Some((theta, g)) = angle_and_gradient(pos) else { return };
    let wsum: f64 = (0..4).map(|a| ws[a] * g[a].norm_squared()).sum();
    if wsum == 0.0 {
        return;
    }
    let (alpha_t, gamma) = k.factors(&c.compliance);
    let grad_dx = if gamma > 0.0 { (0..4).map(|a| g[a].dot(&(pos[a] - Vec3::from(prev[idx[a]])))).sum() } else { 0.0 };
    let dl = delta_lambda(wrap(theta - c.rest), c.lambda, wsum, alpha_t, gamma, grad_dx);
    c.lambda += dl;
    for a in 0..4 {
        x[idx[a]] = (pos[a] + g[a] * (ws[a] * dl)).into();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folded(phi: f64) -> [Vec3; 4] {
        // Edge along x; tip 2 in the xy-plane, tip 3 rotated by phi about the edge.
        [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.3, 1.0, 0.0),
            Vec3::new(0.6, -phi.cos(), -phi.sin()),
        ]
    }

    #[test]
    fn gradient_matches_finite_differences_at_any_angle() {
        for &phi in &[0.0, 0.4, -1.2, 2.5, 3.1, -3.1] {
            let x = folded(phi);
            let (theta, g) = angle_and_gradient(x).unwrap();
            for a in 0..4 {
                for d in 0..3 {
                    let eps = 1e-6;
                    let (mut xp, mut xm) = (x, x);
                    xp[a][d] += eps;
                    xm[a][d] -= eps;
                    let fd = wrap(angle_and_gradient(xp).unwrap().0 - angle_and_gradient(xm).unwrap().0) / (2.0 * eps);
                    // Central differences: error O(eps²·θ''') ≈ 1e-11 here.
                    assert!((fd - g[a][d]).abs() < 1e-7, "phi {phi} particle {a} axis {d}: {fd} vs {}", g[a][d]);
                }
            }
            assert!(theta.is_finite());
        }
    }

    #[test]
    fn flat_pair_has_zero_angle_and_the_fold_is_signed() {
        assert!(angle_and_gradient(folded(0.0)).unwrap().0.abs() < 1e-15);
        let a = angle_and_gradient(folded(0.5)).unwrap().0;
        let b = angle_and_gradient(folded(-0.5)).unwrap().0;
        assert!((a + b).abs() < 1e-12 && (a.abs() - 0.5).abs() < 1e-12);
    }

    #[test]
    fn projection_restores_the_rest_angle() {
        let mut x: Vec<[f64; 3]> = folded(0.8).iter().map(|v| [v.x, v.y, v.z]).collect();
        let prev = x.clone();
        let mut c = Bending { p: [0, 1, 2, 3], rest: 0.0, compliance: Compliance::default(), id: 0, lambda: 0.0 };
        for _ in 0..20 {
            project(&mut c, &mut x, &prev, &[1.0; 4], &Substep::new(0.01));
        }
        let pos = [0, 1, 2, 3].map(|i| Vec3::from(x[i]));
        assert!(angle_and_gradient(pos).unwrap().0.abs() < 1e-9);
    }
}
