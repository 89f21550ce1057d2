//! How much further a contact on a rounded surface closes in a substep than
//! its normal velocity says: the curvature of its separation in time.
//!
//! A rounded side's contact point is where the surface is nearest the other
//! body (see [`Rounding`](super::solver_body::Rounding)), not a material
//! point. A disk wobbling on its rim rolls that point around the rim: the
//! separation's rate is the material point's normal velocity (exact to first
//! order), but over the substep the nearest point moves on to rim that lies
//! lower, and the separation falls by `½ r sin α (φ̇ h)²` more than the rate
//! carries it (`φ̇` the point's angular speed along the rim). A velocity step
//! that holds the rate at zero leaves that much penetration each substep for
//! the soft push-out to undo at its slow rate: Euler's disk (r 0.2 m, tilted
//! 57°, 30 rad/s) sank 1.43 mm in 0.1 s, at 5 rad/s 7 mm in 0.5 s. Each pass
//! asks instead for the normal velocity that keeps the separation where the
//! rate would: `v_n + curve / h`, with `curve` the separation's second
//! difference over the substep (material anchor and rounded surface
//! together, so a cylinder rolling on its side, whose separation does not
//! change, gets none), the body turning at its angular velocity as the pass
//! finds it, changed by its free rotation's gyroscopic acceleration (without
//! that term the disk's rim still sank 0.84 mm in 0.1 s; at the angular
//! velocity of the substep's start, before the contact's impulses, 7 µm).

use super::contact::{Constraint, ContactSolver, Point};
use super::solver_body::{SolverBody, Surface};
use crate::math::{quat, Quat, Vec3};

/// Smallest curve taken, in rest depths (see `impulse::REST_DEPTH`): 10 nm
/// at the default slop. The separation's second difference holds the second
/// order of the body's whole turn at its current angular velocity, which the
/// contacts themselves change: a cylinder rolling on its side with a wobble
/// of 5e-4 rad/s got curves of ±2e-10 m at its two ends and rocked at 1e-7
/// m/s. Left out, a curve sinks a point by at most `curve / (h b)` (`b` the
/// push-out rate, 9 /s at the defaults): a third of a rest depth.
const MIN_CURVE: f64 = 0.01;

/// The curve (m) of point `p` of constraint `c` over a substep of `h` (s),
/// its bodies turning at `w1` and `w2` (rad/s): the second-order change of
/// its separation.
#[inline]
fn curve(bodies: &[SolverBody], c: &Constraint, p: &Point, (w1, w2): (&Vec3, &Vec3), h: f64) -> f64 {
    let (b1, b2) = (&bodies[c.s1 as usize], &bodies[c.s2 as usize]);
    b1.rounded_curve(p, (1, &c.normal), w1, h) + b2.rounded_curve(p, (2, &c.normal), w2, h)
}

/// Point `p`'s curve again, where it has one, at the angular velocities a
/// pass finds: `w`, or the solver bodies' own (`None`); substep `1 / inv_h`.
#[inline(always)]
pub(super) fn curve_now(bodies: &[SolverBody], c: &Constraint, p: &Point, w: Option<(&Vec3, &Vec3)>, inv_h: f64) -> f64 {
    if p.curve == 0.0 {
        return 0.0;
    }
    let own = || (&bodies[c.s1 as usize].w, &bodies[c.s2 as usize].w);
    curve(bodies, c, p, w.unwrap_or_else(own), 1.0 / inv_h)
}

impl SolverBody {
    /// The second-order change (m) over a substep of `h` (s), turning at `w`,
    /// of the part of point `p`'s separation that side `side` (1 or 2) of a
    /// contact of normal `n` contributes; 0 unless that side is rounded there.
    fn rounded_curve(&self, p: &Point, (side, n): (u8, &Vec3), w: &Vec3, h: f64) -> f64 {
        if self.surface != Surface::Rounded || p.corner == side {
            return 0.0;
        }
        let (anchor, sign) = if side == 1 { (&p.anchor1, -1.0) } else { (&p.anchor2, 1.0) };
        let alpha = self.gyroscopic(w);
        let u = self.rounding.across(n);
        let gap = |q: &Quat| u.map_or(0.0, |u| self.rounding.gap_change_across(&quat::rotate(&q.conjugate(), n), &u));
        let of = |q: Quat| sign * n.dot(&quat::rotate(&q, anchor)) + gap(&q);
        let at = |t: f64| of(quat::exp(&((w + alpha * (0.5 * t)) * t)) * self.dq);
        // Of a quadratic `a + b t + c t²`: `s(h) − 2 s(h/2) + s(0) = c h² / 2`.
        2.0 * (at(h) - 2.0 * at(0.5 * h) + of(self.dq))
    }

    /// The angular acceleration of its free rotation at angular velocity `w`,
    /// `−I⁻¹ (ω × I ω)` (rad/s², world frame): zero for an isotropic body.
    fn gyroscopic(&self, w: &Vec3) -> Vec3 {
        if self.iso.is_some() {
            return Vec3::zeros();
        }
        match self.inv_i.try_inverse() {
            Some(inertia) => -(self.inv_i * w.cross(&(inertia * w))),
            None => Vec3::zeros(),
        }
    }
}

