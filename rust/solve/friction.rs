//! Coulomb friction on a true cone, one friction patch per manifold (as Bepu and
//! PhysX's patch friction): a 2D tangential impulse at the centre of the
//! manifold's points and a twist impulse about the normal, limited together by
//! the patch's limit surface (see [`super::limit_surface`]): `μ` times the
//! manifold's total normal impulse for the force, times the patch's lever for
//! the twist, the two coupled.
//!
//! A patch sticks while the impulse that stops it (force and twist solved
//! together) fits the static limit `μs N`; once sliding it feels the friction of
//! its slip and spin with `μk N` (Coulomb's law over the patch) until it stops. How the load of a rigid body splits between its contact points
//! is an artefact of the solve, so friction is not decided point by point: a
//! Gauss–Seidel sweep would have each point try to stop the whole body alone and
//! give up, and points sliding independently would fan and yaw a sliding box. No
//! pyramid: the friction force has no preferred axes.

use super::contact::{Constraint, ContactSolver, Point};
use super::impulse::{close_gaps, Rule};
use super::limit_surface::{inside, norm2, onto, PatchShape};
use super::pair::Pair;
use super::solver_body::{Gap, SolverBody, Surface};
use crate::math::Vec3;

/// Slip speed (m/s) below which a sliding patch's friction keeps the direction of
/// the impulse that would stop it: the direction of a slower slip is noise.
pub(crate) const SLIP_EPS: f64 = 1e-3;

/// How far (m) beyond the nearest point of a manifold (or beyond touching) a
/// point still counts as part of its patch: far below what a contact resolves,
/// far above the round-off of a face resting flat.
const TOUCH: f64 = 1e-4;

/// Separation (m) up to which a point of a manifold counts as touching, given
/// the separation of its nearest point.
pub(crate) fn touch_reach(nearest: f64) -> f64 {
    nearest.max(0.0) + TOUCH
}

/// The friction of one manifold.
#[derive(Clone, Copy, Debug, Default, serde::Serialize, serde::Deserialize)]
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
    /// Inverse of the 3x3 effective mass of the tangent directions and the twist
    /// together, `[k00, k01, k02, k11, k12, k22]` (the tangent block alone when
    /// the patch has no lever).
    pub friction_mass: [f64; 6],
    /// The lever of the patch's twist (m; see [`PatchShape`]), 0 for a patch
    /// of one point. The polygon itself is kept apart, in
    /// `ContactSolver::shapes` (same index): only a patch that slides reads
    /// it, and inside the patch its 128 bytes were a quarter of what every
    /// friction pass streams through (a 1000-ball pit's patches have none).
    pub lever: f64,
    /// The lever (m) of the friction against the spin about the normal of a
    /// [`Constraint::central`] contact (a ball's): `3π/16` of the radius of
    /// the Hertz patch its depth presses (see `super::prepare`); 0 elsewhere.
    /// A point has no patch to twist, and a ball that rolls to and fro in the
    /// groove of two others turns about both contacts' normals: without it,
    /// nothing stopped that.
    #[serde(default)]
    pub spin: f64,
    /// `1 / (n·(I1⁻¹ + I2⁻¹) n)`, the effective inertia of that spin (kg·m²).
    #[serde(default)]
    pub spin_mass: f64,
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
    /// How much farther (m, along `t1`, `t2`) body 2's material point at the
    /// centre travels in a substep than body 1's beyond what their velocities
    /// carry them (see [`SolverBody::chord_gap`]): sticking, friction holds
    /// their relative velocity at minus this over the substep, so that the
    /// points travel together.
    pub drift: [f64; 2],
}

impl Patch {
    /// Arms, effective masses, lever and polygon of the patch of `points` at
    /// their centre.
    pub fn new(c: &Constraint, points: &[Point], bodies: &[SolverBody]) -> (Self, PatchShape) {
        let (mut f, mut shape) = (Patch::default(), PatchShape::default());
        f.set_geometry(&mut shape, c, points, bodies);
        (f, shape)
    }

