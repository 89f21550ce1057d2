//! The solver bodies gathered from the world before each pass (velocities,
//! pose changes, inverse inertias) and scattered back after, and the refresh
//! of the contact arms of the bodies that moved.

use super::contact::{Constraint, ContactSolver};
use super::refresh::refresh;
use super::solver_body::{chord, SolverBody, Surface};
use crate::body::Bodies;
use crate::math::{quat, Quat, Vec3};
use rayon::prelude::*;

/// [`ContactSolver::gather`] of the solver bodies `bodies`, the first of
/// them entry `from`, from the world's bodies `b` (`p0`, `q0`: every entry's
/// pose at the step start; `later`: not the step's first gather); whether
/// one moved enough for its contacts to be refreshed.
fn gather_range(bodies: &mut [SolverBody], from: usize, (p0, q0): (&[Vec3], &[Quat]), b: &Bodies, (later, inv_h): (bool, f64)) -> bool {
    let mut any = false;
    for (s, (p0, q0)) in bodies.iter_mut().zip(p0.iter().skip(from).zip(q0.iter().skip(from))) {
        let i = s.body as usize;
        s.v = Vec3::from(b.linear_velocity[i]);
        s.w = Vec3::from(b.angular_velocity[i]);
        // The turn of this substep, not the step start's. A body that turns
        // is refreshed every substep (it turns more than `MOVE_EPS`); one that
        // starts or stops turning is refreshed too, even if it hardly moved,
        // so that its patches' drift starts or stops with it (a ball's points
        // have none: see `chord_gap`): a can whose
        // spin friction stopped within a step kept its chord and was pushed
        // at 1e-8 m/s as it came to rest. A ball has no use for its chord
        // (three divisions a ball and gather in a ball pit).
        let new_turn = s.surface != Surface::Ball && {
            let turn = chord(s.w / inv_h);
            let new = (turn == Vec3::zeros()) != (s.chord == Vec3::zeros());
            s.chord = turn;
            new
        };
        s.dp = Vec3::from(b.position[i]) - p0;
        s.dq = b.q(i) * q0.conjugate();
        // A ball's contact geometry does not turn with it (its points stay
        // under its centre, `chord_gap` is zero): only its translation counts.
        let turned = if s.surface == Surface::Ball { 0.0 } else { (s.dq - s.dq_ref).norm_squared() };
        let far = MOVE_EPS * MOVE_EPS;
        s.moved = later && ((s.dp - s.dp_ref).norm_squared() > far || turned > far || new_turn);
        if s.moved {
            s.dp_ref = s.dp;
            s.dq_ref = s.dq;
            s.turn_inertia(b, i);
            any = true;
        }
    }
    any
}

/// Whether constraint `c` is due a refresh of its arms on the solver bodies
/// `bodies` (after a gather): a body of it moved by more than [`MOVE_EPS`]
/// since its last refresh. A central contact's refresh reads only how far
/// its bodies moved apart, `Δp2 − Δp1` (its line of centres, its arms
/// about the point the masses share, see `refresh`), so it waits until that
/// changed by `MOVE_EPS` since its own last refresh (`apart`, updated):
/// balls falling or rolling together keep their contacts' arms. A ball's
/// contact with a fixed body is never due: its point stays under the ball's
/// centre (its arm is its anchor whatever the ball does) and its normal is
/// the fixed surface's; the refresh only moved the fixed side's arm, which
/// no impulse reads (the fixed bodies' entry neither moves nor turns). In the
/// first 200 steps of a 1000-ball pit that was one refresh in five (1.58 M of
/// them, 1.30 M now).
fn refresh_due(c: &Constraint, bodies: &[SolverBody], apart: &mut Vec3) -> bool {
    let (a, b) = (&bodies[c.s1 as usize], &bodies[c.s2 as usize]);
    if !(a.moved || b.moved) {
        return false;
    }
    if !c.central {
        return true;
    }
    if c.s1 == 0 || c.s2 == 0 {
        return false;
    }
    let now = b.dp - a.dp;
    if (now - *apart).norm_squared() <= MOVE_EPS * MOVE_EPS {
        return false;
    }
    *apart = now;
    true
}

/// Displacement (m) and quaternion change (rad/2) since the last refresh below
/// which a body's contact arms are not recomputed: 1 µm, far below what a contact
/// resolves (the slop is 5 mm) and above what a body resting in a stack or a
/// pyramid sags or creeps per substep, so at rest nothing is recomputed. A body
/// moving faster than 1 µm per substep is refreshed every substep.
pub(crate) const MOVE_EPS: f64 = 1e-6;

/// Fewest constraints for the refresh of a gather to be split over threads.
const MIN_PARALLEL_REFRESH: usize = 256;

