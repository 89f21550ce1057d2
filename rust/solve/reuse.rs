//! Contact geometry kept from one step to the next while the bodies of a
//! manifold stay put: the arms, effective masses and friction patch of a
//! constraint, and `K`, its factor and the least-norm operator of a support
//! block, are recomputed only when something they depend on has moved.
//!
//! A resting pyramid rebuilt them every step for nothing: the patch geometry and
//! the blocks took 22 % of its step. The tolerance is the one within a step (see
//! `gather::MOVE_EPS`): a body that has moved less than 1 µm keeps its
//! arms. Kept geometry is taken whole, anchors and normal included, so what the
//! solve sees is exactly what was computed at those anchors, and the next step
//! compares against the same anchors: a slow creep adds up until it shows.
//!
//! Each world body's inertia is taken at a reference orientation that follows
//! the body once it has turned by more than the tolerance, so an unchanged
//! inertia is equal bit for bit and a block's `K` can be kept whole too.

use super::block::{Block, RowKind};
use super::contact::{Constraint, ContactSolver, PairContext, Point};
use super::friction::Patch;
use super::solver_body::SolverBody;
use crate::body::Bodies;
use crate::math::{Mat3, Quat, Vec3};

/// Displacement (m) and quaternion change below which geometry is kept: the
/// substeps' tolerance.
const KEEP_EPS: f64 = super::gather::MOVE_EPS;

/// The previous step's constraints and blocks, kept for their geometry.
#[derive(Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct Previous {
    pub constraints: Vec<Constraint>,
    pub points: Vec<Point>,
    pub patches: Vec<Patch>,
    pub shapes: Vec<super::limit_surface::PatchShape>,
    pub bodies: Vec<SolverBody>,
    /// Next constraint to look at (constraints come in the order of their
    /// pairs, run by run: see [`Self::find`]).
    cursor: usize,
    /// The runs of the constraints in pair order, `(start, end)`: one, or
    /// one per half and the seam after a split (see `super::seams`). Found
    /// when they are set aside.
    #[serde(skip)]
    runs: Vec<(usize, usize)>,
    /// Which run of this step's questions is being asked, and the last key
    /// asked.
    #[serde(skip)]
    run: usize,
    #[serde(skip)]
    asked: Option<((u32, u32), u32)>,
    /// This step's constraints are built half by half (see `super::seams`):
    /// its questions come in runs. Set by the build.
    #[serde(skip)]
    in_runs: bool,
    /// Which constraint of this step took the geometry of which of the last.
    pub kept: Vec<u32>,
    pub blocks: Vec<Block>,
    pub faces: Vec<u32>,
    pub rows: Vec<super::block::Row>,
    pub k: Vec<f64>,
    pub factor: Vec<f64>,
    /// Per world body: its block last step (`u32::MAX`: none).
    pub block_of: Vec<u32>,
    /// Per world body: the orientation its inertia is taken at.
    pub orientation: Vec<Quat>,
    /// Per world body that was body 1 of a tracked constraint (see
    /// `still_slack`) last step: its orientation then.
    pub built_at: Vec<Quat>,
}

impl Previous {
    /// Exchanges the support plan (blocks, faces, rows, `K` and factors) with
    /// `s`'s.
    fn swap_plan(&mut self, s: &mut super::support::Support) {
        std::mem::swap(&mut self.blocks, &mut s.blocks);
        std::mem::swap(&mut self.faces, &mut s.faces);
        std::mem::swap(&mut self.rows, &mut s.rows);
        std::mem::swap(&mut self.k, &mut s.k);
        std::mem::swap(&mut self.factor, &mut s.factor);
    }

