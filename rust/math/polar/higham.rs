//! Newton's iteration for the orthogonal polar factor with Higham's scaling:
//! `X₀ = A`, `X_{k+1} = ½(γ_k X_k + (γ_k X_k)⁻ᵀ)`, `γ_k = (‖X_k⁻¹‖_F / ‖X_k‖_F)^½`.
//!
//! Every singular value maps as `σ ← ½(γσ + 1/(γσ))`, so all go to 1 and the
//! iterate to `U Vᵀ` (quadratically once near; the scaling makes the first steps
//! fast even at condition 1e12, ~10 iterations). The inverse comes from the
//! cofactor matrix, `X⁻ᵀ = cof(X)/det X`. A (numerically) singular `A` has no
//! inverse to iterate with, and near it the iteration loses what it needs: when
//! `‖A‖_F ‖A⁻¹‖_F` exceeds [`MAX_CONDITION`] the SVD takes over (the rank-deficient
//! fallback). For `det A < 0` the limit is a reflection, turned into the nearest
//! proper rotation by [`super::unreflect`].

use super::{cofactor, polish, svd, unreflect, Mat3};

/// Condition number `‖A‖_F ‖A⁻¹‖_F` above which `A` counts as singular.
pub(super) const MAX_CONDITION: f64 = 1e13;
/// Iterations before giving up (never reached in practice: ≤ 12 at cond 1e13).
const MAX_ITERATIONS: usize = 60;
/// Below this change per step the scaling stops (Higham: it would only slow the
/// final quadratic convergence).
const UNSCALED_BELOW: f64 = 1e-2;
/// Converged when a step changes X by less than this (‖X‖_F = √3).
const TOLERANCE: f64 = 1e-14;

/// `a` finite with ‖a‖_F = 1.
pub(super) fn rotation(a: &Mat3) -> Mat3 {
    let det = a.determinant();
    let cof = cofactor(a);
    let condition = cof.norm() / det.abs();
    if condition.is_nan() || condition > MAX_CONDITION {
        return svd::rotation(a);
    }
    let mut x = *a;
    let mut scaled = true;
    for _ in 0..MAX_ITERATIONS {
        let cof = cofactor(&x);
        let inv_t = cof / x.determinant();
        let gamma = if scaled { (inv_t.norm() / x.norm()).sqrt() } else { 1.0 };
        let next = (x * gamma + inv_t / gamma) * 0.5;
        let change = (next - x).norm();
        x = next;
        if !x.iter().all(|v| v.is_finite()) {
            return svd::rotation(a);
        }
        scaled &= change > UNSCALED_BELOW;
        if change <= TOLERANCE {
            break;
        }
    }
    let x = polish(&x);
    if det < 0.0 {
        polish(&unreflect(&x, &(x.transpose() * a)))
    } else {
        x
    }
}