    /// The geometry of `o` (arms, effective masses, lever) and no impulses,
    /// field by field in place.
    pub fn take_geometry_of(&mut self, o: &Patch) {
        // Every field is set below: a new one fails to compile here.
        let Patch { rt1: _, rt2: _, irt1: _, irt2: _, in1: _, in2: _, tangent_mass: _, friction_mass: _, lever: _, spin: _, spin_mass: _, impulse: _, twist: _, total: _, sliding: _, settled: _, drift: _ } = o;
        self.rt1 = o.rt1;
        self.rt2 = o.rt2;
        self.irt1 = o.irt1;
        self.irt2 = o.irt2;
        self.in1 = o.in1;
        self.in2 = o.in2;
        self.tangent_mass = o.tangent_mass;
        self.friction_mass = o.friction_mass;
        self.lever = o.lever;
        self.spin = o.spin;
        self.spin_mass = o.spin_mass;
        self.drift = o.drift;
        self.forget_impulses();
    }

    /// No impulses, totals or regime: the patch's geometry for a new step.
    pub fn forget_impulses(&mut self) {
        self.impulse = [0.0; 2];
        self.twist = 0.0;
        self.total = [0.0; 2];
        self.sliding = false;
        self.settled = 0.0;
    }

    /// The [`drift`](Patch::drift) friction holds the points to: all of it
    /// while the patch sticks, none while it slides (a can spinning on its
    /// cap: the centre of the points pressing hardest wanders off its axis,
    /// and its chord with it, and the can was pushed sideways at 3e-6 m/s).
    #[inline(always)]
    pub fn holding_drift(&self) -> [f64; 2] {
        if self.sliding {
            [0.0; 2]
        } else {
            self.drift
        }
    }

    /// Brings the arms, effective masses, lever and polygon (`shape`) up to
    /// the points' current arms, keeping the impulses and regime.
    ///
    /// Two balls' one point (isotropic inertias, no chord gap, no polygon)
    /// takes the same arithmetic without the per-side dispatch: a settling pit
    /// sets every ball contact's patch again at every substep (11 500 a step
    /// for 1000 balls), and the dispatch was 5 % of the instructions of its
    /// first 150 steps.
    pub fn set_geometry(&mut self, shape: &mut PatchShape, c: &Constraint, points: &[Point], bodies: &[SolverBody]) {
        let (a1, a2) = (&bodies[c.s1 as usize], &bodies[c.s2 as usize]);
        let m = a1.inv_m + a2.inv_m;
        if let (Some(iso), [p]) = (ball_pair(a1, a2), points) {
            if p.corner == 0 {
                *shape = PatchShape::default();
                self.lever = shape.lever;
                return self.set_ball_geometry(c, (&p.r1, &p.r2), m, iso);
            }
        }
        let (r1, r2) = if points.len() == 1 {
            // One point (a ball's) is its own patch, with no lever.
            *shape = PatchShape::default();
            (points[0].r1, points[0].r2)
        } else {
            patch_of_touching(shape, c, points, bodies)
        };
        self.lever = shape.lever;
        let gap = a2.chord_gap(&r2, &c.normal) - a1.chord_gap(&r1, &c.normal);
        self.fill(c, (&r1, &r2), (gap, m), (|v: &Vec3| a1.inv_i_mul(v), |v: &Vec3| a2.inv_i_mul(v)));
    }

    /// [`Self::set_geometry`] of two balls' one point at arms `r1`, `r2`,
    /// their inverse masses summing to `m`, their isotropic inverse inertias
    /// `s1`, `s2`; its lever and shape (none) are left as they are (see
    /// `refresh::refresh_balls`).
    #[inline(always)]
    pub(crate) fn set_ball_geometry(&mut self, c: &Constraint, arms: (&Vec3, &Vec3), m: f64, (s1, s2): (f64, f64)) {
        self.fill(c, arms, (Vec3::zeros(), m), (|v: &Vec3| v * s1, |v: &Vec3| v * s2));
    }

