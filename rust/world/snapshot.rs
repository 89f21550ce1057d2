//! Snapshots: a world is its own snapshot (`Clone` copies every bit a step
//! reads: state, applied forces, time, manifolds and warm starts, friction
//! patches, islands and sleep timers, multipliers, articulation state, plastic
//! rest shapes, caches). Restoring copies one back into a live world.

use super::World;
use crate::error::{Error, Result};

/// Counts that fix the length of the arrays NumPy views show: bodies,
/// particles, joints.
fn layout(w: &World) -> (usize, usize, usize) {
    (w.bodies.len(), w.particles().map_or(0, |p| p.len()), w.joint_position.len())
}

/// `old` takes `new`'s values in its own memory, and `new` takes that memory:
/// views into `old` stay valid and show the restored values.
fn keep<T: Copy>(old: &mut Vec<T>, new: &mut Vec<T>) {
    old.copy_from_slice(new);
    std::mem::swap(old, new);
}

/// Moves the memory of every array a view can point into from `old` to `new`
/// (same layout), after copying `new`'s values into it.
fn keep_view_memory(old: &mut World, new: &mut World) {
    let (a, b) = (&mut old.bodies, &mut new.bodies);
    keep(&mut a.position, &mut b.position);
    keep(&mut a.orientation, &mut b.orientation);
    keep(&mut a.linear_velocity, &mut b.linear_velocity);
    keep(&mut a.angular_velocity, &mut b.angular_velocity);
    keep(&mut a.force, &mut b.force);
    keep(&mut a.torque, &mut b.torque);
    keep(&mut a.mass, &mut b.mass);
    keep(&mut a.inv_mass, &mut b.inv_mass);
    keep(&mut a.inertia, &mut b.inertia);
    keep(&mut a.inv_inertia, &mut b.inv_inertia);
    keep(&mut a.sleeping, &mut b.sleeping);
    keep(&mut a.rotation, &mut b.rotation);
    keep(&mut a.angular_momentum, &mut b.angular_momentum);
    keep(&mut a.inertia_world, &mut b.inertia_world);
    if let (Some(x), Some(y)) = (old.xpbd.as_mut(), new.xpbd.as_mut()) {
        let (p, q) = (&mut x.particles, &mut y.particles);
        keep(&mut p.position, &mut q.position);
        keep(&mut p.velocity, &mut q.velocity);
        keep(&mut p.inv_mass, &mut q.inv_mass);
        keep(&mut p.mass, &mut q.mass);
        keep(&mut p.radius, &mut q.radius);
    }
    keep(&mut old.joint_position, &mut new.joint_position);
    keep(&mut old.joint_velocity, &mut new.joint_velocity);
    keep(&mut old.joint_target, &mut new.joint_target);
    keep(&mut old.joint_force, &mut new.joint_force);
    #[cfg(test)]
    {
        new.fail_at = old.fail_at;
    }
}

impl World {
    /// Makes this world `snap` again, bit for bit (but for the stage timings,
    /// which carry on). `snap` must have the same
    /// numbers of bodies, particles and joints (a snapshot of this world, or of
    /// one built from the same scene); otherwise nothing changes.
    pub fn restore(&mut self, snap: &World) -> Result<()> {
        let (have, got) = (layout(self), layout(snap));
        if have != got {
            return Err(Error::input(format!(
                "snapshot has {} bodies, {} particles and {} joints, this world {}, {} and {}: \
                 restore a snapshot of this world (or of one built from the same scene)",
                got.0, got.1, got.2, have.0, have.1, have.2
            )));
        }
        let mut next = snap.clone();
        keep_view_memory(self, &mut next);
        // Stage timings are this world's, not state: they carry on, and the
        // restored plan's stages take their slots in them.
        next.profile = std::mem::take(&mut self.profile);
        next.plan.assign_slots(&mut next.profile);
        *self = next;
        Ok(())
    }
}
