//! One large group of bodies in contact (a ball pit: a thousand balls, one
//! group) laid out in two halves, so that two threads can share the passes
//! over its contacts (see [`super::team`]).
//!
//! The dynamic bodies of the touching pairs are split at the median of their
//! positions along the axis they spread furthest on. A pair whose dynamic
//! bodies are all on one side belongs to that half; one that joins the two
//! halves, or touches a kinematic body (which both halves would write),
//! belongs to the seam. The constraints are built half by half: the first
//! half's pairs, the second's, the seam's, each in pair order. A pass on one
//! thread goes over them in that order, as always; on two, the halves go side
//! by side (they share no body a pass writes) and the seam after them. The
//! same contacts meet in the same order either way: every thread count gives
//! the same bits.
//!
//! Only a step after one whose contacts were all solved both ways (no support
//! blocks, no articulated link) and numerous enough is built so: the layout
//! is decided from the last step's plan (`ContactSolver::split`, kept in
//! snapshots), so that a restored world builds as the one that kept going.

use super::contact::ContactSolver;
use crate::body::Bodies;
use crate::collide::collider::Collider;
use crate::collide::narrow_phase::{NarrowPhase, PairState};
use crate::math::Vec3;

/// Touching pairs, and contacts solved both ways, from which a step's
/// contacts are laid out in two halves: below it the hand-offs of a pass
/// cost more than its half. The 1000-ball pit has 2800.
pub(crate) const MIN_SPLIT: usize = 1024;

/// Most share of the contacts the seam may take: beyond it the halves are
/// not worth their hand-offs (a pile that is one long column).
const MAX_SEAM_SHARE: f64 = 0.25;

/// The seam's part (the halves are 0 and 1).
const SEAM: u8 = 2;
/// No side: a fixed or sleeping body (solver entry 0, never written).
const NO_SIDE: u8 = u8::MAX;
/// A kinematic body: its contacts go to the seam.
const KINEMATIC: u8 = u8::MAX - 1;

impl ContactSolver {
    /// The touching pairs in the order their constraints are built, half by
    /// half, after a step that could split (see the module docs); `None`:
    /// in pair order. Finds each body's side.
    /// With the order, where its first and second halves' pairs end.
    pub(crate) fn build_order(&mut self, narrow: &NarrowPhase, colliders: &[Collider], b: &Bodies) -> Option<(Vec<u32>, [usize; 2])> {
        self.side.clear();
        if !self.split || narrow.touching.len() < MIN_SPLIT {
            return None;
        }
        self.side.resize(b.len(), NO_SIDE);
        let body = |c: u32| colliders.get(c as usize).map_or(u32::MAX, |c| c.body);
        let pairs: Vec<[u32; 2]> = narrow.touching.iter().map(|&s| narrow.pairs.get(s as usize).map_or([u32::MAX; 2], |p| [body(p.key.0), body(p.key.1)])).collect();
        let mut at = Vec::new();
        for &i in pairs.iter().flatten() {
            let i = i as usize;
            if i >= b.len() || self.side[i] != NO_SIDE || !b.moving(i) {
                continue;
            }
            self.side[i] = KINEMATIC;
            if b.awake(i) {
                self.side[i] = 0;
                at.push((i, Vec3::from(b.position[i])));
            }
        }
        if !self.split_at_median(&at) {
            self.side.clear();
            return None;
        }
        self.previous.ask_in_runs();
        let parts: Vec<u8> = pairs.iter().map(|&[i, j]| self.part_of(i, j)).collect();
        let mut order = Vec::with_capacity(parts.len());
        let mut ends = [0; 2];
        for p in 0..=SEAM {
            order.extend(narrow.touching.iter().zip(&parts).filter(|&(_, &q)| q == p).map(|(&s, _)| s));
            if let Some(e) = ends.get_mut(p as usize) {
                *e = order.len();
            }
        }
        Some((order, ends))
    }

    /// Sides for the bodies `at` (index, position): 1 above the median along
    /// the axis of their widest spread, else 0. False without bodies.
    fn split_at_median(&mut self, at: &[(usize, Vec3)]) -> bool {
        let (mut lo, mut hi) = (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY));
        for (_, p) in at {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        let axis = (hi - lo).imax();
        let mut along: Vec<f64> = at.iter().map(|(_, p)| p[axis]).collect();
        if along.is_empty() {
            return false;
        }
        let mid = along.len() / 2;
        let (_, &mut median, _) = along.select_nth_unstable_by(mid, f64::total_cmp);
        for (i, p) in at {
            self.side[*i] = (p[axis] > median) as u8;
        }
        true
    }

