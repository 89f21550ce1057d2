//! Contact constraints built once per step from the narrow phase's manifolds:
//! anchors, normal and tangent basis, effective masses; and the bookkeeping
//! around the solve (totals for reporting, data kept for next step). The warm
//! start is in [`super::warm_start`], the refresh of the arms as the bodies
//! move in [`super::refresh`].
//!
//! Anchors are fixed at the step start; the separation is updated during the
//! substeps from how far each body has moved and turned since (as in Box2D v3),
//! without running collision detection again. The solve works on a packed copy of
//! the bodies it touches (`SolverBody`), gathered before and scattered after each
//! solve phase, so its inner loops read one contiguous record per body.

use super::friction::Patch;
use super::limit_surface::PatchShape;
use super::soft::Softness;
use super::pair::Pair;
use super::solver_body::{Gap, SolverBody};
use crate::body::Bodies;
use crate::collide::corners::Corners;
use crate::collide::material::ContactMaterial;
use crate::collide::narrow_phase::{ContactReport, NarrowPhase};
use nalgebra::Isometry3;
use crate::math::{quat, Mat3, Quat, Vec3};

/// Contact solver parameters, each with its unit and default.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SolverSettings {
    /// Rate at which penetration beyond the rest depth is pushed out, as a natural
    /// frequency (Hz); capped at a quarter of the substep rate (the Python build
    /// warns when it is). Default 30.
    pub contact_hertz: f64,
    /// Damping ratio of contacts (–). Default 10 (over-damped: no bounce from the
    /// position correction).
    pub contact_damping_ratio: f64,
    /// Largest speed at which penetration is pushed out (m/s). Default 3.
    pub max_push_velocity: f64,
    /// Approach speed below which contacts do not bounce (m/s; 0 allowed).
    /// Default `None`: [`RESTING_APPROACH`] times the speed gravity gives in a
    /// contact substep, `|g| h` (0.08 m/s at 60 Hz and 4 substeps; 0 without
    /// gravity), the most a resting contact approaches at after the kick.
    pub restitution_threshold: Option<f64>,
    /// Linear slop (m): contacts are created this far before touching, on top of
    /// the distance bodies can close in a step; resting contacts sink less than
    /// it (they rest at `REST_DEPTH` of it, 1 µm by default). Default 0.005.
    pub slop: f64,
}

/// The default restitution threshold, in substeps of gravity (`|g| h`): a
/// contact at rest approaches at `|g| h` after a substep's kick, and one
/// slower than twice that is resting, not landing. A fixed 1 m/s (Box2D's
/// default, the default here before) kept every body slower than that from
/// bouncing whatever its restitution: a ball of e = 0.9 dropped from 5 cm,
/// or a Newton's cradle at 1 m/s, came to rest as if e were 0.
pub const RESTING_APPROACH: f64 = 2.0;

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            contact_hertz: 30.0,
            contact_damping_ratio: 10.0,
            max_push_velocity: 3.0,
            restitution_threshold: None,
            slop: 0.005,
        }
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
    /// Which contact points of each shape are its corners.
    pub corners: [Corners; 2],
    /// Each collider's radius if it is a ball (m), else 0.
    pub radii: [f64; 2],
    pub pair: (u32, u32),
    /// Index of the pair in the narrow phase's `pairs`.
    pub slot: u32,
}

