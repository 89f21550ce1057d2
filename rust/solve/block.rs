//! The block of one body on its supports (see [`super::support`]): every normal
//! point, friction direction and twist of the support contacts under it, as rows
//! `J` over its six velocities with the bodies under it held, solved together.
//!
//! A Gauss–Seidel pass over the points of a face does not solve it: the corners
//! of a box are coupled through its rotation, and a friction impulse at the face
//! tilts it. Under a heavy load, what such a pass leaves over is passed down to
//! the bodies below as a rocking that grows down a column. So the block is solved
//! exactly, `K Δλ = r` with `K = J M⁻¹ Jᵀ`, and the answer kept if every point
//! pushes and every friction impulse fits its cone. Where the rows hold all six
//! velocities of the body (a face, or faces), the answer is the least-norm one
//! through a 6 × 6 operator ([`min_norm`]), kept while the block's bodies have
//! not moved; otherwise `K` is factored (dependent rows dropped). A body that
//! tips or slides on its supports is solved by projected Gauss–Seidel on `K`, in
//! impulse space. The rows, `K` and `Q` are built in
//! [`super::block_assembly`].

use super::contact::{Constraint, ContactSolver, Point};
use super::friction::Patch;
use super::island_sweeps::Sweep;
use super::limit_surface::inside;
use super::active_set::Pivot;
use super::projected_gauss_seidel::Runs;
use crate::math::Vec3;
use super::ldlt::solve_factored;
use nalgebra::{Matrix6, Vector6};

/// Largest change of an upper body's velocity (at its contacts' lever) an exact
/// solve may make per unit of the largest change its rows ask: levers of one
/// face differ by a few times; a least-squares fit along a direction the rows
/// barely hold amplifies by 1/angle² between their normals.
const MAX_AMPLIFICATION: f64 = 100.0;

/// Weight of a friction or twist row against a normal one in the least-norm
/// solve: of the impulses that give the same motion, the one that rests a body
/// on the normals of its points (statics) and asks friction only for what they
/// cannot give (a sideways force, a turn about the normal).
const FRICTION_WEIGHT: f64 = 1e3;

/// One body on its supports.
#[derive(Clone, Copy, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Block {
    /// Solver index of the upper body, and its height in the support graph.
    pub body: u32,
    pub level: u32,
    /// Its island (see [`super::quiet`]).
    pub island: u32,
    /// Ranges in `Support::faces` and `Support::rows`; offset of `K` and its
    /// factor in `Support::k`, `Support::factor`.
    pub faces: (u32, u32),
    pub rows: (u32, u32),
    pub k: u32,
    /// `J` and `Q` need recomputing (a body of the block moved).
    pub dirty: bool,
    /// The sweep pass in which it was last solved.
    pub solved_pass: u64,
    /// `K` and its factor are those of the current `J`.
    pub k_ready: bool,
    /// `Q = P⁻¹ M P⁻¹` with `P = Jᵀ W⁻¹ J`, when the rows hold all six of the
    /// upper body's velocities (`P` invertible): see [`min_norm`].
    pub q: Option<Matrix6<f64>>,
    /// Smallest and largest effective separation of its points at the step
    /// start (m), and the longest lever of its rows (m, at least 1): see
    /// [`super::quiet`].
    pub low: f64,
    pub high: f64,
    pub arm: f64,
}

/// What a row constrains.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum RowKind {
    /// The normal of point `.0` (index in `ContactSolver::points`).
    Normal(u32),
    /// Friction along the patch's `t1` (0) or `t2` (1).
    Tangent(u8),
    /// Friction about the normal.
    Twist,
}

/// One row of a block: its velocity is `ju·(v, ω)_upper + jl·(v, ω)_lower`.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct Row {
    pub ju: [Vec3; 2],
    pub jl: [Vec3; 2],
    /// `M⁻¹ juᵀ` of the upper body.
    pub wu: [Vec3; 2],
    /// Solver index of the lower body, the constraint (face) and the block.
    pub lower: u32,
    pub face: u32,
    pub block: u32,
    pub kind: RowKind,
}

/// What a solve asks of a row.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Target {
    /// A normal: velocity (or position change) at least this, pushing only.
    AtLeast(f64),
    /// Friction: this velocity, within the patch's cone.
    Friction(f64),
    /// This change, without bound (friction rows of the position pass).
    Free(f64),
    /// Left alone this pass (a gap after the drift).
    Skip,
}

impl Target {
    /// The value asked for (0 for a row left alone).
    #[inline(always)]
    pub fn value(self) -> f64 {
        match self {
            Target::AtLeast(t) | Target::Friction(t) | Target::Free(t) => t,
            Target::Skip => 0.0,
        }
    }
}

