//! The rotation of a polar decomposition `M = R S`, behind the one interface the
//! shape-matching code uses, [`polar_rotation`]. Implemented here with Müller,
//! Bender, Chentanez and Macklin's iterative rotation extraction (2016), warm
//! started from the cluster's previous rotation; it may later be switched to the
//! shared polar-decomposition module.
//!
//! The iteration climbs `f(R) = tr(Rᵀ M)` on SO(3):
//! `ω = Σₖ rₖ × mₖ / (|Σₖ rₖ·mₖ| + ε)`, `q ← exp(ω) q` (`rₖ`, `mₖ` the columns),
//! with the exact Newton step where it is safe (see [`climb`]). It stops at a stationary point, which may be a saddle (e.g. `M` a 180° turn of
//! the warm start: every `rₖ × mₖ` vanishes). A stationary `R` is the maximum iff
//! `tr(S) I − S ⪰ 0` for `S = sym(Rᵀ M)`, i.e. the two smallest eigenvalues of `S`
//! sum to ≥ 0; otherwise turning `R` by π about the eigenvector of the largest
//! eigenvalue of `S` reaches the maximum (the eigenvalues become `s₁, −s₂, −s₃`),
//! and the iteration polishes from there. The result is always a proper rotation
//! (det +1, orthonormal to round-off), also for inverted, singular, rank-1, zero
//! or non-finite `M` (then the warm start is kept): never NaN.

use nalgebra::{Matrix3, Unit, UnitQuaternion, Vector3};

/// Iterations per call at most; each costs about 60 flops.
const MAX_ITERATIONS: usize = 200;
/// Stop when the step `|ω|` (rad) falls below this.
const TOLERANCE: f64 = 1e-15;

/// The rotation `R` of `m = R S` (S symmetric), the proper rotation closest to
/// `m`, warm started from `warm` (identity if `None`).
pub fn polar_rotation(m: &Matrix3<f64>, warm: Option<&UnitQuaternion<f64>>) -> Matrix3<f64> {
    rotation_quaternion(m, warm).to_rotation_matrix().into_inner()
}

/// [`polar_rotation`] as a unit quaternion (what a cluster keeps as warm start).
pub fn rotation_quaternion(m: &Matrix3<f64>, warm: Option<&UnitQuaternion<f64>>) -> UnitQuaternion<f64> {
    let start = warm.copied().unwrap_or_else(UnitQuaternion::identity);
    let start = if start.coords.iter().all(|c| c.is_finite()) { start } else { UnitQuaternion::identity() };
    let scale = m.amax();
    if !(scale > 0.0 && scale.is_finite() && m.iter().all(|x| x.is_finite())) {
        return start;
    }
    let a = m / scale;
    let mut q = climb(&a, start);
    // At most two flips: each one strictly raises tr(RᵀM).
    for _ in 0..2 {
        match flip_axis(&a, &q) {
            Some(axis) => q = climb(&a, q * UnitQuaternion::from_axis_angle(&axis, std::f64::consts::PI)),
            None => break,
        }
    }
    q
}

/// Müller et al.'s fixed-point iteration from `q`, with Newton steps where they
/// are safe.
///
/// With `B = A Rᵀ`, the gradient of `tr(Rᵀ A)` under `R ← exp(ω̂) R` is
/// `g = Σₖ rₖ × aₖ` and its Hessian is `−H`, `H = tr(B_s) I − B_s` (`B_s` the
/// symmetric part). Müller's step is `ω = g / (|tr B| + ε)`, i.e. `H ≈ tr(B) I`;
/// it converges at a rate of `1 − (s₂ + s₃)/tr S` per iteration, hopeless for a
/// needle-like cluster (`s₂, s₃ ≪ s₁`). Where `H` is positive definite (near a
/// maximum) the exact Newton step `ω = H⁻¹ g` is taken instead (quadratic
/// convergence); elsewhere (near saddles, degenerate `A`) Müller's step.
fn climb(a: &Matrix3<f64>, mut q: UnitQuaternion<f64>) -> UnitQuaternion<f64> {
    for _ in 0..MAX_ITERATIONS {
        let r = q.to_rotation_matrix().into_inner();
        let mut g = Vector3::zeros();
        let mut trace = 0.0;
        for k in 0..3 {
            g += r.column(k).cross(&a.column(k));
            trace += r.column(k).dot(&a.column(k));
        }
        let omega = newton_step(a, &r, &g, trace).unwrap_or_else(|| g / (trace.abs() + 1e-9));
        let w = omega.norm();
        if !(w > TOLERANCE) {
            break;
        }
        q = UnitQuaternion::from_axis_angle(&Unit::new_unchecked(omega / w), w) * q;
        q.renormalize();
    }
    q
}

