//! Contact constraints built once per step from the narrow phase's manifolds:
//! anchors, normal and tangent basis, effective masses; and the bookkeeping
//! around the solve (solver bodies, warm start, totals for reporting, data kept
//! for next step).
//!
//! Anchors are fixed at the step start; the separation is updated during the
//! substeps from how far each body has moved and turned since (as in Box2D v3),
//! without running collision detection again. The solve works on a packed copy of
//! the bodies it touches (`SolverBody`), gathered before and scattered after each
//! solve phase, so its inner loops read one contiguous record per body.

use super::soft::Softness;
use crate::body::Bodies;
use crate::collide::collider::Collider;
use crate::collide::material::{combine, ContactMaterial};
use crate::collide::narrow_phase::{ContactReport, Manifold, NarrowPhase};
use nalgebra::Isometry3;
use crate::math::{quat, Mat3, Quat, Vec3};

/// Contact solver parameters, each with its unit and default.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolverSettings {
    /// Stiffness of contacts as a natural frequency (Hz); capped at a quarter of
    /// the substep rate. Default 30.
    pub contact_hertz: f64,
    /// Damping ratio of contacts (–). Default 10 (over-damped: no bounce from the
    /// position correction).
    pub contact_damping_ratio: f64,
    /// Largest speed at which penetration is pushed out (m/s). Default 3.
    pub max_push_velocity: f64,
    /// Approach speed below which contacts do not bounce (m/s). Default 1; 0 allowed.
    pub restitution_threshold: f64,
    /// Distance within which contacts are created before touching (m), on top of
    /// the distance bodies can close in a step. Default 0.005.
    pub margin: f64,
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            contact_hertz: 30.0,
            contact_damping_ratio: 10.0,
            max_push_velocity: 3.0,
            restitution_threshold: 1.0,
            margin: 0.005,
        }
    }
}

/// A body as the solver sees it. Entry 0 stands for every fixed body.
#[derive(Clone, Copy, Debug)]
pub struct SolverBody {
    pub v: Vec3,
    pub w: Vec3,
    /// Position and rotation change since the step start.
    pub dp: Vec3,
    pub dq: Quat,
    pub inv_m: f64,
    pub inv_i: Mat3,
    /// Index in the world's bodies, and whether its velocities are written back.
    pub body: u32,
    pub dynamic: bool,
}

impl Default for SolverBody {
    fn default() -> Self {
        Self {
            v: Vec3::zeros(),
            w: Vec3::zeros(),
            dp: Vec3::zeros(),
            dq: Quat::identity(),
            inv_m: 0.0,
            inv_i: Mat3::zeros(),
            body: u32::MAX,
            dynamic: false,
        }
    }
}

/// The two bodies of a constraint, held in registers while its points are solved.
pub struct Pair {
    pub v1: Vec3,
    pub w1: Vec3,
    pub v2: Vec3,
    pub w2: Vec3,
    m1: f64,
    m2: f64,
    dp1: Vec3,
    dp2: Vec3,
    dq1: Quat,
    dq2: Quat,
}

impl Pair {
    #[inline(always)]
    pub fn load(bodies: &[SolverBody], c: &Constraint) -> Self {
        let (a, b) = (&bodies[c.s1 as usize], &bodies[c.s2 as usize]);
        Self { v1: a.v, w1: a.w, v2: b.v, w2: b.w, m1: a.inv_m, m2: b.inv_m, dp1: a.dp, dp2: b.dp, dq1: a.dq, dq2: b.dq }
    }

    /// Writes the velocities back (the fixed entry 0 receives zeros unchanged).
    #[inline(always)]
    pub fn store(&self, bodies: &mut [SolverBody], c: &Constraint) {
        let a = &mut bodies[c.s1 as usize];
        a.v = self.v1;
        a.w = self.w1;
        let b = &mut bodies[c.s2 as usize];
        b.v = self.v2;
        b.w = self.w2;
    }

    /// Current separation: the step-start separation plus how far the anchors
    /// have moved apart along the normal since (m).
    #[inline(always)]
    pub fn separation(&self, c: &Constraint, p: &Point) -> f64 {
        let d2 = self.dp2 + if c.s2 == 0 { p.anchor2 } else { rotate(&self.dq2, &p.anchor2) };
        let d1 = self.dp1 + if c.s1 == 0 { p.anchor1 } else { rotate(&self.dq1, &p.anchor1) };
        p.base_separation + c.normal.dot(&(d2 - d1))
    }

    #[inline(always)]
    pub fn normal_velocity(&self, c: &Constraint, p: &Point) -> f64 {
        c.normal.dot(&(self.v2 - self.v1)) + self.w2.dot(&p.rn2) - self.w1.dot(&p.rn1)
    }

