//! Contact manifolds per colliding pair, computed by parry and kept across steps:
//! parry matches new contact points to old ones by feature id, carrying the
//! accumulated impulses used to warm-start the solver.

use nalgebra::{Isometry3, Vector3};
use parry3d_f64::query::{ContactManifold, ContactManifoldsWorkspace, DefaultQueryDispatcher, PersistentQueryDispatcher, TrackedContact};

use super::collider::Collider;
use super::approach::{Approach, Motion};
use super::manifolds::{afresh, ball_ball, manifolds_of};
use crate::body::Bodies;
use crate::math::Vec3;

/// What a contact point carries from one step to the next (world frame).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ContactData {
    /// Normal impulse of the last substep (N·s), to warm-start the next.
    pub normal_impulse: f64,
    /// This point's share of its patch's friction impulse (N·s, world) and twist
    /// impulse (N·m·s) of the last substep.
    pub friction_impulse: [f64; 3],
    pub twist_impulse: f64,
    /// Whether its patch was sliding.
    pub sliding: bool,
}

pub type Manifold = ContactManifold<(), ContactData>;
pub type Tracked = TrackedContact<ContactData>;

/// The one point where two balls meet, kept in the pair itself: as parry's
/// ball–ball manifold, without its two heap indirections per pair.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct BallContact {
    /// Normal from ball 1 to ball 2 in ball 1's frame.
    pub local_n1: Vector3<f64>,
    pub point: Tracked,
}

/// The contact points of one manifold as the solver reads them: parry's, or a
/// ball pair's.
#[derive(Clone, Copy)]
pub struct Contacts<'a> {
    /// Normal in the frame of shape 1 (of its sub-shape, if any).
    pub local_n1: Vector3<f64>,
    /// Poses of the sub-shapes in their shapes (compounds, meshes).
    pub subshape_pos1: Option<Isometry3<f64>>,
    pub subshape_pos2: Option<Isometry3<f64>>,
    pub points: &'a [Tracked],
}

impl<'a> From<&'a Manifold> for Contacts<'a> {
    fn from(m: &'a Manifold) -> Self {
        Self { local_n1: m.local_n1, subshape_pos1: m.subshape_pos1, subshape_pos2: m.subshape_pos2, points: &m.points }
    }
}

impl<'a> From<&'a BallContact> for Contacts<'a> {
    fn from(b: &'a BallContact) -> Self {
        Self { local_n1: b.local_n1, subshape_pos1: None, subshape_pos2: None, points: std::slice::from_ref(&b.point) }
    }
}

/// The manifold index standing for a pair's [`BallContact`].
pub const BALL: u32 = u32::MAX;

#[derive(Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct PairState {
    /// The collider pair, smaller index first.
    pub key: (u32, u32),
    pub manifolds: Vec<Manifold>,
    /// How far ahead contacts were predicted for this pair this step (m); parry
    /// may report points of a manifold beyond it, which are not contacts yet.
    pub prediction: f64,
    workspace: Option<ContactManifoldsWorkspace>,
    /// For two balls, their contact (then `manifolds` stays empty).
    pub ball: Option<BallContact>,
    /// The relative pose and prediction the manifolds were last computed at
    /// (see [`STILL`]).
    computed_at: Option<(Isometry3<f64>, f64)>,
    /// This step kept the manifolds (see [`STILL`]): they are last step's,
    /// bit for bit, and so is every point's distance.
    #[serde(skip)]
    pub still: bool,
}

impl PairState {
    /// The pair's manifolds for the solver, each with its index (`BALL` for a ball
    /// pair's contact).
    pub fn contacts(&self) -> impl Iterator<Item = (u32, Contacts<'_>)> {
        let ball = self.ball.iter().map(|b| (BALL, Contacts::from(b)));
        ball.chain(self.manifolds.iter().enumerate().map(|(k, m)| (k as u32, Contacts::from(m))))
    }

    /// Whether its manifolds are kept while the pair is still (see [`STILL`]).
    pub fn keeps_manifolds(&self) -> bool {
        self.computed_at.is_some()
    }