    /// The last step's constraint of manifold `index` of `pair`, if there was
    /// one. Asked in pair order, as the constraints were built: a cursor walks
    /// them.
    ///
    /// This step's questions and last step's constraints both come in runs
    /// in pair order (one, or the halves' and the seam's: see
    /// `super::seams`). A question smaller than the last starts the next run
    /// of questions, walked through the same run of last step's constraints
    /// (through the first again if last step had only one); a manifold not
    /// in that run (its pair changed halves) is looked up in the others.
    #[inline]
    pub(crate) fn find(&mut self, pair: (u32, u32), index: u32) -> Option<usize> {
        let key = (pair, index);
        let key_of = |o: &Constraint| (o.pair, o.manifold);
        if self.in_runs && self.asked.is_some_and(|last| key < last) {
            self.run += 1;
            self.cursor = self.runs.get(self.run).map_or(0, |r| r.0);
        }
        self.asked = Some(key);
        let end = if self.in_runs { self.runs.get(self.run).or(self.runs.first()).map_or(0, |r| r.1) } else { self.constraints.len() };
        while self.cursor < end && self.constraints.get(self.cursor).is_some_and(|o| key_of(o) < key) {
            self.cursor += 1;
        }
        if self.cursor < end && self.constraints.get(self.cursor).is_some_and(|o| key_of(o) == key) {
            return Some(self.cursor);
        }
        let runs = if self.in_runs && self.runs.len() > 1 { &self.runs[..] } else { &[] };
        runs.iter().find_map(|&(a, b)| {
            let run = self.constraints.get(a..b)?;
            let at = a + run.partition_point(|o| key_of(o) < key);
            self.constraints.get(at).filter(|o| at < b && key_of(o) == key).map(|_| at)
        })
    }

    /// This step's questions come in runs (see [`Self::find`]): the runs of
    /// the constraints set aside.
    pub(crate) fn ask_in_runs(&mut self) {
        self.in_runs = true;
        self.runs.clear();
        let mut start = 0;
        for (k, w) in self.constraints.windows(2).enumerate() {
            if (w[1].pair, w[1].manifold) < (w[0].pair, w[0].manifold) {
                self.runs.push((start, k + 1));
                start = k + 1;
            }
        }
        self.runs.push((start, self.constraints.len()));
        self.run = 0;
        self.asked = None;
    }
}

/// Whether the geometry of the last step's constraint `oi` holds for `points`,
/// just laid out with normal `n`: the same bodies, points and normal within
/// [`KEEP_EPS`]. Returns the largest squared distance of a new anchor or the
/// normal from the old one.
#[inline]
pub(crate) fn holds(p: &Previous, bodies: &[SolverBody], oi: usize, ctx: &PairContext, n: &Vec3, points: &[Point]) -> Option<f64> {
    let o = &p.constraints[oi];
    // Distances compared squared: this runs for every constraint every step.
    let far = KEEP_EPS * KEEP_EPS;
    let turned = (o.normal - n).norm_squared();
    if !o.as_built || o.len as usize != points.len() || turned > far || !same_bodies(p, bodies, o, ctx) {
        return None;
    }
    let old = &p.points[o.start as usize..(o.start + o.len) as usize];
    let mut worst = turned;
    for (a, b) in points.iter().zip(old) {
        if a.manifold != b.manifold || a.manifold_point != b.manifold_point || a.corner != b.corner {
            return None;
        }
        worst = worst.max((a.anchor1 - b.anchor1).norm_squared()).max((a.anchor2 - b.anchor2).norm_squared());
    }
    (worst <= far && touching(points) == touching(old)).then_some(worst)
}

/// Whether constraint `o`'s solver bodies are this step's `ctx.s1`, `ctx.s2`
/// as to fixedness, mass and inertia.
#[inline]
fn same_bodies(p: &Previous, bodies: &[SolverBody], o: &Constraint, ctx: &PairContext) -> bool {
    let same = |os: u32, ns: u32| {
        let (a, b) = (&p.bodies[os as usize], &bodies[ns as usize]);
        (os == 0) == (ns == 0) && a.inv_m == b.inv_m && a.inv_i == b.inv_i && a.dynamic == b.dynamic
    };
    same(o.s1, ctx.s1) && same(o.s2, ctx.s2)
}

/// Room (m) a constraint's anchors leave for computation round-off and for
/// the jitter of a still pair (its relative pose within `STILL` of where its
/// manifolds were computed), per metre of its longest anchor.
const STILL_MARGIN: f64 = 1e3 * crate::collide::narrow_phase::STILL;

