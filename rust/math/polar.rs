//! Polar decomposition `M = R S` of a 3×3 matrix: `R` the proper rotation nearest
//! to `M` (det +1, maximising `tr(Rᵀ M)`), `S = Rᵀ M`.
//!
//! When `det M > 0`, `S` is symmetric positive semi-definite and `R` is the
//! orthogonal polar factor. When `det M < 0` (an inverted element), the orthogonal
//! polar factor is a reflection; `R` is then the nearest proper rotation,
//! `U diag(1, 1, −1) Vᵀ` with the sign on the smallest singular value, and `S` is
//! symmetric with one negative eigenvalue. `R` is unique iff `σ₂ + sign(det M) σ₃ > 0`
//! (singular values σ₁ ≥ σ₂ ≥ σ₃); rank-1 and zero matrices have a family of
//! equally near rotations and any of them is returned.
//!
//! Three methods (see their files): [`svd`] (one-sided Jacobi SVD), [`higham`] (scaled
//! Newton iteration) and [`muller`] (Müller et al. 2016, warm-started). Each
//! returns an orthonormal `R` (to ~1e-15) with det +1 and never NaN for finite
//! input; the accuracy of `R` is bounded by the conditioning of the polar factor,
//! `~ε σ₁ / (σ₂ + sign(det M) σ₃)`.

mod higham;
mod muller;
mod svd;

use super::{quat, Mat3, Quat, Vec3};
use crate::error::{Error, Result};

/// How to compute the rotation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum PolarMethod {
    /// Singular value decomposition (one-sided Jacobi) with the reflection moved
    /// to the smallest singular value. The reference: backward stable.
    Svd,
    /// Newton iteration `R ← ½(γR + (γR)⁻ᵀ)` with Higham's scaling γ; the SVD for
    /// (numerically) singular input, which the iteration cannot invert.
    Higham,
    /// Müller et al. 2016: rotate a quaternion by `Σ rᵢ × mᵢ / |Σ rᵢ · mᵢ|` until
    /// it stops; cheap with a warm start (the previous rotation).
    Muller,
}

impl PolarMethod {
    pub const ALL: [PolarMethod; 3] = [PolarMethod::Svd, PolarMethod::Higham, PolarMethod::Muller];

    pub fn name(self) -> &'static str {
        match self {
            PolarMethod::Svd => "svd",
            PolarMethod::Higham => "higham",
            PolarMethod::Muller => "muller",
        }
    }

    pub fn from_name(name: &str) -> Result<Self> {
        Self::ALL.into_iter().find(|m| m.name() == name).ok_or_else(|| {
            Error::input(format!("method: unknown polar decomposition method {name:?}; choose one of svd, higham, muller"))
        })
    }
}

/// The two factors, `m = r * s`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Polar {
    /// Proper rotation (det +1).
    pub r: Mat3,
    /// `rᵀ m`: symmetric (to the accuracy of `r`) for every input.
    pub s: Mat3,
}

/// Polar decomposition of a finite `m` by `method`. `warm` (a unit quaternion, the
/// previous rotation) starts the Müller iteration; the other methods ignore it.
/// Errors on a non-finite entry.
pub fn polar(m: &Mat3, method: PolarMethod, warm: Option<&Quat>) -> Result<Polar> {
    if !m.iter().all(|x| x.is_finite()) {
        return Err(Error::input(format!("matrix must be finite, got {m:?}")));
    }
    let r = rotation(m, method, warm);
    Ok(Polar { r, s: r.transpose() * m })
}

/// The rotation factor of a finite `m` (a non-finite `m` gives the identity).
pub fn rotation(m: &Mat3, method: PolarMethod, warm: Option<&Quat>) -> Mat3 {
    let Some(a) = normalized(m) else { return warm.map_or(Mat3::identity(), quat::to_matrix) };
    match method {
        PolarMethod::Svd => svd::rotation(&a),
        PolarMethod::Higham => higham::rotation(&a),
        PolarMethod::Muller => quat::to_matrix(&muller::rotation(&a, warm.copied().unwrap_or_else(Quat::identity))),
    }
}

/// `m / ‖m‖_F` (the rotation factor does not depend on scale), or `None` for a
/// zero or non-finite `m`. Scaled by the largest entry first so that neither
/// 1e-200 nor 1e200 under- or overflows.
fn normalized(m: &Mat3) -> Option<Mat3> {
    let big = m.amax();
    if !(big > 0.0 && big.is_finite()) {
        return None;
    }
    let a = m / big;
    Some(a / a.norm())
}

/// Turns an orthogonal `q` with det −1 into the nearest proper rotation, given the
/// symmetric factor `h = qᵀ a`: the reflection moves onto the eigenvector of `h`
/// with the smallest eigenvalue, `q (I − 2 v vᵀ)`.
fn unreflect(q: &Mat3, h: &Mat3) -> Mat3 {
    let sym = (h + h.transpose()) * 0.5;
    let eig = sym.symmetric_eigen();
    let k = eig.eigenvalues.imin();
    let v = eig.eigenvectors.column(k).into_owned();
    q - (q * v) * (2.0 * v.transpose())
}

/// One Newton step `½(X + X⁻ᵀ)` at a converged orthogonal `X`: removes the last
/// rounding from its orthonormality (quadratic convergence).
fn polish(x: &Mat3) -> Mat3 {
    let det = x.determinant();
    (x + cofactor(x) / det) * 0.5
}

/// Any unit vector orthogonal to the unit `n`.
fn orthonormal(n: &Vec3) -> Vec3 {
    let a = if n.x.abs() < 0.577 { Vec3::x() } else if n.y.abs() < 0.577 { Vec3::y() } else { Vec3::z() };
    let t = a - n * n.dot(&a);
    t / t.norm()
}

/// The cofactor matrix, `det(X) X⁻ᵀ`, defined for every `X`.
fn cofactor(x: &Mat3) -> Mat3 {
    let (c0, c1, c2) = (x.column(0), x.column(1), x.column(2));
    Mat3::from_columns(&[c1.cross(&c2), c2.cross(&c0), c0.cross(&c1)])
}

#[cfg(test)]
mod tests;