impl ContactSolver {
    /// Copies velocities and pose changes of the solver bodies from the world,
    /// and brings the inverse inertias and contact arms up to the current poses
    /// (after the first gather of a step, when they already are).
    ///
    /// A body that has moved less than `MOVE_EPS` since its last refresh keeps its
    /// arms: at rest (a stack, a pyramid) nothing is recomputed, and the angular
    /// momentum left unbalanced is at most that distance times the impulse.
    /// `relax`: the gather before the relax pass (the rounded contacts'
    /// curves are found before each velocity pass).
    pub fn gather(&mut self, b: &Bodies, relax: bool) {
        let later = self.substeps_done > 0 || self.gathered;
        self.gathered = true;
        let (p0, q0, inv_h) = (&self.p0[..], &self.q0[..], self.inv_h);
        let gather = |bodies: &mut [SolverBody], from: usize| gather_range(bodies, from, (p0, q0), b, (later, inv_h));
        let halves = self.by_halves().and(self.body_ends).filter(|&[k0, k1]| 1 <= k0 && k0 <= k1 && k1 <= self.bodies.len());
        let any = match halves {
            // Each thread writes the solver bodies its half's passes read next
            // (written here by the stepping thread alone, the helper's half
            // of the warm start fetched every one of them back: 31 µs a
            // substep against 18 for the stepping thread's half).
            Some([k0, k1]) => {
                let (head, rest) = self.bodies.split_at_mut(k0);
                let (second, seam) = rest.split_at_mut(k1 - k0);
                let (a, b) = super::team::both(|| gather(&mut head[1..], 1), || gather(second, k0));
                gather(seam, k1) | a | b
            }
            None => {
                let n = self.bodies.len();
                gather(self.bodies.get_mut(1..n).unwrap_or_default(), 1)
            }
        };
        if any {
            self.refresh_moved();
        }
        // Each substep, before its velocity pass (not again before the relax:
        // its velocities start the next substep, which takes its own). Once a
        // step, points whose curve was below the least at the step start were
        // left out until the next: Euler's disk at 30 rad/s sank 29 / 23 µm in
        // 0.1 s (1.77 / 1.98 µm now), and 300 cylinders tumbling onto a plane
        // stepped 1.17× faster.
        if !relax && self.bodies.iter().any(|s| s.surface == Surface::Rounded) {
            self.set_curves();
        }
    }

    /// The arms of the constraints of the bodies [`Self::gather`] found moved.
    fn refresh_moved(&mut self) {
        self.apart.resize(self.constraints.len(), Vec3::zeros());
        if self.wide() && self.constraints.len() >= MIN_PARALLEL_REFRESH && self.refresh_in_parallel() {
            return;
        }
        if let Some(h) = self.by_halves() {
            // Each constraint's refresh writes only its own points and patch
            // (and no support group: a split step has no blocks).
            self.each_half(h, |cs, range| {
                for ci in range {
                    if refresh_due(&cs.constraints[ci], &cs.bodies, &mut cs.apart[ci]) {
                        cs.refresh_constraint(ci);
                    }
                }
                false
            });
            return;
        }
        for ci in 0..self.constraints.len() {
            if refresh_due(&self.constraints[ci], &self.bodies, &mut self.apart[ci]) {
                self.refresh_constraint(ci);
            }
        }
    }

    /// The refresh of `gather` on the pool's threads (each constraint writes
    /// only its own points and patch); false, with nothing done, if the points
    /// are not laid out constraint after constraint.
    fn refresh_in_parallel(&mut self) -> bool {
        let bodies = &self.bodies;
        let ranges = self.constraints.iter().map(|c| (c.start as usize, c.len as usize));
        let Some(runs) = super::lists::runs(&mut self.points, ranges) else {
            return false;
        };
        let patches = self.patches.iter_mut().zip(self.shapes.iter_mut());
        let all = self.constraints.iter_mut().zip(self.apart.iter_mut()).zip(patches).zip(runs);
        let mut jobs: Vec<_> = all.filter_map(|(((c, apart), patch), points)| refresh_due(c, bodies, apart).then_some((c, patch, points))).collect();
        jobs.par_iter_mut().for_each(|(c, (patch, shape), points)| refresh(c, (patch, shape), points, bodies));
        let touched: Vec<u32> = jobs.iter().filter(|(c, _, _)| c.lower != 0).map(|(c, _, _)| c.group).collect();
        touched.into_iter().for_each(|g| self.support.touch(g));
        true
    }

    /// Writes the solved velocities of the dynamic solver bodies back.
    pub fn scatter(&self, b: &mut Bodies) {
        for s in &self.bodies[1..] {
            if s.dynamic {
                b.linear_velocity[s.body as usize] = s.v.into();
                b.angular_velocity[s.body as usize] = s.w.into();
            }
        }
    }