    /// The part (half 0 or 1, or the seam) of a contact between world bodies
    /// `i` and `j`, from their sides.
    fn part_of(&self, i: u32, j: u32) -> u8 {
        let side = |k: u32| self.side.get(k as usize).copied().unwrap_or(NO_SIDE);
        match (side(i), side(j)) {
            (KINEMATIC, _) | (_, KINEMATIC) => SEAM,
            (NO_SIDE, NO_SIDE) => 0,
            (x, NO_SIDE) | (NO_SIDE, x) => x,
            (x, y) if x == y => x,
            _ => SEAM,
        }
    }

    /// Where the halves of this step's constraints end, if they were laid
    /// out half by half (and the layout holds: each constraint's part no
    /// lower than the one before).
    fn ends(&self) -> Option<[usize; 2]> {
        if self.side.is_empty() {
            return None;
        }
        let mut ends = [self.constraints.len(); 2];
        let mut last = 0;
        for (k, c) in self.constraints.iter().enumerate() {
            let p = self.part_of(c.b1, c.b2);
            if p < last {
                return None;
            }
            for e in last..p {
                ends[e as usize] = k;
            }
            last = p;
        }
        Some(ends)
    }

    /// After the plan: whether the halves may go side by side this step
    /// (every contact solved both ways, in order; no support blocks, no
    /// contact on an articulated link; a seam small enough), and whether the
    /// next step is built half by half.
    pub(crate) fn plan_halves(&mut self) {
        self.halves = None;
        let n = self.constraints.len();
        let all = self.ordinary.len() == n && self.ordinary.iter().enumerate().all(|(k, &ci)| ci as usize == k);
        self.split = n >= MIN_SPLIT && all && self.support.blocks.is_empty() && self.gen.constraints.is_empty();
        if let Some(ends) = self.split.then(|| self.ends()).flatten() {
            let seam = n - ends[1];
            if seam as f64 <= MAX_SEAM_SHARE * n as f64 {
                self.halves = Some(ends);
            }
        }
    }

    /// Whether the passes of this step go half by half, side by side (on
    /// the pool with a helper thread: see [`super::team`]).
    pub(crate) fn by_halves(&self) -> Option<[usize; 2]> {
        let n = self.constraints.len();
        // Every contact solved both ways, in order, still (see `plan_halves`).
        let whole = self.ordinary.len() == n;
        self.halves.filter(|&[_, e1]| whole && e1 <= n && self.parallel && super::team::active())
    }

    /// Whether the last step's contacts may be laid out in halves: the next
    /// step then goes to the pool.
    pub fn halves_were_split(&self) -> bool {
        self.split
    }

    /// `work` on the constraints `0..e0` and `e0..e1` (the halves, side by
    /// side: they share no body a pass writes), then on `e1..` (the seam).
    /// Whether any returned true.
    pub(crate) fn each_half(&mut self, [e0, e1]: [usize; 2], work: impl Fn(&mut ContactSolver, std::ops::Range<usize>) -> bool + Sync) -> bool {
        let n = self.constraints.len();
        let solver = super::island_sweeps::Solver(self as *mut ContactSolver);
        // SAFETY: the halves' constraints, points and patches are apart, their
        // dynamic bodies too (see the module docs), and the fixed entry is
        // never written.
        let (first, second) = super::team::both(|| work(unsafe { solver.get() }, 0..e0), || work(unsafe { solver.get() }, e0..e1));
        let seam = work(self, e1..n);
        first || second || seam
    }
}

/// The narrow phase's pair states, written by both halves' ends of a step
/// (see `ContactSolver::finish`), each its own pairs'.
pub(crate) struct SharedPairs(*mut PairState, usize);

// SAFETY: see `get`.
unsafe impl Send for SharedPairs {}
unsafe impl Sync for SharedPairs {}

impl SharedPairs {
    pub(crate) fn of(pairs: &mut [PairState]) -> Self {
        Self(pairs.as_mut_ptr(), pairs.len())
    }

    /// The state of the pair in `slot`, if there is one.
    /// SAFETY: no two threads ask for the same slot while the borrow lives.
    #[allow(clippy::mut_from_ref)]
    pub(crate) unsafe fn get(&self, slot: u32) -> Option<&mut PairState> {
        let k = slot as usize;
        (k < self.1).then(|| unsafe { &mut *self.0.add(k) })
    }
}

#[cfg(test)]
#[path = "seams_tests.rs"]
pub(crate) mod tests;
