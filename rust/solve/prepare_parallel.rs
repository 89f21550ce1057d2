//! The build's two passes for a step on the pool (see `super`): the first,
//! in pair order, gives each group of manifolds its solver bodies, its place
//! among the points and constraints and the last step's constraint it may
//! keep; the second lays each out in its place, over threads.

use rayon::prelude::*;

use super::{each_group, within, Carry, Job, PairBodies, Shared, Source, PER_TASK};
use crate::body::Bodies;
use crate::collide::collider::Collider;
use crate::collide::narrow_phase::NarrowPhase;
use crate::solve::contact::{Constraint, ContactSolver, Point};
use crate::solve::coplanar::{self, Member};
use crate::solve::friction::Patch;
use crate::solve::limit_surface::PatchShape;
use crate::solve::reuse;

impl ContactSolver {
    /// The first pass, in `order`: solver bodies, and a job per group of
    /// manifolds with a point within their pair's prediction (see
    /// [`coplanar`]), and the manifold indices of the groups. For a
    /// build half by half (`pair_ends`: where its halves' pairs end), notes
    /// where the solver bodies each half entered end.
    pub(super) fn place(&mut self, narrow: &NarrowPhase, (order, pair_ends): (&[u32], Option<[usize; 2]>), colliders: &[Collider], b: &Bodies) -> (Vec<PairBodies>, Vec<Job>, Vec<u32>) {
        let mut contexts = Vec::with_capacity(order.len());
        let mut jobs = Vec::with_capacity(order.len());
        let mut members = Vec::with_capacity(order.len());
        let mut start = 0;
        let mut body_ends = [0; 2];
        let mut note = |k: usize, entered: usize| {
            for (e, &at) in body_ends.iter_mut().zip(pair_ends.iter().flatten()) {
                if k == at {
                    *e = entered;
                }
            }
        };
        for (k, &slot) in order.iter().enumerate() {
            note(k, self.bodies.len());
            let state = &narrow.pairs[slot as usize];
            let ctx = self.pair_bodies(colliders, b, state.key, slot);
            let generalized = self.generalized((ctx.s, ctx.b));
            let reach = state.prediction;
            let grouping = |all: &[Member], leads: &mut Vec<u32>| coplanar::group(&ctx.context((colliders, Some(narrow)), b), all, leads);
            each_group(state.contacts(), grouping, reach, |group| {
                let first = members.len() as u32;
                members.extend(group.iter().map(|(m, _)| *m));
                let len = group.iter().map(|(_, c)| within(c, reach)).sum();
                let previous = self.previous.find(ctx.pair, group[0].0);
                let ctx = contexts.len() as u32;
                jobs.push(Job { ctx, members: (first, group.len() as u32), start, len, previous, generalized });
                start += len;
            });
            contexts.push(ctx);
        }
        note(order.len(), self.bodies.len());
        self.body_ends = pair_ends.map(|_| body_ends);
        (contexts, jobs, members)
    }

