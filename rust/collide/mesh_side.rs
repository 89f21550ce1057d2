//! Which side of a fixed mesh a point is on. A mesh's triangles collide on
//! their front only, the side they run counter-clockwise from (parry's
//! oriented meshes, which the internal-edge fix needs): a body behind an open
//! mesh (a terrain or a bowl whose winding faces away from it) passes through
//! it. A ball dropped into a bowl of the other winding fell through it without
//! a contact; so did everything dropped on a floor mesh facing down.

use nalgebra::{Isometry3, Point3};
use parry3d_f64::query::PointQueryWithLocation;
use parry3d_f64::shape::{Shape, TrianglePointLocation};

/// Whether the world point `p` lies behind the mesh `shape` at `pose`: its
/// nearest point on the mesh is inside a triangle whose front faces away from
/// it (beside the mesh, or nearest an edge, it is not behind any triangle).
/// Any other shape has no behind.
pub fn behind(shape: &dyn Shape, pose: &Isometry3<f64>, p: &Point3<f64>) -> bool {
    let Some(mesh) = shape.as_trimesh() else { return false };
    let local = pose.inverse_transform_point(p);
    let Some((proj, (triangle, at))) = mesh.project_local_point_and_get_location_with_max_dist(&local, false, f64::MAX) else {
        return false;
    };
    let Some(normal) = mesh.triangle(triangle).normal() else { return false };
    matches!(at, TrianglePointLocation::OnFace(..)) && normal.dot(&(local - proj.point)) < 0.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use parry3d_f64::shape::TriMesh;

    /// Two triangles making the square [-1, 1]² in z = 0, facing +z (`up`) or −z.
    fn square(up: bool) -> TriMesh {
        let v = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]].map(Point3::from);
        let t = if up { vec![[0, 1, 2], [0, 2, 3]] } else { vec![[0, 2, 1], [0, 3, 2]] };
        TriMesh::new(v.to_vec(), t).unwrap()
    }

    #[test]
    fn a_point_is_behind_a_mesh_only_over_its_back() {
        let at = |x: f64, z: f64| Point3::new(x, 0.3, z);
        let (up, down) = (square(true), square(false));
        let moved = Isometry3::translation(0.0, 0.0, 2.0);
        assert!(!behind(&up, &Isometry3::identity(), &at(0.2, 0.5)));
        assert!(behind(&up, &Isometry3::identity(), &at(0.2, -0.5)));
        assert!(behind(&down, &Isometry3::identity(), &at(0.2, 0.5)));
        // Beside the mesh its nearest point is on an edge: not behind it.
        assert!(!behind(&down, &Isometry3::identity(), &at(3.0, 0.5)));
        // The mesh's pose counts: lifted 2 m, a point at 0.5 m is below it.
        assert!(behind(&up, &moved, &at(0.2, 0.5)));
        let ball = parry3d_f64::shape::Ball::new(1.0);
        assert!(!behind(&ball, &Isometry3::identity(), &at(0.0, 0.0)));
    }
}
