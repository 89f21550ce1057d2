//! The arrays a user can write through views: which ones were handed out,
//! and copies of them compared and written back bitwise, for the step guard's
//! log (`guard`): what the user wrote between two `step` calls.

use super::World;

/// The arrays a user can write through views, one bit each. Only those the
/// user has been given a writable view of (or changed through a method) are
/// compared and logged: the others change only by stepping.
pub mod exposed {
    pub const POSITION: u16 = 1;
    pub const ORIENTATION: u16 = 2;
    pub const LINEAR_VELOCITY: u16 = 4;
    pub const ANGULAR_VELOCITY: u16 = 8;
    pub const FORCE: u16 = 16;
    pub const TORQUE: u16 = 32;
    pub const PARTICLE_POSITION: u16 = 64;
    pub const PARTICLE_VELOCITY: u16 = 128;
    pub const TARGET: u16 = 256;
    /// What a body or particle state is made of (not what acts on it).
    pub const STATE: u16 =
        POSITION | ORIENTATION | LINEAR_VELOCITY | ANGULAR_VELOCITY | PARTICLE_POSITION | PARTICLE_VELOCITY;
}

/// The memory of a slice of `f64` or of arrays of them.
trait Floats: Copy {}
impl Floats for f64 {}
impl<const N: usize> Floats for [f64; N] {}

/// Bitwise equality (`==` on floats would take -0.0 for 0.0 and never NaN for
/// NaN), as one memory compare.
fn same<T: Floats>(a: &[T], b: &[T]) -> bool {
    fn bytes<T: Floats>(v: &[T]) -> &[u8] {
        // Safety: `T` is f64 or an array of f64: no padding, every byte
        // initialised; the slice covers exactly the memory of `v`, borrowed
        // for as long.
        unsafe { std::slice::from_raw_parts(v.as_ptr() as *const u8, std::mem::size_of_val(v)) }
    }
    bytes(a) == bytes(b)
}

/// The view-writable arrays named by `mask`, as they were (the others empty).
#[derive(Clone, Debug, Default)]
pub(super) struct Inputs {
    mask: u16,
    position: Vec<[f64; 3]>,
    orientation: Vec<[f64; 4]>,
    linear_velocity: Vec<[f64; 3]>,
    angular_velocity: Vec<[f64; 3]>,
    force: Vec<[f64; 3]>,
    torque: Vec<[f64; 3]>,
    particle_position: Vec<[f64; 3]>,
    particle_velocity: Vec<[f64; 3]>,
    target: Vec<f64>,
}

/// `f(mask, bit, array of w, field of inputs)` for each view-writable array,
/// and-ed (every call is made).
macro_rules! each_input {
    ($f:ident, $mask:expr, $w:expr, $i:expr) => {{
        use exposed::*;
        let (mut no_position, mut no_velocity) = (Vec::new(), Vec::new());
        let (b, t) = (&mut $w.bodies, &mut $w.joint_target);
        let (pp, pv) = match $w.xpbd.as_mut() {
            Some(x) => (&mut x.particles.position, &mut x.particles.velocity),
            None => (&mut no_position, &mut no_velocity),
        };
        let m = $mask;
        $f(m, POSITION, &mut b.position, &mut $i.position)
            & $f(m, ORIENTATION, &mut b.orientation, &mut $i.orientation)
            & $f(m, LINEAR_VELOCITY, &mut b.linear_velocity, &mut $i.linear_velocity)
            & $f(m, ANGULAR_VELOCITY, &mut b.angular_velocity, &mut $i.angular_velocity)
            & $f(m, FORCE, &mut b.force, &mut $i.force)
            & $f(m, TORQUE, &mut b.torque, &mut $i.torque)
            & $f(m, PARTICLE_POSITION, pp, &mut $i.particle_position)
            & $f(m, PARTICLE_VELOCITY, pv, &mut $i.particle_velocity)
            & $f(m, TARGET, t, &mut $i.target)
    }};
}

fn copy_in<T: Floats>(mask: u16, bit: u16, world: &mut Vec<T>, kept: &mut Vec<T>) -> bool {
    if mask & bit != 0 {
        kept.clone_from(world);
    } else {
        kept.clear();
    }
    true
}

fn equal<T: Floats>(mask: u16, bit: u16, world: &[T], kept: &[T]) -> bool {
    mask & bit == 0 || same(world, kept)
}

fn put_back<T: Floats>(mask: u16, bit: u16, world: &mut [T], kept: &[T]) -> bool {
    if mask & bit != 0 {
        world.copy_from_slice(kept);
    }
    true
}

impl Inputs {
    /// Copies the arrays of `mask` from `w`.
    pub(super) fn read(&mut self, w: &mut World, mask: u16) {
        self.mask = mask;
        let _ = each_input!(copy_in, mask, w, self);
    }

    /// Whether `w`'s arrays of `mask` are bitwise these.
    pub(super) fn same_as(&mut self, w: &mut World, mask: u16) -> bool {
        self.mask == mask && each_input!(equal, mask, w, self)
    }

    /// Whether `w`'s arrays of `bits` are bitwise these (false if these do
    /// not hold them all).
    pub(super) fn same_in(&mut self, w: &mut World, bits: u16) -> bool {
        self.mask & bits == bits && each_input!(equal, bits, w, self)
    }

    /// Writes these values back (into the same memory: views stay valid).
    pub(super) fn write(&mut self, w: &mut World) {
        let _ = each_input!(put_back, self.mask, w, self);
    }

    pub(super) fn bytes(&self) -> usize {
        8 * (3 * (self.position.len() + self.linear_velocity.len() + self.angular_velocity.len() + self.force.len())
            + 3 * (self.torque.len() + self.particle_position.len() + self.particle_velocity.len())
            + 4 * self.orientation.len()
            + self.target.len())
    }
}
