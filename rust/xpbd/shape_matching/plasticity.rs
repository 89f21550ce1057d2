//! Plastic flow of a cluster (Müller et al. 2005, §4.5). With `A` the best linear
//! map from the (plastic) rest shape to the current one and `R` its rotation, the
//! elastic deformation is `S = Rᵀ A`. While `‖S − I‖_F` exceeds the yield, the
//! plastic state creeps towards it,
//! `Sp ← (I + min(h·creep, 1)·(S − I)) Sp`,
//! is scaled to `det Sp = 1` (the plastic flow keeps the volume), and is pulled
//! back along `I + t (Sp − I)` (largest `t` ≤ 1) until `‖Sp − I‖_F ≤ max`.
//! The rest shape becomes `qᵢ = Sp qᵢ⁰`.

use crate::error::{non_negative, Error, Result};
use crate::math::Mat3;

/// Plasticity parameters, each with its unit and default.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Plasticity {
    /// Yield: elastic deformation `‖S − I‖_F` (–) beyond which the cluster flows.
    pub yield_strain: f64,
    /// Creep rate (1/s): how fast the plastic state follows the deformation.
    pub creep: f64,
    /// Cap (–) on the plastic deformation `‖Sp − I‖_F`.
    pub max: f64,
}

impl Plasticity {
    pub fn validate(&self) -> Result<()> {
        non_negative("plastic_yield", self.yield_strain)?;
        non_negative("plastic_creep", self.creep)?;
        // Unbounded (inf) is the documented default; NaN and negatives are refused.
        if !(self.max >= 0.0) {
            return Err(crate::error::Error::input(format!("plastic_max must be non-negative (inf: no cap), got {}", self.max)));
        }
        Ok(())
    }
}

/// Frobenius norm of `m − I`.
#[inline]
pub fn strain(m: &Mat3) -> f64 {
    (m - Mat3::identity()).norm()
}

/// `m / det(m)^(1/3)`, or `None` when `m` is inverted or flat.
fn unit_volume(m: &Mat3) -> Option<Mat3> {
    let d = m.determinant();
    (d > 1e-12 && d.is_finite()).then(|| m / d.cbrt())
}

/// One substep (`h` seconds) of plastic flow of the state `sp`, given the
/// elastic deformation `s`; returns whether `sp` changed.
pub fn flow(p: &Plasticity, sp: &mut Mat3, s: &Mat3, h: f64) -> bool {
    if !(strain(s) > p.yield_strain) || p.creep == 0.0 {
        return false;
    }
    // At most the whole way in one substep.
    let crept = (Mat3::identity() + (s - Mat3::identity()) * (h * p.creep).min(1.0)) * *sp;
    let Some(next) = unit_volume(&crept) else { return false };
    let capped = cap(&next, p.max);
    if !capped.iter().all(|x| x.is_finite()) {
        return false;
    }
    *sp = capped;
    true
}

/// The unit-volume point `unit_volume(I + t (m − I))` with the largest `t` in
/// [0, 1] whose strain is at most `max` (bisection; `m` itself if within).
fn cap(m: &Mat3, max: f64) -> Mat3 {
    if strain(m) <= max {
        return *m;
    }
    let at = |t: f64| unit_volume(&(Mat3::identity() + (m - Mat3::identity()) * t));
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        match at(mid) {
            Some(x) if strain(&x) <= max => lo = mid,
            _ => hi = mid,
        }
    }
    at(lo).unwrap_or_else(Mat3::identity)
}

/// Errors for a plasticity given without the parameters it needs.
pub fn from_parts(yield_strain: Option<f64>, creep: f64, max: f64) -> Result<Option<Plasticity>> {
    match yield_strain {
        None if creep != 0.0 => Err(Error::input("plastic_creep needs plastic_yield as well")),
        None => Ok(None),
        Some(y) => {
            let p = Plasticity { yield_strain: y, creep, max };
            p.validate()?;
            Ok(Some(p))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    #[test]
    fn flow_keeps_volume_and_stays_under_the_cap() {
        let p = Plasticity { yield_strain: 0.05, creep: 50.0, max: 0.3 };
        let s = Mat3::from_diagonal(&Vector3::new(1.8, 0.8, 0.7));
        let mut sp = Mat3::identity();
        for _ in 0..1000 {
            flow(&p, &mut sp, &s, 0.01);
            assert!(strain(&sp) <= 0.3 + 1e-12);
            assert!((sp.determinant() - 1.0).abs() < 1e-12);
        }
        assert!(strain(&sp) > 0.3 - 1e-9, "the cap is reached: {}", strain(&sp));
    }

    #[test]
    fn no_flow_below_yield() {
        let p = Plasticity { yield_strain: 0.5, creep: 50.0, max: 1.0 };
        let mut sp = Mat3::identity();
        assert!(!flow(&p, &mut sp, &Mat3::from_diagonal(&Vector3::new(1.2, 1.0, 1.0)), 0.01));
        assert_eq!(sp, Mat3::identity());
    }
}