    /// The arms' products, drift and effective masses of the patch at arms
    /// `r1`, `r2` (its lever set), for a chord gap `gap` (m), inverse masses
    /// summing to `m` and inverse inertias `i1`, `i2` (world frame).
    #[inline(always)]
    fn fill(&mut self, c: &Constraint, (r1, r2): (&Vec3, &Vec3), (gap, m): (Vec3, f64), (i1, i2): (impl Fn(&Vec3) -> Vec3, impl Fn(&Vec3) -> Vec3)) {
        let f = self;
        for (k, t) in [c.t1, c.t2].iter().enumerate() {
            f.rt1[k] = r1.cross(t);
            f.rt2[k] = r2.cross(t);
            f.irt1[k] = i1(&f.rt1[k]);
            f.irt2[k] = i2(&f.rt2[k]);
        }
        f.drift = [c.t1.dot(&gap), c.t2.dot(&gap)];
        f.in1 = i1(&c.normal);
        f.in2 = i2(&c.normal);
        let k_spin = c.normal.dot(&f.in1) + c.normal.dot(&f.in2);
        f.spin_mass = if k_spin > 0.0 { 1.0 / k_spin } else { 0.0 };
        let k = |a: usize, b: usize, ta: &Vec3, tb: &Vec3| m * ta.dot(tb) + f.rt1[a].dot(&f.irt1[b]) + f.rt2[a].dot(&f.irt2[b]);
        let (a, b, cc) = (k(0, 0, &c.t1, &c.t1), k(0, 1, &c.t1, &c.t2), k(1, 1, &c.t2, &c.t2));
        let det = a * cc - b * b;
        f.tangent_mass = if det > 0.0 { [cc / det, -b / det, a / det] } else { [0.0; 3] };
        // A patch of one point (a ball, an edge touching a face) has no lever for
        // a twist: no torsional friction.
        f.friction_mass = if f.lever > 0.0 {
            let tw = |a: usize| f.rt1[a].dot(&f.in1) + f.rt2[a].dot(&f.in2);
            let kww = c.normal.dot(&f.in1) + c.normal.dot(&f.in2);
            invert3([a, b, tw(0), cc, tw(1), kww])
        } else {
            let [p, q, r] = f.tangent_mass;
            [p, q, 0.0, r, 0.0, 0.0]
        };
    }

    /// The friction force and twist after one solve, within the limit of normal
    /// impulse `jn`, given the slip `v` at the centre and the spin `w` about the
    /// normal; updates the regime.
    #[inline(always)]
    pub fn rub(&mut self, shape: &PatchShape, c: &Constraint, v: [f64; 2], w: f64, jn: f64) -> ([f64; 2], f64) {
        let lever = self.lever;
        let w = if lever > 0.0 { w } else { 0.0 };
        // Without a lever the twist's row and column are zero: the tangent
        // block alone gives the same sums.
        let d = if lever > 0.0 {
            mul3(&self.friction_mass, [-v[0], -v[1], -w])
        } else {
            let k = &self.friction_mass;
            [k[0] * -v[0] + k[1] * -v[1], k[1] * -v[0] + k[3] * -v[1], 0.0]
        };
        let cand = [self.impulse[0] + d[0], self.impulse[1] + d[1]];
        let cand_twist = if lever > 0.0 { self.twist + d[2] } else { 0.0 };
        let (f, t) = self.settle(shape, c, cand, cand_twist, v, w, jn);
        if !self.sliding {
            return (f, t);
        }
        let old = [self.impulse[0], self.impulse[1], if lever > 0.0 { self.twist } else { 0.0 }];
        let p = self.dissipating(c.friction * jn, old, [f[0], f[1], t], [v[0], v[1], w]);
        ([p[0], p[1]], p[2])
    }

    /// The spin impulse of a [`Constraint::central`] contact after one solve
    /// at relative spin `w` (rad/s) about the normal, normal impulse `jn` and
    /// friction impulse `l` just solved. A ball's contact point lies on its
    /// normal, so the spin and the slip of the point do not move each other
    /// and are solved apart; what the patch's Coulomb friction can give them
    /// together is shared on the ellipsoidal limit surface,
    /// `(|l|/μjn)² + (τ/(μjn·spin))² ≤ 1`, the spin taking what the force
    /// leaves (a ball sliding at its cone resists no spin).
    #[inline(always)]
    fn resist_spin(&self, c: &Constraint, w: f64, (jn, l): (f64, [f64; 2])) -> f64 {
        let force = c.friction * jn;
        // The limit is `spin·√room`: a twist within it (a ball at rest, the
        // common case) is judged on squares, with no division or square root
        // on the pass's chain (they were a third of the 1000-ball pit's friction).
        let room = force * force - (l[0] * l[0] + l[1] * l[1]);
        let twist = self.twist - w * self.spin_mass;
        if twist * twist <= self.spin * self.spin * room {
            return twist;
        }
        let limit = self.spin * room.max(0.0).sqrt();
        // Not finite in a diverging step (the guard names it): no panic here.
        if !(limit > 0.0 && limit.is_finite()) {
            return 0.0;
        }
        twist.clamp(-limit, limit)
    }

