//! The normal impulse `J = j n` of the seed, as a sequential-impulse solve:
//! `j = −(1/K)·(v_n + bias)`, the accumulated impulse `λ` clamped at zero
//! (contacts push, never pull), with
//! `K = 1/m1 + 1/m2 + n·(I1⁻¹(r1×n)×r1 + I2⁻¹(r2×n)×r2)` the effective mass.
//!
//! A separated (speculative) point lets the bodies close the gap within the
//! substep and no more: `bias = s/h`. A penetrating one is pushed out at the soft
//! constraint's rate, at most `max_push_velocity`; the relax pass then solves
//! without that bias, so the push-out moves the bodies but leaves no velocity
//! behind: penetration is corrected without adding energy. The relax pass leaves
//! separated points alone.
//!
//! Contacts that carry weight are solved in the support sweeps (see
//! [`super::support`]) and are rigid: each sweep solves a column exactly, so a
//! resting contact needs no spring to be stable and does not sag by its load.
//! Contacts solved both ways in one Gauss–Seidel pass are rigid in velocity
//! against a fixed body (`j = −(1/K)·(v_n + bias)`, the push-out softened by
//! the mass scale `s_m`). Between two moving bodies a penetrating point takes
//! Box2D v3's soft step (`−(1/K)·s_m·(v_n − push) − s_i·λ`) at a third of
//! the substep rate: its leak `s_i·λ` is what brings a ball pit to rest (see
//! [`Rule::law`]).

use super::contact::{Constraint, ContactSolver, Point};
use super::small_lcp::{small_lcp, MAX_POINTS};
use super::soft::Softness;
use super::warm_guard::in_pass;
use super::pair::Pair;
use super::solver_body::{Gap, SolverBody};

/// Sweeps over the points of a manifold that has no warm start.
const FRESH_SWEEPS: u32 = 4;

/// How one pass turns a point's separation and normal velocity into an impulse.
#[derive(Clone, Copy)]
pub(crate) struct Rule {
    soft: Softness,
    /// The soft step of a point between two moving bodies (see
    /// [`Rule::law`]).
    pair: Softness,
    max_push: f64,
    pub(crate) inv_h: f64,
    /// Depth at which a resting contact settles (m): see [`REST_DEPTH`].
    rest: f64,
    pub(crate) relax: bool,
}

/// Fraction of the slop a resting contact settles into (1 µm at the default
/// 5 mm). Contacts are solved for this small overlap rather than for exact
/// touching: at a distance of exactly zero, parry's contact generation is
/// degenerate (a resting triangle mesh has been seen to report a sideways normal
/// 3.5 m deep), and a contact at zero would flicker between touching and apart.
/// Small, so that a body set down touching settles into it in the first substep
/// without a measurable jolt (0.02 of the slop, 0.1 mm, cost a box set down 15 %
/// of its weight in extra friction over its first steps).
pub(crate) const REST_DEPTH: f64 = 2e-4;

/// Natural frequency of the soft step between two moving bodies, as a
/// fraction of the substep rate (see [`Rule::law`]).
const PAIR_RATE: f64 = 1.0 / 3.0;

/// The touching band's upper edge, in rest depths of effective separation
/// (see [`Rule::bias`]): beyond it a gap is asked to close.
pub(crate) const TOUCHING: f64 = 2.0;

impl Rule {
    /// The separation the solver works with: the geometric one plus the rest
    /// depth (m).
    #[inline(always)]
    pub(crate) fn effective(&self, s: f64) -> f64 {
        s + self.rest
    }

