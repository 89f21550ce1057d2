//! The support sweeps ([`super::support`]) and the position pass
//! ([`super::position`]) island by island, the islands in parallel.
//!
//! An island of support blocks (see [`super::quiet`]) shares no dynamic body,
//! block, row, face, point or patch with another: a sweep of one reads and
//! writes only its own, and the fixed and kinematic bodies, which no sweep
//! writes. Each island is swept in the order the serial sweep visits its
//! blocks (bottom up, then top down a level at a time), so its arithmetic is
//! the same whatever the other islands do or when: one thread or many, the
//! same bits. A tumbling 4000-cube pile has some 700 islands; a pyramid or a
//! single heap is one, and stays on the calling thread.

use super::block::Scratch;
use super::contact::ContactSolver;
use rayon::prelude::*;
use std::sync::Mutex;

/// Fewest blocks in the islands of a pass for it to be split over threads:
/// below this, the hand-off costs more than the sweeps (a block's solve is a
/// few microseconds).
const MIN_PARALLEL_BLOCKS: usize = 128;

/// Tasks per pool thread the islands of a pass are cut into at least (an
/// island each where there are fewer): a tumbling 4000-cube pile's 500
/// islands in tasks of 1, 4, 7 (this grain) or 16 stepped alike on two
/// threads (9.60 against 9.65 s for 120 steps with tasks of 1).
const TASKS_PER_THREAD: usize = 32;

/// What one thread's sweeps of some islands keep apart from the solver: the
/// scratch of its block solves, the blocks it solved (first time this pass)
/// and whether it saw a slow body rock (see [`super::rocking`]).
#[derive(Clone, Default)]
pub struct Sweep {
    pub scratch: Scratch,
    pub solved: Vec<u32>,
    pub rocking: bool,
}

impl Sweep {
    /// Adds the blocks solved and the rocking seen to the pass's, and starts
    /// afresh.
    fn hand_over(&mut self, support: &mut super::support::Support) {
        support.solved.extend_from_slice(&self.solved);
        support.rocking.seen |= self.rocking;
        self.solved.clear();
        self.rocking = false;
    }
}

/// Each pool thread's [`Sweep`] (scratch only: a clone starts empty).
#[derive(Default)]
pub struct ThreadSweeps(Vec<Mutex<Sweep>>);

impl Clone for ThreadSweeps {
    fn clone(&self) -> Self {
        Self::default()
    }
}

/// The solver, shared by the threads that sweep its islands (or pass over
/// its groups: see [`super::contact_groups`]).
pub(super) struct Solver(pub(super) *mut ContactSolver);

// SAFETY: the threads given a `Solver` sweep disjoint islands (see the module
// docs): none writes what another reads or writes, and nothing is pushed to or
// resized in the solver while they run.
unsafe impl Send for Solver {}
unsafe impl Sync for Solver {}

impl Solver {
    /// SAFETY: the caller touches only the island (or group) it was given.
    #[allow(clippy::mut_from_ref)]
    pub(super) unsafe fn get(&self) -> &mut ContactSolver {
        unsafe { &mut *self.0 }
    }
}

impl ContactSolver {
    /// Whether this step's support islands are many enough to be swept in
    /// parallel; the work around the sweeps (the gathers' refresh of arms and
    /// patches, the blocks' reassembly) then goes to the threads too. A step
    /// without them keeps that work on one thread: a 1000-ball pit whose
    /// gathers refreshed their 2900 constraints on two threads stepped 10 %
    /// slower than on one (the hand-offs, and the data one thread wrote being
    /// read from the other's cache by the serial solve).
    pub(crate) fn wide(&self) -> bool {
        self.parallel && self.support.islands >= 2 && self.support.blocks.len() >= MIN_PARALLEL_BLOCKS
    }

    /// Whether some pass of the last step had islands enough to sweep in
    /// parallel (whatever the threads it had): the next step then goes to the
    /// pool.
    pub fn islands_were_split(&self) -> bool {
        self.support.split
    }

    /// Lists the blocks of each island, in block order (bottom up), after the
    /// plan.
    pub(crate) fn index_islands(&mut self) {
        let s = &mut self.support;
        s.index.fill(s.islands, s.blocks.iter().enumerate().map(|(g, b)| (b.island, g as u32)));
    }

