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
#[derive(Clone, Copy, Debug)]
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