impl Row {
    /// The row's velocity for the given (v, ω) of its upper and lower bodies.
    #[inline(always)]
    pub fn velocity(&self, upper: &(Vec3, Vec3), lower: &(Vec3, Vec3)) -> f64 {
        self.ju[0].dot(&upper.0) + self.ju[1].dot(&upper.1) + self.jl[0].dot(&lower.0) + self.jl[1].dot(&lower.1)
    }

    /// The accumulated impulse of the row.
    #[inline(always)]
    pub fn lambda(&self, points: &[Point], patches: &[Patch]) -> f64 {
        match self.kind {
            RowKind::Normal(pi) => points[pi as usize].normal_impulse,
            RowKind::Tangent(a) => patches[self.face as usize].impulse[a as usize],
            RowKind::Twist => patches[self.face as usize].twist,
        }
    }

    #[inline(always)]
    pub fn set_lambda(&self, points: &mut [Point], patches: &mut [Patch], l: f64) {
        match self.kind {
            RowKind::Normal(pi) => points[pi as usize].normal_impulse = l,
            RowKind::Tangent(a) => patches[self.face as usize].impulse[a as usize] = l,
            RowKind::Twist => patches[self.face as usize].twist = l,
        }
    }

    /// Inverse weight of the row in the least-norm solve.
    #[inline(always)]
    pub(super) fn inv_weight(&self) -> f64 {
        if let RowKind::Normal(_) = self.kind {
            1.0
        } else {
            1.0 / FRICTION_WEIGHT
        }
    }

    #[inline(always)]
    pub(super) fn ju6(&self) -> Vector6<f64> {
        Vector6::new(self.ju[0].x, self.ju[0].y, self.ju[0].z, self.ju[1].x, self.ju[1].y, self.ju[1].z)
    }
}

impl Constraint {
    /// Solver index of the upper body of a support contact.
    #[inline(always)]
    pub fn upper_body(&self) -> u32 {
        if self.lower == 1 {
            self.s2
        } else {
            self.s1
        }
    }
}

/// Scratch space of one block solve (taken out of `Support` while it runs).
#[derive(Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct Scratch {
    pub r: Vec<f64>,
    pub lambda: Vec<f64>,
    pub y: Vec<f64>,
    /// Per row: its diagonal entry of `K`.
    pub(super) diag: Vec<f64>,
    /// Per row opening a patch's friction rows: the inverse of their 3×3 `K`.
    pub(super) inv3: Vec<[f64; 6]>,
    /// `y` before a projected Gauss–Seidel sweep.
    pub(super) before: Vec<f64>,
    /// Of the active-set solve and of the faces solved together in projected
    /// Gauss–Seidel (overwritten by each solve, never saved).
    #[serde(skip)]
    pub(super) pivot: Pivot,
    #[serde(skip)]
    pub(super) runs: Runs,
}

impl Scratch {
    /// The round-off of a block solve: a point that carries nothing may come
    /// out at -1e-12 of the block's largest impulse.
    pub(super) fn round_off(&self) -> f64 {
        1e-9 * self.lambda.iter().chain(&self.y).fold(0.0f64, |a, x| a.max(x.abs()))
    }

    /// `m` entries in each (their values are overwritten by each solve).
    fn reset(&mut self, m: usize) {
        for v in [&mut self.r, &mut self.lambda, &mut self.y, &mut self.diag, &mut self.before] {
            v.truncate(m);
            v.resize(m, 0.0);
        }
        self.inv3.truncate(m);
        self.inv3.resize(m, [0.0; 6]);
    }
}

impl ContactSolver {
    /// Solves block `g` for the targets of its rows in `Support::targets`:
    /// exactly if the answer pushes at every point and fits every cone, else by
    /// projected Gauss–Seidel. Applies the change to the upper body, adds it to
    /// the accumulated impulses and keeps it as debt for the lower bodies.
    pub(crate) fn solve_block(&mut self, g: usize, sw: &mut Sweep) {
        let b = self.support.blocks[g];
        let (r0, r1) = (b.rows.0 as usize, b.rows.1 as usize);
        let sc = &mut sw.scratch;
        sc.reset(r1 - r0);
        let upper = &self.bodies[b.body as usize];
        let nu = (upper.v, upper.w);
        let mut largest = 0.0f64;
        for (i, row) in self.support.rows[r0..r1].iter().enumerate() {
            let lo = &self.bodies[row.lower as usize];
            let r = match self.support.targets[r0 + i] {
                Target::Skip => 0.0,
                t => t.value() - row.velocity(&nu, &(lo.v, lo.w)),
            };
            sc.r[i] = r;
            largest = largest.max(r.abs());
            sc.lambda[i] = row.lambda(&self.points, &self.patches);
        }
        if largest == 0.0 {
            return;
        }
        if self.support.blocks[g].solved_pass != self.support.pass {
            self.support.blocks[g].solved_pass = self.support.pass;
            sw.solved.push(g as u32);
            for i in 0..r1 - r0 {
                self.support.start_lambda[r0 + i] = sc.lambda[i];
            }
        }
        self.block_increment(g, sc, Some(&mut sw.rocking));
        let (mut dv, mut dw) = (Vec3::zeros(), Vec3::zeros());
        for i in 0..r1 - r0 {
            let row = self.support.rows[r0 + i];
            if let RowKind::Normal(_) = row.kind {
                // A point the solve left at round-off below zero pushes nothing.
                sc.y[i] = sc.y[i].max(-sc.lambda[i]);
            }
            let y = sc.y[i];
            if y == 0.0 {
                continue;
            }
            dv += row.wu[0] * y;
            dw += row.wu[1] * y;
            row.set_lambda(&mut self.points, &mut self.patches, sc.lambda[i] + y);
            self.support.debt[r0 + i] += y;
        }
        self.touch_body(b.body as usize);
        let ub = &mut self.bodies[b.body as usize];
        ub.v += dv;
        ub.w += dw;
    }

