//! Goal positions of a cluster (Müller et al. 2005, §3–4). With weights `wᵢ`,
//! current centre `c`, offsets `pᵢ = xᵢ − c` and rest offsets `qᵢ`:
//!
//! - `Apq = Σ wᵢ pᵢ qᵢᵀ`, `R` its polar rotation ([`super::rotation`]);
//! - rigid: `gᵢ = R qᵢ + c`;
//! - linear: `A = Apq Aqq⁻¹` (scaled to `det A = 1` when the volume is kept),
//!   `gᵢ = (β A + (1 − β) R) qᵢ + c`;
//! - quadratic: `Ã = Ãpq Ãqq⁻¹` (3×9) on `q̃ᵢ = (q, q², cross terms) − mean`,
//!   `gᵢ = (β Ã + (1 − β) [R 0 0]) q̃ᵢ + c`. Müller's paper does not subtract
//!   the weighted mean of the quadratic terms; without it the goals' centre drifts
//!   by `Ã·mean` and the cluster gains momentum. With it the fitted space is the
//!   same (the mean is a translation, which `c` carries).
//!
//! Each goal moves the cluster's particles without changing their weighted
//! linear or angular momentum: `Σ wᵢ (gᵢ − xᵢ) = 0` since the goals share the
//! centre `c`, and `Σ wᵢ pᵢ × (gᵢ − xᵢ) = 0` since `Σ wᵢ (T q̃ᵢ) pᵢᵀ` is symmetric
//! for each of the transforms `T` above.

use nalgebra::SMatrix;

use super::cluster::{Cluster, Mode};
use super::rotation::rotation_quaternion;
use crate::math::{Mat3, Vec3};

/// What a goal computation leaves behind besides the goals.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct Fit {
    /// Polar rotation of `Apq`.
    pub rotation: Mat3,
    /// Best linear map `Apq Aqq⁻¹` (unscaled), for plasticity.
    pub linear: Mat3,
}

/// Writes the goal of each of the cluster's particles (positions `x`) into
/// `goals`; updates the cluster's rotation (warm start) and centre.
pub fn goals(c: &mut Cluster, x: &[[f64; 3]], goals: &mut Vec<Vec3>) -> Fit {
    let total: f64 = c.weights.iter().sum();
    let center: Vec3 = c.particles.iter().zip(&c.weights).map(|(&i, &w)| Vec3::from(x[i as usize]) * w).sum::<Vec3>() / total;
    let mut apq = Mat3::zeros();
    for ((&i, &w), q) in c.particles.iter().zip(&c.weights).zip(&c.rest) {
        apq += (Vec3::from(x[i as usize]) - center) * (q * w).transpose();
    }
    c.rotation = rotation_quaternion(&apq, Some(&c.rotation));
    c.center = center;
    let r = c.rotation.to_rotation_matrix().into_inner();
    let linear = apq * c.aqq_inv;
    goals.clear();
    let beta = c.spec.beta;
    match c.spec.mode {
        Mode::Rigid => goals.extend(c.rest.iter().map(|q| r * q + center)),
        Mode::Linear => {
            let a = if c.spec.preserve_volume { volume_preserving(&linear, &r) } else { linear };
            let t = a * beta + r * (1.0 - beta);
            goals.extend(c.rest.iter().map(|q| t * q + center));
        }
        Mode::Quadratic => {
            let mut apq9 = SMatrix::<f64, 3, 9>::zeros();
            for ((&i, &w), q) in c.particles.iter().zip(&c.weights).zip(&c.rest) {
                apq9 += (Vec3::from(x[i as usize]) - center) * (c.centred_terms(q) * w).transpose();
            }
            let mut t = apq9 * c.aqq9_inv * beta;
            let mut rr = t.fixed_view_mut::<3, 3>(0, 0);
            rr += r * (1.0 - beta);
            goals.extend(c.rest.iter().map(|q| t * c.centred_terms(q) + center));
        }
    }
    Fit { rotation: r, linear }
}