    /// Manifold `index` (see [`PairState::contacts`]).
    pub fn manifold(&self, index: u32) -> Option<Contacts<'_>> {
        if index == BALL {
            self.ball.as_ref().map(Contacts::from)
        } else {
            self.manifolds.get(index as usize).map(Contacts::from)
        }
    }

    /// Drops what the solver stored in the points beyond the pair's prediction:
    /// they were not contacts this step, so they carry nothing into the next.
    pub fn forget_beyond_reach(&mut self) {
        let reach = self.prediction;
        let points = self.manifolds.iter_mut().flat_map(|m| m.points.iter_mut()).chain(self.ball.as_mut().map(|b| &mut b.point));
        points.filter(|tp| !(tp.dist <= reach)).for_each(|tp| tp.data = ContactData::default());
    }

    /// The points of manifold `index` (see [`PairState::contacts`]), to store what
    /// the solver carries to the next step.
    pub fn points_mut(&mut self, index: u32) -> Option<&mut [Tracked]> {
        if index == BALL {
            self.ball.as_mut().map(|b| std::slice::from_mut(&mut b.point))
        } else {
            self.manifolds.get_mut(index as usize).map(|m| &mut m.points[..])
        }
    }
}

/// The persistent pairs. Each keeps its slot in `pairs` while it lasts (a freed
/// slot is reused), and `order` lists the live ones sorted by key: the broad
/// phase's candidates come sorted, so a step's pairs are matched to the last
/// step's by a merge, without hashing, and the merge moves 12-byte entries, not
/// pair states (moving the states was 6 % of a ball pit's step). `touching`:
/// the slots of the pairs with contact points this step, in key order.
///
/// The pairs of a step are matched first, then stepped, each on its own state
/// (in parallel when asked: a pair's arithmetic does not depend on the others,
/// so every thread count gives the same bits), then the ones apart are freed.
#[derive(Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct NarrowPhase {
    pub pairs: Vec<PairState>,
    order: Vec<((u32, u32), u32)>,
    free: Vec<u32>,
    pub touching: Vec<u32>,
    spare: Vec<((u32, u32), u32)>,
    /// Per slot, during `update`: what stepping the pair found (`Found`).
    #[serde(skip)]
    found: Vec<Found>,
    /// Per collider, its world pose at this step's bodies, found once by
    /// `update` where the candidates are many (see [`POSES_PER_CANDIDATE`]),
    /// else empty: read by every pair of the collider and again by the
    /// build of its constraints (four poses a pair; 1000 balls, 2800 pairs).
    /// Cleared by [`NarrowPhase::forget_poses`] when the bodies move on.
    #[serde(skip)]
    poses: Vec<Isometry3<f64>>,
    /// Per body, how it moves over the step (see [`Motion`]), found by
    /// `update` with the poses: every pair of the body read it, and its
    /// square roots were half of what finding a pair's reach cost (5 % of
    /// a resting 1000-ball pit's instructions, 4300 pairs a step).
    #[serde(skip)]
    motions: Vec<Motion>,
}

/// Candidates per collider from which `update` finds every collider's pose
/// once rather than each pair its two: a scene of free bodies with few
/// candidates (a million boxes on a grid) pays for none.
const POSES_PER_CANDIDATE: usize = 4;

#[path = "pair_slots.rs"]
mod pair_slots;

/// What a step found for the pair in a slot.
#[derive(Clone, Copy, Default, PartialEq)]
enum Found {
    /// Not a candidate this step: kept as it was (asleep) or free.
    #[default]
    Idle,
    /// A candidate, to be stepped.
    Due,
    /// Further apart than the prediction: the pair ends.
    Apart,
    /// Within reach, no point within the prediction.
    Near,
    Touching,
}

