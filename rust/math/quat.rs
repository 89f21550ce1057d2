//! Quaternions as stored in the state arrays: `[x, y, z, w]`, the order SciPy uses.
//! A unit quaternion `q` maps body-frame vectors to the world: `v_w = q v_b q*`.

use super::{Mat3, Quat, Vec3};

#[inline(always)]
pub fn from_xyzw(a: [f64; 4]) -> Quat {
    Quat::new(a[3], a[0], a[1], a[2])
}

#[inline(always)]
pub fn to_xyzw(q: &Quat) -> [f64; 4] {
    [q.i, q.j, q.k, q.w]
}

/// `q / |q|`, refined by one Newton step `q (3 − |q|²)/2` so that `|q|² − 1` is
/// not biased upwards. Plain division leaves `|q|²` above 1 by +0.4 ulp on
/// average (`sqrt` of a sum just above 1 rounds to 1 and leaves the larger ulp
/// above 1 in place); [`rotate`] of a vector scales it by `|q|²` to first order,
/// so a world-to-body-to-world round trip every step made `|L|` grow
/// systematically (1e-11 after 10⁴ Suzuki steps of the Dzhanibekov box).
#[inline(always)]
pub fn normalize(q: &Quat) -> Quat {
    let u = q / q.norm();
    u * (1.5 - 0.5 * u.norm_squared())
}

/// Rotates `v` by the unit quaternion `q` (body to world).
#[inline(always)]
pub fn rotate(q: &Quat, v: &Vec3) -> Vec3 {
    let u = Vec3::new(q.i, q.j, q.k);
    let t = 2.0 * u.cross(v);
    v + q.w * t + u.cross(&t)
}

/// Rotates `v` by the inverse of the unit quaternion `q` (world to body).
#[inline(always)]
pub fn rotate_inv(q: &Quat, v: &Vec3) -> Vec3 {
    let u = Vec3::new(-q.i, -q.j, -q.k);
    let t = 2.0 * u.cross(v);
    v + q.w * t + u.cross(&t)
}

/// The rotation matrix of a unit quaternion.
#[inline]
pub fn to_matrix(q: &Quat) -> Mat3 {
    let (x, y, z, w) = (q.i, q.j, q.k, q.w);
    Mat3::new(
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y - z * w),
        2.0 * (x * z + y * w),
        2.0 * (x * y + z * w),
        1.0 - 2.0 * (x * x + z * z),
        2.0 * (y * z - x * w),
        2.0 * (x * z - y * w),
        2.0 * (y * z + x * w),
        1.0 - 2.0 * (x * x + y * y),
    )
}

/// The unit quaternion of a proper rotation matrix (Shepperd's method: the largest
/// diagonal pivot keeps it accurate near 180°).
pub fn from_matrix(m: &Mat3) -> Quat {
    let t = m.trace();
    let q = if t > m[(0, 0)] && t > m[(1, 1)] && t > m[(2, 2)] {
        let s = (1.0 + t).sqrt() * 2.0;
        Quat::new(0.25 * s, (m[(2, 1)] - m[(1, 2)]) / s, (m[(0, 2)] - m[(2, 0)]) / s, (m[(1, 0)] - m[(0, 1)]) / s)
    } else if m[(0, 0)] > m[(1, 1)] && m[(0, 0)] > m[(2, 2)] {
        let s = (1.0 + m[(0, 0)] - m[(1, 1)] - m[(2, 2)]).sqrt() * 2.0;
        Quat::new((m[(2, 1)] - m[(1, 2)]) / s, 0.25 * s, (m[(0, 1)] + m[(1, 0)]) / s, (m[(0, 2)] + m[(2, 0)]) / s)
    } else if m[(1, 1)] > m[(2, 2)] {
        let s = (1.0 + m[(1, 1)] - m[(0, 0)] - m[(2, 2)]).sqrt() * 2.0;
        Quat::new((m[(0, 2)] - m[(2, 0)]) / s, (m[(0, 1)] + m[(1, 0)]) / s, 0.25 * s, (m[(1, 2)] + m[(2, 1)]) / s)
    } else {
        let s = (1.0 + m[(2, 2)] - m[(0, 0)] - m[(1, 1)]).sqrt() * 2.0;
        Quat::new((m[(1, 0)] - m[(0, 1)]) / s, (m[(0, 2)] + m[(2, 0)]) / s, (m[(1, 2)] + m[(2, 1)]) / s, 0.25 * s)
    };
    let n = q.norm();
    q / n
}

