//! The pairs' slots laid out in the order their constraints are built.
//!
//! A pair keeps its slot while it lives and a new one takes the first free
//! slot, so after a while the slots of neighbouring pairs lie anywhere: the
//! constraints' build and the narrow phase then read the pairs' states at
//! random (a 1000-ball pit built half by half, `solve::seams`, read them out
//! of their order: 4 % of its step on one thread). Where the order the
//! solver built its constraints in has drifted far from the slots' order, the
//! states are moved so that it is theirs again. Only where a pair's state is
//! kept changes: every pair is stepped, matched and built as before, and
//! every step gives the same bits.

use super::{Found, NarrowPhase};

/// Breaks in the slots' sequence (a constraint whose pair's slot does not
/// follow the last one's), per pair, from which the states are moved: after
/// a move there are none, and a pit at rest keeps its pairs.
const MOST_BREAKS: usize = 8;

/// Not given a slot yet.
const UNSET: u32 = u32::MAX;

impl NarrowPhase {
    /// Moves the pairs' states so that the slots `built` (the pairs of the
    /// last step's constraints, in their order; repeats allowed) come first,
    /// in that order, then the other kept pairs by key, then the free slots,
    /// if the slots have drifted from that order by more than one break in
    /// [`MOST_BREAKS`] pairs. Before `update`: no slot of a constraint is
    /// read after it until the next build.
    pub fn arrange(&mut self, built: impl Iterator<Item = u32> + Clone) {
        let n = self.pairs.len();
        let (mut pairs, mut breaks, mut last) = (0usize, 0usize, None);
        for s in built.clone() {
            if last != Some(s) {
                pairs += 1;
                breaks += last.is_some_and(|l| s != l + 1) as usize;
                last = Some(s);
            }
        }
        if breaks * MOST_BREAKS <= pairs || n == 0 {
            return;
        }
        let mut new_of = vec![UNSET; n];
        let mut next = 0u32;
        let kept = self.order.iter().map(|&(_, s)| s);
        for s in built.chain(kept).chain(self.free.iter().copied()).chain(0..n as u32) {
            if let Some(t) = new_of.get_mut(s as usize).filter(|t| **t == UNSET) {
                *t = next;
                next += 1;
            }
        }
        self.permute(&new_of);
    }

    /// Moves the state in slot `s` to slot `new_of[s]` (a permutation), and
    /// renames the slots wherever they are kept.
    fn permute(&mut self, new_of: &[u32]) {
        // Each cycle of the permutation once: the state in `i` is swapped to
        // where it goes until `i` holds the one that belongs there.
        let mut placed = vec![false; new_of.len()];
        for i in 0..new_of.len() {
            if placed[i] {
                continue;
            }
            let mut j = new_of[i] as usize;
            while j != i {
                self.pairs.swap(i, j);
                placed[j] = true;
                j = new_of[j] as usize;
            }
            placed[i] = true;
        }
        let rename = |s: &mut u32| *s = new_of.get(*s as usize).copied().unwrap_or(*s);
        self.order.iter_mut().for_each(|(_, s)| rename(s));
        self.free.iter_mut().for_each(rename);
        self.touching.iter_mut().for_each(rename);
        // Free slots are taken from the end of the list: the lowest first.
        self.free.sort_unstable_by(|a, b| b.cmp(a));
        self.found.clear();
        self.found.resize(self.pairs.len(), Found::Idle);
    }
}

#[cfg(test)]
mod tests {
    use super::super::{NarrowPhase, PairState};

    /// Eight slots: six pairs kept (keys `(k, k + 1)` in slots given out of
    /// order), two free. Arranged by the built order, each pair keeps its
    /// state under its new slot, the built pairs come first in their order,
    /// the other kept pairs next, the free slots last (the lowest taken first).
    #[test]
    fn arranged_slots_follow_the_built_order_and_keep_every_state() {
        let slot_of_key = [5u32, 2, 7, 0, 3, 6];
        let mut narrow = NarrowPhase { pairs: (0..8).map(|_| PairState::default()).collect(), ..Default::default() };
        for (k, &s) in slot_of_key.iter().enumerate() {
            narrow.pairs[s as usize] = PairState { key: (k as u32, k as u32 + 1), prediction: k as f64, ..Default::default() };
            narrow.order.push(((k as u32, k as u32 + 1), s));
        }
        narrow.free = vec![4, 1];
        narrow.touching = vec![5, 2];
        let built = [7u32, 7, 0, 5, 3];
        narrow.arrange(built.iter().copied());
        for &((a, b), s) in &narrow.order {
            let state = &narrow.pairs[s as usize];
            assert_eq!((state.key, state.prediction), ((a, b), a as f64));
        }
        let slot = |key: u32| narrow.order.iter().find(|(k, _)| k.0 == key).map(|&(_, s)| s);
        assert_eq!([slot(2), slot(3), slot(0), slot(4)], [Some(0), Some(1), Some(2), Some(3)]);
        assert_eq!([slot(1), slot(5)], [Some(4), Some(5)]);
        assert_eq!(narrow.free, vec![7, 6]);
        assert_eq!(narrow.touching, vec![2, 4]);
        assert!(narrow.free.iter().all(|&s| narrow.pairs[s as usize].key == (0, 0)));
        // In order already: nothing moves.
        let before: Vec<_> = narrow.order.clone();
        narrow.arrange([0u32, 1, 2, 3].into_iter());
        assert_eq!(narrow.order, before);
    }
}
