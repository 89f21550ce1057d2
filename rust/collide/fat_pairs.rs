//! The pairs of fat boxes brought up to date in place when only a few boxes
//! changed, instead of a new sweep of them all.
//!
//! Every body of a settling pile leaves its fat box now and then, and each
//! time one did, the broad phase swept every box again: a 1000-ball pit at
//! rest did so every other step, 280 µs of its 3 ms. Dropping the pairs of the
//! changed boxes and finding theirs again finds the same set: the sweep
//! reports exactly the overlapping pairs that `keep` allows, and both are
//! kept sorted, so the pairs, and everything after them, have the same bits
//! either way.
//!
//! A changed box is tested against the boxes of the last sweep's columns it
//! spans ([`SweepAndPrune::near`]), which hold every box that has not changed
//! since that sweep, and against the boxes that have (the `stale`), not
//! against every box: the balls spilling over a 3000-ball pit's walls
//! changed 275 boxes a step, and their tests against every box cost more
//! than a sweep (1.5 ms a step).

use super::broad_phase::Aabb;
use super::sweep_and_prune::SweepAndPrune;

/// Fewest boxes per changed one for the update in place by testing each
/// changed box against every box: a test costs a few nanoseconds a box, a
/// sweep some hundred nanoseconds a box.
const BOXES_PER_CHANGE: usize = 32;

/// Most tests of a changed box against the boxes changed since the last sweep,
/// per box, for the update in place from the sweep's columns.
const STALE_TESTS_PER_BOX: usize = 64;

/// The boxes changed in one call, and scratch kept between calls.
#[derive(Clone, Debug, Default)]
pub struct Changes {
    /// Finite colliders whose fat box changed.
    pub boxes: Vec<u32>,
    changed: Vec<bool>,
    found: Vec<(u32, u32)>,
    merged: Vec<(u32, u32)>,
    /// The finite colliders whose fat box changed since the last sweep, and
    /// a mark per collider: stale, and the changed box that last met it.
    stale: Vec<u32>,
    is_stale: Vec<bool>,
    met: Vec<u32>,
    /// The mark of the changed box being tested (see `met`).
    tick: u32,
}

impl Changes {
    /// Whether updating the pairs in place costs less than a sweep of `finite` boxes.
    pub fn few(&self, finite: usize, sap: &SweepAndPrune) -> bool {
        let k = self.boxes.len();
        if sap.has_grid() {
            // The boxes not yet stale join the stale ones.
            let stale = self.stale.len() + self.boxes.iter().filter(|&&b| !self.is_stale.get(b as usize).copied().unwrap_or(false)).count();
            return k.saturating_mul(stale) <= STALE_TESTS_PER_BOX * finite;
        }
        k * BOXES_PER_CHANGE <= finite
    }

    /// A sweep of every box was made: none is stale.
    pub fn swept(&mut self) {
        for &b in &self.stale {
            self.is_stale[b as usize] = false;
        }
        self.stale.clear();
    }

    /// `pairs` (sorted: every pair `i < j` of `finite` whose boxes in `fat`
    /// overlap and that `keep` allows, before `self.boxes` changed) brought up
    /// to date.
    pub fn update(&mut self, pairs: &mut Vec<(u32, u32)>, (fat, finite, sap): (&[Aabb], &[u32], &SweepAndPrune), keep: impl Fn(u32, u32) -> bool) {
        self.changed.clear();
        self.changed.resize(fat.len(), false);
        for &k in &self.boxes {
            self.changed[k as usize] = true;
        }
        self.is_stale.resize(fat.len(), false);
        self.met.resize(fat.len(), 0);
        for &k in &self.boxes {
            if !self.is_stale[k as usize] {
                self.is_stale[k as usize] = true;
                self.stale.push(k);
            }
        }
        let changed = &self.changed;
        pairs.retain(|&(i, j)| !changed[i as usize] && !changed[j as usize]);
        self.found.clear();
        for &m in &self.boxes {
            let bm = &fat[m as usize];
            self.tick = match self.tick.checked_add(1) {
                Some(t) => t,
                None => {
                    self.met.iter_mut().for_each(|t| *t = 0);
                    1
                }
            };
            let (found, met, is_stale, tick) = (&mut self.found, &mut self.met, &self.is_stale, self.tick);
            let mut test = |j: u32| {
                // Two changed boxes meet once, from the first of them; a box
                // in several of the columns is tested once.
                if j == m || met[j as usize] == tick || (changed[j as usize] && j < m) {
                    return;
                }
                met[j as usize] = tick;
                let (lo, hi) = (m.min(j), m.max(j));
                if bm.overlaps(&fat[j as usize]) && keep(lo, hi) {
                    found.push((lo, hi));
                }
            };
            let near = sap.has_grid() && sap.near(bm, |j| if !is_stale[j as usize] { test(j) });
            if near {
                self.stale.iter().for_each(|&j| test(j));
            } else {
                finite.iter().for_each(|&j| test(j));
            }
        }
        self.found.sort_unstable();
        let mid = pairs.len();
        pairs.extend_from_slice(&self.found);
        merge_sorted(pairs, mid, &mut self.merged);
    }
}

