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
//! would leave them; a turned body keeps its world angular momentum.

use super::contact::{inertia_world, Constraint, ContactSolver};
use crate::body::Bodies;
use crate::integrate::kick::KickSources;
use super::friction::cone;
use crate::math::Vec3;

/// Gauss–Seidel passes over the points of one manifold for a simultaneous impact.
const MANIFOLD_PASSES: usize = 24;

impl ContactSolver {
    /// Runs the impacts of one substep of length `h`, after a kick by `src`.
    /// Velocities are the solver bodies'; positions moved back are the world's.
    pub fn impacts(&mut self, b: &mut Bodies, h: f64, src: &KickSources) {
        let bouncy: Vec<usize> = (0..self.constraints.len()).filter(|&c| self.constraints[c].restitution > 0.0).collect();
        let max_sweeps = 2 * bouncy.len() + 8;
        for _ in 0..max_sweeps {
            let mut any = false;
            for &ci in &bouncy {
                any |= self.impact(b, ci, h, src);
            }
            if !any {
                break;
            }
        }
    }

    fn impact(&mut self, b: &mut Bodies, ci: usize, h: f64, src: &KickSources) -> bool {
        let c = self.constraints[ci];
        let thr = self.settings.restitution_threshold;
        let accel = |s: u32, i: u32| {
            if !self.bodies[s as usize].dynamic {
                return Vec3::zeros();
            }
            let i = i as usize;
            let f = if src.force { Vec3::from(b.force[i]) * b.inv_mass[i] } else { Vec3::zeros() };
            src.gravity + f
        };
        let a_n = c.normal.dot(&(accel(c.s2, c.b2) - accel(c.s1, c.b1)));
        let mut target = [None; 8];
        let mut t_c = h;
        for (slot, k) in (c.start..c.start + c.len).enumerate().take(8) {
            let p = self.points[k as usize];
            let vn = self.normal_velocity(&c, &p);
            if vn < -thr.max(1e-12) {
                let s = self.separation(&c, &p);
                if s <= -vn * h {
                    let t = s.max(0.0) / -vn;
                    let tau = h - t;
                    target[slot] = Some(-c.restitution * (vn - a_n * tau) + a_n * tau);
                    t_c = t_c.min(t);
                }
            }
        }
        if target.iter().all(|t| t.is_none()) {
            return false;
        }
        self.advance(b, &c, t_c, 1.0);
        self.refresh_constraint(ci);
        let mut lambda = [0.0; 8];
        for _ in 0..MANIFOLD_PASSES {
            for (slot, k) in (c.start..c.start + c.len).enumerate().take(8) {
                let Some(goal) = target[slot] else { continue };
                let p = self.points[k as usize];
                let vn = self.normal_velocity(&c, &p);
                let total = (lambda[slot] + p.normal_mass * (goal - vn)).max(0.0);
                let d = total - lambda[slot];
                lambda[slot] = total;
                if d != 0.0 {
                    self.apply_normal(&c, &p, d);
                }
            }
        }
        for (slot, k) in (c.start..c.start + c.len).enumerate().take(8) {
            let t = self.impact_friction(&c, k as usize, lambda[slot]);
            let q = &mut self.points[k as usize];
            q.total_normal += lambda[slot];
            q.total_tangent[0] += t[0];
            q.total_tangent[1] += t[1];
        }
        self.advance(b, &c, t_c, -1.0);
        self.refresh_constraint(ci);
        true
    }

    /// Friction impulse of an impact of normal impulse `jn` at point `k`.
    fn impact_friction(&mut self, c: &Constraint, k: usize, jn: f64) -> [f64; 2] {
        if jn <= 0.0 || c.static_friction == 0.0 {
            return [0.0; 2];
        }
        let p = self.points[k];
        let l = cone(c, &p, self.tangent_velocity(c, &p), [0.0; 2], jn);
        self.apply_tangent(c, &p, l);
        l
    }

    /// Moves the dynamic bodies of `c` along their velocities by `sign·t`; a turn
    /// keeps the body's world angular momentum `I ω`.
    fn advance(&mut self, b: &mut Bodies, c: &Constraint, t: f64, sign: f64) {
        if t <= 0.0 {
            return;
        }
        for s in [c.s1 as usize, c.s2 as usize] {
            if !self.bodies[s].dynamic {
                continue;
            }
            let (v, w, i) = (self.bodies[s].v, self.bodies[s].w, self.bodies[s].body as usize);
            let momentum = inertia_world(b, i) * w;
            self.displace(b, s, &(v * (sign * t)), &(w * (sign * t)));
            self.bodies[s].w = self.bodies[s].inv_i * momentum;
        }
    }
}
