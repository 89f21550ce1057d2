//! A step's constraints built from the narrow phase's manifolds: the points,
//! arms, masses and patch of each manifold, its geometry kept from the last
//! step's constraint where it holds. On the pool, in two passes
//! (`prepare_parallel.rs`): one in pair order that gives each manifold its
//! solver bodies, its place and the last step's constraint it may keep, then
//! one that lays each out in its place over threads; on one thread, in one
//! pass in pair order, each manifold's records written once (a resting ball
//! pit's where last step's lie: `prepare_in_place.rs`; a still pair's taken
//! whole: `prepare_still.rs`). A manifold's arithmetic depends on nothing
//! built beside it, so every path and thread count gives the same bits (a
//! resting pyramid of 820 boxes spent a third of its step here).

use super::contact::{normal_mass, orthonormal, Constraint, ContactSolver, PairContext, Point};
use super::coplanar::{self, Member};
use super::friction::Patch;
use super::limit_surface::PatchShape;
use super::reuse::{self, Previous};
use super::soft::Softness;
use super::solver_body::{Rounding, SolverBody, Surface};
use crate::body::Bodies;
use crate::collide::collider::Collider;
use crate::collide::material::combine;
use crate::collide::narrow_phase::{pose_in, Contacts, NarrowPhase};
use crate::math::{Mat3, Quat, Vec3};
pub(crate) use still::Carry;

/// Touching pairs below which the constraints are built on one thread (in a
/// step that runs on the pool: see `narrow_phase::MIN_PARALLEL_PAIRS`).
const MIN_PARALLEL: usize = 256;
/// Manifolds handed to a thread at a time.
const PER_TASK: usize = 32;

/// What building a step's constraints needs to know.
pub struct Preparation {
    /// The contact substep (s).
    pub h: f64,
    /// Gravity (m/s²): the support sweeps follow it.
    pub gravity: Vec3,
    /// Lay the constraints out with rayon's parallel iterators.
    pub parallel: bool,
}

#[path = "prepare_still.rs"]
mod still;

#[path = "prepare_in_place.rs"]
mod in_place;

#[path = "prepare_parallel.rs"]
mod parallel;

/// A collider pair's solver bodies, found in the build's first pass (in
/// order: it enters new ones); the rest of its [`PairContext`] is found
/// where its constraints are laid out.
#[derive(Clone, Copy)]
struct PairBodies {
    s: [u32; 2],
    b: [u32; 2],
    pair: (u32, u32),
    slot: u32,
}

impl PairBodies {
    /// The pair's context, at the bodies `b` (the colliders' poses as
    /// `narrow` found them there, if it did).
    fn context(&self, (colliders, narrow): (&[Collider], Option<&NarrowPhase>), b: &Bodies) -> PairContext {
        let (c1, c2) = (&colliders[self.pair.0 as usize], &colliders[self.pair.1 as usize]);
        let [b1, b2] = self.b;
        let poses = narrow.map_or(&[][..], |n| n.poses());
        PairContext {
            s1: self.s[0],
            s2: self.s[1],
            b1,
            b2,
            pose1: pose_in(poses, self.pair.0, c1, b),
            pose2: pose_in(poses, self.pair.1, c2, b),
            x1: Vec3::from(b.position[b1 as usize]),
            x2: Vec3::from(b.position[b2 as usize]),
            material: combine(&c1.material, &c2.material),
            corners: [c1.corners, c2.corners],
            radii: [c1.ball.unwrap_or(0.0), c2.ball.unwrap_or(0.0)],
            pair: self.pair,
            slot: self.slot,
        }
    }
}

/// Where one constraint goes, decided by the first pass.
struct Job {
    /// Its pair's context in the pass's list.
    ctx: u32,
    /// Its manifolds' indices in the pair: `members.1` from `members.0` in the
    /// parallel build's list (see [`super::coplanar`]; the serial build hands
    /// the manifolds over directly).
    members: (u32, u32),
    /// Its points: `len` from `start` in the solver's points.
    start: u32,
    len: u32,
    /// The last step's constraint of the same manifold, if any.
    previous: Option<usize>,
    generalized: bool,
}

