//! Bodies that start behind a fixed or kinematic mesh they could touch (see
//! [`crate::collide::mesh_side`]): they will pass through it. Found when the
//! world is built, so that the user hears of it (a warning from Python) rather
//! than watching a body fall through a terrain whose triangles face down.

use super::World;
use crate::body::BodyKind;
use crate::collide::collider::body_pose;
use crate::collide::mesh_side::behind;
use nalgebra::Point3;

impl World {
    /// `(body, mesh body)` for each dynamic body whose centre lies behind a
    /// non-dynamic body's mesh that its collision filter lets it touch.
    pub fn behind_meshes(&self) -> Vec<(u32, u32)> {
        let Some(c) = self.collision.as_ref() else { return Vec::new() };
        let (cols, b) = (&c.colliders, &self.bodies);
        let meshes = cols.iter().filter(|m| m.shape.as_trimesh().is_some() && b.kind[m.body as usize] != BodyKind::Dynamic);
        let mut found = Vec::new();
        for m in meshes {
            let pose = body_pose(b, m.body as usize) * m.local;
            for d in cols.iter().filter(|d| b.kind[d.body as usize] == BodyKind::Dynamic && d.filter.allows(&m.filter)) {
                let centre = Point3::from(crate::math::Vec3::from(b.position[d.body as usize]));
                if behind(m.shape.as_ref(), &pose, &centre) {
                    found.push((d.body, m.body));
                }
            }
        }
        found
    }
}