    /// The second pass, over threads: each job's points, constraint and patch
    /// in its place.
    pub(super) fn lay_out(&mut self, (narrow, colliders): (&NarrowPhase, &[Collider]), (contexts, jobs, members): (&[PairBodies], &[Job], &[u32]), world: &Bodies) {
        let rest_depth = self.rest_depth();
        let points = jobs.last().map_or(0, |j| (j.start + j.len) as usize);
        // Every slot is written below: only those beyond the arrays' length
        // (two steps old) are zeroed first (zeroing them all was 5 % of a
        // pyramid's step).
        fit(&mut self.points, points);
        fit(&mut self.constraints, jobs.len());
        fit(&mut self.patches, jobs.len());
        fit(&mut self.shapes, jobs.len());
        self.previous.kept.resize(jobs.len(), reuse::NONE);
        let (mut rest, mut parts) = (&mut self.points[..], Vec::with_capacity(jobs.len()));
        for j in jobs {
            let (part, tail) = std::mem::take(&mut rest).split_at_mut(j.len as usize);
            parts.push(part);
            rest = tail;
        }
        let mut kept = std::mem::take(&mut self.previous.kept);
        let shared = Shared { bodies: &self.bodies, previous: &self.previous, world, rest: rest_depth };
        let one = |((((j, pts), c), (f, shape)), k): ((((&Job, &mut &mut [Point]), &mut Constraint), (&mut Patch, &mut PatchShape)), &mut u32)| {
            // The pair's context found by the thread that builds it (handed
            // over from the first pass, the helper read every context of its
            // half from the stepping thread's cache: 40 µs of a 1000-ball pit's step).
            let ctx = &contexts[j.ctx as usize].context((colliders, Some(narrow)), world);
            let state = &narrow.pairs[ctx.slot as usize];
            let indices = &members[j.members.0 as usize..(j.members.0 + j.members.1) as usize];
            let member = |&m: &u32| state.manifold(m).map(|c| (m, c));
            // Most jobs are one manifold: no allocation for them.
            let one: [Member; 1];
            let many: Vec<Member>;
            let group: &[Member] = match indices {
                [m] => {
                    let Some(only) = member(m) else { return };
                    one = [only];
                    &one
                }
                _ => {
                    many = indices.iter().filter_map(member).collect();
                    &many
                }
            };
            if group.len() != indices.len() {
                return;
            }
            let mut src = Source::new(ctx, group, Carry::of(state), state.prediction);
            let mut slots = pts.iter_mut();
            let still = shared.still(j, &src, |p| slots.next().into_iter().for_each(|s| *s = p));
            if still.is_none() {
                src.find_normal();
                let mut slots = pts.iter_mut();
                src.points(|p| slots.next().into_iter().for_each(|s| *s = p));
            }
            let (constraint, kept) = shared.constraint_or_still(j, &src, still, pts);
            shared.patch((f, shape), &constraint, kept, &src, pts);
            *c = constraint;
            *k = kept.map_or(reuse::NONE, |o| o as u32);
        };
        if crate::solve::team::active() {
            // Two halves of the jobs, one on the step's helper thread: after a
            // split (see `crate::solve::seams`) the second half holds the second half
            // of the contacts, built where its passes will run.
            let mid = jobs.len() / 2;
            let (j0, j1) = jobs.split_at(mid);
            let (p0, p1) = parts.split_at_mut(mid);
            let (c0, c1) = self.constraints.split_at_mut(mid);
            let (f0, f1) = self.patches.split_at_mut(mid);
            let (s0, s1) = self.shapes.split_at_mut(mid);
            let (k0, k1) = kept.split_at_mut(mid);
            let run = |j: &[Job], p: &mut [&mut [Point]], c: &mut [Constraint], (f, s): (&mut [Patch], &mut [PatchShape]), k: &mut [u32]| {
                let each = j.iter().zip(p.iter_mut()).zip(c.iter_mut());
                each.zip(f.iter_mut().zip(s.iter_mut())).zip(k.iter_mut()).for_each(one);
            };
            crate::solve::team::both(|| run(j0, p0, c0, (f0, s0), k0), || run(j1, p1, c1, (f1, s1), k1));
        } else {
            let (constraints, patches) = (&mut self.constraints, self.patches.par_iter_mut().zip(self.shapes.par_iter_mut()));
            let each = jobs.par_iter().zip(parts.par_iter_mut()).zip(constraints.par_iter_mut());
            each.zip(patches).zip(kept.par_iter_mut()).with_min_len(PER_TASK).for_each(one);
        }
        self.previous.kept = kept;
    }
}

/// `v` at length `n`, zeroing only the new slots.
fn fit<T: Default + Clone>(v: &mut Vec<T>, n: usize) {
    v.truncate(n);
    v.resize(n, T::default());
}
