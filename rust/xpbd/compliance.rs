//! XPBD compliance and damping (Macklin, Müller, Chentanez 2016): the update of a
//! constraint's Lagrange multiplier in one projection.
//!
//! For a constraint `C(x)` with compliance `α` (inverse stiffness) and damping
//! `β`, over a substep of length `h`:
//!
//! ```text
//! α̃ = α / h²,   γ = α̃ β̃ / h = α β / h   (β̃ = h² β)
//! Δλ = (−C − α̃ λ − γ ∇C·(x − x_prev)) / ((1 + γ) Σ wᵢ |∇ᵢC|² + α̃)
//! xᵢ += wᵢ ∇ᵢC Δλ
//! ```
//!
//! `λ` starts at 0 each substep and sums the `Δλ` of every iteration. The force
//! the constraint exerts on particle `i` over the substep is `(λ / h²) ∇ᵢC`, so
//! `λ / h²` is the constraint's generalized force (N for a length constraint,
//! N·m for an angle, Pa for a volume). With `α = 0` the constraint is rigid
//! (plain PBD projection) and the damping has no effect.

use crate::error::{non_negative, Result};

/// Compliance and damping of one constraint.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Compliance {
    /// Compliance `α`: inverse stiffness in units of C per unit of generalized
    /// force (m/N for lengths, rad/(N·m) for angles, m³/Pa = m⁵/N for volumes).
    /// 0 (the default) is rigid.
    pub alpha: f64,
    /// Damping `β`: dashpot coefficient on `dC/dt` (N·s/m for lengths,
    /// N·m·s/rad for angles, Pa·s/m³ for volumes). Default 0. Acts only with α > 0.
    pub damping: f64,
}

impl Compliance {
    pub fn new(alpha: f64, damping: f64) -> Result<Self> {
        non_negative("compliance", alpha)?;
        non_negative("damping", damping)?;
        Ok(Self { alpha, damping })
    }
}

/// Per-substep factors: `1/h` and `1/h²` of the substep `h` (s).
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct Substep {
    pub h: f64,
    pub inv_h: f64,
    pub inv_h2: f64,
}

impl Substep {
    pub fn new(h: f64) -> Self {
        Self { h, inv_h: 1.0 / h, inv_h2: 1.0 / (h * h) }
    }

    /// `(α̃, γ)` of a constraint for this substep.
    #[inline(always)]
    pub fn factors(&self, k: &Compliance) -> (f64, f64) {
        (k.alpha * self.inv_h2, k.alpha * k.damping * self.inv_h)
    }
}

/// The multiplier update `Δλ` (see the module docs). `w` is `Σ wᵢ|∇ᵢC|²` and
/// `grad_dx` is `∇C·(x − x_prev)`. Returns 0 when nothing can move.
#[inline(always)]
pub fn delta_lambda(c: f64, lambda: f64, w: f64, alpha_t: f64, gamma: f64, grad_dx: f64) -> f64 {
    let denom = (1.0 + gamma) * w + alpha_t;
    if !(denom > 0.0) {
        return 0.0;
    }
    (-c - alpha_t * lambda - gamma * grad_dx) / denom
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rigid_projection_removes_the_error_in_one_step() {
        // α = 0, one particle of inverse mass 2 on a unit gradient: Δx = w Δλ = −C.
        let dl = delta_lambda(0.3, 0.0, 2.0, 0.0, 0.0, 0.0);
        assert!((2.0 * dl + 0.3).abs() < 1e-16);
    }

    #[test]
    fn compliant_projection_solves_the_regularized_equation() {
        // After the update, C + wΔλ + α̃(λ + Δλ) = 0 (the linear case converges in one step).
        let (c, l, w, at) = (0.2, -0.05, 3.0, 0.7);
        let dl = delta_lambda(c, l, w, at, 0.0, 0.0);
        assert!((c + w * dl + at * (l + dl)).abs() < 1e-15);
    }

    #[test]
    fn nothing_moves_without_mass_or_compliance() {
        assert_eq!(delta_lambda(1.0, 0.0, 0.0, 0.0, 0.0, 0.0), 0.0);
        assert!(Compliance::new(-1e-6, 0.0).is_err());
        assert!(Compliance::new(f64::NAN, 0.0).is_err());
        assert!(Compliance::new(0.0, -1.0).is_err());
    }
}