    /// The velocity bias of a point at (effective) separation `s` (m/s) for the
    /// support blocks: a gap may close within the substep; a penetration is the
    /// position pass's business. A point counts as touching, and keeps its
    /// distance, over a band of two rest depths either side of resting: from
    /// the position pass's edge (a rest depth deeper) to a geometric gap of a
    /// rest depth (1 µm at the default slop). Bodies rest inside it, whether
    /// placed touching (geometric 0) or landed (at the rest depth), so the
    /// round-off drift of a resting pile has a micrometre to go before anything
    /// acts on it. The old edge, 1 nm from where the bodies rested, was crossed
    /// after 160 steps of a resting pyramid, and a face with one corner across
    /// it asks for a tilt its other corners forbid, which a block solves only in
    /// least squares, pass after pass (600 block solves a step from then on).
    /// Beyond the band the whole gap closes, to the rest depth.
    #[inline(always)]
    pub(crate) fn bias(&self, s: f64) -> f64 {
        if s > TOUCHING * self.rest {
            s * self.inv_h
        } else {
            0.0
        }
    }

    /// The speed (m/s) at which a point at (effective) separation `s` is pushed
    /// out in the first pass: 0 unless it penetrates.
    #[inline(always)]
    pub(crate) fn push_out_speed(&self, s: f64) -> f64 {
        self.push_at(&self.soft, s)
    }

    /// The push-out speed (m/s) of soft step `soft` at separation `s`.
    #[inline(always)]
    fn push_at(&self, soft: &Softness, s: f64) -> f64 {
        if s < 0.0 {
            (-soft.bias_rate * s).min(self.max_push)
        } else {
            0.0
        }
    }

    /// Impulse increment of a point solved both ways: rigid, a penetration pushed
    /// out at the soft contact's rate (at most `max_push_velocity`) in the first
    /// pass and the push-out taken back by the relax pass.
    #[inline(always)]
    pub(crate) fn both_ways(&self, s: f64, vn: f64, p: &Point) -> f64 {
        -p.normal_mass * (vn + self.rigid_bias(s))
    }

    /// The velocity bias of [`Rule::both_ways`] at separation `s` (m/s): the
    /// point's velocity is solved for `v_n + bias = 0` (or more).
    #[inline(always)]
    fn rigid_bias(&self, s: f64) -> f64 {
        if s > 0.0 {
            s * self.inv_h
        } else if !self.relax {
            -self.soft.mass_scale * self.push_out_speed(s)
        } else {
            0.0
        }
    }

    /// How a point at (effective) separation `s` is solved this pass, between
    /// two `moving` bodies or not: `None` if it is left alone (a gap in the
    /// relax pass, which is the next substep's business: closing it here
    /// would brake a body that has not arrived yet).
    ///
    /// Between two moving bodies (balls in a pit) a penetrating point takes
    /// Box2D's soft step,
    /// `−(1/K)·s_m·(v_n − push) − s_i·λ`, its spring at a third of the
    /// substep rate (80 Hz at the defaults) with the contacts' damping ratio,
    /// its push-out at that spring's rate; any other point is solved as
    /// [`Rule::both_ways`].
    /// Rigid, a pile of balls solved by one Gauss–Seidel pass a substep never
    /// comes to rest: its contacts trade the warm start's impulses back and
    /// forth (1000 balls still at a median 5 mm/s after 10 s, bursts of
    /// 0.36 m/s); the leak `s_i·λ` damps that (median 1.4e-7 m/s). Its price
    /// is a sag by the load, `s_i λ / (K s_m b)` (`b` the bias rate), falling
    /// as the square of the rate. Measured, deepest contact of the 1000-ball
    /// pit / of a pile six deep: at 60 Hz 4.2 / 0.82 mm, at rest; at 80 Hz
    /// 1.9 / 0.53 mm, at rest; at 120 Hz 0.75 / 0.25 mm, but a median
    /// 1e-4 m/s left and a ball wedged at 2 cm/s.
    #[inline(always)]
    pub(crate) fn law(&self, s: f64, moving: bool) -> Option<Law> {
        if self.relax && s > 0.0 {
            None
        } else if moving && s <= 0.0 && !self.relax {
            let push = self.push_at(&self.pair, s);
            Some(Law { mass_scale: self.pair.mass_scale, impulse_scale: self.pair.impulse_scale, bias: -push })
        } else {
            Some(Law { mass_scale: 1.0, impulse_scale: 0.0, bias: self.rigid_bias(s) })
        }
    }
}