    /// The change `sc.y` of block `g`'s impulses from `sc.lambda` that meets its
    /// targets (`sc.r`: target minus current row velocity). In a `velocity`
    /// pass, an exact answer that pulls at some points is tried again with them
    /// let go ([`super::active_set`]) before projected Gauss–Seidel. (In the
    /// position passes, whose friction rows are unbounded, the same left the
    /// columns of a landed box pile rocking at 4–9 cm/s for ever.) `rocking`:
    /// a velocity pass's note of a slow body rocking (see [`super::rocking`]);
    /// `None` in a position pass.
    fn block_increment(&mut self, g: usize, sc: &mut Scratch, rocking: Option<&mut bool>) {
        let velocity = rocking.is_some();
        let b = self.support.blocks[g];
        let (r0, r1) = (b.rows.0 as usize, b.rows.1 as usize);
        let m = r1 - r0;
        if !self.support.targets[r0..r1].contains(&Target::Skip) {
            match &b.q {
                Some(q) => min_norm(q, &self.support.rows[r0..r1], &sc.r, &mut sc.y),
                None => {
                    self.ensure_k(g);
                    let fac = &self.support.factor[b.k as usize..b.k as usize + m * m];
                    solve_factored(fac, &sc.r, &mut sc.y);
                }
            }
            if self.well_conditioned(g, sc) && self.fits(g, sc) {
                return;
            }
            if let Some(seen) = rocking {
                *seen = *seen || self.rocks(g, sc);
            }
            if velocity && self.active_set(g, sc) {
                return;
            }
        }
        self.projected_gauss_seidel(g, sc, velocity);
    }

    /// Whether the exact solve's change of the upper body is of the size of
    /// what its rows ask. The exact solves fit the row velocities to their
    /// targets in least squares (`Δu = P⁻¹ Jᵀ W⁻¹ r`, see [`min_norm`]); where
    /// two faces have nearly the same normal and different targets, the fit
    /// lies far along the direction the two barely hold, the rows hardly see
    /// it, and every impulse can still come out positive: a box of a tumbling
    /// pile was thrown at 1e14 m/s in one step. Such a block is solved by
    /// projected Gauss–Seidel instead.
    pub(super) fn well_conditioned(&self, g: usize, sc: &Scratch) -> bool {
        let b = self.support.blocks[g];
        let rows = &self.support.rows[b.rows.0 as usize..b.rows.1 as usize];
        let (mut dv, mut dw, mut lever) = (Vec3::zeros(), Vec3::zeros(), 0.0f64);
        for (row, &y) in rows.iter().zip(&sc.y) {
            dv += row.wu[0] * y;
            dw += row.wu[1] * y;
            if let RowKind::Normal(_) = row.kind {
                lever = lever.max(row.ju[1].norm());
            }
        }
        let asked = sc.r.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        // A body already diverged (a change that is not finite) is the step
        // guard's to name, not this check's to pass on to its neighbours.
        let change = dv.norm() + dw.norm() * lever;
        !(change > MAX_AMPLIFICATION * asked + self.support.residual) || !change.is_finite()
    }