/// `pairs` (distinct, each index below `n`) sorted, as `sort_unstable` would:
/// a counting sort by the first index, then each run by the second (a few
/// pairs a run). A sweep's 15 000 pairs of a 3000-ball pit took 250 µs to
/// sort by comparisons, a step's rebuild of them all 1.5 ms.
pub fn sort_pairs(pairs: &mut Vec<(u32, u32)>, n: usize, (starts, scratch): (&mut Vec<u32>, &mut Vec<(u32, u32)>)) {
    if pairs.iter().any(|&(i, _)| i as usize >= n) {
        pairs.sort_unstable();
        return;
    }
    starts.clear();
    starts.resize(n + 1, 0);
    for &(i, _) in pairs.iter() {
        starts[i as usize + 1] += 1;
    }
    for k in 0..n {
        starts[k + 1] += starts[k];
    }
    scratch.clear();
    scratch.resize(pairs.len(), (0, 0));
    for &(i, j) in pairs.iter() {
        let at = &mut starts[i as usize];
        scratch[*at as usize] = (i, j);
        *at += 1;
    }
    // `starts[k]` is now the end of run k, the start of run k + 1.
    let mut from = 0;
    for &to in &starts[..n] {
        scratch[from..to as usize].sort_unstable();
        from = to as usize;
    }
    std::mem::swap(pairs, scratch);
}