/// The slack last step's constraint `oi` keeps this step if its pair is
/// still (its manifolds last step's: see `narrow_phase::STILL`), without
/// laying out the points afresh; `None` if it must be checked by [`holds`].
///
/// Anchors and normal computed afresh for a still pair are fixed in body 1
/// (up to the pair's jitter): they turn with it and do not move as it moves.
/// A turn of the orientation quaternion by `|Δq|` moves a vector of length
/// `r` by at most `2 |Δq| r`. So after [`holds`] found them within `KEEP_EPS
/// − slack` of the kept anchors, every later step of a still pair takes
/// `2 |Δq| arm` off the slack, and while it stays above the margin, the
/// anchors [`holds`] would compute still hold: the constraint keeps its
/// geometry as it would after that check, and the points are not laid out
/// (a resting pyramid of 820 boxes spent a third of its step building its
/// constraints).
#[inline]
pub(crate) fn still_slack(p: &Previous, bodies: &[SolverBody], oi: usize, ctx: &PairContext, (len, q1): (u32, Quat)) -> Option<f64> {
    let o = &p.constraints[oi];
    // Body 1's turn since the last build (none known: no keeping).
    let turned = p.built_at.get(ctx.b1 as usize).map_or(f64::INFINITY, |q| 2.0 * (q1 - q).norm());
    let slack = o.slack - turned * o.arm;
    (o.as_built && o.len == len && slack >= STILL_MARGIN * o.arm && same_bodies(p, bodies, o, ctx)).then_some(slack)
}

/// The slack and arm (see [`still_slack`]) of a constraint whose points
/// `points` were checked, `worst`: the squared distance [`holds`] found
/// (0 for geometry computed afresh).
pub(crate) fn slack_of(points: &[Point], worst: f64) -> (f64, f64) {
    let arm2 = points.iter().fold(1.0f64, |a, p| a.max(p.anchor1.norm_squared()).max(p.anchor2.norm_squared()));
    (KEEP_EPS - worst.sqrt(), arm2.sqrt())
}

/// Takes the geometry of the last step's constraint `oi` for `points`; returns
/// its normal and tangents (its patch: [`Patch::take_geometry_of`]).
#[inline]
pub(crate) fn keep(p: &Previous, oi: usize, points: &mut [Point]) -> (Vec3, Vec3, Vec3) {
    let o = &p.constraints[oi];
    let old = &p.points[o.start as usize..(o.start + o.len) as usize];
    for (p, q) in points.iter_mut().zip(old) {
        p.anchor1 = q.anchor1;
        p.anchor2 = q.anchor2;
        p.r1 = q.anchor1;
        p.r2 = q.anchor2;
        p.rn1 = q.rn1;
        p.rn2 = q.rn2;
        p.irn1 = q.irn1;
        p.irn2 = q.irn2;
        p.normal_mass = q.normal_mass;
        p.base_separation = p.separation - o.normal.dot(&(q.anchor2 - q.anchor1));
    }
    (o.normal, o.t1, o.t2)
}

/// Marks a constraint whose geometry was computed afresh.
pub const NONE: u32 = u32::MAX;

impl ContactSolver {
    /// Sets this step's constraints and blocks aside as the last step's. The
    /// arrays they swap with (two steps old) keep their length: the build
    /// clears them or overwrites them whole.
    pub(crate) fn set_aside(&mut self) {
        let p = &mut self.previous;
        // Forget the blocks of two steps ago before their bodies go.
        for b in &p.blocks {
            if let Some(e) = p.bodies.get(b.body as usize).and_then(|sb| p.block_of.get_mut(sb.body as usize)) {
                *e = NONE;
            }
        }
        std::mem::swap(&mut p.constraints, &mut self.constraints);
        std::mem::swap(&mut p.points, &mut self.points);
        std::mem::swap(&mut p.patches, &mut self.patches);
        std::mem::swap(&mut p.shapes, &mut self.shapes);
        std::mem::swap(&mut p.bodies, &mut self.bodies);
        p.swap_plan(&mut self.support);
        p.block_of.resize(self.slot.len(), NONE);
        for (g, b) in p.blocks.iter().enumerate() {
            if let Some(e) = p.bodies.get(b.body as usize).and_then(|sb| p.block_of.get_mut(sb.body as usize)) {
                *e = g as u32;
            }
        }
        p.cursor = 0;
        p.in_runs = false;
        p.asked = None;
        p.kept.clear();
        self.bodies.clear();
    }

    /// The inverse world inertia of body `i` at its reference orientation.
    pub(crate) fn reference_inv_inertia(&mut self, b: &Bodies, i: usize) -> Mat3 {
        let o = &mut self.previous.orientation;
        if o.len() <= i {
            o.resize(i + 1, Quat::new(0.0, 0.0, 0.0, 0.0));
        }
        let q = b.q(i);
        if (q - o[i]).norm() > KEEP_EPS {
            o[i] = q;
        }
        super::contact::inv_inertia_at(b, i, &o[i])
    }

