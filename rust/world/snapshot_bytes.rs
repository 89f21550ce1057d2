//! A world as bytes: every field serialized (postcard) inside a checked frame
//! (see `framing`); decoding checks the frame, then that the arrays agree in
//! length, so that no step of a loaded world indexes out of bounds.

use super::framing::{frame, unframe, WORLD};
use super::profile::Profile;
use super::World;
use crate::error::{Error, Result};

impl World {
    pub fn to_bytes(&self) -> Result<Vec<u8>> {
        let payload = postcard::to_stdvec(self).map_err(|e| Error::input(format!("world could not be encoded: {e}")))?;
        Ok(frame(WORLD, &payload))
    }

    pub fn from_bytes(data: &[u8]) -> Result<World> {
        let payload = unframe(WORLD, data)?;
        let (mut w, rest): (World, &[u8]) = postcard::take_from_bytes(payload)
            .map_err(|e| Error::input(format!("world snapshot data could not be decoded ({e}): it was not written by this build of rigidrs")))?;
        if !rest.is_empty() {
            return Err(Error::input(format!("world snapshot data has {} bytes after the world", rest.len())));
        }
        w.check_lengths()?;
        // The profile is not saved; the plan's stages take slots in a new one.
        w.profile = Profile::default();
        w.plan.assign_slots(&mut w.profile);
        Ok(w)
    }

    /// Whether every per-body, per-particle and per-joint array has the length
    /// of the others, and every body index is in range.
    fn check_lengths(&self) -> Result<()> {
        let b = &self.bodies;
        let n = b.len();
        let body_lens = [
            b.orientation.len(), b.linear_velocity.len(), b.angular_velocity.len(), b.force.len(), b.torque.len(),
            b.mass.len(), b.inv_mass.len(), b.inertia.len(), b.inv_inertia.len(), b.kind.len(), b.sleeping.len(),
            b.rotation.len(), b.angular_momentum.len(), b.inertia_world.len(), self.shapes.len(),
            self.articulated_body.len(), self.body_names.len(),
        ];
        let j = self.joint_position.len();
        let joint_lens = [self.joint_velocity.len(), self.joint_target.len(), self.joint_force.len(), self.joint_names.len()];
        let particles_ok = self.particles().is_none_or(|p| {
            let m = p.len();
            [p.velocity.len(), p.inv_mass.len(), p.mass.len(), p.radius.len(), p.friction.len(), p.filter.len(), p.prev.len(), p.initial.len()]
                .iter()
                .all(|&l| l == m)
        });
        let colliders_ok = self.collision.as_ref().is_none_or(|c| c.colliders.iter().all(|k| (k.body as usize) < n));
        if body_lens.iter().any(|&l| l != n) || joint_lens.iter().any(|&l| l != j) || !particles_ok || !colliders_ok {
            return Err(Error::input("world snapshot data is inconsistent (arrays of different lengths): it was not written by this build of rigidrs"));
        }
        Ok(())
    }
}