/// `v[..mid]` and `v[mid..]`, each sorted, merged in place (`scratch`: any
/// vector, reused).
pub fn merge_sorted(v: &mut Vec<(u32, u32)>, mid: usize, scratch: &mut Vec<(u32, u32)>) {
    scratch.clear();
    let (a, b) = v.split_at(mid);
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        if b[j] < a[i] {
            scratch.push(b[j]);
            j += 1;
        } else {
            scratch.push(a[i]);
            i += 1;
        }
    }
    scratch.extend_from_slice(&a[i..]);
    scratch.extend_from_slice(&b[j..]);
    std::mem::swap(v, scratch);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collide::sweep_and_prune::SweepAndPrune;

    fn boxes(n: usize, seed: u64, spread: f64) -> Vec<Aabb> {
        let mut s = seed;
        let mut next = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        (0..n)
            .map(|_| {
                let c = [next() * spread, next() * spread, next() * spread];
                let h = 0.2 + 0.3 * next();
                Aabb { min: c.map(|x| x - h), max: c.map(|x| x + h) }
            })
            .collect()
    }

    fn swept(fat: &[Aabb], finite: &[u32], keep: impl Fn(u32, u32) -> bool) -> Vec<(u32, u32)> {
        let mut out = Vec::new();
        SweepAndPrune::default().pairs(fat, finite, keep, &mut out);
        out.sort_unstable();
        out
    }

    #[test]
    fn the_counting_sort_of_pairs_is_the_sort() {
        for seed in 0..10u64 {
            let (fat, finite): (Vec<Aabb>, Vec<u32>) = (boxes(400, seed, 5.0), (0..400).collect());
            let mut pairs = Vec::new();
            SweepAndPrune::default().pairs(&fat, &finite, |_, _| true, &mut pairs);
            let mut want = pairs.clone();
            want.sort_unstable();
            sort_pairs(&mut pairs, fat.len(), (&mut Vec::new(), &mut Vec::new()));
            assert_eq!(pairs, want, "seed {seed}");
        }
        let mut odd = vec![(7, 2), (900, 1), (3, 4)];
        sort_pairs(&mut odd, 10, (&mut Vec::new(), &mut Vec::new()));
        assert_eq!(odd, vec![(3, 4), (7, 2), (900, 1)]);
    }

    #[test]
    fn an_update_in_place_finds_the_pairs_a_new_sweep_finds() {
        let keep = |i: u32, j: u32| (i + j) % 7 != 3;
        for seed in 0..20 {
            let mut fat = boxes(300, seed, 6.0);
            let finite: Vec<u32> = (0..300).filter(|k| k % 11 != 5).collect();
            let mut pairs = swept(&fat, &finite, keep);
            let mut changes = Changes::default();
            let moved = boxes(9, seed + 100, 6.0);
            changes.boxes = finite.iter().copied().filter(|k| k % 37 == seed as u32).take(8).collect();
            for (&k, b) in changes.boxes.iter().zip(&moved) {
                fat[k as usize] = *b;
            }
            // No sweep's grid: each changed box against every box.
            let sap = SweepAndPrune::default();
            assert!(!changes.boxes.is_empty() && changes.few(finite.len(), &sap));
            changes.update(&mut pairs, (&fat, &finite, &sap), keep);
            assert_eq!(pairs, swept(&fat, &finite, keep), "seed {seed}");
        }
    }

    /// Rounds of a few boxes moving, some of them again and again (as balls
    /// falling past a pit's walls), the pairs updated in place from the
    /// sweep's columns and the boxes changed since: after every round the
    /// pairs a new sweep finds. Boxes moved far outside the grid, boxes grown
    /// across many columns and a NaN box included.
    #[test]
    fn updates_from_the_columns_find_the_pairs_a_new_sweep_finds() {
        let keep = |i: u32, j: u32| (i + j) % 7 != 3;
        for seed in 0..10u64 {
            let mut fat = boxes(400, seed, 6.0);
            let finite: Vec<u32> = (0..400).filter(|k| k % 13 != 4).collect();
            let mut sap = SweepAndPrune::default();
            let mut pairs = Vec::new();
            sap.pairs(&fat, &finite, keep, &mut pairs);
            pairs.sort_unstable();
            let mut changes = Changes::default();
            let (mut in_place, mut from_columns) = (0, 0);
            for round in 0..12u64 {
                let moved = boxes(6, seed * 100 + round, 6.0);
                let falling = finite.iter().copied().filter(|k| k % 50 == seed as u32 % 50).take(2);
                let others = finite.iter().copied().filter(|k| (k * 7 + round as u32) % 97 == 0).take(4);
                changes.boxes = falling.chain(others).collect();
                changes.boxes.sort_unstable();
                changes.boxes.dedup();
                for (n, (&k, b)) in changes.boxes.iter().zip(&moved).enumerate() {
                    fat[k as usize] = match (round % 4, n) {
                        (1, 0) => Aabb { min: b.min.map(|x| x - 40.0), max: b.max.map(|x| x - 40.0) },
                        (2, 0) => Aabb { min: b.min.map(|x| x - 5.0), max: b.max.map(|x| x + 5.0) },
                        (3, 1) => Aabb { min: [f64::NAN; 3], max: [f64::NAN; 3] },
                        _ => *b,
                    };
                }
                if changes.few(finite.len(), &sap) {
                    in_place += 1;
                    from_columns += usize::from(sap.has_grid());
                    changes.update(&mut pairs, (&fat, &finite, &sap), keep);
                } else {
                    pairs.clear();
                    sap.pairs(&fat, &finite, keep, &mut pairs);
                    pairs.sort_unstable();
                    changes.swept();
                }
                assert_eq!(pairs, swept(&fat, &finite, keep), "seed {seed} round {round}");
            }
            assert!(in_place >= 10 && from_columns == in_place, "{in_place} {from_columns}");
        }
    }
}
