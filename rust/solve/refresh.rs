//! The refresh of a constraint: its points' arms, a ball contact's line of
//! centres and its patch brought up to the bodies' moves within the step.

use super::contact::{normal_mass, orthonormal, Constraint, ContactSolver, Point};
use super::friction::{ball_pair, Patch};
use super::limit_surface::PatchShape;
use super::solver_body::SolverBody;
use crate::math::{quat, Vec3};

impl ContactSolver {
    /// Arms and effective masses of one constraint's points at the current poses.
    ///
    /// A corner of one body (a box's, a top's tip: see [`Corners`]) is a material
    /// point: it turns with that body. Any other contact point moves with the
    /// bodies' translations weighted by their inverse masses: it stays under a
    /// sphere sliding on the ground and follows a box across it (following the
    /// material point would tilt a sliding sphere's arm and spin it up without
    /// friction). Both arms end at the same point, so equal and opposite impulses
    /// keep angular momentum exactly.
    pub(crate) fn refresh_constraint(&mut self, ci: usize) {
        let c = &mut self.constraints[ci];
        let range = c.start as usize..(c.start + c.len) as usize;
        refresh(c, (&mut self.patches[ci], &mut self.shapes[ci]), &mut self.points[range], &self.bodies);
        let (lower, group) = (c.lower, c.group);
        if lower != 0 {
            self.support.touch(group);
        }
    }

    /// The patch of constraint `ci` at its points' current arms, keeping its
    /// impulses and state.
    pub(crate) fn refresh_patch(&mut self, ci: usize) {
        let c = &mut self.constraints[ci];
        let range = c.start as usize..(c.start + c.len) as usize;
        refresh_patch_of(c, (&mut self.patches[ci], &mut self.shapes[ci]), &self.points[range], &self.bodies);
    }
}

/// [`ContactSolver::refresh_constraint`] of constraint `c`, its patch and its
/// points, on the solver bodies `bodies` (the touch of its block left to the
/// caller).
pub(crate) fn refresh(c: &mut Constraint, patch: (&mut Patch, &mut PatchShape), points: &mut [Point], bodies: &[SolverBody]) {
    let (b1, b2) = (&bodies[c.s1 as usize], &bodies[c.s2 as usize]);
    if c.central && c.s1 != 0 && c.s2 != 0 {
        if let [p] = &mut *points {
            if let (Some(iso), 0) = (ball_pair(b1, b2), p.corner) {
                return refresh_balls(c, patch.0, p, (b1, b2), iso);
            }
            line_of_centres(c, p, (b1, b2));
        }
    }
    let normal = c.normal;
    let (dp1, dp2) = (b1.dp, b2.dp);
    let shift = shift(b1, b2);
    for p in points.iter_mut() {
        // Both anchors start at one world point: x1 + a1 = x2 + a2. A corner
        // turns with its body; a rounded surface's point goes where the surface
        // is nearest the other body (a disk nutating on its rim: see
        // `Rounding`); any other point follows the translations.
        let turned1 = if p.corner == 1 { Some(quat::rotate(&b1.dq, &p.anchor1)) } else { b1.rounded_arm(p, 1, &normal) };
        let turned2 = if p.corner == 2 { Some(quat::rotate(&b2.dq, &p.anchor2)) } else { b2.rounded_arm(p, 2, &normal) };
        // A corner first, then body 2's rounded surface, then body 1's.
        (p.r1, p.r2) = match (p.corner, turned1, turned2) {
            (1, Some(r1), _) | (_, Some(r1), None) => (r1, p.anchor2 + (dp1 + r1 - p.anchor1) - dp2),
            (_, _, Some(r2)) => (p.anchor1 + (dp2 + r2 - p.anchor2) - dp1, r2),
            _ => (p.anchor1 + shift - dp1, p.anchor2 + shift - dp2),
        };
        // A central point's mass does not depend on its arms: kept as built.
        if !c.central {
            normal_mass(p, (b1, b2), &normal, false);
        }
    }
    refresh_patch_of(c, patch, points, bodies);
}

/// [`refresh`] of a contact between two balls (one point, isotropic
/// inverse inertias `iso`), with the same arithmetic and bits: a ball's point
/// neither turns with it nor follows a rounded surface, so its arms follow the
/// translations, and its patch (one point's) keeps its empty shape. A settling
/// pit refreshes every ball contact at every substep (11 500 a step for 1000
/// balls): the general path's per-point dispatch and the shape written again
/// were 3 % of the instructions of its first 150 steps.
fn refresh_balls(c: &mut Constraint, patch: &mut Patch, p: &mut Point, (b1, b2): (&SolverBody, &SolverBody), iso: (f64, f64)) {
    line_of_centres(c, p, (b1, b2));
    let shift = shift(b1, b2);
    (p.r1, p.r2) = (p.anchor1 + shift - b1.dp, p.anchor2 + shift - b2.dp);
    c.as_built = false;
    patch.set_ball_geometry(c, (&p.r1, &p.r2), b1.inv_m + b2.inv_m, iso);
}

/// How far the point the two bodies' masses share has moved since the step
/// start (their moves weighted by their inverse masses): where a contact
/// point that neither is a corner of nor a rounded surface's goes.
#[inline(always)]
fn shift(b1: &SolverBody, b2: &SolverBody) -> Vec3 {
    let (w1, w2) = if b1.inv_m + b2.inv_m > 0.0 { (b1.inv_m, b2.inv_m) } else { (1.0, 1.0) };
    (b1.dp * w1 + b2.dp * w2) / (w1 + w2)
}

/// The normal of a contact between two balls along the line of their
/// centres as they have moved (`dp`), its tangents carried along with it,
/// and the point's separation the distance of their surfaces. An impulse
/// along the step start's normal through both centres would turn their
/// angular momentum about any point once the centres have moved across it
/// (two balls colliding off centre lost 7.5e-4 of it).
fn line_of_centres(c: &mut Constraint, p: &mut Point, (b1, b2): (&SolverBody, &SolverBody)) {
    let start = p.anchor1 - p.anchor2;
    let d = start + (b2.dp - b1.dp);
    let dd = d.norm_squared();
    if !(dd > 0.0) {
        return;
    }
    // Reciprocals: three divisions each sat on the refresh's chain. The
    // tangent is projected off `d` itself, not off `n`: its square root
    // and division then run beside the normal's, not after them (the
    // chain of a refresh was longer than the refresh, in a settling pit
    // whose every ball contact is refreshed every substep).
    let len = dd.sqrt();
    let n = d * (1.0 / len);
    let radii = start.norm() - p.separation;
    let t = c.t1 - d * (d.dot(&c.t1) / dd);
    let t1 = if t.norm_squared() > 0.25 { t * (1.0 / t.norm()) } else { orthonormal(&n) };
    (c.normal, c.t1, c.t2) = (n, t1, n.cross(&t1));
    // As `Gap::separation` reads it, with a ball's anchors unturned.
    p.base_separation = (len - radii) - n.dot(&(b2.dp - b1.dp)) - n.dot(&p.anchor2) + n.dot(&p.anchor1);
}

/// The patch of constraint `c` at its points' current arms, keeping its
/// impulses and state.
fn refresh_patch_of(c: &mut Constraint, (patch, shape): (&mut Patch, &mut PatchShape), points: &[Point], bodies: &[SolverBody]) {
    c.as_built = false;
    patch.set_geometry(shape, c, points, bodies);
}
