//! The block of one body on its supports (see [`super::support`]): every normal
//! point, friction direction and twist of the support contacts under it, as rows
//! `J` over its six velocities with the bodies under it held, solved together.
//!
//! A Gauss–Seidel pass over the points of a face does not solve it: the corners
//! of a box are coupled through its rotation, and a friction impulse at the face
//! tilts it. Under a heavy load, what such a pass leaves over is passed down to
//! the bodies below as a rocking that grows down a column. So the block is solved
//! exactly: `K Δλ = r` with `K = J M⁻¹ Jᵀ` (factored once and kept while the
//! block's bodies have not moved; dependent rows, such as a fourth corner of a
//! flat face, are dropped by the factorisation), and the answer kept if every
//! point pushes and every friction impulse fits its cone. A body that tips or
//! slides on its supports is solved instead by projected Gauss–Seidel on `K`, in
//! impulse space.

use super::contact::{Constraint, ContactSolver};
use super::friction::Patch;
use crate::math::Vec3;
use nalgebra::{Matrix6, Vector6};

/// Projected Gauss–Seidel sweeps over a block's rows when its exact solution
/// does not fit the contact conditions (a body tipping or sliding).
const PGS_SWEEPS: usize = 12;

/// Weight of a friction or twist row against a normal one in the least-norm
/// solve: of the impulses that give the same motion, the one that rests a body
/// on the normals of its points (statics) and asks friction only for what they
/// cannot give (a sideways force, a turn about the normal).
const FRICTION_WEIGHT: f64 = 1e3;

/// Inverse weight of a row in the least-norm solve.
#[inline(always)]
fn inv_weight(kind: RowKind) -> f64 {
    if let RowKind::Normal(_) = kind {
        1.0
    } else {
        1.0 / FRICTION_WEIGHT
    }
}

/// A pivot below this fraction of the largest diagonal of `K` marks a row that
/// depends on the ones before it.
const PIVOT_TOLERANCE: f64 = 1e-10;

/// One body on its supports.
#[derive(Clone, Copy, Debug, Default)]
pub struct Block {
    /// Solver index of the upper body, and its height in the support graph.
    pub body: u32,
    pub level: u32,
    /// Ranges in `Support::faces` and `Support::rows`; offset of `K` and its
    /// factor in `Support::k`, `Support::factor`.
    pub faces: (u32, u32),
    pub rows: (u32, u32),
    pub k: u32,
    /// `J`, `K` and the factor need recomputing (a body of the block moved).
    pub dirty: bool,
    /// `Q = P⁻¹ M P⁻¹` with `P = JᵀJ`, when the rows hold all six of the upper
    /// body's velocities (`P` invertible): the least-norm solve (see
    /// [`min_norm`]).
    pub q: Option<Matrix6<f64>>,
}

/// What a row constrains.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RowKind {
    /// The normal of point `.0` (index in `ContactSolver::points`).
    Normal(u32),
    /// Friction along the patch's `t1` (0) or `t2` (1).
    Tangent(u8),
    /// Friction about the normal.
    Twist,
}

/// One row of a block: its velocity is `ju·(v, ω)_upper + jl·(v, ω)_lower`.
#[derive(Clone, Copy, Debug)]
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
#[derive(Clone, Copy, Debug)]
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

impl Row {
    /// The row's velocity for the given (v, ω) of its upper and lower bodies.
    #[inline(always)]
    pub fn velocity(&self, upper: &(Vec3, Vec3), lower: &(Vec3, Vec3)) -> f64 {
        self.ju[0].dot(&upper.0) + self.ju[1].dot(&upper.1) + self.jl[0].dot(&lower.0) + self.jl[1].dot(&lower.1)
    }

    /// The accumulated impulse of the row.
    #[inline(always)]
    pub fn lambda(&self, points: &[super::contact::Point], patches: &[Patch]) -> f64 {
        match self.kind {
            RowKind::Normal(pi) => points[pi as usize].normal_impulse,
            RowKind::Tangent(a) => patches[self.face as usize].impulse[a as usize],
            RowKind::Twist => patches[self.face as usize].twist,
        }
    }