/// What the second pass reads.
struct Shared<'a> {
    bodies: &'a [SolverBody],
    previous: &'a Previous,
    /// The world's bodies (their orientations, for [`reuse::still_slack`]).
    world: &'a Bodies,
    /// The depth resting contacts settle to (m; see `super::impulse::REST_DEPTH`).
    rest: f64,
}

impl ContactSolver {
    /// Builds the constraints of this step from the touching pairs (in
    /// parallel on the pool the caller installed, if `step.parallel`).
    pub fn prepare(&mut self, narrow: &NarrowPhase, colliders: &[Collider], b: &Bodies, step: &Preparation) {
        let warm_scale = self.start_step(step.h);
        self.parallel = step.parallel;
        self.support.split = false;
        self.forget_groups();
        let halves = self.build_order(narrow, colliders, b);
        let order = halves.as_ref().map_or(&narrow.touching[..], |(o, _)| &o[..]);
        self.body_ends = None;
        self.in_place = 0;
        if step.parallel && order.len() >= MIN_PARALLEL {
            let pair_ends = halves.as_ref().map(|(_, e)| *e);
            let (contexts, jobs, members) = self.place(narrow, (order, pair_ends), colliders, b);
            self.lay_out((narrow, colliders), (&contexts, &jobs, &members), b);
        } else {
            let done = self.build_in_place(narrow, order, colliders, b);
            self.in_place = done;
            // One pass: each manifold's points are written once, while in cache.
            for &slot in order.get(done..).unwrap_or_default() {
                let state = &narrow.pairs[slot as usize];
                let ctx = self.pair_context((colliders, Some(narrow)), b, state.key, slot);
                self.push_pair(state.contacts(), &ctx, (Carry::of(state), state.prediction), b);
            }
        }
        self.note_orientations(b);
        self.join_flush_pairs(b);
        self.scale_warm_start(warm_scale);
        let g = step.gravity.norm();
        let up = if g > 0.0 { -step.gravity / g } else { Vec3::zeros() };
        self.plan_support(&up, g, b);
        self.plan_links();
        self.plan_halves();
    }

    /// Sets last step's constraints aside and starts this step's with the
    /// fixed world as solver body 0; returns the ratio of this step's substep
    /// to the last one's, by which the warm start is scaled.
    fn start_step(&mut self, h: f64) -> f64 {
        let ratio = if self.inv_h > 0.0 { h * self.inv_h } else { 1.0 };
        for s in &self.bodies[self.bodies.len().min(1)..] {
            self.slot[s.body as usize] = 0;
            self.touching[s.body as usize] = false;
        }
        self.set_aside();
        self.apart.clear();
        self.bodies.push(SolverBody::default());
        self.p0.clear();
        self.q0.clear();
        self.p0.push(Vec3::zeros());
        self.q0.push(Quat::identity());
        self.substeps_done = 0;
        self.gathered = false;
        let hertz = self.settings.contact_hertz.min(0.25 / h);
        self.softness = Softness::new(hertz, self.settings.contact_damping_ratio, h);
        self.inv_h = 1.0 / h;
        ratio
    }

    /// The solver index of world body `i`, creating its entry if it moves.
    fn enter(&mut self, b: &Bodies, i: usize) -> u32 {
        if self.slot[i] != 0 {
            return self.slot[i];
        }
        if !b.moving(i) {
            return 0;
        }
        let dynamic = b.awake(i);
        let [x, y, z] = b.inv_inertia[i];
        let iso = if !dynamic {
            Some(0.0)
        } else if x == y && y == z {
            Some(x)
        } else {
            None
        };
        let inv_i = match iso {
            Some(s) => Mat3::from_diagonal_element(s),
            None => self.reference_inv_inertia(b, i),
        };
        let chord = super::solver_body::chord(Vec3::from(b.angular_velocity[i]) / self.inv_h);
        self.bodies.push(SolverBody {
            inv_m: if dynamic { b.inv_mass[i] } else { 0.0 },
            inv_i,
            iso,
            body: i as u32,
            dynamic,
            chord,
            ..Default::default()
        });
        self.p0.push(Vec3::from(b.position[i]));
        self.q0.push(b.q(i));
        self.touching[i] = dynamic;
        self.slot[i] = (self.bodies.len() - 1) as u32;
        self.slot[i]
    }

