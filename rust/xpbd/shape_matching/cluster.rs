//! A shape-matching cluster (Müller, Heidelberger, Teschner, Gross 2005): a set
//! of particles, their rest shape, the matching mode and its parameters, and the
//! state kept between substeps (rotation for the warm start, plastic deformation).

use nalgebra::{SMatrix, SVector, UnitQuaternion};

use super::plasticity::Plasticity;
use crate::error::{Error, Result};
use crate::math::{Mat3, Vec3};

pub type Mat9 = SMatrix<f64, 9, 9>;
pub type Vec9 = SVector<f64, 9>;

/// How far the goal shape may deform from the rest shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Mode {
    /// Goal = the best rotation of the rest shape.
    Rigid,
    /// Goal = `β A + (1 − β) R` applied to the rest shape, `A` the best linear map.
    Linear,
    /// Goal = `β Ã + (1 − β) [R 0 0]` applied to the quadratic rest terms `q̃`.
    Quadratic,
}

impl Mode {
    pub fn from_name(s: &str) -> Result<Self> {
        match s {
            "rigid" => Ok(Mode::Rigid),
            "linear" => Ok(Mode::Linear),
            "quadratic" => Ok(Mode::Quadratic),
            _ => Err(Error::input(format!("mode must be \"rigid\", \"linear\" or \"quadratic\", got {s:?}"))),
        }
    }

    pub fn name(&self) -> &'static str {
        match self {
            Mode::Rigid => "rigid",
            Mode::Linear => "linear",
            Mode::Quadratic => "quadratic",
        }
    }
}

/// What `Scene::add_shape_matching` takes, each with its unit and default.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct ClusterSpec {
    /// Default [`Mode::Linear`].
    pub mode: Mode,
    /// Fraction of the way to the goal each particle moves per substep, in
    /// [0, 1] (Müller's α). Default 1.
    pub stiffness: f64,
    /// Blend between the deformable (β = 1) and the rigid goal (β = 0), in
    /// [0, 1]; linear and quadratic modes. Default 0.5.
    pub beta: f64,
    /// Linear mode: scale `A` to `det A = 1` so the goal keeps the rest volume.
    /// Default true. (Rigid goals keep it by construction; quadratic goals are
    /// not scaled.)
    pub preserve_volume: bool,
    /// Plastic flow; default none.
    pub plasticity: Option<Plasticity>,
}

impl Default for ClusterSpec {
    fn default() -> Self {
        Self { mode: Mode::Linear, stiffness: 1.0, beta: 0.5, preserve_volume: true, plasticity: None }
    }
}

impl ClusterSpec {
    pub fn validate(&self) -> Result<()> {
        for (name, v) in [("stiffness", self.stiffness), ("beta", self.beta)] {
            if !(v.is_finite() && (0.0..=1.0).contains(&v)) {
                return Err(Error::input(format!("{name} must be in [0, 1], got {v}")));
            }
        }
        if let Some(p) = &self.plasticity {
            p.validate()?;
        }
        Ok(())
    }
}

/// The quadratic terms `(x, y, z, x², y², z², xy, yz, zx)` of a rest offset. A
/// cluster subtracts their weighted mean (see `Cluster::quad_mean`).
#[inline]
pub fn quadratic_terms(q: &Vec3) -> Vec9 {
    Vec9::from([q.x, q.y, q.z, q.x * q.x, q.y * q.y, q.z * q.z, q.x * q.y, q.y * q.z, q.z * q.x])
}

#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Cluster {
    pub particles: Vec<u32>,
    pub spec: ClusterSpec,
    /// Matching weight of each particle: its mass shared among the clusters that
    /// hold it, `mᵢ / cᵢ` (kg); set when the world is built.
    pub weights: Vec<f64>,
    /// Rest offsets from the weighted rest centre as added (m).
    pub rest0: Vec<Vec3>,
    /// Rest offsets after plastic flow, `Sp q⁰` (m).
    pub rest: Vec<Vec3>,
    /// `(Σ w q qᵀ)⁻¹` (1/(kg·m²)) and, in quadratic mode, `(Σ w q̃ q̃ᵀ)⁻¹`.
    pub aqq_inv: Mat3,
    pub aqq9_inv: Mat9,
    /// Weighted mean of the quadratic terms over the rest shape. Müller's `q̃`
    /// minus this: centred like the `q`, so that `Σ w Ã q̃ = 0` and the quadratic
    /// goals keep the centre (and the momentum) of the cluster.
    pub quad_mean: Vec9,
    /// Rotation of the last goal (warm start of the next).
    pub rotation: UnitQuaternion<f64>,
    /// Weighted centre of the particles at the last goal (m).
    pub center: Vec3,
    /// Plastic deformation `Sp` (identity until the cluster yields).
    pub plastic: Mat3,
}

/// Eigenvalue ratio below which a moment matrix counts as singular.
const SINGULAR: f64 = 1e-10;