/// Pairs kept from the last step from which a step runs on the pool for its
/// narrow phase and constraints' build alone (a step with support islands to
/// sweep in parallel goes there anyway: see `solve::island_sweeps`). A step
/// handed to the pool pays the hand-offs and the reading of what one thread
/// wrote from the other's cache. The 1000-ball pit (2900 pairs) gained 6 % on
/// the pool one day and lost 8 % the next (353 against 334 steps/s, then 317
/// against 344, two cores; `benches/README.md`): where the gain is that
/// uncertain, a step stays on the calling thread, never slower than one
/// thread. A 3000-ball pit (8600 pairs) still goes to the pool.
pub const MIN_PARALLEL_PAIRS: usize = 4096;

/// Touching pairs of shapes other than two balls, their manifolds found
/// again (not still), from which a step runs on the pool too: parry clips
/// their manifolds (a microsecond or more a pair, where two balls' contact
/// takes tens of nanoseconds) and each carries up to four points to build,
/// so their share of a step worth splitting comes at far fewer pairs.
/// Measured on two cores (`examples/contact_scenes.rs`, the step on the pool
/// against one thread, 2026-12-05): pyramids of 210 boxes (400 such pairs)
/// 0.98–1.0×, of 465 (900) 1.1×, of 630 (1225) 1.14×, of 820 (1600)
/// 1.12–1.18×, of 1275 (2500) 1.3×; the 1000-ball pit (350) 0.9–1.0×. A
/// still pair costs neither (its manifolds and constraints are kept), and
/// once pyramids at rest kept them, counting their still pairs sent them to
/// the pool for 0.95× (465 boxes) and 0.95–1.03× (820) of one thread.
pub const MIN_PARALLEL_MANIFOLD_PAIRS: usize = 640;
/// Pairs handed to a thread at a time.
const PAIRS_PER_TASK: usize = 64;

/// This step's prediction and manifolds of a pair: `None` if the balls around the
/// two bodies that hold their shapes are further apart than the prediction (the
/// pair is left as it was), else whether some point is within it.
fn step_pair(state: &mut PairState, (colliders, poses, motions): (&[Collider], &[Isometry3<f64>], &[Motion]), bodies: &Bodies, pred: &Prediction) -> Option<bool> {
    let (approach, prediction) = reach_of(colliders, (bodies, motions), state.key, pred)?;
    let (c1, c2) = (&colliders[state.key.0 as usize], &colliders[state.key.1 as usize]);
    state.prediction = super::passing::narrowed(c1, c2, bodies, pred, &approach, prediction);
    let pos12 = pose_in(poses, state.key.0, c1, bodies).inv_mul(&pose_in(poses, state.key.1, c2, bodies));
    Some(update_pair(state, c1, c2, (bodies, &pos12)))
}

/// The world pose of collider `k` (`c`) at the bodies `bodies`: the one
/// in `poses` (the narrow phase's, found at these bodies) if there is one,
/// else found now.
pub fn pose_in(poses: &[Isometry3<f64>], k: u32, c: &Collider, bodies: &Bodies) -> Isometry3<f64> {
    poses.get(k as usize).copied().unwrap_or_else(|| c.pose(bodies))
}

/// How collider pair `key` approaches and how far ahead its contacts are
/// predicted (m), or `None` if the balls around the two bodies that hold their
/// shapes are further apart than that.
fn reach_of(colliders: &[Collider], (bodies, motions): (&Bodies, &[Motion]), key: (u32, u32), pred: &Prediction) -> Option<(Approach, f64)> {
    let (c1, c2) = (&colliders[key.0 as usize], &colliders[key.1 as usize]);
    let approach = Approach::of(c1, c2, (bodies, motions), pred);
    let prediction = prediction_of(c1, c2, &approach, pred);
    (!far_apart(c1, c2, bodies, prediction)).then_some((approach, prediction))
}

/// How far ahead (m) contacts are predicted for a pair.
pub struct Prediction {
    /// Always added (m).
    pub margin: f64,
    /// Step (s): points moving toward each other within `dt` are predicted.
    pub dt: f64,
    /// Gravity (m/s²).
    pub gravity: Vec3,
}