/// One contact point.
///
/// Laid out (`repr(C)`, a cache line each) by what the passes read of it:
/// its impulses, effective mass and the anchors of its separation first
/// (all a [`Constraint::central`] point's solve and warm start read: two
/// lines, not three; 4 % fewer misses of a simulated 1 MB second-level cache
/// in the 1000-ball pit's first 150 steps), then its arms across the normal
/// and their products, which the others read too; the rest after them.
#[derive(Clone, Copy, Debug, Default, serde::Serialize, serde::Deserialize)]
#[repr(C, align(64))]
pub struct Point {
    /// Accumulated normal impulse of the current substep (N·s).
    pub normal_impulse: f64,
    /// Normal impulse summed over the step, for reporting (N·s).
    pub total_normal: f64,
    /// `1/K` with `K = 1/m1 + 1/m2 + n·(I1⁻¹(r1×n)×r1 + I2⁻¹(r2×n)×r2)` (kg).
    pub normal_mass: f64,
    /// Separation at the step start minus `n·(anchor2 − anchor1)` (m).
    pub base_separation: f64,
    /// Anchors relative to each centre of mass at the step start, world (m).
    pub anchor1: Vec3,
    pub anchor2: Vec3,
    /// `I⁻¹ (r × n)` of each body.
    pub irn1: Vec3,
    pub irn2: Vec3,
    /// `r × n` of each body.
    pub rn1: Vec3,
    pub rn2: Vec3,
    /// How much further (m) the separation falls in the substep than its
    /// normal velocity carries it, on a rounded side (see
    /// [`super::rounded_curve`]); 0 elsewhere.
    pub curve: f64,
    /// Index of its manifold in the pair (a constraint may gather several:
    /// see [`super::coplanar`]), and of the point in that manifold.
    pub manifold: u32,
    pub manifold_point: u16,
    /// Which body the point is a corner of and turns with (1 or 2), or 0: it
    /// moves with the bodies' translations only (see `refresh_constraint`).
    pub corner: u8,
    /// Which pair of a joined constraint it came from (see
    /// [`super::flush_pairs`]); 0 in any other.
    #[serde(default)]
    pub part: u8,
    /// Current arms from each centre of mass to the contact point (m): both end at
    /// the same world point, midway between the anchors as the bodies have moved,
    /// so equal and opposite impulses keep angular momentum exactly.
    pub r1: Vec3,
    pub r2: Vec3,
    /// Separation at the step start (m); negative when penetrating.
    pub separation: f64,
    /// World contact point at the step start, midway between the surfaces (m).
    pub point: Vec3,
}

/// The points of one manifold, sharing bodies, normal and material.
///
/// Laid out (`repr(C)`, from a cache line's start) so that what every pass
/// reads (bodies, points, normal, tangents, friction, whether it is fresh
/// or central) fills its first two lines: `central` and `fresh` in the third
/// line cost the 1000-ball pit's velocity passes and warm starts a line more
/// a contact, 2 % of its misses in a simulated 1 MB second-level cache.
#[derive(Clone, Copy, Debug, Default, serde::Serialize, serde::Deserialize)]
#[repr(C, align(64))]
pub struct Constraint {
    /// Solver-body indices (0: fixed).
    pub s1: u32,
    pub s2: u32,
    /// Range of the points in `ContactSolver::points`.
    pub start: u32,
    pub len: u32,
    /// World normal from body 1 to body 2, and the tangent basis.
    pub normal: Vec3,
    pub t1: Vec3,
    pub t2: Vec3,
    pub friction: f64,
    pub static_friction: f64,
    /// Whether its points started this step without impulses to warm start from.
    pub fresh: bool,
    /// Each side is a ball or fixed, and it is no support contact (see
    /// `super::support::unequal`): no arm crosses the normal, a normal impulse
    /// moves the bodies' centres only, and between two balls the normal is
    /// their line of centres, taken again whenever they move within the step
    /// (see `super::refresh::refresh`), so that the impulse keeps angular momentum.
    #[serde(default)]
    pub central: bool,
    /// Bodies, collider pair, its index in the narrow phase's `pairs`, and the
    /// manifold index it came from.
    pub b1: u32,
    pub b2: u32,
    pub pair: (u32, u32),
    pub slot: u32,
    pub manifold: u32,
    pub restitution: f64,
    /// Support contacts (see `super::support`): which body is below, 1 or 2; 0
    /// for a contact solved both ways.
    pub lower: u8,
    /// The support group of its upper body (when `lower != 0`).
    pub group: u32,
    /// It touches an articulated link: solved through the articulation (see
    /// `super::generalized`), never a support contact.
    pub generalized: bool,
    /// Its bodies met slower than `SETTLED` substeps of gravity at its points
    /// at the step start, or one of them is fixed or kinematic: only then may
    /// the support sweeps hold its lower body (see `super::support`).
    pub settled: bool,
    /// Settled as a flat landing faster than `SETTLED` (see
    /// `super::support::LANDING`): held only on a held body.
    #[serde(default)]
    pub landing: bool,
    /// Its arms, masses and patch are still those of its anchors (not
    /// refreshed since built): they may be kept next step (see `super::reuse`).
    pub as_built: bool,
    /// Its points came from several pairs (see [`super::flush_pairs`]).
    #[serde(default)]
    pub joined: bool,
    /// How much further (m) the anchors computed afresh may move from its
    /// anchors before they stop holding, and the longest of its anchors (m,
    /// at least 1; 0 for a constraint whose pair never keeps its manifolds,
    /// which is not tracked): see [`super::reuse::still_slack`].
    pub slack: f64,
    pub arm: f64,
    /// Kept from last step's constraint of a still pair without its points
    /// being laid out and checked (see [`super::reuse::still_slack`]).
    pub still: bool,
    /// A side of it is a ball (see `PairContext::radii`): its points, however
    /// many (one on each of the flush tiles under it), are one point, no face.
    #[serde(default)]
    pub ball: bool,
}