impl Cluster {
    /// Validates the particle positions `x` (with masses `m`) of a new cluster.
    pub fn new(particles: Vec<u32>, spec: ClusterSpec, x: &[Vec3], m: &[f64]) -> Result<Self> {
        spec.validate()?;
        let minimum = match spec.mode {
            Mode::Rigid => 3,
            Mode::Linear => 4,
            Mode::Quadratic => 10,
        };
        if particles.len() < minimum {
            return Err(Error::shape(format!(
                "{} shape matching needs at least {minimum} particles, got {}",
                spec.mode.name(),
                particles.len()
            )));
        }
        let mut c = Self {
            particles,
            spec,
            weights: m.to_vec(),
            rest0: x.to_vec(),
            rest: Vec::new(),
            aqq_inv: Mat3::identity(),
            aqq9_inv: Mat9::identity(),
            quad_mean: Vec9::zeros(),
            rotation: UnitQuaternion::identity(),
            center: Vec3::zeros(),
            plastic: Mat3::identity(),
        };
        c.prepare_rest(x)?;
        Ok(c)
    }

    /// Rest offsets from the weighted centre of `x`, and the moment matrices;
    /// rejects coincident, collinear (and, for the deformable modes, coplanar)
    /// particles.
    fn prepare_rest(&mut self, x: &[Vec3]) -> Result<()> {
        let total: f64 = self.weights.iter().sum();
        let c: Vec3 = x.iter().zip(&self.weights).map(|(p, w)| p * *w).sum::<Vec3>() / total;
        self.center = c;
        self.rest0 = x.iter().map(|p| p - c).collect();
        self.rest = self.rest0.clone();
        self.update_moments()
    }

    /// Sets the weights (`mᵢ / cᵢ`) and recomputes the rest shape from the
    /// particles' rest positions `x`.
    pub fn set_weights(&mut self, weights: Vec<f64>, x: &[Vec3]) -> Result<()> {
        self.weights = weights;
        self.prepare_rest(x)
    }

    /// `aqq_inv` (and `aqq9_inv`) from the current rest shape.
    pub fn update_moments(&mut self) -> Result<()> {
        let aqq: Mat3 = self.rest.iter().zip(&self.weights).map(|(q, w)| q * q.transpose() * *w).sum();
        let eig = aqq.symmetric_eigen().eigenvalues;
        let (lo, hi) = (eig.min(), eig.max());
        let mid = eig.sum() - lo - hi;
        if !(hi > 0.0) || mid <= SINGULAR * hi {
            let what = if !(hi > 0.0) { "coincident" } else { "collinear" };
            return Err(Error::shape(format!("the cluster's particles are {what}: no rotation can be fitted")));
        }
        let deformable = self.spec.mode != Mode::Rigid;
        if deformable && lo <= SINGULAR * hi {
            return Err(Error::shape(format!(
                "the cluster's particles are coplanar: {} shape matching needs particles spanning a volume",
                self.spec.mode.name()
            )));
        }
        self.aqq_inv = aqq.try_inverse().unwrap_or_else(Mat3::zeros);
        if self.spec.mode == Mode::Quadratic {
            let total: f64 = self.weights.iter().sum();
            self.quad_mean = self.rest.iter().zip(&self.weights).map(|(q, w)| quadratic_terms(q) * *w).sum::<Vec9>() / total;
            self.aqq9_inv = self.quadratic_moments(hi.sqrt())?;
        }
        Ok(())
    }

    /// Centred quadratic terms of a rest offset, `q̃ = terms(q) − mean`.
    #[inline]
    pub fn centred_terms(&self, q: &Vec3) -> Vec9 {
        quadratic_terms(q) - self.quad_mean
    }

    /// `(Σ w q̃ q̃ᵀ)⁻¹` of the centred terms, checked for rank on offsets scaled to
    /// unit size.
    fn quadratic_moments(&self, size: f64) -> Result<Mat9> {
        let total: f64 = self.weights.iter().sum();
        let s = (size * size / total).sqrt().max(f64::MIN_POSITIVE);
        let d = Vec9::from([1.0 / s, 1.0 / s, 1.0 / s, 1.0 / (s * s), 1.0 / (s * s), 1.0 / (s * s), 1.0 / (s * s), 1.0 / (s * s), 1.0 / (s * s)]);
        let scaled: Mat9 = self
            .rest
            .iter()
            .zip(&self.weights)
            .map(|(q, w)| {
                let t = self.centred_terms(q).component_mul(&d);
                t * t.transpose() * *w
            })
            .sum();
        let eig = scaled.symmetric_eigen().eigenvalues;
        if eig.min() <= SINGULAR * eig.max() {
            return Err(Error::shape(
                "quadratic shape matching needs particles that determine a quadratic map \
                 (at least 10 in general position, e.g. a 3×3×3 grid)",
            ));
        }
        let inv = scaled.try_inverse().ok_or_else(|| Error::shape("quadratic moment matrix is singular"))?;
        // Undo the scaling: the scaled terms are D q̃ with D = diag(1/s, …, 1/s², …).
        Ok(Mat9::from_diagonal(&d) * inv * Mat9::from_diagonal(&d))
    }
}