/// `H⁻¹ g` when `H = tr(B_s) I − B_s` is safely positive definite (then it is an
/// ascent direction), shortened to at most 0.5 rad; `None` otherwise.
fn newton_step(a: &Matrix3<f64>, r: &Matrix3<f64>, g: &Vector3<f64>, trace: f64) -> Option<Vector3<f64>> {
    let b = a * r.transpose();
    let bs = (b + b.transpose()) * 0.5;
    let h = Matrix3::identity() * trace - bs;
    let chol = h.cholesky()?;
    let l = chol.l_dirty();
    let smallest_pivot = (0..3).map(|i| l[(i, i)]).fold(f64::INFINITY, f64::min);
    if !(smallest_pivot * smallest_pivot > 1e-14 * trace.abs()) {
        return None;
    }
    let step = chol.solve(g);
    let n = step.norm();
    Some(if n > 0.5 { step * (0.5 / n) } else { step })
}

/// The axis (body frame of `q`) of the half turn that lifts a saddle of
/// `tr(Rᵀ a)` to its maximum, or `None` when `q` is the maximum.
fn flip_axis(a: &Matrix3<f64>, q: &UnitQuaternion<f64>) -> Option<Unit<Vector3<f64>>> {
    let s = q.to_rotation_matrix().into_inner().transpose() * a;
    let sym = (s + s.transpose()) * 0.5;
    let eig = sym.symmetric_eigen();
    let mut order = [0usize, 1, 2];
    order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
    let (s3, s2, s1) = (eig.eigenvalues[order[0]], eig.eigenvalues[order[1]], eig.eigenvalues[order[2]]);
    // Relative to the scale of `a` (its largest entry is 1).
    if s2 + s3 >= -1e-12 * (1.0 + s1.abs()) {
        return None;
    }
    let v = eig.eigenvectors.column(order[2]).into_owned();
    Unit::try_new(v, 1e-12)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Rotation3;

    fn check_rotation(r: &Matrix3<f64>) {
        assert!(r.iter().all(|x| x.is_finite()));
        assert!((r.transpose() * r - Matrix3::identity()).amax() < 1e-12);
        assert!((r.determinant() - 1.0).abs() < 1e-12);
    }

    fn rotations() -> Vec<Matrix3<f64>> {
        let mut v = Vec::new();
        for k in 0..20 {
            let t = k as f64;
            let axis = Unit::new_normalize(Vector3::new((t * 1.3).sin(), (t * 0.7).cos(), 0.5 + (t * 0.3).sin()));
            v.push(Rotation3::from_axis_angle(&axis, 0.37 * t - 3.0).into_inner());
        }
        for axis in [Vector3::x_axis(), Vector3::y_axis(), Vector3::z_axis()] {
            v.push(Rotation3::from_axis_angle(&axis, std::f64::consts::PI).into_inner());
        }
        let diag = Unit::new_normalize(Vector3::new(1.0, 1.0, 1.0));
        v.push(Rotation3::from_axis_angle(&diag, std::f64::consts::PI).into_inner());
        v
    }

    #[test]
    fn recovers_rotations_including_half_turns_from_identity() {
        for r in rotations() {
            for c in [1e-6, 1.0, 1e6] {
                let got = polar_rotation(&(r * c), None);
                check_rotation(&got);
                assert!((got - r).amax() < 1e-12, "{r} -> {got}");
            }
        }
    }

    #[test]
    fn recovers_r_of_r_times_spd_with_warm_starts() {
        let s = Matrix3::new(3.0, 0.5, 0.1, 0.5, 1.0, 0.2, 0.1, 0.2, 0.4);
        for r in rotations() {
            for warm in [None, Some(UnitQuaternion::from_axis_angle(&Vector3::y_axis(), 2.0))] {
                let got = polar_rotation(&(r * s), warm.as_ref());
                check_rotation(&got);
                assert!((got - r).amax() < 1e-12);
            }
        }
    }

    #[test]
    fn ill_conditioned_spd_factor() {
        // Condition number 1e9: the maximum is still R.
        let s = Matrix3::from_diagonal(&Vector3::new(1.0, 1e-3, 1e-9));
        for r in rotations() {
            let got = polar_rotation(&(r * s), None);
            check_rotation(&got);
            assert!((got - r).amax() < 1e-6, "{r} -> {got}");
        }
    }

    #[test]
    fn degenerate_matrices_give_rotations() {
        let cases = [
            Matrix3::from_diagonal(&Vector3::new(2.0, 1.0, -0.5)),
            Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 0.0)),
            Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 1e-8)),
            Vector3::new(1.0, 2.0, 3.0) * Vector3::new(-1.0, 0.5, 2.0).transpose(),
            Matrix3::zeros(),
            Matrix3::from_element(f64::NAN),
        ];
        for m in cases {
            check_rotation(&polar_rotation(&m, None));
        }
        let inverted = polar_rotation(&cases[0], None);
        assert!((inverted - Matrix3::identity()).amax() < 1e-12);
        assert!((polar_rotation(&cases[1], None) - Matrix3::identity()).amax() < 1e-12);
    }
}
