//! Mass properties of a body whose density varies: point quadrature of
//! `m = ∫ρ dV`, `c = ∫ρ x dV / m`, `I0 = ∫ρ (rᵀr·Id − r rᵀ) dV` with `r = x − c`
//! over samples (a point, the volume it stands for, the density there).
//!
//! Each sample is treated as a point mass (midpoint rule): a sample of a cubic cell
//! of edge `a` leaves out that cell's own inertia `m a²/6`, so the error falls as the
//! square of the sample spacing.

use super::mass::MassProps;
use crate::error::{Error, Result};
use crate::math::{Mat3, Vec3};

/// Samples of a density field, each a point (m), a volume (m³) and a density (kg/m³).
pub struct DensitySamples<'a> {
    pub points: &'a [[f64; 3]],
    pub volumes: &'a [f64],
    pub densities: &'a [f64],
}

impl DensitySamples<'_> {
    fn check(&self) -> Result<()> {
        let n = self.points.len();
        if n == 0 {
            return Err(Error::input("mass_properties: points is empty"));
        }
        for (name, len) in [("volumes", self.volumes.len()), ("densities", self.densities.len())] {
            if len != n {
                return Err(Error::input(format!("mass_properties: {name} has {len} entries, points has {n}")));
            }
        }
        for i in 0..n {
            if !self.points[i].iter().all(|x| x.is_finite()) {
                return Err(Error::input(format!("mass_properties: points[{i}] is not finite")));
            }
            let (v, r) = (self.volumes[i], self.densities[i]);
            if !(v.is_finite() && v >= 0.0) {
                return Err(Error::input(format!("mass_properties: volumes[{i}] must be >= 0 and finite, got {v}")));
            }
            if !(r.is_finite() && r >= 0.0) {
                return Err(Error::input(format!("mass_properties: densities[{i}] must be >= 0 and finite, got {r}")));
            }
        }
        Ok(())
    }

    /// Integrates mass, centre of mass and inertia. Two passes (centre first) keep
    /// the inertia accurate far from the origin.
    pub fn integrate(&self) -> Result<MassProps> {
        self.check()?;
        let weights = || self.volumes.iter().zip(self.densities).map(|(v, r)| v * r);
        let mass: f64 = weights().sum();
        if !(mass > 0.0 && mass.is_finite()) {
            return Err(Error::input(format!("mass_properties: total mass must be positive and finite, got {mass}")));
        }
        let mut first = Vec3::zeros();
        for (p, w) in self.points.iter().zip(weights()) {
            first += w * Vec3::from(*p);
        }
        let com = first / mass;
        let mut inertia = Mat3::zeros();
        for (p, w) in self.points.iter().zip(weights()) {
            let r = Vec3::from(*p) - com;
            inertia += w * (Mat3::identity() * r.norm_squared() - r * r.transpose());
        }
        let props = MassProps { mass, com, inertia };
        props.validate("mass_properties").map_err(|e| {
            Error::input(format!("{e} (are the weighted samples collinear or a single point?)"))
        })?;
        Ok(props)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_point_masses_are_rejected_as_collinear() {
        let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
        let s = DensitySamples { points: &pts, volumes: &[1.0, 1.0], densities: &[1.0, 1.0] };
        assert!(s.integrate().is_err());
    }

    #[test]
    fn length_mismatch_is_named() {
        let pts = [[0.0, 0.0, 0.0]];
        let s = DensitySamples { points: &pts, volumes: &[1.0, 1.0], densities: &[1.0] };
        let e = s.integrate().unwrap_err();
        assert!(e.message.contains("volumes"), "{}", e.message);
    }
}
