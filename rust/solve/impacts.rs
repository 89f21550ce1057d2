//! Restitution as impacts. Before the contact solve of a substep, every manifold
//! whose points approach faster than the restitution threshold and would touch
//! within the substep takes an impact impulse that sets the approach speed of
//! those points to `−e` times itself (solved over the manifold's points together,
//! so a box landing flat bounces flat), with Coulomb friction on the same cone.
//! Impacts are swept until none remains, in the spirit of Guendelman et al.
//! (2003): a Newton's cradle passes its momentum down the line ball by ball.
//!
//! Each impact happens at its time of impact `t_c` inside the substep, not at its
//! start. The kick before it gave the bodies the whole substep's acceleration `a`;
//! the impact reverses the approach speed they had at `t_c` (`v_n − a_n (h − t_c)`)
//! and the remaining `h − t_c` of acceleration acts after it. The bodies are moved
//! to where they are at `t_c`, take the impulses there (so that linear and angular
//! momentum balance about one point), and are moved back along their new
//! velocities by `t_c`, so that after the drift they are where a bounce at `t_c`
//! would leave them. Their turns are torque-free flows: momentum and energy are
//! those of the impact itself.

use super::contact::{Constraint, ContactSolver, RESTING_APPROACH};
use super::friction::Patch;
use super::pair::Pair;
use crate::collide::manifolds::manifolds_of;
use crate::collide::narrow_phase::Manifold;
use crate::collide::Collider;
use crate::integrate::free_rotation::flow_one;
use crate::body::Bodies;
use crate::integrate::kick::KickSources;
use crate::math::Vec3;

/// Gauss–Seidel passes over the points of an impact, so they act together.
const MANIFOLD_PASSES: usize = 24;

impl ContactSolver {
    /// Runs the impacts of one substep of length `h`, after a kick by `src`.
    /// Velocities are the solver bodies'; positions moved are the world's.
    pub fn impacts(&mut self, b: &mut Bodies, h: f64, src: &KickSources, colliders: &[Collider]) {
        let bouncy: Vec<usize> = (0..self.constraints.len()).filter(|&c| self.constraints[c].restitution > 0.0).collect();
        let max_sweeps = 2 * bouncy.len() + 8;
        for _ in 0..max_sweeps {
            let mut any = false;
            for &ci in &bouncy {
                any |= self.impact(b, ci, h, src, colliders);
            }
            if !any {
                break;
            }
        }
    }

    /// The earliest time in the substep at which a point of constraint `ci`
    /// approaching faster than the threshold touches, if any.
    fn time_of_impact(&self, ci: usize, h: f64) -> Option<f64> {
        let c = self.constraints[ci];
        let thr = self.restitution_threshold(h).max(1e-12);
        let mut first: Option<f64> = None;
        for p in &self.points[c.start as usize..(c.start + c.len) as usize] {
            let vn = self.normal_velocity(&c, p);
            if vn < -thr {
                let s = self.separation(&c, p);
                if s <= -vn * h {
                    let t = s.max(0.0) / -vn;
                    first = Some(first.map_or(t, |f: f64| f.min(t)));
                }
            }
        }
        first
    }

    /// The approach speed (m/s) below which a contact does not bounce in a
    /// substep of `h` (s): the one set, or [`RESTING_APPROACH`] times what
    /// gravity gives in the substep.
    fn restitution_threshold(&self, h: f64) -> f64 {
        let gravity = self.support.substep_gravity() * self.inv_h;
        self.settings.restitution_threshold.unwrap_or(RESTING_APPROACH * gravity * h)
    }

    /// One impact: the bodies are taken to the time of impact, where their contact
    /// is computed afresh (normal and points of that instant, both arms at the same
    /// points: momentum balances exactly), the impulses are applied, and the bodies
    /// are taken back along their new motion.
    fn impact(&mut self, b: &mut Bodies, ci: usize, h: f64, src: &KickSources, colliders: &[Collider]) -> bool {
        let Some(t_c) = self.time_of_impact(ci, h) else { return false };
        let c = self.constraints[ci];
        self.advance(b, &c, t_c, 1.0);
        let (first_c, first_p) = (self.constraints.len(), self.points.len());
        // A joined constraint's pairs (see `super::flush_pairs`) are fixed
        // faces flush with each other: its own points, refreshed, are the
        // contact of the instant.
        if !c.joined {
            self.fresh_contacts(b, colliders, c.pair, c.slot);
        }
        let fresh: Vec<usize> = if self.constraints.len() > first_c {
            (first_c..self.constraints.len()).collect()
        } else {
            self.refresh_constraint(ci);
            vec![ci]
        };
        let total = self.bounce(b, &fresh, h - t_c, src);
        self.constraints.truncate(first_c);
        self.patches.truncate(first_c);
        self.shapes.truncate(first_c);
        self.points.truncate(first_p);
        self.points[c.start as usize].total_normal += c.normal.dot(&total);
        let f = &mut self.patches[ci];
        f.total[0] += c.t1.dot(&total);
        f.total[1] += c.t2.dot(&total);
        self.advance(b, &c, t_c, -1.0);
        self.refresh_constraint(ci);
        true
    }

