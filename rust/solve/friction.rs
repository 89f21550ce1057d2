//! Coulomb friction on a true cone, one friction patch per manifold (as Bepu and
//! PhysX's patch friction): a 2D tangential impulse at the centre of the
//! manifold's points and a twist impulse about the normal, limited together by
//! `μ` times the manifold's total normal impulse.
//!
//! A patch sticks while the impulse that stops it fits the static cone `μs N`;
//! once sliding it feels `μk N` against its slip velocity (Coulomb's law) until
//! the slip stops. How the load of a rigid body splits between its contact points
//! is an artefact of the solve, so friction is not decided point by point: a
//! Gauss–Seidel sweep would have each point try to stop the whole body alone and
//! give up, and points sliding independently would fan and yaw a sliding box. No
//! pyramid: the friction force has no preferred axes.

use super::contact::{Constraint, ContactSolver, Point};
use super::solver_body::{Pair, SolverBody};
use crate::math::Vec3;

/// Slip speed (m/s) below which a sliding patch's friction keeps the direction of
/// the impulse that would stop it: the direction of a slower slip is noise.
pub(crate) const SLIP_EPS: f64 = 1e-3;

/// The friction of one manifold.
#[derive(Clone, Copy, Debug, Default)]
pub struct Patch {
    /// `r × t` and `I⁻¹ (r × t)` of each body at the patch centre, for `t1`, `t2`.
    pub rt1: [Vec3; 2],
    pub rt2: [Vec3; 2],
    pub irt1: [Vec3; 2],
    pub irt2: [Vec3; 2],
    /// `I⁻¹ n` of each body, for the twist.
    pub in1: Vec3,
    pub in2: Vec3,
    /// Inverse 2x2 tangent effective mass `[a, b, c]` of `[[a, b], [b, c]]` (kg).
    pub tangent_mass: [f64; 3],
    /// Effective inertia about the normal (kg·m²).
    pub twist_mass: f64,
    /// Mean distance of the points from the centre (m): the twist's lever.
    pub radius: f64,
    /// Accumulated impulses of the current substep (N·s, N·m·s).
    pub impulse: [f64; 2],
    pub twist: f64,
    /// Tangential impulse summed over the step, for reporting (N·s).
    pub total: [f64; 2],
    pub sliding: bool,
    /// The manifold's normal impulse at the end of the previous substep (N·s):
    /// the cone is at least that wide, so a body held at the edge of its cone is
    /// not let go by the noise of one pass's normal impulse.
    pub settled: f64,
}

impl Patch {
    /// Arms, effective masses and lever of the patch of `points` at their centre.
    pub fn new(c: &Constraint, points: &[Point], bodies: &[SolverBody]) -> Self {
        let mut f = Patch::default();
        f.set_geometry(c, points, bodies);
        f
    }

    /// Brings the arms, effective masses and lever up to the points' current arms,
    /// keeping the impulses and regime.
    pub fn set_geometry(&mut self, c: &Constraint, points: &[Point], bodies: &[SolverBody]) {
        let (a1, a2) = (&bodies[c.s1 as usize], &bodies[c.s2 as usize]);
        let f = self;
        let n = points.len() as f64;
        let r1 = points.iter().map(|p| p.r1).sum::<Vec3>() / n;
        let r2 = points.iter().map(|p| p.r2).sum::<Vec3>() / n;
        f.radius = if points.len() > 1 { points.iter().map(|p| (p.r1 - r1).norm()).sum::<f64>() / n } else { 0.0 };
        for (k, t) in [c.t1, c.t2].iter().enumerate() {
            f.rt1[k] = r1.cross(t);
            f.rt2[k] = r2.cross(t);
            f.irt1[k] = a1.inv_i * f.rt1[k];
            f.irt2[k] = a2.inv_i * f.rt2[k];
        }
        // A patch of one point (a ball, an edge touching a face) has no lever for
        // a twist: no torsional friction, and nothing to compute for it.
        if f.radius > 0.0 {
            f.in1 = a1.inv_i * c.normal;
            f.in2 = a2.inv_i * c.normal;
        } else {
            f.in1 = Vec3::zeros();
            f.in2 = Vec3::zeros();
        }
        let m = a1.inv_m + a2.inv_m;
        let k = |a: usize, b: usize, ta: &Vec3, tb: &Vec3| m * ta.dot(tb) + f.rt1[a].dot(&f.irt1[b]) + f.rt2[a].dot(&f.irt2[b]);
        let (a, b, cc) = (k(0, 0, &c.t1, &c.t1), k(0, 1, &c.t1, &c.t2), k(1, 1, &c.t2, &c.t2));
        let det = a * cc - b * b;
        f.tangent_mass = if det > 0.0 { [cc / det, -b / det, a / det] } else { [0.0; 3] };
        let kt = c.normal.dot(&f.in1) + c.normal.dot(&f.in2);
        f.twist_mass = if kt > 0.0 && f.radius > 0.0 { 1.0 / kt } else { 0.0 };
    }

