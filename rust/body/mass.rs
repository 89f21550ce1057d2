//! Mass properties: mass, centre of mass and inertia tensor, and their principal
//! form (moments and axes), with the physical checks a user's input must pass.

use crate::error::{Error, Result};
use crate::math::{quat, Mat3, Quat, Vec3};

/// Mass properties in some source frame (a shape's or a sample set's).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MassProps {
    /// Mass (kg).
    pub mass: f64,
    /// Centre of mass in the source frame (m).
    pub com: Vec3,
    /// Inertia tensor about the centre of mass, source-frame axes (kg·m²).
    pub inertia: Mat3,
}

/// Principal form of an inertia tensor: `I = A diag(moments) Aᵀ` with `A` the
/// rotation of `frame`; its columns are the principal axes in the source frame.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Principal {
    /// Principal moments (kg·m²).
    pub moments: [f64; 3],
    /// Rotation from the principal frame to the source frame (det +1).
    pub frame: Quat,
}

/// Relative size of off-diagonal terms below which a tensor is taken as diagonal, so
/// that shapes whose axes are already principal keep the frame the user gave.
const DIAGONAL_TOL: f64 = 1e-13;
/// Relative slack for the triangle inequality: flat plates sit exactly on it.
const TRIANGLE_TOL: f64 = 1e-9;

impl MassProps {
    /// Checks mass and inertia, naming `what` in the error.
    pub fn validate(&self, what: &str) -> Result<()> {
        // 1/mass must be finite too: a subnormal mass (< 2.2e-308 kg) has an infinite
        // inverse, and the first force on the body made its state NaN.
        if !(self.mass.is_finite() && self.mass > 0.0 && (1.0 / self.mass).is_finite()) {
            return Err(Error::input(format!("{what}: mass must be positive and finite, got {}", self.mass)));
        }
        if !self.com.iter().all(|x| x.is_finite()) {
            return Err(Error::input(format!("{what}: centre of mass must be finite, got {:?}", self.com.as_slice())));
        }
        validate_inertia(&self.inertia, what)
    }

    pub fn principal(&self) -> Principal {
        principal_of(&self.inertia)
    }

    /// The same body with its density scaled so that its mass is `mass`.
    pub fn with_mass(&self, mass: f64) -> Self {
        let s = mass / self.mass;
        Self { mass, com: self.com, inertia: self.inertia * s }
    }
}

/// Checks that `inertia` is finite, symmetric, positive definite and obeys the
/// triangle inequality of its principal moments (`Ia + Ib ≥ Ic`).
pub fn validate_inertia(inertia: &Mat3, what: &str) -> Result<()> {
    if !inertia.iter().all(|x| x.is_finite()) {
        return Err(Error::input(format!("{what}: inertia must be finite")));
    }
    let scale = inertia.amax();
    if (inertia - inertia.transpose()).amax() > 1e-12 * scale {
        return Err(Error::input(format!("{what}: inertia tensor must be symmetric")));
    }
    let m = principal_of(inertia).moments;
    // Positive, with a finite inverse (a subnormal moment has none).
    if m.iter().any(|&x| !(x > 0.0 && (1.0 / x).is_finite())) {
        return Err(Error::input(format!(
            "{what}: inertia must be positive definite, principal moments are {m:?}"
        )));
    }
    let sum: f64 = m.iter().sum();
    for &x in &m {
        if x > (sum - x) * (1.0 + TRIANGLE_TOL) {
            return Err(Error::input(format!(
                "{what}: principal moments {m:?} violate the triangle inequality (each must be at most the sum of the other two)"
            )));
        }
    }
    Ok(())
}

/// Principal moments (ascending unless the tensor is already diagonal, in which
/// case the source axes are kept) and the principal frame.
pub fn principal_of(inertia: &Mat3) -> Principal {
    let sym = 0.5 * (inertia + inertia.transpose());
    let diag = Vec3::new(sym[(0, 0)], sym[(1, 1)], sym[(2, 2)]);
    let off = sym[(0, 1)].abs().max(sym[(0, 2)].abs()).max(sym[(1, 2)].abs());
    if off <= DIAGONAL_TOL * diag.amax() {
        return Principal { moments: [diag.x, diag.y, diag.z], frame: Quat::identity() };
    }
    let eig = sym.symmetric_eigen();
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
    let mut axes = Mat3::zeros();
    for (k, &j) in order.iter().enumerate() {
        axes.set_column(k, &eig.eigenvectors.column(j));
    }
    if axes.determinant() < 0.0 {
        let c = -axes.column(2);
        axes.set_column(2, &c);
    }
    Principal {
        moments: [eig.eigenvalues[order[0]], eig.eigenvalues[order[1]], eig.eigenvalues[order[2]]],
        frame: quat::from_matrix(&axes),
    }
}

/// `I = R diag(moments) Rᵀ`.
pub fn inertia_matrix(moments: &[f64; 3], frame: &Quat) -> Mat3 {
    let r = quat::to_matrix(frame);
    r * Mat3::from_diagonal(&Vec3::from(*moments)) * r.transpose()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn principal_reconstructs_tensor() {
        let r = quat::exp(&Vec3::new(0.4, -0.2, 1.1));
        let i = inertia_matrix(&[1.0, 2.0, 2.5], &r);
        let p = principal_of(&i);
        assert!((inertia_matrix(&p.moments, &p.frame) - i).amax() < 1e-14);
        assert!((p.moments[0] - 1.0).abs() < 1e-14 && (p.moments[2] - 2.5).abs() < 1e-14);
    }

    #[test]
    fn diagonal_tensor_keeps_its_axes() {
        let p = principal_of(&Mat3::from_diagonal(&Vec3::new(3.0, 1.0, 2.0)));
        assert_eq!(p.moments, [3.0, 1.0, 2.0]);
        assert_eq!(p.frame, Quat::identity());
    }

    #[test]
    fn subnormal_mass_and_moments_are_rejected() {
        let tiny = MassProps { mass: 1e-320, com: Vec3::zeros(), inertia: Mat3::identity() };
        assert!(tiny.validate("body 0").is_err());
        assert!(validate_inertia(&Mat3::from_diagonal_element(1e-320), "body 0").is_err());
    }

    #[test]
    fn rejects_triangle_violation() {
        let i = Mat3::from_diagonal(&Vec3::new(0.1, 0.1, 0.5));
        assert!(validate_inertia(&i, "body 0").is_err());
        let flat = Mat3::from_diagonal(&Vec3::new(1.0, 2.0, 3.0));
        assert!(validate_inertia(&flat, "body 0").is_ok());
    }
}
