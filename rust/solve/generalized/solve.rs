//! The Gauss–Seidel passes over the constraints touching a link: the shared
//! rules (see [`crate::solve::impulse`] and [`crate::solve::friction`]) on rows
//! whose velocities are read through the articulations' joint velocities and
//! whose impulses move them by their responses.

use super::Row;
use crate::solve::contact::ContactSolver;
use crate::solve::solver_body::{Gap, SolverBody};

/// Gauss–Seidel sweeps at most per pass over the constraints touching a link,
/// and the impulse change (relative to the largest impulse) below which a pass
/// stops early (a chain at rest, warm-started: one sweep).
const SWEEPS: usize = 16;
const TOLERANCE: f64 = 1e-6;

impl Row {
    /// The row's velocity (m/s, or rad/s for a twist).
    #[inline(always)]
    fn velocity(&self, bodies: &[SolverBody], qd: &[f64], jac: &[f64]) -> f64 {
        let mut v = 0.0;
        for t in self.body.iter().filter(|t| t.s != 0) {
            let b = &bodies[t.s as usize];
            v += t.lin.dot(&b.v) + t.ang.dot(&b.w);
        }
        for t in self.art.iter().filter(|t| t.n != 0) {
            let (at, q, n) = (t.at as usize, t.qd as usize, t.n as usize);
            v += jac[at..at + n].iter().zip(&qd[q..q + n]).map(|(j, x)| j * x).sum::<f64>();
        }
        v
    }

    /// Applies an impulse `d` along the row: to the articulated sides, and to
    /// the body sides unless `links_only`.
    #[inline(always)]
    fn apply(&self, d: f64, bodies: &mut [SolverBody], qd: &mut [f64], resp: &[f64], links_only: bool) {
        if d == 0.0 {
            return;
        }
        if !links_only {
            for t in self.body.iter().filter(|t| t.s != 0) {
                let b = &mut bodies[t.s as usize];
                b.v += t.dlin * d;
                b.w += t.dang * d;
            }
        }
        for t in self.art.iter().filter(|t| t.n != 0) {
            let (at, q, n) = (t.at as usize, t.qd as usize, t.n as usize);
            for (x, r) in qd[q..q + n].iter_mut().zip(&resp[at..at + n]) {
                *x += r * d;
            }
        }
    }
}

impl ContactSolver {
    /// The links' share of the warm start (the shared warm start has applied
    /// the impulses to the other bodies, and kept the step's totals).
    pub fn warm_start_links(&mut self) {
        let g = &mut self.gen;
        for lc in &g.constraints {
            let c = &self.constraints[lc.ci as usize];
            let mut row = lc.row as usize;
            for p in &self.points[c.start as usize..(c.start + c.len) as usize] {
                g.rows[row].apply(p.normal_impulse, &mut self.bodies, &mut g.qd, &g.resp, true);
                row += 1;
            }
            let f = &self.patches[lc.ci as usize];
            if lc.friction {
                g.rows[row].apply(f.impulse[0], &mut self.bodies, &mut g.qd, &g.resp, true);
                g.rows[row + 1].apply(f.impulse[1], &mut self.bodies, &mut g.qd, &g.resp, true);
            }
            if lc.twist {
                g.rows[row + 2].apply(f.twist, &mut self.bodies, &mut g.qd, &g.resp, true);
            }
        }
    }

    /// The constraints touching a link, by Gauss–Seidel sweeps (each point's
    /// normal, then its patch's friction, constraint after constraint) until no
    /// impulse changes by more than [`TOLERANCE`] of the largest, at most
    /// [`SWEEPS`]: the rows of one articulation are coupled through all of its
    /// joints, and one sweep leaves an impulse on one link that sets a light
    /// mode of the chain spinning (a 20-link chain draped over a box blew up
    /// with one sweep per pass; it comes to rest with these). The shared rules:
    /// normals solved both ways (`relax`: the relax pass), friction on the
    /// patch's cone with its twist.
    pub fn solve_links(&mut self, relax: bool) {
        if self.gen.constraints.is_empty() {
            return;
        }
        for _ in 0..SWEEPS {
            let (change, largest) = self.sweep_links(relax);
            if change <= TOLERANCE * largest {
                break;
            }
        }
    }

    /// One sweep; returns the largest impulse change and the largest impulse (N·s).
    fn sweep_links(&mut self, relax: bool) -> (f64, f64) {
        let rule = self.rule(relax);
        let (mut change, mut largest) = (0.0f64, 0.0f64);
        let g = &mut self.gen;
        for lc in &g.constraints {
            let ci = lc.ci as usize;
            let c = &self.constraints[ci];
            let gap = Gap::new(&self.bodies, c);
            let mut jn = 0.0;
            for i in 0..c.len as usize {
                let p = &mut self.points[c.start as usize + i];
                let s = rule.effective(gap.separation(p));
                if !(relax && s > 0.0) {
                    // After the drift a gap is the next substep's business.
                    let row = &g.rows[lc.row as usize + i];
                    let vn = row.velocity(&self.bodies, &g.qd, &g.jac);
                    let total = (p.normal_impulse + rule.both_ways(s, vn, p)).max(0.0);
                    let delta = total - p.normal_impulse;
                    p.normal_impulse = total;
                    row.apply(delta, &mut self.bodies, &mut g.qd, &g.resp, false);
                    change = change.max(delta.abs());
                }
                jn += p.normal_impulse;
            }
            largest = largest.max(jn);
            let f = &mut self.patches[ci];
            if !lc.friction || (jn == 0.0 && f.impulse == [0.0; 2] && f.twist == 0.0) {
                continue;
            }
            let t = lc.row as usize + c.len as usize;
            let (r1, r2) = (&g.rows[t], &g.rows[t + 1]);
            let vt = [r1.velocity(&self.bodies, &g.qd, &g.jac), r2.velocity(&self.bodies, &g.qd, &g.jac)];
            let l = super::cone::cone(f, c, lc.k, vt, jn);
            let d = [l[0] - f.impulse[0], l[1] - f.impulse[1]];
            f.impulse = l;
            let mut dt = 0.0;
            if lc.twist {
                let mu = if f.sliding { c.friction } else { c.static_friction };
                let limit = mu * jn.max(f.settled) * f.lever;
                let spin = g.rows[t + 2].velocity(&self.bodies, &g.qd, &g.jac);
                // Not `clamp`: it panics on a NaN bound, and a step must not.
                let twist = (f.twist - lc.twist_mass * spin).min(limit).max(-limit);
                dt = twist - f.twist;
                f.twist = twist;
            }
            change = change.max(d[0].abs()).max(d[1].abs()).max(dt.abs() / f.lever.max(f64::MIN_POSITIVE));
            g.rows[t].apply(d[0], &mut self.bodies, &mut g.qd, &g.resp, false);
            g.rows[t + 1].apply(d[1], &mut self.bodies, &mut g.qd, &g.resp, false);
            if lc.twist {
                g.rows[t + 2].apply(dt, &mut self.bodies, &mut g.qd, &g.resp, false);
            }
        }
        (change, largest)
    }
}