/// The contact solver's state for one step.
#[derive(Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct ContactSolver {
    pub constraints: Vec<Constraint>,
    /// The friction patch of each constraint (same index).
    pub patches: Vec<Patch>,
    /// The polygon of each patch (same index; see [`Patch::lever`]).
    pub shapes: Vec<PatchShape>,
    pub points: Vec<Point>,
    pub bodies: Vec<SolverBody>,
    /// Constraints solved both ways, and the support blocks.
    pub(crate) ordinary: Vec<u32>,
    pub(crate) support: super::support::Support,
    /// Per world body: its solver index this step (0 when not in the solve).
    pub(crate) slot: Vec<u32>,
    /// Per solver body: pose at the step start.
    pub(crate) p0: Vec<Vec3>,
    pub(crate) q0: Vec<Quat>,
    /// Per world body: whether it is dynamic, awake and in some constraint this step.
    pub touching: Vec<bool>,
    pub softness: Softness,
    pub inv_h: f64,
    pub settings: SolverSettings,
    pub(crate) substeps_done: u32,
    /// Whether the solver bodies have been gathered since `prepare`.
    pub(crate) gathered: bool,
    /// The contacts on articulated links.
    pub gen: super::generalized::Generalized,
    /// Where the pairs of the joined constraints begin, in point order (see
    /// [`super::flush_pairs`]).
    #[serde(default)]
    pub parts: Vec<super::flush_pairs::Part>,
    /// Last step's constraints and blocks, for their geometry.
    pub(crate) previous: super::reuse::Previous,
    /// Velocities before this substep's warm start (see `super::warm_guard`).
    pub(crate) guard: super::warm_guard::WarmGuard,
    /// This step runs on the world's pool: the islands of the support sweeps
    /// may be swept in parallel (see `super::island_sweeps`). Not state.
    #[serde(skip)]
    pub(crate) parallel: bool,
    /// This step's groups of bodies in contact (see `super::contact_groups`).
    #[serde(skip)]
    pub(crate) groups: super::contact_groups::Groups,
    /// Whether this step's contacts could be split in halves (see
    /// `super::seams`): the next step builds them half by half.
    #[serde(default)]
    pub(crate) split: bool,
    /// Pairs whose constraints the last serial build updated in place (see
    /// `prepare_in_place`).
    #[serde(skip)]
    pub(crate) in_place: usize,
    /// Where the halves of this step's constraints end (the seam after
    /// them), if they may be passed over side by side (see `super::seams`).
    /// Not state.
    #[serde(skip)]
    pub(crate) halves: Option<[usize; 2]>,
    /// Per world body, the side of the split of this step's build (see
    /// `super::seams`). Not state.
    #[serde(skip)]
    pub(crate) side: Vec<u8>,
    /// Where the solver bodies entered by the first half's pairs end, and
    /// those entered by the second's, in a build half by half (the bodies
    /// only the seam touches after them; see `super::seams`). Not state.
    #[serde(skip)]
    pub(crate) body_ends: Option<[usize; 2]>,
    /// Per constraint, how far its bodies had moved apart (`Δp2 − Δp1`, m) at
    /// the last refresh of its arms this step, for the central ones (see
    /// `ContactSolver::refresh_due`). Not state: zero at each step's build.
    #[serde(skip)]
    pub(crate) apart: Vec<Vec3>,
    /// Whether every awake body was slow at this step's start (see
    /// `super::second_pass`; found only in a world with support blocks).
    #[serde(skip)]
    pub(crate) settling_now: bool,
}