/// The soft step of one point: `Δλ = −(1/K)·s_m·(v_n + bias) − s_i·λ` (rigid:
/// `s_m = 1`, `s_i = 0`).
#[derive(Clone, Copy, Default)]
pub(crate) struct Law {
    mass_scale: f64,
    impulse_scale: f64,
    bias: f64,
}

impl Law {
    /// The impulse increment of point `p` at normal velocity `vn`.
    #[inline(always)]
    pub(crate) fn impulse(&self, vn: f64, p: &Point) -> f64 {
        -p.normal_mass * self.mass_scale * (vn + self.bias) - self.impulse_scale * p.normal_impulse
    }
}

impl ContactSolver {
    /// The support sweeps (normals and friction), then one pass over the
    /// normals of the contacts solved both ways: what a wall or a paddle does
    /// to a body is then exact at the end of the pass. The relax pass (after the
    /// drift) takes back the push-out of the contacts solved both ways, and
    /// sweeps again the islands of blocks they touch (see
    /// [`Self::pushed_islands`]; blocks have no push-out: the position pass
    /// moves them).
    pub fn solve_normal(&mut self, relax: bool) {
        let rule = self.rule(relax);
        let changed = self.velocity_pass(&rule);
        // See `super::warm_guard`: a pass that ends with energy it may not have
        // added is done again without the warm start.
        if !relax && self.gained_energy(&rule, changed) {
            self.without_warm_start();
            self.velocity_pass(&rule);
            self.end_redo();
        }
    }

    /// One pass; whether it changed anything after the warm start.
    fn velocity_pass(&mut self, rule: &Rule) -> bool {
        if self.by_groups() {
            return self.velocity_pass_by_groups(rule);
        }
        if let Some(h) = self.by_halves() {
            // No support blocks to sweep or release (see `super::seams`).
            self.each_half(h, |cs, r| {
                let list = cs.ordinary.get(r).unwrap_or(&[]);
                solve_each(list, &cs.constraints, &mut cs.points, &mut cs.bodies, (&cs.guard.redo, rule));
                false
            });
            return !self.ordinary.is_empty() || !self.support.solved.is_empty();
        }
        self.sweep_supports(rule);
        let (cs, points, bodies) = (&self.constraints, &mut self.points, &mut self.bodies);
        solve_each(&self.ordinary, cs, points, bodies, (&self.guard.redo, rule));
        // See `super::release`. (The relax pass's excess is released after
        // the next warm start.)
        let released = !rule.relax && self.release_excess(rule);
        released || !self.ordinary.is_empty() || !self.support.solved.is_empty()
    }

    /// The depth resting contacts settle to (m): [`REST_DEPTH`] of the slop.
    pub(crate) fn rest_depth(&self) -> f64 {
        REST_DEPTH * self.settings.slop
    }

    pub(crate) fn rule(&self, relax: bool) -> Rule {
        let rest = self.rest_depth();
        let pair = Softness::new(PAIR_RATE * self.inv_h, self.settings.contact_damping_ratio, 1.0 / self.inv_h);
        Rule { soft: self.softness, pair, max_push: self.settings.max_push_velocity, inv_h: self.inv_h, rest, relax }
    }
}

/// [`solve`] for the constraints `list` in order (those in the pass, `redo`:
/// see `super::warm_guard`). The one place `solve` is inlined: with a copy
/// for the group-by-group passes too (`super::contact_groups`), the compiler
/// stopped inlining what `solve` calls and the ball pit's velocity passes
/// took 11 % more instructions.
#[inline(never)]
pub(super) fn solve_each(list: &[u32], cs: &[Constraint], points: &mut [Point], bodies: &mut [SolverBody], (redo, rule): (&[bool], &Rule)) {
    for &ci in list {
        let c = &cs[ci as usize];
        if in_pass(redo, c) {
            solve(c, points, bodies, rule);
        }
    }
}

