//! Joints in the scene and the world: `Scene::add_joint` validates and compiles a
//! [`JointSpec`]; the world's `joints` stage projects them each substep (see
//! [`crate::xpbd::joints`] and, for where the stage sits in a substep,
//! [`super::pipeline`]); the forces they applied are read back per joint.

use super::{Scene, World};
use crate::error::Result;
use crate::xpbd::joints::{Joint, JointSpec};

impl Scene {
    /// Validates `spec` against the bodies added so far and adds the joint;
    /// returns its index. On error (naming the joint and the field) the scene is
    /// unchanged.
    pub fn add_joint(&mut self, spec: JointSpec) -> Result<usize> {
        let index = self.joints.len();
        let bodies = self.bodies();
        let joint = spec.compile(bodies.len(), |i| &bodies[i].init).map_err(|e| e.context(format!("joint {index}")))?;
        self.joints.push(joint);
        Ok(index)
    }

    pub fn joints(&self) -> &[Joint] {
        &self.joints
    }
}

impl World {
    /// The `joints` stage: one substep's projection of every joint.
    pub(crate) fn project_joints(&mut self, h: f64) {
        self.joints.project(&mut self.bodies, h, self.settings.iterations);
    }

    /// Force (N, world) each joint applied to its body a over the last substep;
    /// body b received the opposite.
    pub fn joint_forces(&self) -> &[[f64; 3]] {
        &self.joints.force
    }

    /// Couple (N·m, world) each joint's angular constraints applied to body a
    /// over the last substep: with the force, the wrench about a's anchor.
    pub fn joint_torques(&self) -> &[[f64; 3]] {
        &self.joints.torque
    }

    /// Body pairs tied by a joint, smaller index first (the world left out).
    pub(crate) fn joint_pairs(scene: &Scene) -> Vec<(u32, u32)> {
        let mut pairs: Vec<(u32, u32)> =
            scene.joints().iter().filter_map(|j| j.body_b.map(|b| (j.body_a.min(b), j.body_a.max(b)))).collect();
        pairs.sort_unstable();
        pairs.dedup();
        pairs
    }
}

/// Whether bodies `a` and `b` are tied by a joint (`pairs` sorted, smaller first).
pub(crate) fn jointed(pairs: &[(u32, u32)], a: u32, b: u32) -> bool {
    !pairs.is_empty() && pairs.binary_search(&(a.min(b), a.max(b))).is_ok()
}

/// Beyond this many colliders the exact search below is skipped (it is O(n²) in
/// the worst case) and the collision stages stay.
const EXACT_SEARCH_LIMIT: usize = 2000;

/// Whether some pair of colliders that filters, kinds and shapes let touch is not
/// tied by a joint: a pendulum or a chain whose only possible contacts are
/// between jointed bodies needs no collision stage at all. Called after the
/// cheaper per-filter test said some pair can touch.
pub(crate) fn some_pair_unjointed(
    cols: &[crate::collide::Collider],
    kinds: &[crate::body::BodyKind],
    pairs: &[(u32, u32)],
) -> bool {
    if pairs.is_empty() || cols.len() > EXACT_SEARCH_LIMIT {
        return true;
    }
    let movable = |c: &crate::collide::Collider| kinds[c.body as usize] != crate::body::BodyKind::Fixed;
    cols.iter().enumerate().any(|(k, ci)| {
        cols[k + 1..].iter().any(|cj| {
            ci.body != cj.body
                && ci.filter.allows(&cj.filter)
                && (movable(ci) || movable(cj))
                && !(ci.infinite && cj.infinite)
                && !jointed(pairs, ci.body, cj.body)
        })
    })
}
