//! Every method on every matrix of REFERENCES.md: R orthonormal to 1e-12 with
//! det +1, no NaN, optimal (tr(RᵀM) = σ₁ + σ₂ + sign(det M) σ₃, the largest value
//! over SO(3)), and all methods agree where R is unique. Tolerances scale with the
//! conditioning of the polar factor: a perturbation δM moves R by
//! ~‖δM‖/(σ₂ + sign(det M) σ₃), and the computations perturb M by a few ε‖M‖.

use super::*;
use crate::math::so3;
use crate::math::Vec3;
use nalgebra::DMatrix;

/// Deterministic pseudo-random numbers in [−1, 1) (no rand crate in the core).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
    fn rotation(&mut self) -> Mat3 {
        let q = Quat::new(self.next(), self.next(), self.next(), self.next());
        quat::to_matrix(&(q / q.norm()))
    }
}

fn singular_values(m: &Mat3) -> [f64; 3] {
    let s = DMatrix::from_column_slice(3, 3, m.as_slice()).singular_values();
    let mut v = [s[0], s[1], s[2]];
    v.sort_by(|a, b| b.total_cmp(a));
    v
}

fn cases() -> Vec<(String, Mat3)> {
    let mut g = Lcg(7);
    let mut out = vec![("identity".to_string(), Mat3::identity())];
    for k in 0..20 {
        out.push((format!("random rotation {k}"), g.rotation()));
    }
    for axis in [Vec3::x(), Vec3::y(), Vec3::z(), Vec3::new(1.0, -2.0, 0.5).normalize()] {
        out.push((format!("180° about {axis:?}"), so3::exp(&(axis * std::f64::consts::PI))));
    }
    for c in [1e-6, 1e6] {
        out.push((format!("{c}·R"), g.rotation() * c));
    }
    for cond in [1e3f64, 1e6, 1e9] {
        for mid in [1.0, cond.sqrt(), cond] {
            let q = g.rotation();
            let s = q * Mat3::from_diagonal(&Vec3::new(1.0, 1.0 / mid, 1.0 / cond)) * q.transpose();
            out.push((format!("R·S cond {cond:e} mid {mid:e}"), g.rotation() * s));
        }
    }
    out.push(("inverted diag(2, 1, −0.5)".into(), Mat3::from_diagonal(&Vec3::new(2.0, 1.0, -0.5))));
    let (p, q) = (g.rotation(), g.rotation());
    out.push(("rotated inverted".into(), p * Mat3::from_diagonal(&Vec3::new(2.0, 1.0, -0.5)) * q));
    out.push(("singular diag(1, 1, 0)".into(), Mat3::from_diagonal(&Vec3::new(1.0, 1.0, 0.0))));
    out.push(("rotated singular".into(), p * Mat3::from_diagonal(&Vec3::new(3.0, 1.0, 0.0)) * q));
    out.push(("near-singular diag(1, 1, 1e-8)".into(), Mat3::from_diagonal(&Vec3::new(1.0, 1.0, 1e-8))));
    out.push(("rank 1".into(), Vec3::new(1.0, 2.0, -3.0) * Vec3::new(0.5, -1.0, 0.25).transpose()));
    out.push(("zero".into(), Mat3::zeros()));
    out
}

/// `ε σ₁ / (σ₂ + sign(det) σ₃)` times a safety factor, or `None` if R is not unique.
fn uniqueness_scale(m: &Mat3) -> Option<f64> {
    let s = singular_values(m);
    let gap = s[1] + m.determinant().signum() * s[2];
    (gap > 1e-14 * s[0]).then(|| f64::EPSILON * s[0] / gap)
}

fn check(name: &str, method: PolarMethod, m: &Mat3) -> Mat3 {
    let p = polar(m, method, None).unwrap_or_else(|e| panic!("{name}: {e}"));
    let r = p.r;
    assert!(r.iter().chain(p.s.iter()).all(|x| x.is_finite()), "{name} {method:?}: NaN");
    let ortho = (r.transpose() * r - Mat3::identity()).amax();
    assert!(ortho <= 1e-12, "{name} {method:?}: ‖RᵀR − I‖ = {ortho:e}");
    assert!((r.determinant() - 1.0).abs() <= 1e-12, "{name} {method:?}: det {}", r.determinant());
    let sv = singular_values(m);
    let best = sv[0] + sv[1] + m.determinant().signum() * sv[2];
    let got = (r.transpose() * m).trace();
    assert!(best - got <= 1e-12 * sv[0].max(f64::MIN_POSITIVE), "{name} {method:?}: tr(RᵀM) {got} < {best}");
    assert!((r * p.s - m).amax() <= 1e-14 * m.amax(), "{name} {method:?}: R S ≠ M");
    r
}

