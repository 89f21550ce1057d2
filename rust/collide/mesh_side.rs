//! Which side of a fixed mesh a point is on. A mesh's triangles collide on
//! their front only, the side they run counter-clockwise from (parry's
//! oriented meshes, which the internal-edge fix needs): a body behind an open
//! mesh (a terrain or a bowl whose winding faces away from it) passes through
//! it. A ball dropped into a bowl of the other winding fell through it without
//! a contact; so did everything dropped on a floor mesh facing down.

use nalgebra::{Isometry3, Point3};
use parry3d_f64::query::PointQueryWithLocation;
use parry3d_f64::shape::TrianglePointLocation;

use super::collider::Collider;

/// Whether the world point `p` lies behind mesh collider `c` at `pose`: its
/// nearest point on the mesh is inside a triangle whose front faces away from
/// it (beside the mesh, or nearest an edge, it is not behind any triangle).
pub fn behind(c: &Collider, pose: &Isometry3<f64>, p: &Point3<f64>) -> bool {
    let Some(mesh) = c.shape.as_trimesh() else { return false };
    let local = pose.inverse_transform_point(p);
    let Some((proj, (triangle, at))) = mesh.project_local_point_and_get_location_with_max_dist(&local, false, f64::MAX) else {
        return false;
    };
    let Some(normal) = mesh.triangle(triangle).normal() else { return false };
    matches!(at, TrianglePointLocation::OnFace(..)) && normal.dot(&(local - proj.point)) < 0.0
}
