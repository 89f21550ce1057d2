//! The rows of the support blocks ([`super::block`]) laid out, and each
//! block's `J`, `M⁻¹Jᵀ`, `K` with its factor and the least-norm operator `Q`
//! built from the current arms: once after planning, then for the blocks whose
//! bodies moved.

use super::block::{Block, Row, RowKind};
use super::contact::{Constraint, ContactSolver, Point};
use super::friction::Patch;
use super::ldlt::factor;
use super::solver_body::SolverBody;
use crate::math::Vec3;
use nalgebra::Matrix6;
use rayon::prelude::*;

/// Fewest blocks to reassemble for the work to be split over threads.
const MIN_PARALLEL_ASSEMBLY: usize = 64;

impl ContactSolver {
    /// Builds the rows of every block (`all`, after planning) or recomputes
    /// `J` and `Q` of the blocks whose bodies moved (those on the pool's
    /// threads, when the step runs there: each block writes only its own rows).
    pub(crate) fn assemble_blocks(&mut self, all: bool) {
        if all {
            self.lay_out_rows();
            // Keeping or assembling a block writes only its rows, `K`, factor
            // and record.
            let n = self.support.blocks.len();
            self.par_map(n, self.parallel && n >= MIN_PARALLEL_ASSEMBLY, |cs, g| {
                if !cs.keep_block(g) {
                    cs.assemble_block(g);
                }
            });
            return;
        }
        let dirty = self.support.blocks.iter().filter(|b| b.dirty).count();
        let wide = self.wide();
        let src = Source { constraints: &self.constraints, patches: &self.patches, points: &self.points, bodies: &self.bodies };
        let s = &mut self.support;
        let jobs = if wide && dirty >= MIN_PARALLEL_ASSEMBLY { dirty_rows(&mut s.blocks, &mut s.rows) } else { None };
        match jobs {
            Some(jobs) => jobs.into_par_iter().for_each(|(b, rows)| assemble(b, rows, &src)),
            None => {
                for b in s.blocks.iter_mut().filter(|b| b.dirty) {
                    assemble(b, &mut s.rows[b.rows.0 as usize..b.rows.1 as usize], &src);
                }
            }
        }
    }

    /// `J`, `M⁻¹Jᵀ` and `Q` of block `g`'s rows at the current arms.
    fn assemble_block(&mut self, g: usize) {
        let src = Source { constraints: &self.constraints, patches: &self.patches, points: &self.points, bodies: &self.bodies };
        let s = &mut self.support;
        let b = &mut s.blocks[g];
        assemble(b, &mut s.rows[b.rows.0 as usize..b.rows.1 as usize], &src);
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
                let lower = if c.lower == 1 { c.s1 } else { c.s2 };
                let mut push = |kind| {
                    let zero = [Vec3::zeros(); 2];
                    s.rows.push(Row { ju: zero, jl: zero, wu: zero, lower, face: ci, block: g as u32, kind });
                };
                for pi in c.start..c.start + c.len {
                    push(RowKind::Normal(pi));
                }
                if c.static_friction > 0.0 {
                    push(RowKind::Tangent(0));
                    push(RowKind::Tangent(1));
                    if self.patches[ci as usize].lever > 0.0 {
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
        // Only grown, never cleared: `ensure_k` writes every entry of a block's
        // `K` and `factor` every entry it reads before either is used, and
        // zeroing them each step cost 4 % of a pyramid's step.
        if s.k.len() < koff as usize {
            s.k.resize(koff as usize, 0.0);
            s.factor.resize(koff as usize, 0.0);
        }
    }

    /// `K` of block `g` and its factor, if not already those of its rows.
    pub(super) fn ensure_k(&mut self, g: usize) {
        let b = self.support.blocks[g];
        if b.k_ready {
            return;
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
        self.support.blocks[g].k_ready = true;
    }
}

/// What a block's rows are built from.
struct Source<'a> {
    constraints: &'a [Constraint],
    patches: &'a [Patch],
    points: &'a [Point],
    bodies: &'a [SolverBody],
}

/// The dirty blocks, each with its rows; `None` if the rows are not laid out
/// block after block (as `lay_out_rows` does).
fn dirty_rows<'a>(blocks: &'a mut [Block], rows: &'a mut [Row]) -> Option<Vec<(&'a mut Block, &'a mut [Row])>> {
    let ranges = blocks.iter().map(|b| (b.rows.0 as usize, (b.rows.1 as usize).saturating_sub(b.rows.0 as usize)));
    let runs = super::lists::runs(rows, ranges)?;
    Some(blocks.iter_mut().zip(runs).filter(|(b, _)| b.dirty).collect())
}

/// `J`, `M⁻¹Jᵀ` and `Q` of block `b`'s rows (`rows`, its range of
/// `Support::rows`) at the current arms.
fn assemble(b: &mut Block, rows: &mut [Row], src: &Source) {
    let upper = &src.bodies[b.body as usize];
    let (inv_m, inv_i) = (upper.inv_m, upper.inv_i);
    for row in rows.iter_mut() {
        let c = &src.constraints[row.face as usize];
        let f = &src.patches[row.face as usize];
        // Body 2 receives +J λ, body 1 −J λ.
        let (lin, a1, a2) = match row.kind {
            RowKind::Normal(pi) => {
                let p = &src.points[pi as usize];
                (c.normal, p.rn1, p.rn2)
            }
            RowKind::Tangent(a) => {
                let t = if a == 0 { c.t1 } else { c.t2 };
                (t, f.rt1[a as usize], f.rt2[a as usize])
            }
            RowKind::Twist => (Vec3::zeros(), c.normal, c.normal),
        };
        let (ju, jl) = if c.lower == 1 { ([lin, a2], [-lin, -a1]) } else { ([-lin, -a1], [lin, a2]) };
        row.ju = ju;
        row.jl = jl;
        row.wu = [ju[0] * inv_m, inv_i * ju[1]];
    }
    b.q = least_norm_operator(rows, upper);
    b.dirty = false;
    b.k_ready = false;
}

/// `Q = P⁻¹ M P⁻¹` of a block whose rows `J` hold all six velocities of its
/// upper body (`P = Jᵀ W⁻¹ J` well conditioned, `W` the rows' weights), else
/// `None`.
fn least_norm_operator(rows: &[Row], upper: &SolverBody) -> Option<Matrix6<f64>> {
    if rows.len() < 6 || upper.inv_m <= 0.0 {
        return None;
    }
    let mut p = Matrix6::zeros();
    for r in rows {
        let j = r.ju6();
        p += j * j.transpose() * r.inv_weight();
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