    /// The sliding impulses `p` (force, twist), or as much of the way to them
    /// as takes energy out. Coulomb's force against the slip is applied along
    /// the slip, not in the metric of the patch's effective mass `K`: where
    /// `K` is far from isotropic (a body turning fast on a tilted patch), the
    /// change from the impulses `old` to `p` overshoots across the slip and
    /// gains energy, pass after pass. A cube spun at 1e6 rad/s while wedged in
    /// a column went from 3.3e9 to 1.4e13 J in one step
    /// (`tests/test_fast_spin_in_contact.py`). The change is judged from `old`
    /// brought into the limit of `mu_n` (m/s of slip `u`, impulses as `old`):
    /// a friction lowered because its normal impulse fell gives back what the
    /// higher one took, and is not held (a sliding ball then rolled late: it
    /// broke the work-precision report's `slip_roll`).
    fn dissipating(&self, mu_n: f64, old: [f64; 3], p: [f64; 3], u: [f64; 3]) -> [f64; 3] {
        let twist = self.lever > 0.0;
        let k = if twist {
            invert3(self.friction_mass)
        } else {
            let [a, b, _, d, _, _] = self.friction_mass;
            invert3([a, b, 0.0, d, 0.0, 1.0])
        };
        let keep = |x: [f64; 3]| if twist { x } else { [x[0], x[1], 0.0] };
        let (old, pk, u) = (keep(old), keep(p), keep(u));
        let size = norm2(norm2(old[0], old[1]), if twist { old[2] / self.lever } else { 0.0 });
        let pull = if size > mu_n && size > 0.0 { mu_n / size } else { 1.0 };
        let base = [old[0] * pull, old[1] * pull, old[2] * pull];
        let d = [pk[0] - base[0], pk[1] - base[1], pk[2] - base[2]];
        let kd = mul3(&k, d);
        let kb = mul3(&k, [base[0] - old[0], base[1] - old[1], base[2] - old[2]]);
        let curvature: f64 = (0..3).map(|i| d[i] * kd[i]).sum();
        let slope: f64 = (0..3).map(|i| d[i] * (u[i] + kb[i])).sum();
        let gain = slope + 0.5 * curvature;
        // A gain at round-off of the change is none.
        if !(curvature > 0.0) || gain <= 1e-9 * (slope.abs() + 0.5 * curvature) {
            return p;
        }
        let s = (-2.0 * slope / curvature).clamp(0.0, 1.0);
        [base[0] + s * d[0], base[1] + s * d[1], if twist { base[2] + s * d[2] } else { p[2] }]
    }