impl ContactSolver {
    /// Every point's [`curve`](Point::curve) at the gathered velocities (in a
    /// step with a rounded body, before each velocity pass); the passes take it again at
    /// the velocities they find where it is not zero. A side whose bound
    /// ([`Spin::bound`]) is below the least curve taken is not evaluated: a
    /// body at rest costs a few products a point, not three rotations.
    pub(crate) fn set_curves(&mut self) {
        let h = 1.0 / self.inv_h;
        let least = MIN_CURVE * super::impulse::REST_DEPTH * self.settings.slop;
        let spins: Vec<Spin> = self.bodies.iter().map(|b| Spin::of(b, h)).collect();
        for c in &self.constraints {
            let (b1, b2) = (&self.bodies[c.s1 as usize], &self.bodies[c.s2 as usize]);
            if b1.surface != Surface::Rounded && b2.surface != Surface::Rounded {
                continue;
            }
            let (s1, s2) = (&spins[c.s1 as usize], &spins[c.s2 as usize]);
            for p in &mut self.points[c.start as usize..(c.start + c.len) as usize] {
                let bound = s1.bound(b1, p, (1, &c.normal)) + s2.bound(b2, p, (2, &c.normal));
                let k = if bound < least { 0.0 } else { curve(&self.bodies, c, p, (&b1.w, &b2.w), h) };
                p.curve = if k.abs() >= least { k } else { 0.0 };
            }
        }
    }
}

/// What bounds a rounded body's curves in a substep: see [`Spin::bound`].
struct Spin {
    /// `2 (Ω² + |α|) h²`, `Ω` the fastest turn in the substep (rad/s), `α`
    /// the gyroscopic acceleration (rad/s²); 0 for a body not rounded.
    scale: f64,
    /// Its fastest turn in the substep (rad).
    turn: f64,
    /// Its axis turned to now (zero for a capsule's).
    axis: Vec3,
}

impl Spin {
    fn of(b: &SolverBody, h: f64) -> Self {
        if b.surface != Surface::Rounded {
            return Spin { scale: 0.0, turn: 0.0, axis: Vec3::zeros() };
        }
        let alpha = b.gyroscopic(&b.w).norm();
        let fastest = b.w.norm() + alpha * h;
        let axis = if b.rounding.axis == Vec3::zeros() { Vec3::zeros() } else { quat::rotate(&b.dq, &b.rounding.axis) };
        Spin { scale: 2.0 * (fastest * fastest + alpha) * h * h, turn: fastest * h, axis }
    }

    /// An upper bound (m) on the magnitude of body `b`'s
    /// [`SolverBody::rounded_curve`] at point `p`: the second difference over
    /// `h` of a function is at most its second derivative times `h² / 4`,
    /// here `(Ω² + |α|)` times the lengths turned, the anchor and the radius
    /// over the rim's `(1 − t²)^{3/2}` (`t` the normal's part along the axis,
    /// kept above what the substep's turn can take it to; none where the
    /// normal meets a flat cap); taken ×8 for the rotation's coupling of rate
    /// and axis.
    #[inline]
    fn bound(&self, b: &SolverBody, p: &Point, (side, n): (u8, &Vec3)) -> f64 {
        if self.scale == 0.0 || p.corner == side {
            return 0.0;
        }
        let anchor = if side == 1 { p.anchor1.norm() } else { p.anchor2.norm() };
        let rim = if self.axis == Vec3::zeros() {
            1.0
        } else if b.rounding.across(n).is_none() {
            // A normal along the axis meets a flat cap: no rounded gap.
            0.0
        } else {
            let t = n.dot(&self.axis);
            let across = (1.0 - t * t - 2.0 * self.turn).max(0.5 * crate::collide::cylinder_cap::ACROSS_AXIS);
            1.0 + 1.0 / (across * across.sqrt())
        };
        self.scale * (anchor + b.rounding.radius * rim)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Mat3;
    use proptest::prelude::*;

    fn unit(v: [f64; 3]) -> Vec3 {
        let v = Vec3::from(v);
        if v.norm() < 1e-3 { Vec3::z() } else { v.normalize() }
    }

    proptest! {
        /// The bound that lets `set_curves` skip a side holds whatever the
        /// turn, the gyroscopic acceleration, the rim's tilt and the step.
        #[test]
        fn the_curve_bound_bounds_the_curve(
            w in prop::array::uniform3(-40.0f64..40.0),
            turned in prop::array::uniform3(-1.0f64..1.0),
            axis in prop::array::uniform3(-1.0f64..1.0),
            normal in prop::array::uniform3(-1.0f64..1.0),
            anchor in prop::array::uniform3(-0.3f64..0.3),
            inertia in prop::array::uniform3(0.2f64..5.0),
            capsule in any::<bool>(),
            radius in 0.01f64..0.5,
            substeps in 1u32..64,
        ) {
            let h = 1.0 / (60.0 * substeps as f64);
            let dq = quat::exp(&Vec3::from(turned));
            let rotation = quat::to_matrix(&dq);
            let body_inv = Mat3::from_diagonal(&Vec3::from(inertia).map(|x| 1.0 / x));
            let body = SolverBody {
                w: Vec3::from(w),
                dq,
                surface: Surface::Rounded,
                inv_i: rotation * body_inv * rotation.transpose(),
                rounding: super::super::solver_body::Rounding {
                    radius,
                    axis: if capsule { Vec3::zeros() } else { unit(axis) },
                },
                ..Default::default()
            };
            let n = unit(normal);
            let p = Point { anchor2: Vec3::from(anchor), ..Default::default() };
            let exact = body.rounded_curve(&p, (2, &n), &body.w, h).abs();
            let bound = Spin::of(&body, h).bound(&body, &p, (2, &n));
            prop_assert!(exact <= bound, "curve {exact:e} above its bound {bound:e}");
        }
    }
}