/// Largest `|x|` for which [`sin_cos`] uses its polynomial: the truncated terms are
/// below 1e-17 relative there (`x¹³/13!` for the sine, `x¹⁴/14!` for the cosine).
pub const SIN_COS_POLY_MAX: f64 = 0.25;

/// `sin(x)/x` and `cos(x)` from `y = x²`, for `y ≤ SIN_COS_POLY_MAX²`: Taylor
/// series to `y⁵/11!` and `y⁶/12!`, evaluated as `1 + y·P(y)` so that the result
/// is rounded once (within an ulp of libm, mostly identical).
#[inline(always)]
fn sinc_cos_poly(y: f64) -> (f64, f64) {
    const S: [f64; 5] = [
        -1.0 / 6.0,
        1.0 / 120.0,
        -1.0 / 5040.0,
        1.0 / 362_880.0,
        -1.0 / 39_916_800.0,
    ];
    const C: [f64; 6] = [
        -1.0 / 2.0,
        1.0 / 24.0,
        -1.0 / 720.0,
        1.0 / 40_320.0,
        -1.0 / 3_628_800.0,
        1.0 / 479_001_600.0,
    ];
    let ps = S[0] + y * (S[1] + y * (S[2] + y * (S[3] + y * S[4])));
    let pc = C[0] + y * (C[1] + y * (C[2] + y * (C[3] + y * (C[4] + y * C[5]))));
    (1.0 + y * ps, 1.0 + y * pc)
}

/// `(sin x, cos x)`: an inlined polynomial for the small angles of a time step
/// (`|x| ≤ SIN_COS_POLY_MAX`), libm beyond. The polynomial spares the call, and
/// with it the spilling of every live register around it.
#[inline(always)]
pub fn sin_cos(x: f64) -> (f64, f64) {
    if x.abs() <= SIN_COS_POLY_MAX {
        let (sinc, c) = sinc_cos_poly(x * x);
        (x * sinc, c)
    } else {
        x.sin_cos()
    }
}

/// The unit quaternion of the rotation by the vector `theta` (axis times angle).
/// Exact for every angle: below a half-angle of `SIN_COS_POLY_MAX` the series
/// in `|theta|²` needs no square root, division or libm call.
#[inline(always)]
pub fn exp(theta: &Vec3) -> Quat {
    let a2 = theta.norm_squared();
    let (s_over_a, c) = if a2 <= 4.0 * SIN_COS_POLY_MAX * SIN_COS_POLY_MAX {
        // x = a/2: sin(a/2)/a = ½ sin(x)/x.
        let (sinc, c) = sinc_cos_poly(0.25 * a2);
        (0.5 * sinc, c)
    } else {
        let a = a2.sqrt();
        let (s, c) = (0.5 * a).sin_cos();
        (s / a, c)
    };
    Quat::new(c, s_over_a * theta.x, s_over_a * theta.y, s_over_a * theta.z)
}

/// Right multiplication by the rotation of angle `theta` about body axis `j`:
/// `q ⊗ (cos θ/2, sin θ/2 e_j)`, given `(sin θ/2, cos θ/2)`.
#[inline(always)]
pub fn mul_axis(q: &Quat, j: usize, s: f64, c: f64) -> Quat {
    let (w, x, y, z) = (q.w, q.i, q.j, q.k);
    match j {
        0 => Quat::new(w * c - x * s, x * c + w * s, y * c + z * s, z * c - y * s),
        1 => Quat::new(w * c - y * s, x * c - z * s, y * c + w * s, z * c + x * s),
        _ => Quat::new(w * c - z * s, x * c + y * s, y * c - x * s, z * c + w * s),
    }
}

