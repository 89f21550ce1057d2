//! A collider: a shape attached to a body at a fixed pose in the body's frame,
//! with a material and collision filter.

use nalgebra::{Isometry3, Translation3, UnitQuaternion};
use parry3d_f64::shape::SharedShape;

use super::material::Material;
use crate::body::Bodies;
use crate::math::quat;

/// Collision filter: a pair may touch iff `a.group & b.mask != 0` and
/// `b.group & a.mask != 0`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Filter {
    /// Bits this collider belongs to. Default 1.
    pub group: u32,
    /// Bits this collider collides with. Default all.
    pub mask: u32,
}

impl Default for Filter {
    fn default() -> Self {
        Self { group: 1, mask: u32::MAX }
    }
}

impl Filter {
    pub fn allows(&self, other: &Filter) -> bool {
        self.group & other.mask != 0 && other.group & self.mask != 0
    }
}

#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub struct Collider {
    pub body: u32,
    pub shape: SharedShape,
    /// Pose of parry's shape in the body's principal frame.
    pub local: Isometry3<f64>,
    pub material: Material,
    pub filter: Filter,
    /// Whether the shape is a half-space (infinite; handled apart in the broad phase).
    pub infinite: bool,
    /// Radius of a ball around the body's centre that contains the shape (m);
    /// bounds how far a point of it moves per radian.
    pub reach: f64,
    /// Whether the body asked for continuous collision detection.
    pub ccd: bool,
    /// The radius of a ball shape (m): two balls meet in one point, computed
    /// without parry's manifolds.
    pub ball: Option<f64>,
    /// A hull (or a compound with one) with a face of more than four corners,
    /// which parry's manifolds hold at four (see `face_points`).
    pub many_cornered: bool,
    /// Which of its contact points are corners (see [`super::corners`]).
    pub corners: super::corners::Corners,
}

impl Collider {
    /// World pose of the collider shape for the body pose in `bodies`.
    #[inline]
    pub fn pose(&self, bodies: &Bodies) -> Isometry3<f64> {
        let i = self.body as usize;
        body_pose(bodies, i) * self.local
    }
}

/// The pose of body `i` (centre of mass, principal frame).
#[inline]
pub fn body_pose(bodies: &Bodies, i: usize) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::from(crate::math::Vec3::from(bodies.position[i])),
        UnitQuaternion::new_unchecked(quat::from_xyzw(bodies.orientation[i])),
    )
}