    /// Whether a pair's constraints touch an articulated link.
    fn generalized(&self, ([s1, s2], [b1, b2]): ([u32; 2], [u32; 2])) -> bool {
        (s1 != 0 && self.is_link(b1)) || (s2 != 0 && self.is_link(b2))
    }

    /// What the constraints of a collider pair share, at the bodies' current
    /// poses (the colliders' poses as `narrow` found them at these bodies, if
    /// it did).
    pub(crate) fn pair_context(&mut self, (colliders, narrow): (&[Collider], Option<&NarrowPhase>), b: &Bodies, pair: (u32, u32), slot: u32) -> PairContext {
        self.pair_bodies(colliders, b, pair, slot).context((colliders, narrow), b)
    }

    /// The solver bodies of a collider pair, entered if new.
    fn pair_bodies(&mut self, colliders: &[Collider], b: &Bodies, pair: (u32, u32), slot: u32) -> PairBodies {
        let (c1, c2) = (&colliders[pair.0 as usize], &colliders[pair.1 as usize]);
        let (b1, b2) = (c1.body as usize, c2.body as usize);
        let (s1, s2) = (self.enter(b, b1), self.enter(b, b2));
        for (s, c) in [(s1, c1), (s2, c2)] {
            if s != 0 {
                // At the step start's orientation (impacts build contacts later
                // in the step, and the gap turns the axis by the change since).
                let (surface, rounding) = surface_of(c, &self.q0[s as usize]);
                self.bodies[s as usize].surface = surface;
                self.bodies[s as usize].rounding = rounding;
            }
        }
        PairBodies { s: [s1, s2], b: [b1 as u32, b2 as u32], pair, slot }
    }

    /// Appends the constraints of a pair's manifolds (those of one normal
    /// together: see [`super::coplanar`]), of their points no further apart
    /// than `reach` (m), with what they carry over from last step (see
    /// [`Carry`]).
    pub(crate) fn push_pair<'a>(&mut self, contacts: impl Iterator<Item = Member<'a>>, ctx: &PairContext, (carry, reach): (Carry, f64), world: &Bodies) {
        let grouping = |all: &[Member], leads: &mut Vec<u32>| coplanar::group(ctx, all, leads);
        each_group(contacts, grouping, reach, |group| self.push_group(group, ctx, (carry, reach), world));
    }

    /// Appends the constraint of a group of a pair's manifolds (see
    /// [`ContactSolver::push_pair`]).
    fn push_group(&mut self, group: &[Member], ctx: &PairContext, (carry, reach): (Carry, f64), world: &Bodies) {
        let len = group.iter().map(|(_, c)| within(c, reach)).sum();
        let previous = if carry.warm { self.previous.find(ctx.pair, group[0].0) } else { None };
        let start = self.points.len() as u32;
        let job = Job { ctx: 0, members: (0, group.len() as u32), start, len, previous, generalized: self.generalized(([ctx.s1, ctx.s2], [ctx.b1, ctx.b2])) };
        let mut src = Source::new(ctx, group, carry, reach);
        let shared = Shared { bodies: &self.bodies, previous: &self.previous, world, rest: self.rest_depth() };
        let points = &mut self.points;
        let kept_still = shared.still(&job, &src, |p| points.push(p));
        if kept_still.is_none() {
            points.truncate(start as usize);
            src.find_normal();
            src.points(|p| points.push(p));
        }
        let pts = &mut self.points[start as usize..];
        let (constraint, kept) = shared.constraint_or_still(&job, &src, kept_still, pts);
        self.patches.push(Patch::default());
        self.shapes.push(PatchShape::default());
        if let (Some(patch), Some(shape)) = (self.patches.last_mut(), self.shapes.last_mut()) {
            shared.patch((patch, shape), &constraint, kept, &src, pts);
        }
        self.constraints.push(constraint);
        if carry.warm {
            self.previous.kept.push(kept.map_or(reuse::NONE, |o| o as u32));
        }
    }
}

/// How many points of a manifold are within `reach` (m).
fn within(manifold: &Contacts, reach: f64) -> u32 {
    manifold.points.iter().filter(|tp| tp.dist <= reach).count() as u32
}