/// Any unit vector orthogonal to `n`.
pub fn orthonormal(n: &Vec3) -> Vec3 {
    let a = if n.x.abs() < 0.577 { Vec3::x() } else if n.y.abs() < 0.577 { Vec3::y() } else { Vec3::z() };
    let t = a - n * n.dot(&a);
    t / t.norm()
}

impl ContactSolver {
    pub fn new(n_bodies: usize, settings: SolverSettings) -> Self {
        Self { slot: vec![0; n_bodies], touching: vec![false; n_bodies], settings, ..Default::default() }
    }

    /// Changes the substep of this step to `h` (before its first substep): the
    /// soft contacts' constants and what depends on `1/h`.
    pub fn set_substep(&mut self, h: f64) {
        let ratio = h * self.inv_h;
        self.scale_warm_start(ratio);
        let hertz = self.settings.contact_hertz.min(0.25 / h);
        self.softness = Softness::new(hertz, self.settings.contact_damping_ratio, h);
        self.support.residual *= ratio;
        self.inv_h = 1.0 / h;
        for s in &mut self.bodies {
            s.chord = super::solver_body::chord(s.chord * ratio);
        }
    }

    /// Applies a normal impulse `j` (N·s) at the point.
    pub fn apply_normal(&mut self, c: &Constraint, p: &Point, j: f64) {
        let mut pair = Pair::load(&self.bodies, c);
        pair.apply_normal(c, p, j);
        pair.store(&mut self.bodies, c);
    }

    pub fn normal_velocity(&self, c: &Constraint, p: &Point) -> f64 {
        Pair::load(&self.bodies, c).normal_velocity(c, p)
    }

    pub fn separation(&self, c: &Constraint, p: &Point) -> f64 {
        Gap::new(&self.bodies, c).separation(p)
    }

    /// Ends the step: adds the last substep to the totals and keeps the impulses
    /// in the manifolds for the next step's warm start.
    ///
    /// A patch's friction and twist are kept as shares on its points and summed
    /// back at the next step's build, over every point of its manifolds. A point
    /// beyond the prediction is no contact and is not written here, so it kept
    /// the share of the last step it touched and added it to every later warm
    /// start: a cube wedged in a V between two others (pour 4 of
    /// `tests/test_pile_rest.py`) was pushed down the groove by a stale share
    /// and sank 6 mm in 10 s with both contacts inside their cones. Such points,
    /// and those of pairs that no longer touch, are cleared first.
    pub fn finish(&mut self, narrow: &mut NarrowPhase) {
        narrow.pairs.iter_mut().for_each(|state| state.forget_beyond_reach());
        let n = self.constraints.len();
        let pairs = super::seams::SharedPairs::of(&mut narrow.pairs);
        match self.by_halves().filter(|_| self.parts.is_empty()) {
            // Each thread ends its own half (its patches, points and pairs'
            // states, which its next step reads first): ended on the stepping
            // thread, every one of them was fetched back by the helper.
            Some(h) => {
                // SAFETY: a pair's constraints are all in one half or all in
                // the seam (its part follows its bodies: see `super::seams`),
                // and no constraint joins pairs (`parts` empty).
                self.each_half(h, |cs, range| {
                    unsafe { cs.finish_range(range, &pairs) };
                    false
                });
            }
            // SAFETY: one thread.
            None => unsafe { self.finish_range(0..n, &pairs) },
        }
    }

