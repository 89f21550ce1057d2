//! The two corrections every joint is built from (Müller et al. 2020, §3.3):
//! a positional one that closes a gap between two attachment points, and an
//! angular one that removes a relative rotation. Both are XPBD updates of one
//! Lagrange multiplier with compliance `α` (`α̃ = α / h²`):
//!
//! `Δλ = (−c − α̃ λ) / (w_a + w_b + α̃)`, `λ += Δλ`, impulse `p = Δλ n`,
//!
//! with `c n` the violation and the generalised inverse masses
//! `w = 1/m + (r × n)ᵀ I⁻¹ (r × n)` (positional, attachment at `r` from the centre
//! of mass) or `w = nᵀ I⁻¹ n` (angular), `I⁻¹` in the world frame. Body a moves by
//! `+p`, body b by `−p`. Each body's velocities get the same correction divided by
//! `h` (`v += Δx/h`, `ω += Δθ/h`), so the drift's own motion (the integrators'
//! exact free rotation) is kept and only the constraint's part is added.
//! The three-dimensional constraints (two points together, a kept orientation)
//! use the block form of the same update, in [`super::block`].

use crate::body::Bodies;
use crate::math::{quat, Mat3, Quat, Vec3};

/// The two ends of one joint during a projection, and its multipliers.
pub struct Pair<'s> {
    pub bodies: &'s mut Bodies,
    /// Body a (always a body) and body b (`None`: the world).
    pub a: usize,
    pub b: Option<usize>,
    /// Substep (s).
    pub h: f64,
    pub state: &'s mut Multipliers,
}

/// What a joint accumulates over one substep (reset at its start).
#[derive(Clone, Copy, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Multipliers {
    /// λ of each of the joint's scalar constraints (N·s² for positions, N·m·s²
    /// for angles).
    pub lambda: [f64; 3],
    /// λ of the attachment of two points (vector, N·s²).
    pub point: Vec3,
    /// λ of a kept relative orientation (vector, N·m·s²).
    pub turn: Vec3,
    /// Sum of `Δλ n` of the positional corrections on body a (N·s²): the joint's
    /// force on a is this over `h²`.
    pub linear: Vec3,
    /// Sum of `Δλ n` of the angular corrections on body a (N·m·s²): the couple on
    /// a is this over `h²`.
    pub angular: Vec3,
}

/// Pose of one end: centre of mass (m), orientation, whether it moves, inverse mass.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct Pose {
    pub x: Vec3,
    pub q: Quat,
    pub inv_mass: f64,
    pub moves: bool,
}

impl Pose {
    /// A point given in this end's frame, as an offset from its centre (world).
    pub fn offset(&self, local: &Vec3) -> Vec3 {
        quat::rotate(&self.q, local)
    }
    pub fn point(&self, local: &Vec3) -> Vec3 {
        self.x + self.offset(local)
    }
}

/// Pose of body `i` (or the world): only an awake dynamic body moves.
pub fn pose(b: &Bodies, i: Option<usize>) -> Pose {
    match i {
        None => Pose { x: Vec3::zeros(), q: Quat::identity(), inv_mass: 0.0, moves: false },
        Some(i) => {
            let moves = b.awake(i);
            Pose { x: Vec3::from(b.position[i]), q: b.q(i), inv_mass: if moves { b.inv_mass[i] } else { 0.0 }, moves }
        }
    }
}