/// One pass over the points of constraint `c`: together and exactly where
/// they can be (see [`solve_together`]), else one Gauss–Seidel sweep (a few
/// for a fresh manifold).
#[inline(always)]
fn solve(c: &Constraint, points: &mut [Point], bodies: &mut [SolverBody], rule: &Rule) {
    if c.central && c.len == 1 {
        if let Some(p) = points.get_mut(c.start as usize) {
            solve_central(c, p, bodies, rule);
        }
        return;
    }
    let mut pair = Pair::load(bodies, c);
    let gap = Gap::new(bodies, c);
    // A manifold with nothing to warm start from is swept a few times, so its
    // points share the load from the start: one sweep gives the first point all
    // of it, and the torque of that rocks a box set down flat.
    let sweeps = if c.fresh && c.len > 1 && !rule.relax { FRESH_SWEEPS } else { 1 };
    let range = c.start as usize..(c.start + c.len) as usize;
    let moving = bodies[c.s1 as usize].dynamic && bodies[c.s2 as usize].dynamic;
    if c.len > 1 {
        // At the velocities this pass finds (see `super::rounded_curve`).
        for p in points[range.clone()].iter_mut().filter(|p| p.curve != 0.0) {
            p.curve = pair.curve(bodies, c, p, rule.inv_h);
        }
        if solve_together(c, &mut points[range.clone()], &mut pair, &gap, rule, moving) {
            pair.store(bodies, c);
            return;
        }
    }
    for _ in 0..sweeps {
        for p in &mut points[range.clone()] {
            let Some(law) = rule.law(rule.effective(gap.separation(p)), moving) else {
                continue;
            };
            let curve = pair.curve(bodies, c, p, rule.inv_h);
            let imp = law.impulse(pair.normal_velocity(c, p) + curve * rule.inv_h, p);
            let delta = accumulate(p, imp);
            pair.apply_normal(c, p, delta);
        }
    }
    pair.store(bodies, c);
}

/// Adds the increment `imp` (N·s) to point `p`'s accumulated normal impulse,
/// which stays pushing; returns the change made.
#[inline(always)]
fn accumulate(p: &mut Point, imp: f64) -> f64 {
    let total = (p.normal_impulse + imp).max(0.0);
    let delta = total - p.normal_impulse;
    p.normal_impulse = total;
    delta
}

/// [`solve`] for the one point of a [`Constraint::central`] contact: the
/// same arithmetic without the arms across the normal, which are zero, so
/// neither body's angular velocity is read or written (the 1000-ball pit's
/// velocity and relax passes read and wrote both for every point).
#[inline(always)]
fn solve_central(c: &Constraint, p: &mut Point, bodies: &mut [SolverBody], rule: &Rule) {
    let (a, b) = (&bodies[c.s1 as usize], &bodies[c.s2 as usize]);
    let n = c.normal;
    // `Gap::separation` of a point whose sides are balls or fixed.
    let s = p.base_separation + n.dot(&(b.dp - a.dp)) + n.dot(&p.anchor2) - n.dot(&p.anchor1);
    let Some(law) = rule.law(rule.effective(s), a.dynamic && b.dynamic) else {
        return;
    };
    let (m1, m2) = (a.inv_m, b.inv_m);
    let delta = accumulate(p, law.impulse(n.dot(&(b.v - a.v)), p));
    if c.s1 != 0 {
        bodies[c.s1 as usize].v -= n * (delta * m1);
    }
    if c.s2 != 0 {
        bodies[c.s2 as usize].v += n * (delta * m2);
    }
}