    /// Appends constraints for the contact of a collider pair at the current poses.
    fn fresh_contacts(&mut self, b: &Bodies, colliders: &[Collider], pair: (u32, u32), slot: u32) {
        let (c1, c2) = (&colliders[pair.0 as usize], &colliders[pair.1 as usize]);
        let pos12 = c1.pose(b).inv_mul(&c2.pose(b));
        let mut manifolds: Vec<Manifold> = Vec::new();
        let reach = 2.0 * self.settings.slop;
        manifolds_of(c1, c2, &pos12, reach, (&mut manifolds, &mut None));
        let ctx = self.pair_context((colliders, None), b, pair, slot);
        let members = manifolds.iter().enumerate().map(|(m, manifold)| (m as u32, manifold.into()));
        self.push_pair(members, &ctx, (super::prepare::Carry::NONE, reach), b);
    }

    /// Simultaneous restitution impulses on the approaching points of `fresh`
    /// (each reversed to `−e` times its approach speed at the impact, `tau` before
    /// the substep ends), then friction; returns the total impulse on body 2 (N·s).
    fn bounce(&mut self, b: &Bodies, fresh: &[usize], tau: f64, src: &KickSources) -> Vec3 {
        let mut goals: Vec<Option<f64>> = Vec::new();
        for &ci in fresh {
            let c = self.constraints[ci];
            let a_n = c.normal.dot(&(self.accel(b, c.s2, c.b2, src) - self.accel(b, c.s1, c.b1, src)));
            for k in c.start..c.start + c.len {
                let vn = self.normal_velocity(&c, &self.points[k as usize]);
                goals.push((vn < 0.0).then(|| -c.restitution * (vn - a_n * tau) + a_n * tau));
            }
        }
        let mut lambda = vec![0.0; goals.len()];
        for _ in 0..MANIFOLD_PASSES {
            let mut slot = 0;
            for &ci in fresh {
                let c = self.constraints[ci];
                for k in c.start..c.start + c.len {
                    if let Some(goal) = goals[slot] {
                        let p = self.points[k as usize];
                        let total = (lambda[slot] + p.normal_mass * (goal - self.normal_velocity(&c, &p))).max(0.0);
                        let d = total - lambda[slot];
                        lambda[slot] = total;
                        if d != 0.0 {
                            self.apply_normal(&c, &p, d);
                        }
                    }
                    slot += 1;
                }
            }
        }
        let mut total = Vec3::zeros();
        let mut slot = 0;
        for &ci in fresh {
            let c = self.constraints[ci];
            let jn: f64 = lambda[slot..slot + c.len as usize].iter().sum();
            slot += c.len as usize;
            let t = self.impact_friction(ci, jn);
            total += c.normal * jn + c.t1 * t[0] + c.t2 * t[1];
        }
        total
    }

    /// The acceleration the kick gave solver body `s` (world body `i`).
    fn accel(&self, b: &Bodies, s: u32, i: u32, src: &KickSources) -> Vec3 {
        if !self.bodies[s as usize].dynamic {
            return Vec3::zeros();
        }
        src.acceleration(b, i as usize)
    }

    /// Friction impulse of an impact of total normal impulse `jn` on constraint
    /// `ci`, from its patch's current slip (a fresh patch: no impulse yet).
    fn impact_friction(&mut self, ci: usize, jn: f64) -> [f64; 2] {
        let c = self.constraints[ci];
        if jn <= 0.0 || c.static_friction == 0.0 {
            return [0.0; 2];
        }
        let mut f = Patch { impulse: [0.0; 2], sliding: false, ..self.patches[ci] };
        let mut pair = Pair::load(&self.bodies, &c);
        let l = f.cone(&c, pair.patch_velocity(&c, &f), jn);
        pair.apply_patch(&c, &f, l);
        pair.store(&mut self.bodies, &c);
        l
    }

    /// Moves the dynamic bodies of `c` along their motion by `sign·t`: straight
    /// lines and the exact torque-free rotation, which keeps world angular
    /// momentum and energy, so that `−t` undoes `t`.
    fn advance(&mut self, b: &mut Bodies, c: &Constraint, t: f64, sign: f64) {
        if t <= 0.0 {
            return;
        }
        for s in [c.s1 as usize, c.s2 as usize] {
            if !self.bodies[s].dynamic {
                continue;
            }
            let i = self.bodies[s].body as usize;
            b.linear_velocity[i] = self.bodies[s].v.into();
            b.angular_velocity[i] = self.bodies[s].w.into();
            let q_before = b.q(i);
            b.position[i] = (Vec3::from(b.position[i]) + self.bodies[s].v * (sign * t)).into();
            flow_one(b, i, sign * t);
            let sb = &mut self.bodies[s];
            sb.dp += sb.v * (sign * t);
            sb.dq = b.q(i) * q_before.conjugate() * sb.dq;
            sb.w = Vec3::from(b.angular_velocity[i]);
            sb.turn_inertia(b, i);
        }
    }
}