    /// The friction of the patch (polygon `shape`) given the impulse `cand`,
    /// `cand_twist` that would stop it: that one if it fits the limit (it
    /// sticks), else Coulomb over the patch for its slip `v` and spin `w` (it
    /// slides).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub fn settle(&mut self, shape: &PatchShape, c: &Constraint, cand: [f64; 2], cand_twist: f64, v: [f64; 2], w: f64, jn: f64) -> ([f64; 2], f64) {
        // Whether it sticks is judged on at least the settled normal impulse; how
        // hard it rubs when it slides, on this pass's.
        let lever = self.lever;
        let hold = if self.sliding { c.friction } else { c.static_friction } * jn.max(self.settled);
        if inside(cand, cand_twist, hold, lever, 0.0) {
            self.sliding = false;
            return (cand, cand_twist);
        }
        self.sliding = true;
        if (v[0] * v[0] + v[1] * v[1]).sqrt() + lever * w.abs() > SLIP_EPS {
            shape.sliding(v, w, c.friction * jn)
        } else {
            onto(cand, cand_twist, c.friction * jn, lever)
        }
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

/// The patch of the points that touch (its polygon into `shape`), and its
/// centre's arms on each body.
///
/// The patch is where the bodies touch: a point predicted ahead (the rim of
/// a spinning top, inches above the floor) carries no friction and must not
/// move the patch's centre or give it a lever. If none touches yet, the
/// nearest ones.
///
/// Its centre is where a uniform pressure over it is centred: the centroid
/// of its polygon, or, when it gathers several manifolds (see
/// `super::coplanar`), see [`PatchShape::gathered`]: two unequal feet on a
/// plane press about their union's centroid, not their hull's.
fn patch_of_touching(shape: &mut PatchShape, c: &Constraint, points: &[Point], bodies: &[SolverBody]) -> (Vec3, Vec3) {
    let gap = Gap::new(bodies, c);
    let nearest = points.iter().map(|p| gap.separation(p)).fold(f64::INFINITY, f64::min);
    let reach = touch_reach(nearest);
    let touching = |p: &&Point| gap.separation(p) <= reach;
    let n = points.iter().filter(touching).count();
    let mean = |arm: fn(&Point) -> Vec3| points.iter().filter(touching).map(arm).sum::<Vec3>() / n.max(1) as f64;
    let (r1, r2) = (mean(|p| p.r1), mean(|p| p.r2));
    let flat = |p: &Point| {
        let d = p.r1 - r1;
        [d.dot(&c.t1), d.dot(&c.t2)]
    };
    let mut few = [[0.0; 2]; super::limit_surface::MAX_VERTICES * 2];
    let many: Vec<[f64; 2]>;
    let flat = if n <= few.len() {
        for (slot, p) in few.iter_mut().zip(points.iter().filter(touching)) {
            *slot = flat(p);
        }
        &few[..n]
    } else {
        many = points.iter().filter(touching).map(flat).collect();
        &many[..]
    };
    if n <= 1 {
        *shape = PatchShape::default();
        return (r1, r2);
    }
    let manifold = |p: &Point| (p.part, p.manifold);
    let first = points.iter().find(touching).map_or((0, 0), manifold);
    let (s, centre) = if points.iter().filter(touching).all(|p| manifold(p) == first) {
        PatchShape::centred(flat)
    } else {
        PatchShape::gathered(flat, runs(points.iter().filter(touching).map(manifold), flat))
    };
    *shape = s;
    let shift = c.t1 * centre[0] + c.t2 * centre[1];
    (r1 + shift, r2 + shift)
}

/// `flat` cut where `ids` (one per entry, in runs) changes.
fn runs<T: PartialEq>(ids: impl Iterator<Item = T>, flat: &[[f64; 2]]) -> impl Iterator<Item = &[[f64; 2]]> {
    let mut cuts = Vec::new();
    let mut last = None;
    for (k, id) in ids.enumerate() {
        if last.is_some_and(|l| l != id) {
            cuts.push(k);
        }
        last = Some(id);
    }
    cuts.push(flat.len());
    let mut start = 0;
    cuts.into_iter().map(move |end| {
        let run = &flat[start.min(end)..end];
        start = end;
        run
    })
}

impl ContactSolver {
    /// One friction pass over the patches solved both ways (support contacts rub
    /// in their blocks, see `super::support`); `relax`: the pass after the
    /// substep's drift. In the velocity pass a manifold with a gap to close has
    /// its normals solved again after its friction (see
    /// [`super::impulse::close_gaps`]).
    pub fn solve_friction(&mut self, relax: bool) {
        let pass = FrictionPass { closing: (!relax).then(|| self.rule(false)), rate: self.drift_rate(relax) };
        if self.by_groups() {
            return self.friction_by_groups(&pass);
        }
        if let Some(h) = self.by_halves() {
            self.each_half(h, |cs, r| {
                let list = cs.ordinary.get(r).unwrap_or(&[]);
                rub_each(list, &cs.constraints, &mut cs.points, (&mut cs.patches, &cs.shapes), &mut cs.bodies, &pass);
                false
            });
            return;
        }
        let (cs, points, bodies) = (&self.constraints, &mut self.points, &mut self.bodies);
        rub_each(&self.ordinary, cs, points, (&mut self.patches, &self.shapes), bodies, &pass);
    }