impl NarrowPhase {
    /// Updates the manifolds of `candidates` (sorted collider pairs). Pairs that are
    /// no longer candidates are dropped, except those `dormant(i, j)` (both bodies
    /// asleep), whose warm-start data waits for them to wake. `parallel`: step the
    /// pairs with rayon's parallel iterators (on the pool the caller installed).
    pub fn update(
        &mut self,
        colliders: &[Collider],
        bodies: &Bodies,
        candidates: &[(u32, u32)],
        pred: &Prediction,
        parallel: bool,
        dormant: impl Fn(u32, u32) -> bool,
    ) {
        self.touching.clear();
        self.found.clear();
        self.found.resize(self.pairs.len(), Found::Idle);
        self.poses.clear();
        self.motions.clear();
        if candidates.len() * POSES_PER_CANDIDATE >= colliders.len() {
            self.poses.extend(colliders.iter().map(|c| c.pose(bodies)));
            self.motions.extend((0..bodies.len()).map(|i| Motion::of(bodies, i, pred)));
        }
        let motions = std::mem::take(&mut self.motions);
        let within_reach = |key: (u32, u32)| reach_of(colliders, (bodies, &motions), key, pred).is_some();
        self.match_candidates(candidates, dormant, within_reach);
        self.motions = motions;
        let (poses, motions) = (&self.poses, &self.motions);
        let step = |(state, found): (&mut PairState, &mut Found)| {
            if *found == Found::Due {
                *found = match step_pair(state, (colliders, poses, motions), bodies, pred) {
                    None => Found::Apart,
                    Some(false) => Found::Near,
                    Some(true) => Found::Touching,
                };
            }
        };
        if parallel && crate::solve::team::active() {
            // Two halves of the slots, one on the step's helper thread.
            let mid = self.pairs.len() / 2;
            let (p0, p1) = self.pairs.split_at_mut(mid);
            let (f0, f1) = self.found.split_at_mut(mid);
            let b = || p1.iter_mut().zip(f1.iter_mut()).for_each(step);
            crate::solve::team::both(|| p0.iter_mut().zip(f0.iter_mut()).for_each(step), b);
        } else if parallel {
            use rayon::prelude::*;
            self.pairs.par_iter_mut().zip(self.found.par_iter_mut()).with_min_len(PAIRS_PER_TASK).for_each(step);
        } else {
            self.pairs.iter_mut().zip(self.found.iter_mut()).for_each(step);
        }
        self.smooth_seams(colliders, bodies);
        // A pair apart is not kept: it carries warm-start data only for points
        // within its prediction.
        let mut order = std::mem::take(&mut self.order);
        order.retain(|&(_, slot)| match self.found[slot as usize] {
            Found::Apart => {
                self.release(slot);
                false
            }
            Found::Touching => {
                self.touching.push(slot);
                true
            }
            _ => true,
        });
        self.order = order;
    }

    /// The colliders' world poses at the bodies of the last `update`, if it
    /// found them and they are not yet forgotten (else empty; see
    /// [`pose_in`]).
    pub fn poses(&self) -> &[Isometry3<f64>] {
        &self.poses
    }

    /// Forgets the poses `update` found: the bodies have moved on.
    pub fn forget_poses(&mut self) {
        self.poses.clear();
    }

    /// The contacts with seams between flush fixed shapes (see
    /// [`super::internal_edges`]), then which pairs touch after them.
    fn smooth_seams(&mut self, colliders: &[Collider], bodies: &Bodies) {
        let found = &self.found;
        let near = self.order.iter().map(|&(_, s)| s).filter(|&s| matches!(found[s as usize], Found::Touching | Found::Near));
        for s in super::internal_edges::smooth(&mut self.pairs, near, colliders, bodies) {
            self.found[s as usize] = if touches(&self.pairs[s as usize]) { Found::Touching } else { Found::Near };
        }
    }

