//! Soft constraints (Catto, "Solver2D" and Box2D v3): a constraint behaves like a
//! spring of natural frequency `hertz` and damping ratio `zeta`, integrated
//! implicitly over the substep `h`, which makes it unconditionally stable. The
//! position error is fed back at `bias_rate`; `mass_scale` and `impulse_scale`
//! soften the velocity solve.

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Softness {
    /// Position error to velocity (1/s).
    pub bias_rate: f64,
    pub mass_scale: f64,
    pub impulse_scale: f64,
}

impl Default for Softness {
    fn default() -> Self {
        Self::RIGID
    }
}

impl Softness {
    /// A rigid constraint: no bias, full mass.
    pub const RIGID: Softness = Softness { bias_rate: 0.0, mass_scale: 1.0, impulse_scale: 0.0 };

    pub fn new(hertz: f64, zeta: f64, h: f64) -> Self {
        if hertz <= 0.0 {
            return Self::RIGID;
        }
        let omega = 2.0 * std::f64::consts::PI * hertz;
        let a1 = 2.0 * zeta + h * omega;
        let a2 = h * omega * a1;
        let a3 = 1.0 / (1.0 + a2);
        Self { bias_rate: omega / a1, mass_scale: a2 * a3, impulse_scale: a3 }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stiff_limit_is_rigid_with_full_bias() {
        let s = Softness::new(1e9, 1.0, 1e-3);
        assert!((s.mass_scale - 1.0).abs() < 1e-6 && s.impulse_scale < 1e-6);
        assert!((s.bias_rate - 1.0 / 1e-3).abs() / 1e3 < 1e-5);
    }
}