/// `each` on every group of a pair's manifolds with a point within `reach`
/// (m; see [`super::coplanar`]), in order. A pair of one manifold (most
/// pairs) is its own group, found without allocating.
/// `grouping` groups two or more manifolds as [`coplanar::group`] does.
fn each_group<'a>(
    contacts: impl Iterator<Item = Member<'a>>,
    grouping: impl FnOnce(&[Member<'a>], &mut Vec<u32>) -> usize,
    reach: f64,
    mut each: impl FnMut(&[Member<'a>]),
) {
    let mut touching = contacts.filter(|(_, c)| within(c, reach) > 0);
    let Some(first) = touching.next() else { return };
    let Some(second) = touching.next() else { return each(&[first]) };
    let mut all = vec![first, second];
    all.extend(touching);
    let mut leads = Vec::with_capacity(all.len());
    let n = grouping(&all, &mut leads);
    if n == all.len() {
        return all.chunks(1).for_each(each);
    }
    let mut group = Vec::with_capacity(all.len());
    for g in 0..n as u32 {
        group.clear();
        group.extend(all.iter().zip(&leads).filter(|(_, &l)| l == g).map(|(m, _)| *m));
        each(&group);
    }
}

/// The manifolds of one constraint as the builder reads them.
struct Source<'a, 'b> {
    ctx: &'a PairContext,
    members: &'a [Member<'b>],
    /// Start from the impulses the manifold carries and keep last step's
    /// geometry if it holds (not for an impact's contact).
    warm: bool,
    /// Points further apart than this (m) are left out.
    reach: f64,
    /// World normal: the first manifold's.
    normal: Vec3,
    /// See [`Carry`].
    still: bool,
    tracked: bool,
}

impl<'a, 'b> Source<'a, 'b> {
    /// A still pair's normal is found only if its constraint cannot be kept
    /// as it was (see [`Self::find_normal`]).
    fn new(ctx: &'a PairContext, members: &'a [Member<'b>], carry: Carry, reach: f64) -> Self {
        let Carry { warm, still, tracked } = carry;
        let normal = if still { Vec3::zeros() } else { coplanar::normal_of(ctx, &members[0].1) };
        Source { ctx, members, warm, reach, normal, still, tracked }
    }

    /// The normal, for a still pair whose constraint could not be kept (the
    /// others found it in [`Self::new`]).
    fn find_normal(&mut self) {
        if self.still {
            self.normal = coplanar::normal_of(self.ctx, &self.members[0].1);
        }
    }

    /// Every point of the manifolds, within reach or not.
    fn all_points(&self) -> impl Iterator<Item = &crate::collide::narrow_phase::Tracked> {
        self.members.iter().flat_map(|(_, m)| m.points.iter())
    }

    /// The manifolds' points within reach, anchored at the step start, each
    /// handed to `put`: a serial build pushes them, with no zeroed slots to
    /// overwrite (and no `Option<Point>` moved per point, as by an iterator).
    #[inline(always)]
    fn points(&self, mut put: impl FnMut(Point)) {
        for (index, m) in self.members {
            self.points_of(*index, m, &mut put);
        }
    }

    #[inline(always)]
    fn points_of(&self, index: u32, m: &Contacts, put: &mut impl FnMut(Point)) {
        let (ctx, n) = (self.ctx, self.normal);
        let sub1 = m.subshape_pos1.map_or(ctx.pose1, |s| ctx.pose1 * s);
        let sub2 = m.subshape_pos2.map_or(ctx.pose2, |s| ctx.pose2 * s);
        for (k, tp) in m.points.iter().enumerate().filter(|(_, tp)| tp.dist <= self.reach) {
            let mid = ((sub1 * tp.local_p1).coords + (sub2 * tp.local_p2).coords) * 0.5;
            let (r1, r2) = (mid - ctx.x1, mid - ctx.x2);
            put(Point {
                anchor1: r1,
                anchor2: r2,
                r1,
                r2,
                base_separation: tp.dist - n.dot(&(r2 - r1)),
                separation: tp.dist,
                point: mid,
                normal_impulse: if self.warm { tp.data.normal_impulse } else { 0.0 },
                manifold: index,
                manifold_point: k as u16,
                // A corner of a fixed shape under a moving face (a vertex of a
                // floor's triangle under a box) moves with the face: held
                // still, a sliding face leaves it behind within the step and
                // the patch's polygon and centre with it.
                corner: match (ctx.corners[0].at(tp.fid1, &tp.local_p1), ctx.corners[1].at(tp.fid2, &tp.local_p2)) {
                    (true, false) if ctx.s1 != 0 => 1,
                    (false, true) if ctx.s2 != 0 => 2,
                    _ => 0,
                },
                ..Default::default()
            });
        }
    }
}

impl Shared<'_> {
    /// Last step's constraint, if [`Self::still`] kept it (`still`), else the
    /// one of the points `pts` laid out; and last step's it kept, if any.
    #[inline(always)]
    fn constraint_or_still(&self, job: &Job, src: &Source, still: Option<(usize, f64)>, pts: &mut [Point]) -> (Constraint, Option<usize>) {
        match still {
            Some(kept) => self.kept_still(job, src, kept),
            None => self.constraint(job, src, pts),
        }
    }

    /// The constraint of one manifold whose points `pts` are laid out, their
    /// arms and masses (kept from last step's constraint of the manifold when
    /// they hold, which it returns).
    #[inline(always)]
    fn constraint(&self, job: &Job, src: &Source, pts: &mut [Point]) -> (Constraint, Option<usize>) {
        let ctx = src.ctx;
        let kept = job.previous.and_then(|o| reuse::holds(self.previous, self.bodies, o, ctx, &src.normal, pts).map(|w| (o, w)));
        let central = job.len == 1 && !job.generalized && self.central(ctx);
        let basis = match kept {
            Some((o, _)) => reuse::keep(self.previous, o, pts),
            None => {
                let n = src.normal;
                let t1 = orthonormal(&n);
                let (b1, b2) = (&self.bodies[ctx.s1 as usize], &self.bodies[ctx.s2 as usize]);
                for p in pts.iter_mut() {
                    normal_mass(p, (b1, b2), &n, central);
                }
                (n, t1, n.cross(&t1))
            }
        };
        // Tracked only where a later step may keep it as still (not an
        // impact's contact, built after the step's orientations are noted, nor
        // a pair of balls: its room costs a square root a contact).
        let (slack, arm) = if src.warm && src.tracked {
            reuse::slack_of(pts, kept.map_or(0.0, |(_, w)| w))
        } else {
            (f64::NEG_INFINITY, 0.0)
        };
        (Constraint { central, ..Self::assemble(job, src, basis, (slack, arm)) }, kept.map(|(o, _)| o))
    }

    /// The constraint of `job` with normal and tangents `n, t1, t2`.
    #[inline(always)]
    fn assemble(job: &Job, src: &Source, (n, t1, t2): (Vec3, Vec3, Vec3), (slack, arm): (f64, f64)) -> Constraint {
        let ctx = src.ctx;
        Constraint {
            s1: ctx.s1,
            s2: ctx.s2,
            normal: n,
            t1,
            t2,
            friction: ctx.material.friction,
            static_friction: ctx.material.static_friction,
            restitution: ctx.material.restitution,
            start: job.start,
            len: job.len,
            b1: ctx.b1,
            b2: ctx.b2,
            pair: ctx.pair,
            slot: ctx.slot,
            manifold: src.members[0].0,
            fresh: !src.warm || src.all_points().all(|tp| tp.data.normal_impulse == 0.0),
            lower: 0,
            group: 0,
            generalized: job.generalized,
            settled: true,
            landing: false,
            as_built: true,
            joined: false,
            slack,
            arm,
            still: false,
            central: false,
            ball: ctx.radii.iter().any(|&r| r > 0.0),
        }
    }

    /// Whether each side of the pair is fixed or a ball centred on its body's
    /// centre of mass (not one of varying density), and the two are not so
    /// unequal that one may hold the other as a support (see
    /// [`Constraint::central`]).
    #[inline(always)]
    fn central(&self, ctx: &PairContext) -> bool {
        let (a, b) = (&self.bodies[ctx.s1 as usize], &self.bodies[ctx.s2 as usize]);
        let side = |s: u32, body: &SolverBody, pose: &nalgebra::Isometry3<f64>, x: &Vec3| {
            s == 0 || (body.surface == Surface::Ball && pose.translation.vector == *x)
        };
        side(ctx.s1, a, &ctx.pose1, &ctx.x1) && side(ctx.s2, b, &ctx.pose2, &ctx.x2) && !super::support::unequal(a, b)
    }

    /// The friction patch of constraint `c` (its geometry kept from last step's
    /// constraint `kept`), warm-started from what the manifold's points carry,
    /// written in place: built and moved, the patch and its polygon were 3 %
    /// of a 1000-ball pit's step in `memmove`.
    #[inline(always)]
    fn patch(&self, (patch, shape): (&mut Patch, &mut PatchShape), c: &Constraint, kept: Option<usize>, src: &Source, pts: &[Point]) {
        match kept {
            Some(o) => {
                patch.take_geometry_of(&self.previous.patches[o]);
                *shape = self.previous.shapes[o];
            }
            None => {
                *patch = Patch::default();
                patch.set_geometry(shape, c, pts, self.bodies);
            }
        }
        warm_patch(patch, c, src, pts, self.rest);
    }
}

/// The spin lever and warm start of constraint `c`'s patch, its geometry
/// set (see [`Shared::patch`]).
#[inline(always)]
fn warm_patch(patch: &mut Patch, c: &Constraint, src: &Source, pts: &[Point], rest: f64) {
    patch.spin = if c.central { spin_lever(src.ctx, pts, rest) } else { 0.0 };
    if src.warm {
        // Each point carries its share of the patch's impulses: summed, they
        // survive points that appear or vanish between steps.
        let ft: Vec3 = src.all_points().map(|tp| Vec3::from(tp.data.friction_impulse)).sum();
        patch.impulse = [ft.dot(&c.t1), ft.dot(&c.t2)];
        if patch.lever > 0.0 || patch.spin > 0.0 {
            patch.twist = src.all_points().map(|tp| tp.data.twist_impulse).sum();
        }
        patch.sliding = src.all_points().any(|tp| tp.data.sliding);
    }
}

/// The lever (m) of the spin friction of a central contact's point: Coulomb
/// friction over a Hertz patch of radius `a = √(R δ)` (its pressure
/// elliptical) resists a spin with `3π/16 · a` times its force, `R` the balls' combined radius
/// (`R1 R2 / (R1 + R2)`, a flat side's infinite), `δ` the depth at the step
/// start, at least `rest`, the depth resting contacts settle to (`REST_DEPTH`
/// of the slop, 1 µm at the defaults).
fn spin_lever(ctx: &PairContext, pts: &[Point], rest: f64) -> f64 {
    let [r1, r2] = ctx.radii;
    let r = match (r1 > 0.0, r2 > 0.0) {
        (true, true) => r1 * r2 / (r1 + r2),
        (true, false) => r1,
        (false, true) => r2,
        (false, false) => return 0.0,
    };
    let depth = pts.first().map_or(0.0, |p| -p.separation).max(rest);
    3.0 * std::f64::consts::PI / 16.0 * (r * depth).sqrt()
}

/// How the contact points of collider `c` follow its body as it turns (see
/// [`Gap`](super::solver_body::Gap)), and its rounding for the body's
/// orientation `q`.
fn surface_of(c: &Collider, q: &Quat) -> (Surface, Rounding) {
    use parry3d_f64::shape::TypedShape;
    // A ball known without asking its shape (twice a pair in a ball pit).
    if c.ball.is_some() {
        return (Surface::Ball, Rounding::default());
    }
    match c.shape.as_typed_shape() {
        TypedShape::Ball(_) => (Surface::Ball, Rounding::default()),
        TypedShape::Capsule(k) => (Surface::Rounded, Rounding { radius: k.radius, axis: Vec3::zeros() }),
        // parry's cylinders and cones stand along their frame's y axis (a
        // cone's apex is a corner: see `collide::corners`).
        TypedShape::Cylinder(k) => (Surface::Rounded, Rounding { radius: k.radius, axis: axis_of(c, q) }),
        TypedShape::Cone(k) => (Surface::Rounded, Rounding { radius: k.radius, axis: axis_of(c, q) }),
        _ => (Surface::Material, Rounding::default()),
    }
}

/// The world direction of collider `c`'s y axis for its body's orientation `q`.
fn axis_of(c: &Collider, q: &Quat) -> Vec3 {
    crate::math::quat::rotate(q, &(c.local.rotation * nalgebra::Vector3::y()))
}
