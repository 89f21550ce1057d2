//! Müller, Bender, Chentanez, Macklin 2016, "A Robust Method to Extract the
//! Rotational Part of Deformations": keep a unit quaternion `q` (warm-started with
//! the previous rotation) and turn it about `ω = Σᵢ rᵢ × aᵢ` (columns `rᵢ` of
//! `R(q)`, `aᵢ` of `A`) by `|ω| / |Σᵢ rᵢ · aᵢ|` until `ω` vanishes. `ω` is the
//! gradient of `f(R) = tr(Rᵀ A)` under `R ← exp(ω̂) R`, so the fixed points are the
//! critical points of `f`, and its maximum is the nearest proper rotation: det +1
//! by construction, inverted input included.
//!
//! Along any axis `d`, `f` is exactly `f₀ + (dᵀHd)(cos φ − 1) + (g·d) sin φ` with
//! `g = ω`, `H = tr(B) I − sym(B)`, `B = A Rᵀ`; Müller's angle is the first-order
//! root `|g| / tr(B)` of its derivative, with `dᵀHd ≈ tr(B)`. Three changes are
//! ours, each needed by a matrix of REFERENCES.md:
//! - the angle is the exact maximiser `atan2(g·d, dᵀHd)`: Müller's angle can
//!   overshoot without bound where `tr(B) ≈ 0` (far from the solution) and
//!   crawls where `dᵀHd ≪ tr(B)`;
//! - when `H` is positive definite the axis is Newton's, `H⁻¹ g`: along Müller's
//!   axis convergence is linear at the rate `1 − (σ₂ + σ₃)/(σ₁ + σ₂ + σ₃)`,
//!   ~1e9 iterations at condition 1e9; Newton's is quadratic;
//! - a saddle stops the iteration (started at the identity, a 180° turn has zero
//!   gradient) and a near-saddle holds it for thousands of iterations. `H` has
//!   at a critical point the eigenvalues `λⱼ + λₖ` of pairs of eigenvalues of
//!   `S`; along an eigenvector with negative curvature a turn by π gains
//!   `−2 dᵀHd > 0`, taken when it beats the other axes. (`f` has a single local
//!   maximum on SO(3) for generic `A`, so a critical point where `H` is positive
//!   definite is the answer.)

use std::f64::consts::PI;

use super::Mat3;
use crate::math::{quat, Quat, Vec3};

/// Iterations before returning the current rotation (measured: a warm start
/// needs ≤ 3, a cold start ≤ 7 on every matrix of REFERENCES.md).
const MAX_ITERATIONS: usize = 100;
/// Converged when a Müller turn is shorter than this (rad)...
const TOLERANCE: f64 = 4.0 * f64::EPSILON;
/// ... or a Newton turn (quadratic convergence: the next would be ~1e-20/λ_min(H)).
const NEWTON_TOLERANCE: f64 = 1e-10;
/// Newton turns below this (rad) that no longer halve are round-off.
const STAGNANT: f64 = 1e-6;
/// Curvature (of `f`, with ‖A‖_F = 1) below which `H` is not trusted for a Newton
/// axis, and below minus which a half turn is tried.
const CURVATURE: f64 = 1e-12;

/// `a` finite with ‖a‖_F = 1; `warm` any quaternion (the identity if zero).
pub(super) fn rotation(a: &Mat3, warm: Quat) -> Quat {
    iterate(a, warm).0
}

/// The rotation and the number of turns taken.
pub(super) fn iterate(a: &Mat3, warm: Quat) -> (Quat, usize) {
    let n = warm.norm();
    let mut q = if n > 0.0 && n.is_finite() { warm / n } else { Quat::identity() };
    let mut last = f64::INFINITY;
    for k in 0..MAX_ITERATIONS {
        let Some(step) = ascend(a, &q) else { return (q, k) };
        q = quat::normalize(&(quat::exp(&(step.axis * step.angle)) * q));
        if step.converged(last) {
            return (q, k + 1);
        }
        last = if step.newton { step.angle } else { f64::INFINITY };
    }
    (q, MAX_ITERATIONS)
}

/// A turn by `angle` (rad) about the unit `axis` (world), what it gains in `f`,
/// and whether the axis is Newton's.
#[derive(Clone, Copy)]
struct Step {
    axis: Vec3,
    angle: f64,
    gain: f64,
    newton: bool,
}

impl Step {
    /// Done after this step: a Müller turn at round-off, a Newton turn short
    /// enough that the next would be below round-off, or Newton turns that stop
    /// shrinking (round-off in the gradient over a small curvature, `~ε/λ_min(H)`,
    /// the accuracy the matrix allows) after the previous Newton turn `last`.
    fn converged(&self, last: f64) -> bool {
        if !self.newton {
            return self.angle <= TOLERANCE;
        }
        self.angle <= NEWTON_TOLERANCE || (self.angle <= STAGNANT && self.angle >= 0.5 * last)
    }
}

/// The best turn from `q`, or `None` at a maximum (zero gradient, no negative
/// curvature).
fn ascend(a: &Mat3, q: &Quat) -> Option<Step> {
    let r = quat::to_matrix(q);
    let g = r.column(0).cross(&a.column(0)) + r.column(1).cross(&a.column(1)) + r.column(2).cross(&a.column(2));
    let b = a * r.transpose();
    let h = Mat3::identity() * b.trace() - (b + b.transpose()) * 0.5;
    let newton = newton_axis(&h, &g).and_then(|w| along(&h, &g, &w, true));
    let muller = along(&h, &g, &g, false);
    let flip = half_turn(&h);
    [newton, muller, flip].into_iter().flatten().fold(None, |best: Option<Step>, s| match best {
        Some(b) if b.gain >= s.gain => Some(b),
        _ => Some(s),
    })
}

/// The exact maximiser of `f` along the axis of `w`: `f(φ) − f₀ =
/// (g·d) sin φ − 2 (dᵀHd) sin²(φ/2)`, largest at `φ = atan2(g·d, dᵀHd)`.
fn along(h: &Mat3, g: &Vec3, w: &Vec3, newton: bool) -> Option<Step> {
    let n = w.norm();
    if !(n > 0.0 && n.is_finite()) {
        return None;
    }
    let d = w / n;
    let (slope, curve) = (g.dot(&d), d.dot(&(h * d)));
    let angle = slope.atan2(curve);
    let s = (0.5 * angle).sin();
    Some(Step { axis: d, angle, gain: slope * angle.sin() - 2.0 * curve * s * s, newton })
}

/// `H⁻¹ g` when `H` is safely positive definite.
fn newton_axis(h: &Mat3, g: &Vec3) -> Option<Vec3> {
    let chol = h.cholesky()?;
    let small = chol.l_dirty().diagonal().min();
    (small * small > CURVATURE).then(|| chol.solve(g))
}

/// A turn by π about the eigenvector of the most negative curvature of `H`
/// (gain `−2λ`), if `H` has negative curvature.
fn half_turn(h: &Mat3) -> Option<Step> {
    let eig = h.symmetric_eigen();
    let k = eig.eigenvalues.imin();
    let lambda = eig.eigenvalues[k];
    (lambda < -CURVATURE).then(|| Step {
        axis: eig.eigenvectors.column(k).into_owned(),
        angle: PI,
        gain: -2.0 * lambda,
        newton: false,
    })
}
