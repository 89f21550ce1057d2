//! A step never reads what another thread writes through a view while it runs.
//!
//! `World.step` releases the GIL, and NumPy views write straight into the
//! world's arrays: a thread writing a NaN into `bodies.position` mid-step would
//! have it consumed by that step (and blamed on the engine). So, with the GIL
//! held, the arrays the user holds writable views of are set aside before the
//! steps (the views keep their memory; the steps run on copies swapped in) and
//! swapped back after, taking the steps' results element by element except
//! where a view was written meanwhile: such a write is kept, as if made after
//! the call, and `step`'s check of its inputs validates it before any step uses
//! it (a NaN there raises `StateError` naming the body at the next call). Cost
//! per call: three copies and one bitwise compare of those arrays (+6 % on
//! `step(1)` calls of 1000 free bodies holding all four state views, 11 µs a
//! call, wall clock), nothing for arrays no writable view was taken of.
//! (Clearing NumPy's WRITEABLE flag of the views for the call would cost
//! nothing, but slices taken of a view before the call keep their own flag
//! and would still write into the running step.)

use crate::world::guard::exposed::*;
use crate::world::World;

/// The memory of one view-writable array while the steps run on a copy, and
/// its values when they started.
#[derive(Default)]
struct Aside<T> {
    held: bool,
    memory: Vec<T>,
    before: Vec<T>,
}

/// The bytes of `v`.
fn bytes<T: Copy>(v: &[T]) -> &[u8] {
    // Safety: `T` is f64 or an array of f64 (no padding, every byte
    // initialised); the slice covers exactly the memory of `v`, borrowed as long.
    unsafe { std::slice::from_raw_parts(v.as_ptr() as *const u8, std::mem::size_of_val(v)) }
}

/// Whether `a` and `b` hold the same bits (floats: NaN equals NaN, -0 ≠ 0),
/// as one memory compare.
fn same<T: Copy>(a: &[T], b: &[T]) -> bool {
    bytes(a) == bytes(b)
}

/// `dst = src`, one memory copy (no allocation once `dst` has grown).
fn copy<T: Copy>(dst: &mut Vec<T>, src: &[T]) {
    dst.clear();
    dst.extend_from_slice(src);
}

impl<T: Copy> Aside<T> {
    /// GIL held: the steps will run on a copy of `live`; its memory (the
    /// views') is kept here.
    fn enter(&mut self, live: &mut Vec<T>) {
        copy(&mut self.before, live);
        copy(&mut self.memory, live);
        std::mem::swap(live, &mut self.memory);
        self.held = true;
    }

    /// GIL held: the views' memory goes back into the world with the steps'
    /// results, but where a view was written during the steps. Whether one was.
    fn leave(&mut self, live: &mut Vec<T>) -> bool {
        if !std::mem::take(&mut self.held) {
            return false;
        }
        std::mem::swap(live, &mut self.memory);
        if live.len() != self.memory.len() || live.len() != self.before.len() {
            return false; // cannot happen: a step never resizes these arrays
        }
        if same(live, &self.before) {
            live.copy_from_slice(&self.memory);
            return false;
        }
        for ((view, result), before) in live.iter_mut().zip(&self.memory).zip(&self.before) {
            if same(std::slice::from_ref(view), std::slice::from_ref(before)) {
                *view = *result;
            }
        }
        true
    }
}

/// The view-writable arrays set aside for one `step` call.
#[derive(Default)]
pub struct Shadow {
    position: Aside<[f64; 3]>,
    orientation: Aside<[f64; 4]>,
    linear_velocity: Aside<[f64; 3]>,
    angular_velocity: Aside<[f64; 3]>,
    force: Aside<[f64; 3]>,
    torque: Aside<[f64; 3]>,
    particle_position: Aside<[f64; 3]>,
    particle_velocity: Aside<[f64; 3]>,
    target: Aside<f64>,
}

impl Shadow {
    /// Before the GIL is released: sets aside the arrays of `mask` (the
    /// guard's `exposed` bits).
    pub fn enter(&mut self, w: &mut World, mask: u16) {
        let b = &mut w.bodies;
        let on = |bit: u16| mask & bit != 0;
        if on(POSITION) {
            self.position.enter(&mut b.position);
        }
        if on(ORIENTATION) {
            self.orientation.enter(&mut b.orientation);
        }
        if on(LINEAR_VELOCITY) {
            self.linear_velocity.enter(&mut b.linear_velocity);
        }
        if on(ANGULAR_VELOCITY) {
            self.angular_velocity.enter(&mut b.angular_velocity);
        }
        if on(FORCE) {
            self.force.enter(&mut b.force);
        }
        if on(TORQUE) {
            self.torque.enter(&mut b.torque);
        }
        if on(TARGET) {
            self.target.enter(&mut w.joint_target);
        }
        if let Some(x) = w.xpbd.as_mut() {
            if on(PARTICLE_POSITION) {
                self.particle_position.enter(&mut x.particles.position);
            }
            if on(PARTICLE_VELOCITY) {
                self.particle_velocity.enter(&mut x.particles.velocity);
            }
        }
    }

    /// With the GIL again: the views' memory back in the world, with the
    /// steps' results. Whether a view was written during the steps.
    pub fn leave(&mut self, w: &mut World) -> bool {
        let b = &mut w.bodies;
        let mut written = self.position.leave(&mut b.position);
        written |= self.orientation.leave(&mut b.orientation);
        written |= self.linear_velocity.leave(&mut b.linear_velocity);
        written |= self.angular_velocity.leave(&mut b.angular_velocity);
        written |= self.force.leave(&mut b.force);
        written |= self.torque.leave(&mut b.torque);
        written |= self.target.leave(&mut w.joint_target);
        if let Some(x) = w.xpbd.as_mut() {
            written |= self.particle_position.leave(&mut x.particles.position);
            written |= self.particle_velocity.leave(&mut x.particles.velocity);
        }
        written
    }
}