    /// Matches the candidates to the kept pairs by a merge: the order becomes the
    /// candidates (claiming a slot for each new one `within_reach`, marked
    /// due) and the kept dormant pairs; the others are freed.
    ///
    /// A new candidate out of reach (its bounding boxes overlap, its bounding
    /// balls do not: the diagonal neighbours in a ball pit, 1800 of 4700
    /// candidates a step) gets no slot: claimed and freed again every step,
    /// those slots were 5 % of the pit's step.
    fn match_candidates(&mut self, candidates: &[(u32, u32)], dormant: impl Fn(u32, u32) -> bool, within_reach: impl Fn((u32, u32)) -> bool) {
        let mut last = std::mem::take(&mut self.spare);
        last.clear();
        std::mem::swap(&mut last, &mut self.order);
        let mut old = last.iter().copied().peekable();
        for &key in candidates {
            let mut found = None;
            while let Some((k, slot)) = old.next_if(|o| o.0 <= key) {
                if k == key {
                    found = Some(slot);
                } else {
                    self.keep_if(dormant(k.0, k.1), k, slot);
                }
            }
            let slot = match found {
                Some(slot) => slot,
                None if within_reach(key) => self.claim(key),
                None => continue,
            };
            self.order.push((key, slot));
            if self.found.len() < self.pairs.len() {
                self.found.resize(self.pairs.len(), Found::Idle);
            }
            self.found[slot as usize] = Found::Due;
        }
        for (k, slot) in old {
            self.keep_if(dormant(k.0, k.1), k, slot);
        }
        self.spare = last;
    }

    /// How many pairs touched at the last update whose shapes are not two
    /// balls and whose manifolds were found again (not [`still`](PairState::still):
    /// see [`MIN_PARALLEL_MANIFOLD_PAIRS`]).
    pub fn manifold_pairs(&self) -> usize {
        self.touching.iter().filter(|&&s| self.pairs.get(s as usize).is_some_and(|p| p.ball.is_none() && !p.still)).count()
    }

    /// How many pairs are kept.
    pub fn len(&self) -> usize {
        self.order.len()
    }

    pub fn is_empty(&self) -> bool {
        self.order.is_empty()
    }

    /// A slot for a new pair `key`, without contacts.
    fn claim(&mut self, key: (u32, u32)) -> u32 {
        let state = PairState { key, ..Default::default() };
        match self.free.pop() {
            Some(slot) => {
                self.pairs[slot as usize] = state;
                slot
            }
            None => {
                self.pairs.push(state);
                (self.pairs.len() - 1) as u32
            }
        }
    }

    /// Keeps pair `key` at `slot` in the order, or frees its slot.
    fn keep_if(&mut self, keep: bool, key: (u32, u32), slot: u32) {
        if keep {
            self.order.push((key, slot));
        } else {
            self.release(slot);
        }
    }

    /// Frees the slot of a pair that ends.
    fn release(&mut self, slot: u32) {
        self.pairs[slot as usize] = PairState::default();
        self.free.push(slot);
    }
}

/// How far ahead (m) contacts are predicted for a pair. Contacts are predicted
/// as far as the bodies can travel in a step, but a body without CCD looks no
/// further than its own size ahead: a bullet without CCD may tunnel, with it
/// never does.
fn prediction_of(c1: &Collider, c2: &Collider, approach: &Approach, pred: &Prediction) -> f64 {
    let reach = if c1.ccd || c2.ccd { f64::INFINITY } else { c1.reach.min(c2.reach) };
    pred.margin + (pred.dt * approach.bound(pred.dt)).min(reach)
}

/// Whether the balls of radius `reach` around the two bodies' centres are more
/// than `prediction` apart (never for a half-space, whose reach is infinite).
fn far_apart(c1: &Collider, c2: &Collider, bodies: &Bodies, prediction: f64) -> bool {
    let d = Vec3::from(bodies.position[c1.body as usize]) - Vec3::from(bodies.position[c2.body as usize]);
    let r = c1.reach + c2.reach + prediction;
    d.norm_squared() > r * r
}

