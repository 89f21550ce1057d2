//! Snapshots: a world is its own snapshot (`Clone` copies every bit a step
//! reads: state, applied forces, time, manifolds and warm starts, friction
//! patches, islands and sleep timers, multipliers, articulation state, plastic
//! rest shapes, caches). Restoring copies one back into a live world.

use super::World;
use crate::xpbd::particles::Particles;
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

/// The particles' viewed arrays of `old` take the values of `new`'s, which
/// take their memory (`XpbdModel`'s `clone_from` makes new arrays).
fn keep_particle_memory(old: &mut Particles, new: &mut Particles) {
    keep(&mut old.position, &mut new.position);
    keep(&mut old.velocity, &mut new.velocity);
    keep(&mut old.inv_mass, &mut new.inv_mass);
    keep(&mut old.mass, &mut new.mass);
    keep(&mut old.radius, &mut new.radius);
}

/// The address and length of every array a NumPy view can point into.
pub(crate) fn view_arrays(w: &World) -> Vec<(usize, usize)> {
    fn at<T>(v: &[T]) -> (usize, usize) {
        (v.as_ptr() as usize, v.len())
    }
    let b = &w.bodies;
    let mut a = vec![at(&b.position), at(&b.orientation), at(&b.linear_velocity), at(&b.angular_velocity)];
    a.extend([at(&b.force), at(&b.torque), at(&b.mass), at(&b.inv_mass), at(&b.inertia), at(&b.inv_inertia)]);
    a.extend([at(&b.sleeping), at(&b.rotation), at(&b.angular_momentum), at(&b.inertia_world)]);
    a.extend([at(&w.joint_position), at(&w.joint_velocity), at(&w.joint_target), at(&w.joint_force)]);
    if let Some(x) = &w.xpbd {
        let p = &x.particles;
        a.extend([at(&p.position), at(&p.velocity), at(&p.inv_mass), at(&p.mass), at(&p.radius)]);
    }
    a
}

impl World {
    /// Makes this world `snap` again, bit for bit (but for the stage timings,
    /// which carry on). `snap` must have the same
    /// numbers of bodies, particles and joints (a snapshot of this world, or of
    /// one built from the same scene); otherwise nothing changes.
    pub fn restore(&mut self, snap: &World) -> Result<()> {
        let (have, got) = (layout(self), layout(snap));
        let lengths = |w: &World| view_arrays(w).into_iter().map(|(_, n)| n).collect::<Vec<_>>();
        if have != got || lengths(self) != lengths(snap) {
            return Err(Error::input(format!(
                "snapshot has {} bodies, {} particles and {} joints, this world {}, {} and {}: \
                 restore a snapshot of this world (or of one built from the same scene)",
                got.0, got.1, got.2, have.0, have.1, have.2
            )));
        }
        // Copied into this world's own arrays (see `crate::clone_in_place`),
        // so the bodies' and joints' views stay valid (a `Vec` of the same
        // length is copied without reallocating): a fresh clone cost a
        // million bodies' world a gigabyte of new pages. The particles'
        // arrays are kept by hand (their model's `clone_from` makes new ones).
        let mut particles = self.xpbd.as_mut().map(|x| std::mem::take(&mut x.particles));
        // Stage timings are this world's, not state: they carry on, and the
        // restored plan's stages take their slots in them.
        let profile = std::mem::take(&mut self.profile);
        #[cfg(test)]
        let fail_at = self.fail_at;
        self.clone_from(snap);
        if let (Some(old), Some(x)) = (particles.as_mut(), self.xpbd.as_mut()) {
            keep_particle_memory(old, &mut x.particles);
        }
        #[cfg(test)]
        {
            self.fail_at = fail_at;
        }
        self.profile = profile;
        self.plan.assign_slots(&mut self.profile);
        Ok(())
    }
}