    #[inline(always)]
    pub fn tangent_velocity(&self, c: &Constraint, p: &Point) -> [f64; 2] {
        let dv = self.v2 - self.v1;
        [
            c.t1.dot(&dv) + self.w2.dot(&p.rt2[0]) - self.w1.dot(&p.rt1[0]),
            c.t2.dot(&dv) + self.w2.dot(&p.rt2[1]) - self.w1.dot(&p.rt1[1]),
        ]
    }

    #[inline(always)]
    pub fn apply_normal(&mut self, c: &Constraint, p: &Point, j: f64) {
        self.v1 -= c.normal * (j * self.m1);
        self.w1 -= p.irn1 * j;
        self.v2 += c.normal * (j * self.m2);
        self.w2 += p.irn2 * j;
    }

    #[inline(always)]
    pub fn apply_tangent(&mut self, c: &Constraint, p: &Point, d: [f64; 2]) {
        let imp = c.t1 * d[0] + c.t2 * d[1];
        self.v1 -= imp * self.m1;
        self.w1 -= p.irt1[0] * d[0] + p.irt1[1] * d[1];
        self.v2 += imp * self.m2;
        self.w2 += p.irt2[0] * d[0] + p.irt2[1] * d[1];
    }
}

/// What the constraints of one collider pair share.
pub struct PairContext {
    pub s1: u32,
    pub s2: u32,
    pub b1: u32,
    pub b2: u32,
    pub pose1: Isometry3<f64>,
    pub pose2: Isometry3<f64>,
    pub x1: Vec3,
    pub x2: Vec3,
    pub material: ContactMaterial,
    pub pair: (u32, u32),
}

/// One contact point.
#[derive(Clone, Copy, Debug, Default)]
pub struct Point {
    /// Anchors relative to each centre of mass at the step start, world (m).
    pub anchor1: Vec3,
    pub anchor2: Vec3,
    /// Current arms from each centre of mass to the contact point (m): both end at
    /// the same world point, midway between the anchors as the bodies have moved,
    /// so equal and opposite impulses keep angular momentum exactly.
    pub r1: Vec3,
    pub r2: Vec3,
    /// `r × n` and `I⁻¹ (r × n)` of each body.
    pub rn1: Vec3,
    pub rn2: Vec3,
    pub irn1: Vec3,
    pub irn2: Vec3,
    /// `r × t` and `I⁻¹ (r × t)` of each body, for `t1` and `t2`.
    pub rt1: [Vec3; 2],
    pub rt2: [Vec3; 2],
    pub irt1: [Vec3; 2],
    pub irt2: [Vec3; 2],
    /// Separation at the step start minus `n·(anchor2 − anchor1)` (m).
    pub base_separation: f64,
    /// Separation at the step start (m); negative when penetrating.
    pub separation: f64,
    /// World contact point at the step start, midway between the surfaces (m).
    pub point: Vec3,
    /// `1/K` with `K = 1/m1 + 1/m2 + n·(I1⁻¹(r1×n)×r1 + I2⁻¹(r2×n)×r2)` (kg).
    pub normal_mass: f64,
    /// Inverse of the 2x2 tangent effective mass, `[a, b, c]` of `[[a, b], [b, c]]` (kg).
    pub tangent_mass: [f64; 3],
    /// Accumulated impulses of the current substep (N·s).
    pub normal_impulse: f64,
    pub tangent_impulse: [f64; 2],
    /// Impulses summed over the step, for reporting (N·s).
    pub total_normal: f64,
    pub total_tangent: [f64; 2],
    /// Index of this point in its parry manifold.
    pub manifold_point: u32,
}

/// The points of one manifold, sharing bodies, normal and material.
#[derive(Clone, Copy, Debug)]
pub struct Constraint {
    /// Solver-body indices (0: fixed).
    pub s1: u32,
    pub s2: u32,
    /// World normal from body 1 to body 2, and the tangent basis.
    pub normal: Vec3,
    pub t1: Vec3,
    pub t2: Vec3,
    pub friction: f64,
    pub static_friction: f64,
    pub restitution: f64,
    /// Range of the points in `ContactSolver::points`.
    pub start: u32,
    pub len: u32,
    /// Bodies, collider pair and manifold index it came from.
    pub b1: u32,
    pub b2: u32,
    pub pair: (u32, u32),
    pub manifold: u32,
}