    /// `work` on each of `0..n` (blocks, groups), in order, on the pool's
    /// threads when `parallel`. The caller vouches that `work(k)` touches only
    /// what belongs to `k` (see `Solver`).
    pub(super) fn par_map<R: Send>(&mut self, n: usize, parallel: bool, work: impl Fn(&mut ContactSolver, usize) -> R + Sync) -> Vec<R> {
        if !parallel {
            return (0..n).map(|k| work(self, k)).collect();
        }
        let solver = Solver(self as *mut ContactSolver);
        // SAFETY: each `k` is given to one thread, and `work(k)` touches only
        // what belongs to `k` (the caller's promise).
        (0..n).into_par_iter().map(|k| work(unsafe { solver.get() }, k)).collect()
    }

    /// Runs `work` on each of `islands`, in parallel where the pass is large
    /// and the step runs on the pool; then gathers the blocks solved and the
    /// rocking seen.
    pub(crate) fn in_islands(&mut self, islands: &[u32], work: impl Fn(&mut ContactSolver, usize, &mut Sweep) + Sync) {
        let blocks: usize = islands.iter().map(|&i| self.support.index.of(i as usize).len()).sum();
        let split = islands.len() >= 2 && blocks >= MIN_PARALLEL_BLOCKS;
        self.support.split |= split;
        if self.wide() && split {
            self.sweep_in_parallel(islands, work);
        } else {
            let mut sw = std::mem::take(&mut self.support.sweep);
            for &i in islands {
                work(self, i as usize, &mut sw);
            }
            sw.hand_over(&mut self.support);
            self.support.sweep = sw;
        }
    }

    /// [`Self::in_islands`] on the pool's threads, in small tasks (see
    /// [`TASKS_PER_THREAD`]), each thread with its own scratch. Islands share
    /// nothing: which thread sweeps one changes no bits. Folded over rayon's
    /// halves and quarters, each leaf growing a fresh scratch, one thread of
    /// two sat idle for a quarter of the sweeps of a tumbling 4000-cube pile
    /// (busy 6.1 and 4.7 s of 6.3 s).
    fn sweep_in_parallel(&mut self, islands: &[u32], work: impl Fn(&mut ContactSolver, usize, &mut Sweep) + Sync) {
        let threads = rayon::current_num_threads().max(1);
        let ThreadSweeps(mut scratch) = std::mem::take(&mut self.support.thread_sweeps);
        if scratch.len() < threads {
            scratch.resize_with(threads, Default::default);
        }
        // Tasks of several islands where there are thousands, so that
        // handing them out stays small against the sweeps.
        let per_task = (islands.len() / (threads * TASKS_PER_THREAD)).max(1);
        let solver = Solver(self as *mut ContactSolver);
        islands.par_iter().with_max_len(per_task).for_each(|&i| {
            let t = rayon::current_thread_index().unwrap_or(0).min(threads - 1);
            // Each pool thread takes only its own: the lock is never contended
            // (`work` makes no rayon call that could run another island on
            // this thread while it holds its scratch).
            let mut sw = scratch[t].lock().unwrap_or_else(|e| e.into_inner());
            // SAFETY: each island is given to one thread (see `Solver`).
            work(unsafe { solver.get() }, i as usize, &mut sw);
        });
        for m in &mut scratch {
            m.get_mut().unwrap_or_else(|e| e.into_inner()).hand_over(&mut self.support);
        }
        self.support.thread_sweeps = ThreadSweeps(scratch);
    }

    /// The two sweeps over island `i`'s blocks: bottom up, then top down a
    /// level at a time, each level solved on its supports as the bottom-up
    /// sweep left them before their debts are paid (a box resting on two
    /// others would otherwise find one of them already pushed by a
    /// neighbour's load). A block whose upper body received no reaction since
    /// its bottom-up solve is as that solve left it.
    pub(crate) fn sweep_island(&mut self, i: usize, sw: &mut Sweep) {
        let n = self.support.index.of(i).len();
        let block = |s: &Self, k: usize| s.support.index.of(i)[k] as usize;
        for k in 0..n {
            self.solve_block(block(self, k), sw);
        }
        let mut end = n;
        while end > 0 {
            let level = self.support.blocks[block(self, end - 1)].level;
            let mut start = end;
            while start > 0 && self.support.blocks[block(self, start - 1)].level == level {
                start -= 1;
            }
            for k in (start..end).rev() {
                let g = block(self, k);
                let body = self.support.blocks[g].body as usize;
                if self.support.paid.get(body).copied() == Some(self.support.pass) {
                    self.solve_block(g, sw);
                }
            }
            for k in start..end {
                self.pay(block(self, k));
            }
            end = start;
        }
    }