/// The normals of constraint `c` solved again after its friction, in the
/// velocity pass, when a point of it has a gap to close (effective separation
/// above zero: its target `v_n = −s/h` closes the gap exactly in the substep).
/// That target is a position feedback of gain `1/h`; its friction solved after
/// it at the patch's centre turns the body and leaves the points short of it
/// by different amounts, which the next substep's targets ask back. Across the
/// points of an edge that loop grows: a cube pivoting over its edge (both
/// corners lifted a few µm each substep by the arc of its turn) rocked across
/// its mirror plane ×1.12 a substep, an eigenvalue at 43° (8 substeps a
/// period) of the substep's map, and tipped sideways as its face came down
/// (`tests/test_landing_symmetry.py`). Solving the normals last leaves the
/// gaps closed as asked, and the map contracts (0.75 at 41°). A single point
/// is left alone (its friction acts where its normal does, and that loop
/// contracts without it) unless it has a curve (see `super::rounded_curve`):
/// the turn its friction gives the body changes how far the rounded surface
/// closes in the substep, which the normal asked for at the turn before.
/// Euler's disk with μ = 0.5 sank 0.94 / 1.69 mm at 10 / 30 rad/s and lifted
/// off by 0.11 / 0.06 mm; solved again, 0.044 / 0.058 mm and 4 / 2 µm.
pub(super) fn close_gaps(c: &Constraint, points: &mut [Point], bodies: &mut [SolverBody], rule: &Rule) {
    let range = c.start as usize..(c.start + c.len) as usize;
    if c.len < 2 {
        if points[range].iter().any(|p| p.curve != 0.0) {
            solve(c, points, bodies, rule);
        }
        return;
    }
    let gap = Gap::new(bodies, c);
    if points[range].iter().any(|p| rule.effective(gap.separation(p)) > 0.0) {
        solve(c, points, bodies, rule);
    }
}

/// The points of a manifold (an edge or a face on a face) solved together and
/// exactly (see [`super::small_lcp`]): each point's soft step (see [`Law`])
/// as one, `K Δλ = −s_m (v_n + bias) − s_i K λ`. Returns false (nothing
/// changed) where a point is left alone this pass, or the manifold is too
/// large or degenerate.
fn solve_together(c: &Constraint, pts: &mut [Point], pair: &mut Pair, gap: &Gap, rule: &Rule, moving: bool) -> bool {
    if pts.len() > MAX_POINTS {
        return false;
    }
    // The points solved this pass (a point left alone keeps its impulse).
    let mut idx = [0usize; MAX_POINTS];
    let mut laws = [Law::default(); MAX_POINTS];
    let mut n = 0;
    for (i, p) in pts.iter().enumerate() {
        if let Some(law) = rule.law(rule.effective(gap.separation(p)), moving) {
            idx[n] = i;
            laws[n] = law;
            n += 1;
        }
    }
    if n < 2 {
        return false;
    }
    let mut k = [0.0; MAX_POINTS * MAX_POINTS];
    let (mut b, mut x) = ([0.0; MAX_POINTS], [0.0; MAX_POINTS]);
    for a in 0..n {
        let (pa, law) = (&pts[idx[a]], laws[a]);
        for c2 in 0..n {
            k[a * n + c2] = pair.coupling(pa, &pts[idx[c2]]);
        }
        // `K x + b = 0` at the new impulses `x` of the points that push.
        let held: f64 = (0..n).map(|c2| k[a * n + c2] * pts[idx[c2]].normal_impulse).sum();
        b[a] = law.mass_scale * (pair.normal_velocity(c, pa) + pa.curve * rule.inv_h + law.bias) - (1.0 - law.impulse_scale) * held;
    }
    if !small_lcp(&k[..n * n], &b[..n], &mut x[..n]) {
        return false;
    }
    for a in 0..n {
        let p = &mut pts[idx[a]];
        let delta = x[a] - p.normal_impulse;
        p.normal_impulse = x[a];
        pair.apply_normal(c, p, delta);
    }
    true
}