/// The contact solver's state for one step.
#[derive(Default)]
pub struct ContactSolver {
    pub constraints: Vec<Constraint>,
    pub points: Vec<Point>,
    pub bodies: Vec<SolverBody>,
    /// Per world body: its solver index this step (0 when not in the solve).
    slot: Vec<u32>,
    /// Per solver body: pose at the step start.
    p0: Vec<Vec3>,
    q0: Vec<Quat>,
    /// Per world body: whether it is dynamic, awake and in some constraint this step.
    pub touching: Vec<bool>,
    pub softness: Softness,
    pub inv_h: f64,
    pub settings: SolverSettings,
    substeps_done: u32,
    /// Whether the solver bodies have been gathered since `prepare`.
    gathered: bool,
}

/// Any unit vector orthogonal to `n`.
pub fn orthonormal(n: &Vec3) -> Vec3 {
    let a = if n.x.abs() < 0.577 { Vec3::x() } else if n.y.abs() < 0.577 { Vec3::y() } else { Vec3::z() };
    let t = a - n * n.dot(&a);
    t / t.norm()
}

#[inline(always)]
fn rotate(q: &Quat, v: &Vec3) -> Vec3 {
    quat::rotate(q, v)
}

impl ContactSolver {
    pub fn new(n_bodies: usize, settings: SolverSettings) -> Self {
        Self { slot: vec![0; n_bodies], touching: vec![false; n_bodies], settings, ..Default::default() }
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
        let inv_i = if dynamic { inv_inertia_world(b, i) } else { Mat3::zeros() };
        self.bodies.push(SolverBody {
            inv_m: if dynamic { b.inv_mass[i] } else { 0.0 },
            inv_i,
            body: i as u32,
            dynamic,
            ..Default::default()
        });
        self.p0.push(Vec3::from(b.position[i]));
        self.q0.push(b.q(i));
        self.touching[i] = dynamic;
        self.slot[i] = (self.bodies.len() - 1) as u32;
        self.slot[i]
    }

    /// Builds the constraints of this step from the touching pairs.
    pub fn prepare(&mut self, narrow: &NarrowPhase, colliders: &[Collider], b: &Bodies, h: f64) {
        for s in &self.bodies[self.bodies.len().min(1)..] {
            self.slot[s.body as usize] = 0;
            self.touching[s.body as usize] = false;
        }
        self.constraints.clear();
        self.points.clear();
        self.bodies.clear();
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
        for &(ci, cj) in &narrow.touching {
            let Some(state) = narrow.pairs.get(&(ci, cj)) else { continue };
            let ctx = self.pair_context(colliders, b, (ci, cj));
            for (m, manifold) in state.manifolds.iter().enumerate() {
                self.push_manifold(manifold, &ctx, m as u32, true);
            }
        }
    }

    /// What the constraints of a collider pair share, at the bodies' current poses.
    pub(crate) fn pair_context(&mut self, colliders: &[Collider], b: &Bodies, pair: (u32, u32)) -> PairContext {
        let (c1, c2) = (&colliders[pair.0 as usize], &colliders[pair.1 as usize]);
        let (b1, b2) = (c1.body as usize, c2.body as usize);
        PairContext {
            s1: self.enter(b, b1),
            s2: self.enter(b, b2),
            b1: b1 as u32,
            b2: b2 as u32,
            pose1: c1.pose(b),
            pose2: c2.pose(b),
            x1: Vec3::from(b.position[b1]),
            x2: Vec3::from(b.position[b2]),
            material: combine(&c1.material, &c2.material),
            pair,
        }
    }

    /// Appends the constraint of one parry manifold (nothing if it has no point);
    /// `warm`: start from the impulses the manifold carries.
    pub(crate) fn push_manifold(&mut self, manifold: &Manifold, ctx: &PairContext, index: u32, warm: bool) {
        if manifold.points.is_empty() {
            return;
        }
        let sub1 = manifold.subshape_pos1.map_or(ctx.pose1, |s| ctx.pose1 * s);
        let sub2 = manifold.subshape_pos2.map_or(ctx.pose2, |s| ctx.pose2 * s);
        let n = sub1.rotation * manifold.local_n1;
        let t1 = orthonormal(&n);
        let t2 = n.cross(&t1);
        let start = self.points.len() as u32;
        for (k, tp) in manifold.points.iter().enumerate() {
            let mid = ((sub1 * tp.local_p1).coords + (sub2 * tp.local_p2).coords) * 0.5;
            let (r1, r2) = (mid - ctx.x1, mid - ctx.x2);
            let (jn, ft) = if warm { (tp.data.normal_impulse, Vec3::from(tp.data.friction_impulse)) } else { (0.0, Vec3::zeros()) };
            let mut p = Point {
                anchor1: r1,
                anchor2: r2,
                r1,
                r2,
                base_separation: tp.dist - n.dot(&(r2 - r1)),
                separation: tp.dist,
                point: mid,
                normal_impulse: jn,
                tangent_impulse: [ft.dot(&t1), ft.dot(&t2)],
                manifold_point: k as u32,
                ..Default::default()
            };
            self.masses(&mut p, ctx.s1 as usize, ctx.s2 as usize, &n, &t1, &t2);
            self.points.push(p);
        }
        self.constraints.push(Constraint {
            s1: ctx.s1,
            s2: ctx.s2,
            normal: n,
            t1,
            t2,
            friction: ctx.material.friction,
            static_friction: ctx.material.static_friction,
            restitution: ctx.material.restitution,
            start,
            len: self.points.len() as u32 - start,
            b1: ctx.b1,
            b2: ctx.b2,
            pair: ctx.pair,
            manifold: index,
        });
    }