    /// Whether impulses `lambda + y` push at every point and fit every cone
    /// (marking the patches as sticking if so).
    pub(super) fn fits(&mut self, g: usize, sc: &Scratch) -> bool {
        let b = self.support.blocks[g];
        let (r0, r1) = (b.rows.0 as usize, b.rows.1 as usize);
        let rows = &self.support.rows[r0..r1];
        let targets = &self.support.targets[r0..r1];
        // Taken as zero.
        let tiny = sc.round_off();
        let mut i = 0;
        while i < rows.len() {
            let face = rows[i].face;
            let (mut normal, mut tangent, mut twist, mut bounded) = (0.0, [0.0; 2], 0.0, true);
            while i < rows.len() && rows[i].face == face {
                let l = sc.lambda[i] + sc.y[i];
                match (rows[i].kind, targets[i]) {
                    (RowKind::Normal(_), Target::AtLeast(_)) if l < -tiny => return false,
                    (RowKind::Normal(_), _) => normal += l,
                    (RowKind::Tangent(a), t) => {
                        tangent[a as usize] = l;
                        bounded = !matches!(t, Target::Free(_));
                    }
                    (RowKind::Twist, _) => twist = l,
                }
                i += 1;
            }
            if !bounded {
                continue;
            }
            let (c, f) = (&self.constraints[face as usize], &self.patches[face as usize]);
            let hold = if f.sliding { c.friction } else { c.static_friction } * normal.max(f.settled);
            if !inside(tangent, twist, hold, f.lever, tiny) {
                return false;
            }
        }
        // A velocity solve that holds every patch leaves them sticking (a position
        // pass, whose friction rows are free, says nothing about it).
        if targets.iter().any(|t| matches!(t, Target::Friction(_))) {
            for k in b.faces.0..b.faces.1 {
                let ci = self.support.faces[k as usize];
                self.patches[ci as usize].sliding = false;
            }
        }
        true
    }

    /// One position pass over block `g`: the upper body moved (not its velocity)
    /// so that its points deeper than the rest depth `rest` come out by `rate` of
    /// the excess (at most `cap` a pass), and its patches neither slide nor turn.
    pub(crate) fn push_block(&mut self, g: usize, rate: f64, cap: f64, rest: f64, sc: &mut Scratch) {
        let b = self.support.blocks[g];
        // No point of it can be deeper than the edge yet (see `super::quiet`).
        if b.low - self.block_moved(g) >= -rest {
            return;
        }
        let (r0, r1) = (b.rows.0 as usize, b.rows.1 as usize);
        let mut push = false;
        let mut i = r0;
        while i < r1 {
            let face = self.support.rows[i].face;
            let gap = super::solver_body::Gap::new(&self.bodies, &self.constraints[face as usize]);
            while i < r1 && self.support.rows[i].face == face {
                self.support.targets[i] = match self.support.rows[i].kind {
                    RowKind::Normal(pi) => {
                        // Down to twice the rest depth is resting: a face a hair
                        // out of flat on its support would otherwise be pushed at
                        // one corner and let down at the other for ever.
                        let s = gap.separation(&self.points[pi as usize]) + rest;
                        let deep = s < -rest;
                        push |= deep;
                        Target::AtLeast(if deep { (-rate * s).min(cap) } else { -s.max(0.0) })
                    }
                    _ => Target::Free(0.0),
                };
                i += 1;
            }
        }
        if !push {
            return;
        }
        sc.reset(r1 - r0);
        for i in 0..r1 - r0 {
            sc.r[i] = self.support.targets[r0 + i].value();
            sc.lambda[i] = 0.0;
        }
        self.block_increment(g, sc, None);
        let (mut dx, mut dtheta) = (Vec3::zeros(), Vec3::zeros());
        for (row, y) in self.support.rows[r0..r1].iter().zip(&sc.y) {
            dx += row.wu[0] * *y;
            dtheta += row.wu[1] * *y;
        }
        let ub = &mut self.bodies[b.body as usize];
        if ub.dynamic {
            ub.dp += dx;
            ub.dq = crate::math::quat::exp(&dtheta) * ub.dq;
            ub.pushed = true;
        }
    }
}

/// The least-norm solution `y` of `K y = r` (`K = J M⁻¹ Jᵀ`, least `yᵀ W y`)
/// for rows `J` of full column rank: `y = W⁻¹ J Q Jᵀ W⁻¹ r`. Among the impulses
/// that give the same motion it spreads the load evenly over the points (a box
/// on two boxes rests on both, not on the one whose rows came first) and uses
/// friction only where the normals cannot act.
fn min_norm(q: &Matrix6<f64>, rows: &[Row], r: &[f64], y: &mut [f64]) {
    let mut jr = Vector6::zeros();
    for (row, &ri) in rows.iter().zip(r) {
        jr += row.ju6() * (ri * row.inv_weight());
    }
    let x = q * jr;
    let (xl, xa) = (Vec3::new(x[0], x[1], x[2]), Vec3::new(x[3], x[4], x[5]));
    for (row, yi) in rows.iter().zip(y.iter_mut()) {
        *yi = (row.ju[0].dot(&xl) + row.ju[1].dot(&xa)) * row.inv_weight();
    }
}
