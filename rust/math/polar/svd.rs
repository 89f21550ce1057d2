//! The rotation factor from the singular value decomposition `A = U Σ Vᵀ`:
//! `R = U D Vᵀ` with `D = diag(1, 1, det(U Vᵀ))` applied to the smallest
//! singular value, so an inverted `A` gets the nearest proper rotation.
//!
//! The SVD is one-sided Jacobi (Hestenes): plane rotations `V` orthogonalise the
//! columns of `B = A V`, which are then `σⱼ uⱼ`. It is backward stable with high
//! relative accuracy, and for 3×3 converges in 4–6 sweeps. nalgebra's SVD is not
//! used: its `Matrix3` path goes through the eigenvectors of `AᵀA` (condition
//! squared: the small singular vectors are lost at cond 1e8), and its general
//! Golub–Kahan path left `‖U Σ Vᵀ − A‖ = 3.6e-10` on `Q diag(1, 1, 1e-6) Qᵀ`
//! (nalgebra 0.34.2), a polar factor wrong by 2e-9 where it is determined to 1e-16.
//!
//! The third column of `U` is `det(V) u₁ × u₂` rather than `b₃/σ₃`: it makes
//! `det(U Vᵀ) = +1` (the reflection, if any, lands on the smallest singular value)
//! and needs no division by a vanishing `σ₃` (singular input).

use super::{orthonormal, polish, Mat3};
use crate::math::Vec3;

/// Sweeps before giving up (3×3 converges in ≤ 6; the cap only bounds the loop).
const MAX_SWEEPS: usize = 40;

/// `a` finite with ‖a‖_F = 1.
pub(super) fn rotation(a: &Mat3) -> Mat3 {
    let (b, v) = jacobi(a);
    let norms = [b.column(0).norm(), b.column(1).norm(), b.column(2).norm()];
    let mut k = [0usize, 1, 2];
    k.sort_by(|&i, &j| norms[j].total_cmp(&norms[i]));
    let u0 = b.column(k[0]) / norms[k[0]];
    let u1 = unit_orthogonal(&b.column(k[1]).into_owned(), &u0);
    let vs = Mat3::from_columns(&[v.column(k[0]), v.column(k[1]), v.column(k[2])]);
    let u2 = u0.cross(&u1) * vs.determinant().signum();
    polish(&(Mat3::from_columns(&[u0, u1, u2]) * vs.transpose()))
}

/// `B = A V` with orthogonal columns, and `V`.
fn jacobi(a: &Mat3) -> (Mat3, Mat3) {
    let (mut b, mut v) = (*a, Mat3::identity());
    for _ in 0..MAX_SWEEPS {
        let mut turned = false;
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            turned |= rotate_pair(&mut b, &mut v, p, q);
        }
        if !turned {
            break;
        }
    }
    (b, v)
}

/// The plane rotation that makes columns `p` and `q` of `b` orthogonal, applied
/// to `b` and `v`; false when they already are to round-off.
fn rotate_pair(b: &mut Mat3, v: &mut Mat3, p: usize, q: usize) -> bool {
    let (bp, bq) = (b.column(p).into_owned(), b.column(q).into_owned());
    let (alpha, beta, gamma) = (bp.norm_squared(), bq.norm_squared(), bp.dot(&bq));
    if gamma.abs() <= f64::EPSILON * (alpha * beta).sqrt() {
        return false;
    }
    let zeta = (beta - alpha) / (2.0 * gamma);
    let t = zeta.signum() / (zeta.abs() + (1.0 + zeta * zeta).sqrt());
    let c = 1.0 / (1.0 + t * t).sqrt();
    let s = c * t;
    for m in [b, v] {
        let (mp, mq) = (m.column(p).into_owned(), m.column(q).into_owned());
        m.set_column(p, &(mp * c - mq * s));
        m.set_column(q, &(mp * s + mq * c));
    }
    true
}

/// `x` made orthogonal to the unit `u` and normalised; any unit vector
/// orthogonal to `u` if nothing of `x` is left (rank ≤ 1).
fn unit_orthogonal(x: &Vec3, u: &Vec3) -> Vec3 {
    let y = x - u * u.dot(x);
    let n = y.norm();
    if n > 1e-300 && (y / n).iter().all(|c| c.is_finite()) {
        y / n
    } else {
        orthonormal(u)
    }
}