    /// Takes `J`, `K`, its factor and `Q` of block `g` from the last step's
    /// block of the same upper body, if every face of it kept its geometry and
    /// the rows are laid out alike; returns whether it did.
    pub(crate) fn keep_block(&mut self, g: usize) -> bool {
        let b = self.support.blocks[g];
        let p = &self.previous;
        let world = self.bodies[b.body as usize].body as usize;
        let Some(&og) = p.block_of.get(world) else { return false };
        let Some(o) = p.blocks.get(og as usize) else { return false };
        let (f0, f1) = (b.faces.0 as usize, b.faces.1 as usize);
        let (g0, g1) = (o.faces.0 as usize, o.faces.1 as usize);
        let (r0, r1) = (b.rows.0 as usize, b.rows.1 as usize);
        let (q0, q1) = (o.rows.0 as usize, o.rows.1 as usize);
        if f1 - f0 != g1 - g0 || r1 - r0 != q1 - q0 {
            return false;
        }
        let same_face = |k: usize| {
            let ci = self.support.faces[f0 + k] as usize;
            let (c, kept) = (&self.constraints[ci], p.kept.get(ci).copied().unwrap_or(NONE));
            kept == p.faces[g0 + k] && p.constraints.get(kept as usize).is_some_and(|oc| oc.lower == c.lower)
        };
        if !(0..f1 - f0).all(same_face) {
            return false;
        }
        let alike = (0..r1 - r0).all(|i| same_kind(self.support.rows[r0 + i].kind, p.rows[q0 + i].kind));
        if !alike {
            return false;
        }
        for i in 0..r1 - r0 {
            let (old, new) = (p.rows[q0 + i], &mut self.support.rows[r0 + i]);
            new.ju = old.ju;
            new.jl = old.jl;
            new.wu = old.wu;
        }
        let m2 = (r1 - r0) * (r1 - r0);
        let (ok, nk) = (o.k as usize, b.k as usize);
        if o.k_ready {
            self.support.k[nk..nk + m2].copy_from_slice(&p.k[ok..ok + m2]);
            self.support.factor[nk..nk + m2].copy_from_slice(&p.factor[ok..ok + m2]);
        }
        let blk = &mut self.support.blocks[g];
        blk.q = o.q;
        blk.k_ready = o.k_ready;
        blk.dirty = false;
        true
    }
}

impl ContactSolver {
    /// Whether last step's support plan holds for this step as it is: the same
    /// solver bodies, every constraint kept whole at its index (so the same
    /// normals, points, masses and support graph) and settled as it was. Then
    /// its blocks, rows, `J`, `K` and `Q` are this step's: planning them again
    /// cost a resting pyramid 15 % of its step.
    pub(crate) fn plan_unchanged(&self) -> bool {
        let p = &self.previous;
        let n = self.constraints.len();
        p.constraints.len() == n
            && p.kept.len() == n
            && p.bodies.len() == self.bodies.len()
            && self.bodies.iter().zip(&p.bodies).all(|(a, b)| a.body == b.body && a.dynamic == b.dynamic)
            && p.kept.iter().enumerate().all(|(i, &k)| k as usize == i)
            && self.constraints.iter().zip(&p.constraints).all(|(c, o)| c.settled == o.settled)
    }

    /// Takes last step's support plan back (see [`Self::plan_unchanged`]).
    pub(crate) fn restore_plan(&mut self) {
        let p = &mut self.previous;
        for (c, o) in self.constraints.iter_mut().zip(&p.constraints) {
            c.lower = o.lower;
            c.group = o.group;
        }
        p.swap_plan(&mut self.support);
        let lowers = self.constraints.iter().enumerate().filter(|(_, c)| c.lower == 0);
        self.ordinary.extend(lowers.map(|(ci, _)| ci as u32));
    }
}

/// Which points of a manifold touch at the step start (see
/// `friction::Patch::patch_of_touching`), as a bit mask.
fn touching(points: &[Point]) -> u64 {
    let nearest = points.iter().map(|p| p.separation).fold(f64::INFINITY, f64::min);
    let reach = super::friction::touch_reach(nearest);
    points.iter().take(64).enumerate().fold(0, |m, (k, p)| if p.separation <= reach { m | 1 << k } else { m })
}

/// Whether two rows constrain the same thing (normals of the points at the
/// same place in their faces, which are alike).
fn same_kind(a: RowKind, b: RowKind) -> bool {
    matches!((a, b), (RowKind::Normal(_), RowKind::Normal(_))) || a == b
}

#[cfg(test)]
#[path = "reuse_tests.rs"]
mod tests;
