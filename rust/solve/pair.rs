//! The two bodies of a constraint, loaded from the solver bodies into
//! registers while its points and patch are solved, and stored back.

use super::contact::{Constraint, Point};
use super::friction::Patch;
use super::solver_body::SolverBody;
use crate::math::Vec3;

/// The two bodies of a constraint, held in registers while its points are solved.
/// Each vector padded to 32 bytes: spilled packed, the compiler wrote `v1.z`
/// and `w1.x` as one 16-byte store and read `w1.xy` back across two, a
/// store-forwarding stall that was 17 % of the ball pit's velocity passes
/// (2 % of its step).
#[repr(C)]
pub struct Pair {
    pub v1: Vec3,
    pad1: f64,
    pub w1: Vec3,
    pad2: f64,
    pub v2: Vec3,
    pad3: f64,
    pub w2: Vec3,
    pad4: f64,
    m1: f64,
    m2: f64,
}

impl Pair {
    #[inline(always)]
    pub fn load(bodies: &[SolverBody], c: &Constraint) -> Self {
        let (a, b) = (&bodies[c.s1 as usize], &bodies[c.s2 as usize]);
        Self {
            v1: a.v,
            pad1: 0.0,
            w1: a.w,
            pad2: 0.0,
            v2: b.v,
            pad3: 0.0,
            w2: b.w,
            pad4: 0.0,
            m1: a.inv_m,
            m2: b.inv_m,
        }
    }

    /// Writes the velocities back. The fixed bodies' entry 0 is left alone:
    /// its zero velocities come back unchanged (no inverse mass or inertia),
    /// and the groups passed over in parallel (see `super::contact_groups`)
    /// all touch it.
    #[inline(always)]
    pub fn store(&self, bodies: &mut [SolverBody], c: &Constraint) {
        if c.s1 != 0 {
            let a = &mut bodies[c.s1 as usize];
            a.v = self.v1;
            a.w = self.w1;
        }
        if c.s2 != 0 {
            let b = &mut bodies[c.s2 as usize];
            b.v = self.v2;
            b.w = self.w2;
        }
    }

    /// Point `p`'s [`curve`](Point::curve) at the pair's angular velocities,
    /// where it has one (substep `1 / inv_h`).
    #[inline(always)]
    pub fn curve(&self, bodies: &[SolverBody], c: &Constraint, p: &Point, inv_h: f64) -> f64 {
        super::rounded_curve::curve_now(bodies, c, p, Some((&self.w1, &self.w2)), inv_h)
    }

    #[inline(always)]
    pub fn normal_velocity(&self, c: &Constraint, p: &Point) -> f64 {
        c.normal.dot(&(self.v2 - self.v1)) + self.w2.dot(&p.rn2) - self.w1.dot(&p.rn1)
    }

    /// Change of point `a`'s normal velocity per unit normal impulse at point
    /// `b` of the same constraint (m/s per N·s): an entry of `K`.
    #[inline(always)]
    pub fn coupling(&self, a: &Point, b: &Point) -> f64 {
        self.m1 + self.m2 + a.rn1.dot(&b.irn1) + a.rn2.dot(&b.irn2)
    }

    #[inline(always)]
    pub fn apply_normal(&mut self, c: &Constraint, p: &Point, j: f64) {
        self.v1 -= c.normal * (j * self.m1);
        self.w1 -= p.irn1 * j;
        self.v2 += c.normal * (j * self.m2);
        self.w2 += p.irn2 * j;
    }

    /// [`Self::apply_normal`] for a [`Constraint::central`] point (its arms
    /// across the normal are zero).
    #[inline(always)]
    pub fn apply_central(&mut self, c: &Constraint, j: f64) {
        self.v1 -= c.normal * (j * self.m1);
        self.v2 += c.normal * (j * self.m2);
    }

    /// Tangential velocity of body 2 relative to body 1 at a patch's centre (m/s).
    #[inline(always)]
    pub fn patch_velocity(&self, c: &Constraint, f: &Patch) -> [f64; 2] {
        let dv = self.v2 - self.v1;
        [
            c.t1.dot(&dv) + self.w2.dot(&f.rt2[0]) - self.w1.dot(&f.rt1[0]),
            c.t2.dot(&dv) + self.w2.dot(&f.rt2[1]) - self.w1.dot(&f.rt1[1]),
        ]
    }

    /// Relative angular velocity about the normal (rad/s).
    #[inline(always)]
    pub fn twist_velocity(&self, c: &Constraint) -> f64 {
        c.normal.dot(&(self.w2 - self.w1))
    }

    /// A tangential impulse `d` (N·s, in the `t1, t2` basis) at a patch's centre.
    #[inline(always)]
    pub fn apply_patch(&mut self, c: &Constraint, f: &Patch, d: [f64; 2]) {
        let imp = c.t1 * d[0] + c.t2 * d[1];
        self.v1 -= imp * self.m1;
        self.w1 -= f.irt1[0] * d[0] + f.irt1[1] * d[1];
        self.v2 += imp * self.m2;
        self.w2 += f.irt2[0] * d[0] + f.irt2[1] * d[1];
    }

    /// An angular impulse `j` (N·m·s) about the normal.
    #[inline(always)]
    pub fn apply_twist(&mut self, f: &Patch, j: f64) {
        self.w1 -= f.in1 * j;
        self.w2 += f.in2 * j;
    }
}