    /// Moves solver body `s` (and its world body) by `dx` and turns it by
    /// `dtheta`, keeping its inverse inertia current.
    pub fn displace(&mut self, b: &mut Bodies, s: usize, dx: &Vec3, dtheta: &Vec3) {
        let i = self.bodies[s].body as usize;
        b.position[i] = (Vec3::from(b.position[i]) + dx).into();
        let turn = quat::exp(dtheta);
        b.orientation[i] = quat::to_xyzw(&quat::normalize(&(turn * b.q(i))));
        let sb = &mut self.bodies[s];
        sb.dp += dx;
        sb.dq = turn * sb.dq;
        sb.turn_inertia(b, i);
    }
}


#[cfg(test)]
mod tests {
    use super::*;
    use super::super::contact::Point;
    use super::super::friction::Patch;
    use super::super::limit_surface::PatchShape;
    use crate::math::Mat3;

    /// Two balls of radius 0.1 m touching along +z (ball 1 under ball 2),
    /// each displaced by `dp1`, `dp2` since the step start: the solver
    /// bodies (fixed entry, ball 1, ball 2) and their constraint and point.
    fn two_balls(dp1: Vec3, dp2: Vec3) -> ([SolverBody; 3], Constraint, Point) {
        let ball = |dp: Vec3| SolverBody { dp, inv_m: 1.0, iso: Some(250.0), inv_i: Mat3::identity() * 250.0, dynamic: true, surface: Surface::Ball, moved: true, ..Default::default() };
        let bodies = [SolverBody::default(), ball(dp1), ball(dp2)];
        let c = Constraint { s1: 1, s2: 2, len: 1, normal: Vec3::z(), t1: Vec3::x(), t2: Vec3::y(), central: true, ..Default::default() };
        let (a1, a2) = (Vec3::new(0.0, 0.0, 0.1), Vec3::new(0.0, 0.0, -0.1));
        // Touching: `Gap::separation` zero at the step start.
        let p = Point { anchor1: a1, anchor2: a2, r1: a1, r2: a2, base_separation: a1.z - a2.z, ..Default::default() };
        (bodies, c, p)
    }

    #[test]
    fn a_balls_contact_with_a_fixed_body_is_never_due() {
        // Ball 2 rolling 3 mm along a fixed floor and sinking 1 µm into it:
        // its arm stays its anchor, its normal the floor's.
        let (bodies, c, _) = two_balls(Vec3::zeros(), Vec3::new(3e-3, 0.0, -1e-6));
        let on_floor = Constraint { s1: 0, ..c };
        let mut apart = Vec3::zeros();
        assert!(!refresh_due(&on_floor, &bodies, &mut apart));
        assert_eq!(apart, Vec3::zeros());
        // Between the two balls the same move is due.
        assert!(refresh_due(&c, &bodies, &mut apart));
    }

    #[test]
    fn balls_moving_together_keep_their_contacts_arms() {
        // Moved together by 1 mm: the refresh gives back the arms as built
        // (to round-off of the displacement), so none is due.
        let together = Vec3::new(1e-3, -2e-3, 0.5e-3);
        let (bodies, mut c, mut p) = two_balls(together, together);
        let (built, _) = Patch::new(&c, &[p], &bodies);
        let mut apart = Vec3::zeros();
        assert!(!refresh_due(&c, &bodies, &mut apart));
        let (mut f, mut shape) = (built, PatchShape::default());
        refresh(&mut c, (&mut f, &mut shape), std::slice::from_mut(&mut p), &bodies);
        assert!((c.normal - Vec3::z()).norm() <= 1e-15 && (p.base_separation - 0.2).abs() <= 1e-15);
        assert!((p.r1 - Vec3::new(0.0, 0.0, 0.1)).norm() <= 1e-15);
        assert!((f.rt1[0] - built.rt1[0]).norm() <= 1e-15 && (f.irt2[1] - built.irt2[1]).norm() <= 1e-13);
        // Ball 2 moved 2 µm sideways relative to ball 1 (more than MOVE_EPS):
        // due, and its line of centres turns by 2e-6 / 0.2 rad.
        let side = Vec3::new(2e-6, 0.0, 0.0);
        let (bodies, mut c, mut p) = two_balls(together, together + side);
        assert!(refresh_due(&c, &bodies, &mut apart));
        assert_eq!(apart, bodies[2].dp - bodies[1].dp);
        refresh(&mut c, (&mut f, &mut shape), std::slice::from_mut(&mut p), &bodies);
        assert!((c.normal.x - 2e-6 / 0.2).abs() <= 1e-15);
        // Not again until they move apart by MOVE_EPS more.
        assert!(!refresh_due(&c, &bodies, &mut apart));
        // A contact that is not central is due whenever a body moved.
        let box_contact = Constraint { central: false, ..c };
        assert!(refresh_due(&box_contact, &bodies, &mut apart));
    }

}