    /// [`Self::finish`] of the constraints `range`.
    /// SAFETY: no other thread writes the states of these constraints' pairs
    /// meanwhile.
    unsafe fn finish_range(&mut self, range: std::ops::Range<usize>, pairs: &super::seams::SharedPairs) {
        let pair = |slot: u32| unsafe { pairs.get(slot) };
        for ci in range {
            let (Some(c), Some(f)) = (self.constraints.get(ci), self.patches.get_mut(ci)) else { return };
            f.total[0] += f.impulse[0];
            f.total[1] += f.impulse[1];
            let share = 1.0 / c.len as f64;
            let friction: [f64; 3] = ((c.t1 * f.impulse[0] + c.t2 * f.impulse[1]) * share).into();
            let parts = super::flush_pairs::parts_of(&self.parts, c);
            let slot_of = |p: &Point| parts.get(p.part as usize).map_or(c.slot, |q| q.slot);
            let mut key = (c.slot, c.manifold);
            let mut state = pair(c.slot);
            let mut kept = state.as_mut().and_then(|s| s.points_mut(c.manifold));
            for p in &mut self.points[c.start as usize..(c.start + c.len) as usize] {
                p.total_normal += p.normal_impulse;
                let now = (slot_of(p), p.manifold);
                if now != key {
                    if now.0 != key.0 {
                        state = pair(now.0);
                    }
                    key = now;
                    kept = state.as_mut().and_then(|s| s.points_mut(p.manifold));
                }
                if let Some(tp) = kept.as_mut().and_then(|m| m.get_mut(p.manifold_point as usize)) {
                    tp.data.normal_impulse = p.normal_impulse;
                    tp.data.friction_impulse = friction;
                    tp.data.twist_impulse = f.twist * share;
                    tp.data.sliding = f.sliding;
                }
            }
        }
    }

    /// This step's contact points.
    pub fn reports(&self) -> Vec<ContactReport> {
        let mut out = Vec::with_capacity(self.points.len());
        for (ci, c) in self.constraints.iter().enumerate() {
            let points = &self.points[c.start as usize..(c.start + c.len) as usize];
            let f = &self.patches[ci];
            let total = c.t1 * f.total[0] + c.t2 * f.total[1];
            let jn: f64 = points.iter().map(|p| p.total_normal).sum();
            let parts = super::flush_pairs::parts_of(&self.parts, c);
            for p in points {
                let share = if jn > 0.0 { p.total_normal / jn } else { 1.0 / points.len() as f64 };
                let (body_a, body_b) = match parts.get(p.part as usize) {
                    Some(part) => (part.b1, part.b2),
                    None => (c.b1, c.b2),
                };
                out.push(ContactReport {
                    body_a,
                    body_b,
                    point: p.point.into(),
                    normal: c.normal.into(),
                    depth: -p.separation,
                    normal_impulse: p.total_normal,
                    friction_impulse: (total * share).into(),
                });
            }
        }
        out
    }
}

/// Arms across the normal and the effective mass of a point; a `central`
/// constraint's arms are zero (see [`Constraint::central`]: a ball's arm lies
/// along the normal, its cross product with it round-off).
pub(crate) fn normal_mass(p: &mut Point, (a1, a2): (&SolverBody, &SolverBody), n: &Vec3, central: bool) {
    if central {
        (p.rn1, p.rn2, p.irn1, p.irn2) = (Vec3::zeros(), Vec3::zeros(), Vec3::zeros(), Vec3::zeros());
        let kn = a1.inv_m + a2.inv_m;
        p.normal_mass = if kn > 0.0 { 1.0 / kn } else { 0.0 };
        return;
    }
    p.rn1 = p.r1.cross(n);
    p.rn2 = p.r2.cross(n);
    p.irn1 = a1.inv_i_mul(&p.rn1);
    p.irn2 = a2.inv_i_mul(&p.rn2);
    let kn = a1.inv_m + a2.inv_m + p.rn1.dot(&p.irn1) + p.rn2.dot(&p.irn2);
    p.normal_mass = if kn > 0.0 { 1.0 / kn } else { 0.0 };
}

/// `R I0 Rᵀ` of body `i`.
pub fn inertia_world(b: &Bodies, i: usize) -> Mat3 {
    let r = quat::to_matrix(&b.q(i));
    r * Mat3::from_diagonal(&Vec3::from(b.inertia[i])) * r.transpose()
}

/// `R I0⁻¹ Rᵀ` of body `i`.
pub fn inv_inertia_world(b: &Bodies, i: usize) -> Mat3 {
    inv_inertia_at(b, i, &b.q(i))
}

/// `R I0⁻¹ Rᵀ` of body `i` turned to orientation `q`.
pub(crate) fn inv_inertia_at(b: &Bodies, i: usize, q: &Quat) -> Mat3 {
    let r = quat::to_matrix(q);
    r * Mat3::from_diagonal(&Vec3::from(b.inv_inertia[i])) * r.transpose()
}