    /// The tangential impulse after one solve, in the cone of normal impulse `jn`,
    /// given the slip `vt` at the centre; updates the regime.
    #[inline(always)]
    pub fn cone(&mut self, c: &Constraint, vt: [f64; 2], jn: f64) -> [f64; 2] {
        // Whether it sticks is judged on at least the settled normal impulse; how
        // hard it rubs when it slides, on this pass's.
        let settled = jn.max(self.settled);
        let [a, b, cc] = self.tangent_mass;
        let l = [self.impulse[0] - (a * vt[0] + b * vt[1]), self.impulse[1] - (b * vt[0] + cc * vt[1])];
        let norm = (l[0] * l[0] + l[1] * l[1]).sqrt();
        let slip = (vt[0] * vt[0] + vt[1] * vt[1]).sqrt();
        // A sticking patch breaks away beyond the static cone; a sliding one stops
        // once dynamic friction can stop it within the substep.
        let hold = if self.sliding { c.friction } else { c.static_friction };
        if norm <= hold * settled {
            self.sliding = false;
            return l;
        }
        self.sliding = true;
        let (dir, len) = if slip > SLIP_EPS { ([-vt[0], -vt[1]], slip) } else { (l, norm) };
        if len == 0.0 {
            return [0.0; 2];
        }
        let s = c.friction * jn / len;
        [dir[0] * s, dir[1] * s]
    }
}

impl ContactSolver {
    /// One friction pass over the patches solved both ways (support contacts rub
    /// in their blocks, see `super::support`).
    pub fn solve_friction(&mut self) {
        let (cs, points, patches, bodies) = (&self.constraints, &self.points, &mut self.patches, &mut self.bodies);
        for &ci in &self.ordinary {
            rub(&cs[ci as usize], points, &mut patches[ci as usize], bodies);
        }
    }
}

/// One friction solve of the patch of constraint `c`.
#[inline(always)]
fn rub(c: &Constraint, points: &[Point], f: &mut Patch, bodies: &mut [SolverBody]) {
    if c.static_friction == 0.0 {
        return;
    }
    let points = &points[c.start as usize..(c.start + c.len) as usize];
    let jn: f64 = points.iter().map(|p| p.normal_impulse).sum();
    if jn == 0.0 && f.impulse == [0.0; 2] && f.twist == 0.0 {
        return;
    }
    let mut pair = Pair::load(bodies, c);
    let l = f.cone(c, pair.patch_velocity(c, f), jn);
    let d = [l[0] - f.impulse[0], l[1] - f.impulse[1]];
    f.impulse = l;
    let mut dt = 0.0;
    if f.radius > 0.0 {
        let mu = if f.sliding { c.friction } else { c.static_friction };
        let limit = mu * jn.max(f.settled) * f.radius;
        let twist = (f.twist - f.twist_mass * pair.twist_velocity(c)).clamp(-limit, limit);
        dt = twist - f.twist;
        f.twist = twist;
    }
    pair.apply_patch(c, f, d);
    pair.apply_twist(f, dt);
    pair.store(bodies, c);
}
