//! Which contact points are corners: material points of a body, which move with
//! it as it turns, rather than points of a smooth surface, which the geometry
//! keeps where the surfaces meet however the body spins.
//!
//! A top's tip, a box's corner on the floor: as the body turns within a step the
//! point of contact turns with it, and an impulse applied at the step-start arm
//! acts with a lever a step behind (a top on its tip precessing at 120 Hz tilted
//! 2.45° in 4 s whatever the substeps). A ball's or a cylinder's side, on the
//! other hand, touches where the floor is: following the material point would
//! tilt the arm of a rolling ball. parry labels the ends of the segment that
//! stands for a cylinder's side as vertices, so the feature alone does not
//! decide: the shape does.

use nalgebra::Point3;
use parry3d_f64::shape::{FeatureId, PackedFeatureId, Shape, TypedShape};

/// Where a shape has corners.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Corners {
    /// No corner (balls, capsules, cylinders; compounds, whose points are in
    /// their parts' frames).
    #[default]
    None,
    /// Every vertex is one (boxes, convex hulls, triangle meshes).
    Polyhedron,
    /// Only the apex, at `(0, half_height, 0)` in parry's frame of the cone.
    Apex { half_height: f64, radius: f64 },
}

impl Corners {
    pub fn of(shape: &dyn Shape) -> Self {
        match shape.as_typed_shape() {
            TypedShape::Cuboid(_) | TypedShape::ConvexPolyhedron(_) | TypedShape::TriMesh(_) | TypedShape::Triangle(_) => {
                Corners::Polyhedron
            }
            TypedShape::Cone(c) => Corners::Apex { half_height: c.half_height, radius: c.radius },
            _ => Corners::None,
        }
    }

    /// Whether the contact point `local` (in parry's frame of the shape) of
    /// feature `fid` is a corner.
    pub fn at(&self, fid: PackedFeatureId, local: &Point3<f64>) -> bool {
        if !matches!(fid.unpack(), FeatureId::Vertex(_)) {
            return false;
        }
        match *self {
            Corners::None => false,
            Corners::Polyhedron => true,
            Corners::Apex { half_height, radius } => {
                let tol = 1e-9 * half_height.max(radius);
                (local.y - half_height).abs() <= tol && local.x.hypot(local.z) <= tol
            }
        }
    }
}