    /// What turns a patch's [`drift`](Patch::drift) into the slip friction
    /// holds (1/s): `1/h` in the pass before the substep's drift, whose
    /// velocities carry the bodies; 0 in the relax pass after it, whose
    /// velocities start the next substep (held there, the chord of a turn
    /// that friction had just stopped pushed a can coming to rest at 1e-8 m/s).
    pub(crate) fn drift_rate(&self, relax: bool) -> f64 {
        if relax {
            0.0
        } else {
            self.inv_h
        }
    }
}

/// One friction pass: the velocity pass's rule, whose gaps are closed again
/// after the friction (`None` in the relax pass), and the rate its patches'
/// drift is held at (see [`ContactSolver::drift_rate`]).
pub(crate) struct FrictionPass {
    pub closing: Option<Rule>,
    pub rate: f64,
}

/// The isotropic inverse inertias of two balls, whose one-point patches
/// take [`Patch::set_ball_geometry`].
#[inline(always)]
pub(crate) fn ball_pair(a1: &SolverBody, a2: &SolverBody) -> Option<(f64, f64)> {
    let ball = |b: &SolverBody| b.surface == Surface::Ball;
    match (a1.iso, a2.iso) {
        (Some(s1), Some(s2)) if ball(a1) && ball(a2) => Some((s1, s2)),
        _ => None,
    }
}

/// [`rub`] for the patches of the constraints `list`, in order: the one
/// place `rub` is inlined (see `super::impulse::solve_each`).
#[inline(never)]
pub(super) fn rub_each(
    list: &[u32],
    cs: &[Constraint],
    points: &mut [Point],
    (patches, shapes): (&mut [Patch], &[PatchShape]),
    bodies: &mut [SolverBody],
    pass: &FrictionPass,
) {
    for &ci in list {
        let c = &cs[ci as usize];
        if rub(c, points, (&mut patches[ci as usize], &shapes[ci as usize]), bodies, pass.rate) {
            if let Some(rule) = &pass.closing {
                close_gaps(c, points, bodies, rule);
            }
        }
    }
}

/// One friction solve of the patch of constraint `c`; whether it changed an
/// impulse.
#[inline(always)]
fn rub(c: &Constraint, points: &[Point], (f, shape): (&mut Patch, &PatchShape), bodies: &mut [SolverBody], rate: f64) -> bool {
    if c.static_friction == 0.0 {
        return false;
    }
    let points = &points[c.start as usize..(c.start + c.len) as usize];
    let jn: f64 = points.iter().map(|p| p.normal_impulse).sum();
    if jn == 0.0 && f.impulse == [0.0; 2] && f.twist == 0.0 {
        return false;
    }
    let mut pair = Pair::load(bodies, c);
    let [u, v] = pair.patch_velocity(c, f);
    let drift = f.holding_drift();
    let slip = [u + drift[0] * rate, v + drift[1] * rate];
    let spin = pair.twist_velocity(c);
    let (l, twist) = f.rub(shape, c, slip, spin, jn);
    let twist = if f.spin > 0.0 { f.resist_spin(c, spin, (jn, l)) } else { twist };
    let d = [l[0] - f.impulse[0], l[1] - f.impulse[1]];
    let dt = twist - f.twist;
    f.impulse = l;
    f.twist = twist;
    pair.apply_patch(c, f, d);
    if dt != 0.0 {
        pair.apply_twist(f, dt);
    }
    pair.store(bodies, c);
    d != [0.0; 2] || dt != 0.0
}

/// Inverse of the symmetric 3x3 `[k00, k01, k02, k11, k12, k22]` (zeros if
/// singular).
pub(crate) fn invert3(k: [f64; 6]) -> [f64; 6] {
    let [a, b, c, d, e, f] = k;
    let (c00, c01, c02) = (d * f - e * e, c * e - b * f, b * e - c * d);
    let det = a * c00 + b * c01 + c * c02;
    if det.abs() <= 1e-300 || !det.is_finite() {
        return [0.0; 6];
    }
    let (c11, c12, c22) = (a * f - c * c, b * c - a * e, a * d - b * b);
    [c00 / det, c01 / det, c02 / det, c11 / det, c12 / det, c22 / det]
}

/// `K x` for the symmetric 3x3 `k`.
#[inline(always)]
pub(crate) fn mul3(k: &[f64; 6], x: [f64; 3]) -> [f64; 3] {
    [
        k[0] * x[0] + k[1] * x[1] + k[2] * x[2],
        k[1] * x[0] + k[3] * x[1] + k[4] * x[2],
        k[2] * x[0] + k[4] * x[1] + k[5] * x[2],
    ]
}