    fn masses(&self, p: &mut Point, s1: usize, s2: usize, n: &Vec3, t1: &Vec3, t2: &Vec3) {
        let (a1, a2) = (&self.bodies[s1], &self.bodies[s2]);
        let (m1, m2) = (a1.inv_m, a2.inv_m);
        p.rn1 = p.r1.cross(n);
        p.rn2 = p.r2.cross(n);
        p.irn1 = a1.inv_i * p.rn1;
        p.irn2 = a2.inv_i * p.rn2;
        let kn = m1 + m2 + p.rn1.dot(&p.irn1) + p.rn2.dot(&p.irn2);
        p.normal_mass = if kn > 0.0 { 1.0 / kn } else { 0.0 };
        for (a, t) in [t1, t2].into_iter().enumerate() {
            p.rt1[a] = p.r1.cross(t);
            p.rt2[a] = p.r2.cross(t);
            p.irt1[a] = a1.inv_i * p.rt1[a];
            p.irt2[a] = a2.inv_i * p.rt2[a];
        }
        let k = |a: usize, c: usize, ta: &Vec3, tc: &Vec3| {
            (m1 + m2) * ta.dot(tc) + p.rt1[a].dot(&p.irt1[c]) + p.rt2[a].dot(&p.irt2[c])
        };
        let (a, bb, c) = (k(0, 0, t1, t1), k(0, 1, t1, t2), k(1, 1, t2, t2));
        let det = a * c - bb * bb;
        p.tangent_mass = if det > 0.0 { [c / det, -bb / det, a / det] } else { [0.0; 3] };
    }

    /// Copies velocities and pose changes of the solver bodies from the world,
    /// and brings the inverse inertias and contact arms up to the current poses
    /// (after the first gather of a step, when they already are).
    pub fn gather(&mut self, b: &Bodies) {
        let moved = self.substeps_done > 0 || self.gathered;
        self.gathered = true;
        for k in 1..self.bodies.len() {
            let s = &mut self.bodies[k];
            let i = s.body as usize;
            s.v = Vec3::from(b.linear_velocity[i]);
            s.w = Vec3::from(b.angular_velocity[i]);
            s.dp = Vec3::from(b.position[i]) - self.p0[k];
            s.dq = b.q(i) * self.q0[k].conjugate();
            if moved && s.dynamic {
                s.inv_i = inv_inertia_world(b, i);
            }
        }
        if moved {
            self.refresh_arms();
        }
    }

    /// Contact arms and effective masses at the current poses.
    fn refresh_arms(&mut self) {
        for ci in 0..self.constraints.len() {
            self.refresh_constraint(ci);
        }
    }