/// `A / det(A)^(1/3)`; the rotation `r` for an inverted or flat `A` (det ≤ 0),
/// which has no volume-preserving scaling.
fn volume_preserving(a: &Mat3, r: &Mat3) -> Mat3 {
    let det = a.determinant();
    if det > 1e-12 * a.amax().powi(3) && det.is_finite() {
        a / det.cbrt()
    } else {
        *r
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::xpbd::shape_matching::ClusterSpec;
    use nalgebra::{Rotation3, Unit};

    /// A 3×3×3 grid, skewed and with varying masses: nothing symmetric.
    fn rest() -> (Vec<Vec3>, Vec<f64>) {
        let mut x = Vec::new();
        let mut m = Vec::new();
        for i in 0..3 {
            for j in 0..3 {
                for k in 0..3 {
                    let t = (i * 9 + j * 3 + k) as f64;
                    x.push(Vec3::new(0.2 * i as f64 + 0.01 * t.sin(), 0.15 * j as f64, 0.1 * k as f64 + 0.02 * t.cos()));
                    m.push(0.1 + 0.01 * t);
                }
            }
        }
        (x, m)
    }

    fn cluster(mode: Mode, beta: f64) -> (Cluster, Vec<Vec3>) {
        let (x, m) = rest();
        let spec = ClusterSpec { mode, beta, ..Default::default() };
        (Cluster::new((0..x.len() as u32).collect(), spec, &x, &m).unwrap(), x)
    }

    fn arrays(x: &[Vec3]) -> Vec<[f64; 3]> {
        x.iter().map(|v| [v.x, v.y, v.z]).collect()
    }

    fn rotations() -> Vec<Mat3> {
        let mut r: Vec<Mat3> = [Vec3::x(), Vec3::y(), Vec3::z(), Vec3::new(1.0, 1.0, 1.0), Vec3::new(1.0, -2.0, 0.5)]
            .iter()
            .map(|a| Rotation3::from_axis_angle(&Unit::new_normalize(*a), std::f64::consts::PI).into_inner())
            .collect();
        r.push(Rotation3::from_euler_angles(0.3, -1.2, 2.0).into_inner());
        r
    }

    #[test]
    fn rigid_motions_are_their_own_goal_in_every_mode() {
        for mode in [Mode::Rigid, Mode::Linear, Mode::Quadratic] {
            let (mut c, x) = cluster(mode, 0.6);
            for r in rotations() {
                let moved: Vec<Vec3> = x.iter().map(|p| r * p + Vec3::new(1.0, -2.0, 0.5)).collect();
                let mut g = Vec::new();
                goals(&mut c, &arrays(&moved), &mut g);
                let err = g.iter().zip(&moved).map(|(a, b)| (a - b).amax()).fold(0.0, f64::max);
                assert!(err < 1e-12, "{mode:?}: {err}");
            }
        }
    }

    #[test]
    fn corrections_keep_the_weighted_momentum() {
        for mode in [Mode::Rigid, Mode::Linear, Mode::Quadratic] {
            for beta in [0.0, 0.4, 1.0] {
                let (mut c, x) = cluster(mode, beta);
                let r = Rotation3::from_euler_angles(0.5, 0.1, -0.7).into_inner();
                let bent: Vec<Vec3> = x
                    .iter()
                    .enumerate()
                    .map(|(i, p)| r * p + Vec3::new((i as f64).sin(), (i as f64 * 1.7).cos(), 0.3) * 0.02)
                    .collect();
                let mut g = Vec::new();
                goals(&mut c, &arrays(&bent), &mut g);
                let w = &c.weights;
                let total: f64 = w.iter().sum();
                let center: Vec3 = bent.iter().zip(w).map(|(p, m)| p * *m).sum::<Vec3>() / total;
                let lin: Vec3 = g.iter().zip(&bent).zip(w).map(|((a, b), m)| (a - b) * *m).sum();
                let ang: Vec3 = g.iter().zip(&bent).zip(w).map(|((a, b), m)| (b - center).cross(&(a - b)) * *m).sum();
                let scale: f64 = g.iter().zip(&bent).zip(w).map(|((a, b), m)| (a - b).norm() * m).sum();
                assert!(scale > 1e-4);
                assert!(lin.amax() < 1e-13 * scale, "{mode:?} β {beta}: {lin}");
                assert!(ang.amax() < 1e-13 * scale, "{mode:?} β {beta}: {ang}");
            }
        }
    }

    #[test]
    fn quadratic_goal_reproduces_a_parabolic_bend() {
        let (mut c, x) = cluster(Mode::Quadratic, 1.0);
        let bent: Vec<Vec3> = x.iter().map(|p| p + Vec3::z() * (0.7 * p.x * p.x - 0.3 * p.x * p.y)).collect();
        let mut g = Vec::new();
        goals(&mut c, &arrays(&bent), &mut g);
        let err = g.iter().zip(&bent).map(|(a, b)| (a - b).amax()).fold(0.0, f64::max);
        assert!(err < 1e-12, "{err}");
    }

    #[test]
    fn linear_goal_keeps_the_volume() {
        let (mut c, x) = cluster(Mode::Linear, 1.0);
        let stretch = Mat3::from_diagonal(&Vec3::new(1.5, 0.9, 1.1));
        let moved: Vec<Vec3> = x.iter().map(|p| stretch * p).collect();
        let mut g = Vec::new();
        let fit = goals(&mut c, &arrays(&moved), &mut g);
        assert!((fit.linear - stretch).amax() < 1e-12);
        // Goals = A q + c with det A = 1: A recovered from two goal differences' span.
        let a = fit.linear / fit.linear.determinant().cbrt();
        for (gi, q) in g.iter().zip(&c.rest) {
            assert!((gi - (a * q + c.center)).amax() < 1e-12);
        }
        assert!((a.determinant() - 1.0).abs() < 1e-12);
    }
}