/// The manifolds of one candidate pair (`pos12`: collider 2's pose in
/// collider 1's frame), up to its `prediction`; returns whether some point is
/// within it.
fn update_pair(state: &mut PairState, c1: &Collider, c2: &Collider, (bodies, pos12): (&Bodies, &Isometry3<f64>)) -> bool {
    let pos12 = *pos12;
    let prediction = state.prediction;
    state.still = false;
    if let (Some(r1), Some(r2)) = (c1.ball, c2.ball) {
        ball_ball(&pos12, r1, r2, prediction, &mut state.ball);
        return state.ball.is_some_and(|b| b.point.dist <= prediction);
    }
    state.still = state.computed_at.is_some_and(|(at, reach)| still(&at, &pos12) && (reach - prediction).abs() <= STILL);
    if state.still {
        return touches(state);
    }
    manifolds_of(c1, c2, &pos12, prediction, (&mut state.manifolds, &mut state.workspace));
    state.computed_at = keeps_manifolds(c1, c2, bodies).then_some((pos12, prediction));
    touches(state)
}

/// How far (m, and rad/2 of the relative turn) a pair of polyhedra may move
/// against each other, and its prediction change, since its manifolds were
/// computed, and keep them as they are: a body at rest in a pyramid creeps
/// some 1e-15 m a step, and its manifolds came out the same each step (a
/// quarter of the 210-box pyramid's step). A kept point's distance is then
/// off by at most this times the shapes' size, a millionth of the rest depth.
pub const STILL: f64 = 1e-12;

/// Whether `a` and `b` are within [`STILL`] of each other.
fn still(a: &Isometry3<f64>, b: &Isometry3<f64>) -> bool {
    let (p, q) = (a.rotation.coords, b.rotation.coords);
    (a.translation.vector - b.translation.vector).amax() <= STILL && (p - q).amax() <= STILL
}

/// Whether a pair's manifolds are a function of the relative pose and the
/// prediction alone, to be kept while those stay [`still`]: not those parry
/// computes afresh (meshes, rolling shapes: see [`manifolds_of`]), nor those
/// of a body on a fixed box or hull, which the seams may change after them
/// (see [`super::internal_edges`]).
fn keeps_manifolds(c1: &Collider, c2: &Collider, bodies: &Bodies) -> bool {
    let (s1, s2) = (c1.shape.as_ref(), c2.shape.as_ref());
    let kept = |s: &dyn parry3d_f64::shape::Shape| !afresh(s) && s.as_compound().is_none();
    kept(s1) && kept(s2) && !super::internal_edges::may_smooth(c1, bodies) && !super::internal_edges::may_smooth(c2, bodies)
}

/// Whether some point of the pair's manifolds is within its prediction.
fn touches(state: &PairState) -> bool {
    state.manifolds.iter().any(|m| m.points.iter().any(|p| p.dist <= state.prediction))
}

/// Whether parry generates contacts between these two shapes (checked at build).
pub fn supported(a: &Collider, b: &Collider) -> bool {
    use parry3d_f64::shape::ShapeType;
    // parry runs mesh-mesh pairs triangle by triangle and drops what it cannot do.
    if a.shape.shape_type() == ShapeType::TriMesh && b.shape.shape_type() == ShapeType::TriMesh {
        return false;
    }
    let mut manifolds: Vec<Manifold> = Vec::new();
    let mut ws = None;
    let far = nalgebra::Isometry3::translation(1e6, 0.0, 0.0);
    DefaultQueryDispatcher
        .contact_manifolds(&far, a.shape.as_ref(), b.shape.as_ref(), 0.0, &mut manifolds, &mut ws)
        .is_ok()
}

/// A plain copy of one contact point, for reporting.
#[derive(Clone, Copy, Debug)]
pub struct ContactReport {
    pub body_a: u32,
    pub body_b: u32,
    /// World contact point, midway between the two surfaces (m).
    pub point: [f64; 3],
    /// World normal, from body a to body b.
    pub normal: [f64; 3],
    /// Penetration depth (m); negative when the point is predicted, not touching.
    pub depth: f64,
    /// Normal impulse over the step (N·s).
    pub normal_impulse: f64,
    /// Friction impulse over the step, world (N·s).
    pub friction_impulse: [f64; 3],
}

#[cfg(test)]
#[path = "narrow_phase_tests.rs"]
mod tests;