/// The angle (rad, in [0, π]) of the rotation taking `a` to `b`: ‖log(aᵀ b)‖.
pub fn angle_between(a: &Quat, b: &Quat) -> f64 {
    let d = a.conjugate() * b;
    let v = (d.i * d.i + d.j * d.j + d.k * d.k).sqrt();
    2.0 * v.atan2(d.w.abs())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotate_matches_matrix() {
        let q = exp(&Vec3::new(0.3, -1.2, 2.0));
        let v = Vec3::new(1.0, 2.0, -0.5);
        // ~20 flops each way: a few ulps of |v| ≈ 2.3.
        assert!((rotate(&q, &v) - to_matrix(&q) * v).norm() < 1e-14);
        assert!((rotate_inv(&q, &rotate(&q, &v)) - v).norm() < 1e-14);
    }

    /// The polynomial agrees with libm to within 2 ulp wherever it is used
    /// (truncation below 1e-17 relative; the rest is rounding), the branch
    /// edge included, and `exp` stays a unit quaternion on both sides of it.
    #[test]
    fn sin_cos_polynomial_matches_libm() {
        let ulp = |x: f64| f64::EPSILON * x.abs().max(f64::MIN_POSITIVE);
        for k in -2000..=2000 {
            let x = SIN_COS_POLY_MAX * k as f64 / 2000.0;
            let ((s, c), (s0, c0)) = (sin_cos(x), x.sin_cos());
            assert!((s - s0).abs() <= 2.0 * ulp(s0), "sin {x}: {s} vs {s0}");
            assert!((c - c0).abs() <= 2.0 * ulp(c0), "cos {x}: {c} vs {c0}");
        }
        for a in [1e-9, 0.1, 2.0 * SIN_COS_POLY_MAX, 2.0 * SIN_COS_POLY_MAX * (1.0 + 1e-12), 1.3] {
            let q = exp(&(Vec3::new(0.6, -0.8, 0.0) * a));
            assert!((q.norm() - 1.0).abs() <= 4.0 * f64::EPSILON, "|exp| at angle {a}");
            assert!((q.w - (0.5 * a).cos()).abs() <= 2.0 * f64::EPSILON, "cos(a/2) at {a}");
        }
    }

    #[test]
    fn mul_axis_matches_general_product() {
        let q = exp(&Vec3::new(0.3, -1.2, 2.0));
        for j in 0..3 {
            let mut e = Vec3::zeros();
            e[j] = 0.7;
            let (s, c) = (0.35f64).sin_cos();
            let want = q * exp(&e);
            assert!((mul_axis(&q, j, s, c) - want).norm() < 1e-15, "axis {j}");
        }
    }

    /// Regression: `q / |q|` left `|q|²` above 1 by +8.5e-17 on average, and the
    /// ω → L → ω round trip of every free-rotation stage turned that into a
    /// systematic growth of |L| (suzuki4: 1.1e-11 after 10⁴ steps of the
    /// Dzhanibekov box, over the 1e-11 bar). Over 20 000 near-unit quaternions the
    /// mean of `|q|² − 1` must stay within ±5e-17 (≈ 0.2 ulp of 1; the statistical
    /// spread of that mean is ~1e-18): `normalize` measures −2.6e-17 here, plain
    /// division +7.4e-17.
    #[test]
    fn normalize_has_no_upward_bias() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut uniform = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let n = 20_000;
        let mut sum = 0.0;
        for _ in 0..n {
            let q = Quat::new(uniform(), uniform(), uniform(), uniform());
            let u = q / q.norm();
            // A product of unit quaternions: |u| = 1 to a few ulps, as in a step.
            let u = u * (1.0 + 4e-16 * uniform());
            let v = normalize(&u);
            // |v|² − 1 without the rounding of the sum: two-product of each term.
            let mut hi = -1.0;
            let mut lo = 0.0;
            for x in [v.w, v.i, v.j, v.k] {
                let p = x * x;
                let e = x.mul_add(x, -p);
                let s = hi + p;
                let bb = s - hi;
                lo += (hi - (s - bb)) + (p - bb) + e;
                hi = s;
            }
            sum += hi + lo;
        }
        let mean = sum / n as f64;
        assert!(mean.abs() < 5e-17, "mean |q|² − 1 = {mean:e}");
    }

    #[test]
    fn matrix_round_trip_near_half_turn() {
        for v in [Vec3::new(std::f64::consts::PI - 2.7e-6, 0.0, 0.0), Vec3::new(0.0, 2.2, 2.2), Vec3::new(1e-9, 0.0, 0.0)] {
            let q = exp(&v);
            let back = from_matrix(&to_matrix(&q));
            assert!(angle_between(&q, &back) < 1e-12);
        }
    }
}