impl Pair<'_> {
    pub fn pose_a(&self) -> Pose {
        pose(self.bodies, Some(self.a))
    }
    pub fn pose_b(&self) -> Pose {
        pose(self.bodies, self.b)
    }

    /// Closes `violation` = (point on a) − (point on b) (world, m), the points at
    /// offsets `r_a`, `r_b` from the centres, with multiplier `slot` and
    /// compliance `alpha` (m/N).
    pub fn positional(&mut self, slot: usize, r_a: &Vec3, r_b: &Vec3, violation: &Vec3, alpha: f64) {
        let c = violation.norm();
        if c == 0.0 || c.is_nan() {
            return;
        }
        let n = violation / c;
        let (pa, pb) = (self.pose_a(), self.pose_b());
        let rn_a = r_a.cross(&n);
        let w = pa.inv_mass + rn_a.dot(&(self.inverse_inertia(self.a, &pa) * rn_a))
            + self.end_b(|s, i| {
                let rn = r_b.cross(&n);
                pb.inv_mass + rn.dot(&(s.inverse_inertia(i, &pb) * rn))
            });
        if let Some(d) = self.multiplier(slot, c, w, alpha) {
            self.push(&pa, &pb, r_a, r_b, &(n * d));
        }
    }

    /// Removes `violation`, the rotation vector (world, rad) by which body a is
    /// turned away from where the constraint wants it relative to b, with
    /// multiplier `slot` and compliance `alpha` (rad/(N·m)).
    pub fn angular(&mut self, slot: usize, violation: &Vec3, alpha: f64) {
        let c = violation.norm();
        if c == 0.0 || c.is_nan() {
            return;
        }
        let n = violation / c;
        let (pa, pb) = (self.pose_a(), self.pose_b());
        let w = n.dot(&(self.inverse_inertia(self.a, &pa) * n)) + self.end_b(|s, i| n.dot(&(s.inverse_inertia(i, &pb) * n)));
        if let Some(d) = self.multiplier(slot, c, w, alpha) {
            self.twist(&pa, &pb, &(n * d));
        }
    }

    /// Applies `p` (`Δλ n`, N·s²) at the points `r_a` (to a) and `r_b` (−p, to b).
    pub(super) fn push(&mut self, pa: &Pose, pb: &Pose, r_a: &Vec3, r_b: &Vec3, p: &Vec3) {
        self.state.linear += p;
        let turn_a = self.inverse_inertia(self.a, pa) * r_a.cross(p);
        self.displace(Some(self.a), pa, &(p * pa.inv_mass), &turn_a);
        let turn_b = self.end_b(|s, i| s.inverse_inertia(i, pb) * r_b.cross(p));
        self.displace(self.b, pb, &(-p * pb.inv_mass), &-turn_b);
    }

    /// Applies the couple `p` (N·m·s²) to a and `−p` to b.
    pub(super) fn twist(&mut self, pa: &Pose, pb: &Pose, p: &Vec3) {
        self.state.angular += p;
        let turn_a = self.inverse_inertia(self.a, pa) * p;
        self.displace(Some(self.a), pa, &Vec3::zeros(), &turn_a);
        let turn_b = self.end_b(|s, i| s.inverse_inertia(i, pb) * p);
        self.displace(self.b, pb, &Vec3::zeros(), &-turn_b);
    }

    /// World-frame `I⁻¹` of an end, zero if it does not move.
    pub(super) fn inverse_inertia(&self, i: usize, p: &Pose) -> Mat3 {
        if !p.moves {
            return Mat3::zeros();
        }
        let rot = quat::to_matrix(&p.q);
        rot * Mat3::from_diagonal(&Vec3::from(self.bodies.inv_inertia[i])) * rot.transpose()
    }

    /// `Δλ` for violation `c`, total inverse mass `w`, compliance `alpha`; `None`
    /// when nothing can move.
    fn multiplier(&mut self, slot: usize, c: f64, w: f64, alpha: f64) -> Option<f64> {
        let alpha_t = alpha / (self.h * self.h);
        let denom = w + alpha_t;
        if denom.is_nan() || denom <= 0.0 {
            return None;
        }
        let lambda = &mut self.state.lambda[slot];
        let d = (-c - alpha_t * *lambda) / denom;
        *lambda += d;
        Some(d)
    }

    /// `f(self, i)` for body b if it is a body, else 0.
    pub(super) fn end_b<T: Default>(&self, f: impl Fn(&Self, usize) -> T) -> T {
        self.b.map_or_else(T::default, |i| f(self, i))
    }

    /// Moves an end by `dx` (m) and turns it by `dtheta` (rad), and adds `dx/h`,
    /// `dtheta/h` to its velocities.
    fn displace(&mut self, i: Option<usize>, p: &Pose, dx: &Vec3, dtheta: &Vec3) {
        let Some(i) = i else { return };
        if !p.moves {
            return;
        }
        let (b, inv_h) = (&mut *self.bodies, 1.0 / self.h);
        b.position[i] = (Vec3::from(b.position[i]) + dx).into();
        b.linear_velocity[i] = (Vec3::from(b.linear_velocity[i]) + dx * inv_h).into();
        if *dtheta != Vec3::zeros() {
            b.orientation[i] = quat::to_xyzw(&quat::normalize(&(quat::exp(dtheta) * b.q(i))));
            b.angular_velocity[i] = (Vec3::from(b.angular_velocity[i]) + dtheta * inv_h).into();
        }
    }
}