    #[inline(always)]
    pub fn set_lambda(&self, points: &mut [super::contact::Point], patches: &mut [Patch], l: f64) {
        match self.kind {
            RowKind::Normal(pi) => points[pi as usize].normal_impulse = l,
            RowKind::Tangent(a) => patches[self.face as usize].impulse[a as usize] = l,
            RowKind::Twist => patches[self.face as usize].twist = l,
        }
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

impl ContactSolver {
    /// Builds the rows of every block (`all`, after planning) or recomputes
    /// `J`, `K` and the factor of the blocks whose bodies moved.
    pub(crate) fn assemble_blocks(&mut self, all: bool) {
        if all {
            self.lay_out_rows();
        }
        for g in 0..self.support.blocks.len() {
            if all || self.support.blocks[g].dirty {
                self.assemble_block(g);
            }
        }
    }

    /// The rows of every block (kinds and faces), and room for `K`.
    fn lay_out_rows(&mut self) {
        let s = &mut self.support;
        s.rows.clear();
        let mut koff = 0u32;
        for g in 0..s.blocks.len() {
            let first = s.rows.len() as u32;
            let (f0, f1) = s.blocks[g].faces;
            for &ci in &s.faces[f0 as usize..f1 as usize] {
                let c = &self.constraints[ci as usize];
                let mut push = |kind| {
                    let lower = if c.lower == 1 { c.s1 } else { c.s2 };
                    s.rows.push(Row { ju: [Vec3::zeros(); 2], jl: [Vec3::zeros(); 2], wu: [Vec3::zeros(); 2], lower, face: ci, block: g as u32, kind });
                };
                for pi in c.start..c.start + c.len {
                    push(RowKind::Normal(pi));
                }
                if c.static_friction > 0.0 {
                    push(RowKind::Tangent(0));
                    push(RowKind::Tangent(1));
                    if self.patches[ci as usize].radius > 0.0 {
                        push(RowKind::Twist);
                    }
                }
            }
            let m = s.rows.len() as u32 - first;
            let b = &mut s.blocks[g];
            b.rows = (first, first + m);
            b.k = koff;
            koff += m * m;
        }
        s.k.resize(koff as usize, 0.0);
        s.factor.resize(koff as usize, 0.0);
    }

    /// `J` and `M⁻¹Jᵀ` of block `g`'s rows at the current arms, `K`, its factor.
    fn assemble_block(&mut self, g: usize) {
        let b = self.support.blocks[g];
        let upper = &self.bodies[b.body as usize];
        let (inv_m, inv_i) = (upper.inv_m, upper.inv_i);
        for ri in b.rows.0 as usize..b.rows.1 as usize {
            let r = self.support.rows[ri];
            let c = &self.constraints[r.face as usize];
            let f = &self.patches[r.face as usize];
            // Body 2 receives +J λ, body 1 −J λ.
            let (lin, a1, a2) = match r.kind {
                RowKind::Normal(pi) => {
                    let p = &self.points[pi as usize];
                    (c.normal, p.rn1, p.rn2)
                }
                RowKind::Tangent(a) => {
                    let t = if a == 0 { c.t1 } else { c.t2 };
                    (t, f.rt1[a as usize], f.rt2[a as usize])
                }
                RowKind::Twist => (Vec3::zeros(), c.normal, c.normal),
            };
            let (ju, jl) = if c.lower == 1 { ([lin, a2], [-lin, -a1]) } else { ([-lin, -a1], [lin, a2]) };
            let row = &mut self.support.rows[ri];
            row.ju = ju;
            row.jl = jl;
            row.wu = [ju[0] * inv_m, inv_i * ju[1]];
        }
        let m = (b.rows.1 - b.rows.0) as usize;
        let rows = &self.support.rows[b.rows.0 as usize..b.rows.1 as usize];
        let k = &mut self.support.k[b.k as usize..b.k as usize + m * m];
        for i in 0..m {
            for j in 0..=i {
                let v = rows[i].ju[0].dot(&rows[j].wu[0]) + rows[i].ju[1].dot(&rows[j].wu[1]);
                k[i * m + j] = v;
                k[j * m + i] = v;
            }
        }
        factor(k, &mut self.support.factor[b.k as usize..b.k as usize + m * m], m);
        let q = least_norm_operator(rows, &self.bodies[b.body as usize]);
        let blk = &mut self.support.blocks[g];
        blk.q = q;
        blk.dirty = false;
    }

    /// Solves block `g` for the velocity targets: exactly if the answer pushes at
    /// every point and fits every cone, else by projected Gauss–Seidel. Applies
    /// the change to the upper body, adds it to the accumulated impulses and
    /// keeps it as debt for the lower bodies.
    pub(crate) fn solve_block(&mut self, g: usize, targets: &[Target]) {
        let b = self.support.blocks[g];
        let (r0, m) = (b.rows.0 as usize, (b.rows.1 - b.rows.0) as usize);
        let upper = &self.bodies[b.body as usize];
        let nu = (upper.v, upper.w);
        let mut r = vec![0.0; m];
        let mut lambda = vec![0.0; m];
        for i in 0..m {
            let row = &self.support.rows[r0 + i];
            let lo = &self.bodies[row.lower as usize];
            let v = row.velocity(&nu, &(lo.v, lo.w));
            r[i] = match targets[i] {
                Target::AtLeast(t) | Target::Friction(t) | Target::Free(t) => t - v,
                Target::Skip => 0.0,
            };
            lambda[i] = row.lambda(&self.points, &self.patches);
        }
        let y = self.block_increment(g, targets, &r, &lambda);
        let (mut dv, mut dw) = (Vec3::zeros(), Vec3::zeros());
        for i in 0..m {
            if y[i] == 0.0 {
                continue;
            }
            let row = self.support.rows[r0 + i];
            dv += row.wu[0] * y[i];
            dw += row.wu[1] * y[i];
            row.set_lambda(&mut self.points, &mut self.patches, lambda[i] + y[i]);
            self.support.debt[r0 + i] += y[i];
        }
        let ub = &mut self.bodies[b.body as usize];
        ub.v += dv;
        ub.w += dw;
    }

    /// The change of block `g`'s impulses from `lambda` that meets the targets
    /// (`r`: target minus current row velocity).
    fn block_increment(&mut self, g: usize, targets: &[Target], r: &[f64], lambda: &[f64]) -> Vec<f64> {
        let b = self.support.blocks[g];
        let m = r.len();
        if !targets.iter().any(|t| matches!(t, Target::Skip)) {
            let y = match &b.q {
                Some(q) => min_norm(q, &self.support.rows[b.rows.0 as usize..b.rows.1 as usize], r),
                None => solve_factored(&self.support.factor[b.k as usize..b.k as usize + m * m], r, m),
            };
            if self.fits(g, targets, lambda, &y) {
                return y;
            }
        }
        self.projected_gauss_seidel(g, targets, r, lambda)
    }

    /// Whether impulses `lambda + y` push at every point and fit every cone
    /// (marking the patches as sticking if so).
    fn fits(&mut self, g: usize, targets: &[Target], lambda: &[f64], y: &[f64]) -> bool {
        let b = self.support.blocks[g];
        let rows = &self.support.rows[b.rows.0 as usize..b.rows.1 as usize];
        let scale = lambda.iter().chain(y).fold(0.0f64, |a, x| a.max(x.abs()));
        let tiny = 1e-12 * scale;
        let mut i = 0;
        while i < rows.len() {
            let face = rows[i].face;
            let (mut normal, mut tangent, mut twist) = (0.0, [0.0; 2], 0.0);
            while i < rows.len() && rows[i].face == face {
                let l = lambda[i] + y[i];
                match (rows[i].kind, targets[i]) {
                    (RowKind::Normal(_), Target::AtLeast(_)) if l < -tiny => return false,
                    (RowKind::Normal(_), _) => normal += l,
                    (RowKind::Tangent(a), _) => tangent[a as usize] = l,
                    (RowKind::Twist, _) => twist = l,
                }
                i += 1;
            }
            if matches!(targets[i - 1], Target::Free(_)) {
                continue;
            }
            let (c, f) = (&self.constraints[face as usize], &self.patches[face as usize]);
            let hold = if f.sliding { c.friction } else { c.static_friction } * normal.max(f.settled);
            let t = (tangent[0] * tangent[0] + tangent[1] * tangent[1]).sqrt();
            if t > hold + tiny || twist.abs() > hold * f.radius + tiny {
                return false;
            }
        }
        let (f0, f1) = b.faces;
        for k in f0..f1 {
            let ci = self.support.faces[k as usize];
            self.patches[ci as usize].sliding = false;
        }
        true
    }

    /// Projected Gauss–Seidel on block `g`'s `K` in impulse space: points push,
    /// friction stays in its cone (Coulomb: a patch that breaks away slides with
    /// the dynamic coefficient), position rows (`Free`) are unbounded.
    fn projected_gauss_seidel(&mut self, g: usize, targets: &[Target], r: &[f64], lambda: &[f64]) -> Vec<f64> {
        let b = self.support.blocks[g];
        let m = r.len();
        let k = &self.support.k[b.k as usize..b.k as usize + m * m];
        let rows = &self.support.rows[b.rows.0 as usize..b.rows.1 as usize];
        let mut y = vec![0.0; m];
        let mut ky = vec![0.0; m];
        let add = |y: &mut [f64], ky: &mut [f64], i: usize, d: f64| {
            if d != 0.0 {
                y[i] += d;
                for (j, kj) in ky.iter_mut().enumerate() {
                    *kj += k[j * m + i] * d;
                }
            }
        };
        for _ in 0..PGS_SWEEPS {
            let mut i = 0;
            while i < m {
                let face = rows[i].face;
                let mut normal = 0.0;
                while i < m && rows[i].face == face {
                    let res = r[i] - ky[i];
                    let kii = k[i * m + i];
                    match (rows[i].kind, targets[i]) {
                        (_, Target::Skip) => {
                            if let RowKind::Normal(_) = rows[i].kind {
                                normal += lambda[i] + y[i];
                            }
                        }
                        (RowKind::Normal(_), Target::AtLeast(_)) => {
                            let l = lambda[i] + y[i];
                            let new = if kii > 0.0 { (l + res / kii).max(0.0) } else { l.max(0.0) };
                            add(&mut y, &mut ky, i, new - l);
                            normal += new;
                        }
                        (RowKind::Tangent(0), Target::Friction(_)) if i + 1 < m => {
                            let patch = &mut self.patches[face as usize];
                            let c = &self.constraints[face as usize];
                            let l = [lambda[i] + y[i], lambda[i + 1] + y[i + 1]];
                            let res2 = r[i + 1] - ky[i + 1];
                            let (a, bb, d) = (kii, k[i * m + i + 1], k[(i + 1) * m + i + 1]);
                            let det = a * d - bb * bb;
                            let step = if det > 0.0 { [(d * res - bb * res2) / det, (a * res2 - bb * res) / det] } else { [0.0; 2] };
                            let cand = [l[0] + step[0], l[1] + step[1]];
                            // With a zero target, what is left to do is minus the slip.
                            let new = cone(patch, c, cand, [-res, -res2], normal);
                            add(&mut y, &mut ky, i, new[0] - l[0]);
                            add(&mut y, &mut ky, i + 1, new[1] - l[1]);
                            i += 1;
                        }
                        (RowKind::Twist, Target::Friction(_)) => {
                            let (patch, c) = (&self.patches[face as usize], &self.constraints[face as usize]);
                            let mu = if patch.sliding { c.friction } else { c.static_friction };
                            let limit = mu * normal.max(patch.settled) * patch.radius;
                            let l = lambda[i] + y[i];
                            let new = if kii > 0.0 { (l + res / kii).clamp(-limit, limit) } else { l };
                            add(&mut y, &mut ky, i, new - l);
                        }
                        _ => {
                            if kii > 0.0 {
                                add(&mut y, &mut ky, i, res / kii);
                            }
                            if let RowKind::Normal(_) = rows[i].kind {
                                normal += lambda[i] + y[i];
                            }
                        }
                    }
                    i += 1;
                }
            }
        }
        y
    }

    /// One position pass over block `g`: the upper body moved (not its velocity)
    /// so that its points deeper than the rest depth `rest` come out by `rate` of
    /// the excess (at most `cap` a pass), and its patches neither slide nor turn.
    pub(crate) fn push_block(&mut self, g: usize, rate: f64, cap: f64, rest: f64) {
        let b = self.support.blocks[g];
        let (r0, m) = (b.rows.0 as usize, (b.rows.1 - b.rows.0) as usize);
        let mut targets = Vec::with_capacity(m);
        let mut r = Vec::with_capacity(m);
        for i in 0..m {
            let row = &self.support.rows[r0 + i];
            let t = match row.kind {
                RowKind::Normal(pi) => {
                    let c = &self.constraints[row.face as usize];
                    let s = super::solver_body::Gap::new(&self.bodies, c).separation(&self.points[pi as usize]);
                    let s = s + rest;
                    if s < 0.0 {
                        Target::AtLeast((-rate * s).min(cap))
                    } else {
                        Target::AtLeast(-s)
                    }
                }
                _ => Target::Free(0.0),
            };
            r.push(match t {
                Target::AtLeast(v) | Target::Friction(v) | Target::Free(v) => v,
                Target::Skip => 0.0,
            });
            targets.push(t);
        }
        if !targets.iter().any(|t| matches!(t, Target::AtLeast(v) if *v > 0.0)) {
            return;
        }
        let zero = vec![0.0; m];
        let y = self.block_increment(g, &targets, &r, &zero);
        let (mut dx, mut dtheta) = (Vec3::zeros(), Vec3::zeros());
        for i in 0..m {
            let row = &self.support.rows[r0 + i];
            dx += row.wu[0] * y[i];
            dtheta += row.wu[1] * y[i];
        }
        let ub = &mut self.bodies[b.body as usize];
        if ub.dynamic {
            ub.dp += dx;
            ub.dq = crate::math::quat::exp(&dtheta) * ub.dq;
            ub.pushed = true;
        }
    }
}

/// `Q = P⁻¹ M P⁻¹` of a block whose rows `J` hold all six velocities of its
/// upper body (`P = Jᵀ W⁻¹ J` well conditioned, `W` the rows' weights), else
/// `None`.
fn least_norm_operator(rows: &[Row], upper: &super::solver_body::SolverBody) -> Option<Matrix6<f64>> {
    if rows.len() < 6 || upper.inv_m <= 0.0 {
        return None;
    }
    let mut p = Matrix6::zeros();
    for r in rows {
        let j = Vector6::new(r.ju[0].x, r.ju[0].y, r.ju[0].z, r.ju[1].x, r.ju[1].y, r.ju[1].z);
        p += j * j.transpose() * inv_weight(r.kind);
    }
    let ch = p.cholesky()?;
    let d = ch.l_dirty().diagonal();
    if d.min() <= 1e-6 * d.max() {
        return None;
    }
    let inertia = upper.inv_i.try_inverse()?;
    let mut mass = Matrix6::zeros();
    mass.fixed_view_mut::<3, 3>(0, 0).copy_from(&(nalgebra::Matrix3::identity() / upper.inv_m));
    mass.fixed_view_mut::<3, 3>(3, 3).copy_from(&inertia);
    let pinv = ch.inverse();
    Some(pinv * mass * pinv)
}

/// The least-norm solution of `K y = r` (`K = J M⁻¹ Jᵀ`, least `yᵀ W y`) for
/// rows `J` of full column rank: `y = W⁻¹ J Q Jᵀ W⁻¹ r`. Among the impulses
/// that give the same motion it spreads the load evenly over the points (a box
/// on two boxes rests on both, not on the one whose rows came first) and uses
/// friction only where the normals cannot act.
fn min_norm(q: &Matrix6<f64>, rows: &[Row], r: &[f64]) -> Vec<f64> {
    let mut jr = Vector6::zeros();
    for (row, &ri) in rows.iter().zip(r) {
        let j = Vector6::new(row.ju[0].x, row.ju[0].y, row.ju[0].z, row.ju[1].x, row.ju[1].y, row.ju[1].z);
        jr += j * (ri * inv_weight(row.kind));
    }
    let x = q * jr;
    let (xl, xa) = (Vec3::new(x[0], x[1], x[2]), Vec3::new(x[3], x[4], x[5]));
    rows.iter().map(|row| (row.ju[0].dot(&xl) + row.ju[1].dot(&xa)) * inv_weight(row.kind)).collect()
}

/// A tangential impulse `cand` (the one that stops the patch) on the cone of
/// normal impulse `normal`: kept if it sticks within the static cone, else the
/// dynamic one against the slip `slip` (Coulomb's law; along `cand` when the slip
/// is too slow to have a direction), and the patch slides.
fn cone(f: &mut Patch, c: &Constraint, cand: [f64; 2], slip: [f64; 2], normal: f64) -> [f64; 2] {
    let len = (cand[0] * cand[0] + cand[1] * cand[1]).sqrt();
    let hold = if f.sliding { c.friction } else { c.static_friction } * normal.max(f.settled);
    if len <= hold {
        f.sliding = false;
        return cand;
    }
    f.sliding = true;
    let speed = (slip[0] * slip[0] + slip[1] * slip[1]).sqrt();
    let (dir, n) = if speed > super::friction::SLIP_EPS { ([-slip[0], -slip[1]], speed) } else { (cand, len) };
    if n == 0.0 {
        return [0.0; 2];
    }
    let s = c.friction * normal / n;
    [dir[0] * s, dir[1] * s]
}

/// `K = L D Lᵀ` of a symmetric positive semi-definite `m × m` matrix: `L` below
/// the diagonal of `out`, `D` on it. A row that depends on the ones before it
/// (pivot below [`PIVOT_TOLERANCE`] of the largest diagonal) gets `D = 0` and
/// is left out of every solve.
pub fn factor(k: &[f64], out: &mut [f64], m: usize) {
    let scale = (0..m).map(|i| k[i * m + i]).fold(0.0f64, f64::max);
    let tol = PIVOT_TOLERANCE * scale;
    for j in 0..m {
        let mut d = k[j * m + j];
        for p in 0..j {
            d -= out[j * m + p] * out[j * m + p] * out[p * m + p];
        }
        if d <= tol {
            out[j * m + j] = 0.0;
            for i in j + 1..m {
                out[i * m + j] = 0.0;
            }
            continue;
        }
        out[j * m + j] = d;
        for i in j + 1..m {
            let mut v = k[i * m + j];
            for p in 0..j {
                v -= out[i * m + p] * out[j * m + p] * out[p * m + p];
            }
            out[i * m + j] = v / d;
        }
    }
}

/// Solves `K y = r` with the factor of [`factor`]; dependent rows get `y = 0`.
pub fn solve_factored(fac: &[f64], r: &[f64], m: usize) -> Vec<f64> {
    let mut z = r.to_vec();
    for i in 0..m {
        for p in 0..i {
            z[i] -= fac[i * m + p] * z[p];
        }
    }
    for i in 0..m {
        let d = fac[i * m + i];
        z[i] = if d > 0.0 { z[i] / d } else { 0.0 };
    }
    for i in (0..m).rev() {
        if fac[i * m + i] == 0.0 {
            continue;
        }
        for p in i + 1..m {
            z[i] -= fac[p * m + i] * z[p];
        }
    }
    z
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dependent_row_is_left_out_and_the_rest_solved_exactly() {
        // Rows 0, 1 independent, row 2 = row 0 + row 1: K = A Aᵀ is rank 2.
        let a = [[1.0, 0.0, 2.0], [0.0, 1.0, -1.0], [1.0, 1.0, 1.0]];
        let mut k = [0.0; 9];
        for i in 0..3 {
            for j in 0..3 {
                k[i * 3 + j] = (0..3).map(|c| a[i][c] * a[j][c]).sum();
            }
        }
        let mut fac = [0.0; 9];
        factor(&k, &mut fac, 3);
        assert_eq!(fac[8], 0.0);
        let r = [1.0, 2.0, 3.0]; // consistent: r2 = r0 + r1
        let y = solve_factored(&fac, &r, 3);
        for i in 0..3 {
            let ky: f64 = (0..3).map(|j| k[i * 3 + j] * y[j]).sum();
            assert!((ky - r[i]).abs() < 1e-12, "{ky} vs {}", r[i]);
        }
    }
}
