//! The rotation group: skew matrices and the exponential and logarithm maps.

use super::{Mat3, Vec3};

/// The skew matrix `v̂` with `v̂ u = v × u`.
#[inline]
pub fn hat(v: &Vec3) -> Mat3 {
    Mat3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// The rotation matrix `exp(v̂)` (Rodrigues), accurate for small angles.
pub fn exp(v: &Vec3) -> Mat3 {
    super::quat::to_matrix(&super::quat::exp(v))
}

/// The rotation vector of a proper rotation matrix: axis times angle in [0, π].
pub fn log(r: &Mat3) -> Vec3 {
    let q = super::quat::from_matrix(r);
    let q = if q.w < 0.0 { -q } else { q };
    let v = Vec3::new(q.i, q.j, q.k);
    let s = v.norm();
    if s < 1e-300 {
        return Vec3::zeros();
    }
    let angle = 2.0 * s.atan2(q.w);
    v * (angle / s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_inverts_exp() {
        for v in [Vec3::new(0.1, 0.2, -0.3), Vec3::new(0.0, 0.0, 3.1), Vec3::new(1e-10, 0.0, 0.0)] {
            assert!((log(&exp(&v)) - v).norm() < 1e-12 * (1.0 + v.norm()));
        }
    }
}