    /// Arms and effective masses of one constraint's points at the current poses.
    ///
    /// The contact point moves with the bodies' translations weighted by their
    /// inverse masses: it stays under a sphere sliding on the ground and follows a
    /// box across it, and both arms end at it, so equal and opposite impulses keep
    /// angular momentum exactly. (Following material points instead would tilt a
    /// sliding sphere's arm and spin it up without friction.)
    pub(crate) fn refresh_constraint(&mut self, ci: usize) {
        let c = self.constraints[ci];
        let (a1, a2) = (&self.bodies[c.s1 as usize], &self.bodies[c.s2 as usize]);
        let (w1, w2) = if a1.inv_m + a2.inv_m > 0.0 { (a1.inv_m, a2.inv_m) } else { (1.0, 1.0) };
        let (dp1, dp2) = (a1.dp, a2.dp);
        let shift = (dp1 * w1 + dp2 * w2) / (w1 + w2);
        for k in c.start..c.start + c.len {
            let mut p = self.points[k as usize];
            p.r1 = p.anchor1 + shift - dp1;
            p.r2 = p.anchor2 + shift - dp2;
            self.masses(&mut p, c.s1 as usize, c.s2 as usize, &c.normal, &c.t1, &c.t2);
            self.points[k as usize] = p;
        }
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

    /// Applies a normal impulse `j` (N·s) at the point.
    pub fn apply_normal(&mut self, c: &Constraint, p: &Point, j: f64) {
        let mut pair = Pair::load(&self.bodies, c);
        pair.apply_normal(c, p, j);
        pair.store(&mut self.bodies, c);
    }

    /// Applies a tangential impulse `d` (N·s, in the `t1, t2` basis) at the point.
    pub fn apply_tangent(&mut self, c: &Constraint, p: &Point, d: [f64; 2]) {
        let mut pair = Pair::load(&self.bodies, c);
        pair.apply_tangent(c, p, d);
        pair.store(&mut self.bodies, c);
    }

    pub fn normal_velocity(&self, c: &Constraint, p: &Point) -> f64 {
        Pair::load(&self.bodies, c).normal_velocity(c, p)
    }

    pub fn tangent_velocity(&self, c: &Constraint, p: &Point) -> [f64; 2] {
        Pair::load(&self.bodies, c).tangent_velocity(c, p)
    }

    pub fn separation(&self, c: &Constraint, p: &Point) -> f64 {
        Pair::load(&self.bodies, c).separation(c, p)
    }

    /// Re-applies the impulses of the previous substep (or step) and adds the
    /// previous substep's to the step totals.
    pub fn warm_start(&mut self) {
        let first = self.substeps_done == 0;
        self.substeps_done += 1;
        for ci in 0..self.constraints.len() {
            let c = self.constraints[ci];
            for k in c.start..c.start + c.len {
                let p = &mut self.points[k as usize];
                if !first {
                    p.total_normal += p.normal_impulse;
                    p.total_tangent[0] += p.tangent_impulse[0];
                    p.total_tangent[1] += p.tangent_impulse[1];
                }
                let p = *p;
                if p.normal_impulse != 0.0 {
                    self.apply_normal(&c, &p, p.normal_impulse);
                }
                if p.tangent_impulse != [0.0; 2] {
                    self.apply_tangent(&c, &p, p.tangent_impulse);
                }
            }
        }
    }

    /// Ends the step: adds the last substep to the totals and keeps the impulses
    /// in the manifolds for the next step's warm start.
    pub fn finish(&mut self, narrow: &mut NarrowPhase) {
        for c in &self.constraints {
            let Some(state) = narrow.pairs.get_mut(&c.pair) else { continue };
            let Some(m) = state.manifolds.get_mut(c.manifold as usize) else { continue };
            for k in c.start..c.start + c.len {
                let p = &mut self.points[k as usize];
                p.total_normal += p.normal_impulse;
                p.total_tangent[0] += p.tangent_impulse[0];
                p.total_tangent[1] += p.tangent_impulse[1];
                if let Some(tp) = m.points.get_mut(p.manifold_point as usize) {
                    tp.data.normal_impulse = p.normal_impulse;
                    tp.data.friction_impulse = (c.t1 * p.tangent_impulse[0] + c.t2 * p.tangent_impulse[1]).into();
                }
            }
        }
    }

    /// This step's contact points.
    pub fn reports(&self) -> Vec<ContactReport> {
        let mut out = Vec::with_capacity(self.points.len());
        for c in &self.constraints {
            for p in &self.points[c.start as usize..(c.start + c.len) as usize] {
                out.push(ContactReport {
                    body_a: c.b1,
                    body_b: c.b2,
                    point: p.point.into(),
                    normal: c.normal.into(),
                    depth: -p.separation,
                    normal_impulse: p.total_normal,
                    friction_impulse: (c.t1 * p.total_tangent[0] + c.t2 * p.total_tangent[1]).into(),
                });
            }
        }
        out
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
        sb.inv_i = inv_inertia_world(b, i);
    }
}

/// `R I0 Rᵀ` of body `i`.
pub fn inertia_world(b: &Bodies, i: usize) -> Mat3 {
    let r = quat::to_matrix(&b.q(i));
    r * Mat3::from_diagonal(&Vec3::from(b.inertia[i])) * r.transpose()
}

/// `R I0⁻¹ Rᵀ` of body `i`.
pub fn inv_inertia_world(b: &Bodies, i: usize) -> Mat3 {
    let r = quat::to_matrix(&b.q(i));
    r * Mat3::from_diagonal(&Vec3::from(b.inv_inertia[i])) * r.transpose()
}