#[test]
fn every_method_on_every_reference_matrix() {
    for (name, m) in cases() {
        let reference = check(&name, PolarMethod::Svd, &m);
        for method in [PolarMethod::Higham, PolarMethod::Muller] {
            let r = check(&name, method, &m);
            if let Some(scale) = uniqueness_scale(&m) {
                // 20 ε κ: each method is backward stable, its R exact for an M moved by
                // ≤ 5 ε‖M‖ (measured ≤ 4), and κ amplifies that (both methods: 2 × 5 × 2).
                let err = (r - reference).amax();
                assert!(err <= 20.0 * scale.max(f64::EPSILON), "{name} {method:?}: differs from svd by {err:e} (κε = {scale:e})");
                let s = r.transpose() * m;
                let asym = (s - s.transpose()).amax();
                assert!(asym <= 20.0 * scale.max(f64::EPSILON) * m.amax(), "{name} {method:?}: S not symmetric ({asym:e})");
            }
        }
    }
}

#[test]
fn inverted_diagonal_gives_the_identity() {
    let m = Mat3::from_diagonal(&Vec3::new(2.0, 1.0, -0.5));
    for method in PolarMethod::ALL {
        let p = polar(&m, method, None).unwrap();
        assert!((p.r - Mat3::identity()).amax() <= 1e-15, "{method:?}: {}", p.r);
        assert!((p.s - m).amax() <= 1e-15);
    }
}

#[test]
fn muller_leaves_the_saddle_of_a_half_turn() {
    // From the identity, tr(RᵀA) has zero gradient at a 180° turn: Müller's step is 0.
    let m = so3::exp(&(Vec3::z() * std::f64::consts::PI));
    let p = polar(&m, PolarMethod::Muller, Some(&Quat::identity())).unwrap();
    assert!((p.r - m).amax() <= 1e-14);
}

#[test]
fn muller_warm_start_is_kept_when_exact() {
    let mut g = Lcg(3);
    let r = g.rotation();
    let q = quat::from_matrix(&r);
    let s = Mat3::from_diagonal(&Vec3::new(1.5, 1.0, 0.7));
    let p = polar(&(r * s), PolarMethod::Muller, Some(&q)).unwrap();
    assert!((p.r - r).amax() <= 1e-14);
}

#[test]
fn extreme_scales_and_bad_input() {
    let r = Lcg(5).rotation();
    for c in [1e-300, 1e300] {
        for method in PolarMethod::ALL {
            let p = polar(&(r * c), method, None).unwrap();
            assert!((p.r - r).amax() <= 1e-14, "{method:?} at scale {c:e}");
        }
    }
    let mut bad = Mat3::identity();
    bad[(1, 2)] = f64::NAN;
    assert!(polar(&bad, PolarMethod::Svd, None).is_err());
    assert_eq!(PolarMethod::from_name("higham").unwrap(), PolarMethod::Higham);
    assert!(PolarMethod::from_name("qr").is_err());
}

#[test]
fn muller_converges_in_a_few_iterations() {
    // Cold (identity start): measured ≤ 5 turns on every reference matrix; the
    // cap is 100. Warm (the previous rotation, a body turning 0.006 rad per call
    // under a fixed stretch): measured ≤ 3.
    for (name, m) in cases() {
        let Some(a) = super::normalized(&m) else { continue };
        let (_, k) = super::muller::iterate(&a, Quat::identity());
        assert!(k <= 8, "{name}: {k} iterations");
    }
    let mut g = Lcg(9);
    let r0 = g.rotation();
    let s = Mat3::from_diagonal(&Vec3::new(1.3, 1.0, 0.8));
    let mut q = quat::from_matrix(&r0);
    for step in 0..100 {
        let r = so3::exp(&(Vec3::new(0.3, -0.2, 0.5) * (0.01 * step as f64))) * r0;
        let a = super::normalized(&(r * s)).unwrap();
        let (next, k) = super::muller::iterate(&a, q);
        assert!(k <= 3, "warm step {step}: {k} iterations");
        assert!((quat::to_matrix(&next) - r).amax() <= 1e-14);
        q = next;
    }
}