    /// One position pass over island `i`'s blocks, bottom up (see
    /// [`Self::push_block`]).
    pub(crate) fn push_island(&mut self, i: usize, sw: &mut Sweep, (rate, cap, rest): (f64, f64, f64)) {
        for k in 0..self.support.index.of(i).len() {
            let g = self.support.index.of(i)[k] as usize;
            self.push_block(g, rate, cap, rest, &mut sw.scratch);
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use crate::body::Shape;
    use crate::world::{BodySpec, Scene, Settings, World};

    /// 1200 cubes tilted at random (a fixed sequence), dropped in three layers
    /// onto each other and the ground, as `tests/test_threads.py`'s heap.
    fn heap(threads: u32) -> World {
        let mut scene = Scene::new([0.0, 0.0, -9.81]).unwrap();
        let ground = Shape::plane([0.0, 0.0, 1.0], 0.0).unwrap();
        scene.add_body(BodySpec { shape: Some(ground), fixed: true, ..Default::default() }).unwrap();
        for k in 0..1200 {
            let n = k as f64 + 1.0;
            let axis = nalgebra::Vector3::new((n * 0.754877f64).fract() - 0.5, (n * 0.569840f64).fract() - 0.5, 0.3).normalize();
            let (s, c) = 0.05f64.sin_cos();
            let (x, y, z) = ((k % 20) as f64 * 0.23, (k / 20 % 20) as f64 * 0.23, 0.12 + 0.23 * (k / 400) as f64);
            let cube = Some(Shape::cuboid([0.1; 3]).unwrap());
            let orientation = [axis.x * s, axis.y * s, axis.z * s, c];
            scene.add_body(BodySpec { shape: cube, density: Some(500.0), position: [x, y, z], orientation, ..Default::default() }).unwrap();
        }
        let mut settings = Settings::new(1.0 / 60.0);
        settings.sleep.enabled = false;
        settings.threads = Some(threads);
        scene.build(&settings).unwrap()
    }

    /// Every body's pose and velocities, bit for bit.
    pub(crate) fn bits(w: &World) -> Vec<u64> {
        let b = &w.bodies;
        (0..b.len())
            .flat_map(|i| [b.position[i], b.linear_velocity[i], b.angular_velocity[i]].into_iter().flatten().chain(b.orientation[i]))
            .map(f64::to_bits)
            .collect()
    }

    /// Steps the worlds `one`, `two`, `three` (one scene on 1, 2 and 3
    /// threads) once each and asserts that they end in the same bits.
    pub(crate) fn step_alike([one, two, three]: [&mut World; 3]) {
        one.step(1).unwrap();
        two.step(1).unwrap();
        three.step(1).unwrap();
        assert!(bits(one) == bits(two));
        assert!(bits(one) == bits(three));
    }

    /// The heap's islands are swept, and its groups of contacts passed over,
    /// in parallel on two threads (checked, so that the test tests that), and
    /// every step ends in the same bits as on one thread; on three (more
    /// threads than this machine's cores, each with its own sweep scratch)
    /// too.
    #[test]
    fn islands_and_groups_solved_in_parallel_give_the_bits_of_one_thread() {
        let (mut one, mut two, mut three) = (heap(1), heap(2), heap(3));
        let (mut wide_steps, mut group_steps) = (0, 0);
        for _ in 0..40 {
            step_alike([&mut one, &mut two, &mut three]);
            let solver = |w: &World| w.collision.as_ref().map(|c| (c.solver.wide(), c.solver.by_groups()));
            let (wide, groups) = solver(&two).unwrap_or_default();
            wide_steps += wide as u32;
            group_steps += groups as u32;
            assert_eq!(solver(&one), Some((false, false)));
        }
        assert!(wide_steps >= 10, "the islands were swept in parallel in {wide_steps} steps of 40");
        assert!(group_steps >= 10, "the groups were passed over in parallel in {group_steps} steps of 40");
    }
}
