//! Distance constraint between two particles: `C = |xᵢ − xⱼ| − L`, rest length
//! `L` (m). `λ/h²` is the force along `xᵢ − xⱼ` on particle `i` (N): negative
//! when the link is stretched (its tension is `−λ/h²`).

use super::compliance::{delta_lambda, Compliance, Substep};
use crate::math::Vec3;

#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct Distance {
    pub i: u32,
    pub j: u32,
    /// Rest length (m).
    pub rest: f64,
    pub compliance: Compliance,
    /// Index in the world's constraint list (`constraint_forces`).
    pub id: u32,
    /// Multiplier of the current substep (N·s²).
    pub lambda: f64,
}

/// Projects one distance constraint (see [`super::compliance`]).
#[inline(always)]
pub fn project(c: &mut Distance, x: &mut [[f64; 3]], prev: &[[f64; 3]], w: &[f64], k: &Substep) {
    let (i, j) = (c.i as usize, c.j as usize);
    let (wi, wj) = (w[i], w[j]);
    let wsum = wi + wj;
    let (xi, xj) = (Vec3::from(x[i]), Vec3::from(x[j]));
    let d = xi - xj;
    let len = d.norm();
    // Coincident particles have no direction to be pushed apart along.
    if wsum == 0.0 || !(len > 0.0) {
        return;
    }
    let n = d / len;
    let (alpha_t, gamma) = k.factors(&c.compliance);
    let grad_dx = if gamma > 0.0 { n.dot(&((xi - Vec3::from(prev[i])) - (xj - Vec3::from(prev[j])))) } else { 0.0 };
    let dl = delta_lambda(len - c.rest, c.lambda, wsum, alpha_t, gamma, grad_dx);
    c.lambda += dl;
    x[i] = (xi + n * (wi * dl)).into();
    x[j] = (xj - n * (wj * dl)).into();
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rigid_link_is_restored_exactly_and_momentum_is_kept() {
        let mut x = vec![[0.0, 0.0, 0.0], [1.3, 0.4, -0.2]];
        let prev = x.clone();
        let w = [1.0, 0.25];
        let mut c = Distance { i: 0, j: 1, rest: 1.0, compliance: Compliance::default(), id: 0, lambda: 0.0 };
        let before: Vec3 = Vec3::from(x[0]) / w[0] + Vec3::from(x[1]) / w[1];
        project(&mut c, &mut x, &prev, &w, &Substep::new(0.01));
        let len = (Vec3::from(x[0]) - Vec3::from(x[1])).norm();
        assert!((len - 1.0).abs() < 1e-15);
        let after: Vec3 = Vec3::from(x[0]) / w[0] + Vec3::from(x[1]) / w[1];
        assert!((after - before).norm() < 1e-14);
    }
}
