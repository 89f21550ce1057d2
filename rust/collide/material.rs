//! Surface materials and how two of them combine at a contact.
//!
//! Combine rule: friction coefficients (static and dynamic) combine by their
//! geometric mean `√(μ₁μ₂)`, restitution by the maximum `max(e₁, e₂)`. Both give
//! the common value when the two bodies agree, a zero-friction surface makes any
//! contact frictionless, and a bouncy body bounces on any floor.

use crate::error::{non_negative, Error, Result};

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Material {
    /// Dynamic (sliding) friction coefficient μk (–). Default 0.5.
    pub friction: f64,
    /// Static (sticking) friction coefficient μs ≥ μk (–). Default: equal to `friction`.
    pub static_friction: f64,
    /// Coefficient of restitution e in [0, 1] (–). Default 0.
    pub restitution: f64,
}

impl Default for Material {
    fn default() -> Self {
        Self { friction: 0.5, static_friction: 0.5, restitution: 0.0 }
    }
}

impl Material {
    /// A validated material; `static_friction` defaults to `friction`.
    pub fn new(friction: f64, static_friction: Option<f64>, restitution: f64) -> Result<Self> {
        non_negative("friction", friction)?;
        let mu_s = static_friction.unwrap_or(friction);
        non_negative("static_friction", mu_s)?;
        if mu_s < friction {
            return Err(Error::input(format!(
                "static_friction ({mu_s}) must be at least friction ({friction}): a body cannot slip before it sticks"
            )));
        }
        if !(restitution.is_finite() && (0.0..=1.0).contains(&restitution)) {
            return Err(Error::input(format!("restitution must be in [0, 1], got {restitution}")));
        }
        Ok(Self { friction, static_friction: mu_s, restitution })
    }
}

/// The material of a contact between `a` and `b`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ContactMaterial {
    pub friction: f64,
    pub static_friction: f64,
    pub restitution: f64,
}

pub fn combine(a: &Material, b: &Material) -> ContactMaterial {
    ContactMaterial {
        friction: geometric_mean(a.friction, b.friction),
        static_friction: geometric_mean(a.static_friction, b.static_friction),
        restitution: a.restitution.max(b.restitution),
    }
}

/// `√(x y)`, and `x` itself for two equal values: the square root of a
/// double's square is the double (when the square neither overflows nor
/// underflows), so most scenes, one material throughout, keep their bits and
/// skip two square roots a contact pair a step.
fn geometric_mean(x: f64, y: f64) -> f64 {
    if x == y {
        x
    } else {
        (x * y).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_mean_of_equal_values_is_their_square_root_of_the_square() {
        // The shortcut gives the bits the square root gave.
        for k in 0..100_000 {
            let x = (k as f64 * 0.618034).fract() * 10f64.powi(k % 40 - 20);
            assert_eq!(geometric_mean(x, x).to_bits(), (x * x).sqrt().to_bits(), "{x}");
        }
    }

    #[test]
    fn equal_materials_keep_their_values() {
        let m = Material::new(0.3, Some(0.4), 0.7).unwrap();
        let c = combine(&m, &m);
        assert!((c.friction - 0.3).abs() < 1e-15 && (c.static_friction - 0.4).abs() < 1e-15);
        assert_eq!(c.restitution, 0.7);
    }

    #[test]
    fn rejects_bad_values() {
        assert!(Material::new(-0.1, None, 0.0).is_err());
        assert!(Material::new(f64::NAN, None, 0.0).is_err());
        assert!(Material::new(0.5, Some(0.4), 0.0).is_err());
        assert!(Material::new(0.5, None, 1.5).is_err());
        assert!(Material::new(0.5, None, -0.1).is_err());
    }
}
