//! Sweep and prune in columns: the boxes are binned into a grid of columns
//! across the sweep axis (cells about twice the size of most boxes) and swept
//! along it within each column, so that only boxes near each other in all three
//! axes are compared.
//!
//! A sweep over one axis alone compares every box with all those whose interval
//! overlaps its own on that axis: a whole slab of a grid of boxes (1e4 of them
//! in a 100³ grid, 1e10 comparisons a call). Binning is a counting sort, the
//! sweeps sort only their own column: O(N log k) for columns of k boxes, and the
//! same work whatever order the boxes come in (an insertion sort kept from call
//! to call was O(N²) on a grid built in the order a user adds it).
//!
//! A pair that shares several columns is reported by one: the column holding
//! the corner `max(min₁, min₂)` of their overlap. Boxes many cells wide (walls,
//! a floor, a body thrown so fast its swept box is long) are few and are tested
//! against every box apart.

use super::broad_phase::Aabb;

/// Cell size over the 90th percentile of the boxes' extent across the sweep:
/// a box spans one or two columns per axis, a column holds a few boxes per
/// position along the sweep.
const CELL_OVER_EXTENT: f64 = 2.0;

/// Boxes wider than this many cells are tested apart, against every box.
const WIDE_CELLS: f64 = 4.0;

/// Most columns a changed box may span for [`SweepAndPrune::near`] to list
/// its neighbours (a box across more is tested against every box).
const MAX_COLUMNS: usize = 16;

/// Most columns per box: a sparse scene gets larger cells rather than a grid
/// mostly empty.
const COLUMNS_PER_BOX: usize = 4;

/// How much more the box centres must spread along another axis before the sweep
/// moves to it: no flip-flopping between two similar axes.
const AXIS_SWITCH: f64 = 1.5;

#[derive(Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct SweepAndPrune {
    pub(crate) axis: usize,
    /// Number of boxes of the last call (a new set picks its axis afresh).
    count: usize,
    /// Scratch kept between calls: column starts, box ids column after column,
    /// their boxes packed in sweep order, the wide boxes, extents.
    starts: Vec<u32>,
    entries: Vec<u32>,
    sorted: Vec<Aabb>,
    wide: Vec<u32>,
    narrow: Vec<u32>,
    extents: Vec<f64>,
    /// Per box, its columns `[u0, w0, u1, w1]` (`Grid::span`, found once a
    /// box), and per entry of a column its sweep key; the columns of the
    /// column's boxes' lower corners in sweep order.
    #[serde(skip)]
    spans: Vec<[u32; 4]>,
    #[serde(skip)]
    keys: Vec<(f64, u32)>,
    #[serde(skip)]
    corners: Vec<[u32; 2]>,
    /// The grid of the last call, whose columns (`starts`, `entries`) and
    /// wide boxes (`wide`) [`Self::near`] reads; none after a restore from
    /// bytes.
    #[serde(skip)]
    last: Option<Grid>,
}

clone_in_place!(SweepAndPrune { axis, count, starts, entries, sorted, wide, narrow, extents, spans, keys, corners, last });

/// The grid of columns across the sweep axis.
#[derive(Clone, Copy, Debug)]
struct Grid {
    /// The two axes across the sweep.
    u: usize,
    w: usize,
    lo: [f64; 2],
    cell: f64,
    n: [usize; 2],
}

impl Grid {
    #[inline(always)]
    fn index(&self, x: f64, k: usize) -> usize {
        let c = ((x - self.lo[k]) / self.cell).floor();
        // `as` saturates (NaN to 0): a box far outside lands in an edge column.
        (c.max(0.0) as usize).min(self.n[k] - 1)
    }

    /// Column range of a box, per cross axis (inclusive).
    #[inline(always)]
    fn span(&self, b: &Aabb) -> [(usize, usize); 2] {
        let axes = [self.u, self.w];
        std::array::from_fn(|k| (self.index(b.min[axes[k]], k), self.index(b.max[axes[k]], k)))
    }

    /// The column that reports a pair: the one holding the corner of their
    /// overlap, from the columns of the boxes' own lower corners (`index` is
    /// monotonic, so the index of the larger `min` is the larger index).
    #[inline(always)]
    fn owner(&self, a: [u32; 2], b: [u32; 2]) -> usize {
        a[0].max(b[0]) as usize * self.n[1] + a[1].max(b[1]) as usize
    }
}

impl SweepAndPrune {
    /// Candidate pairs `(i, j)`, `i < j`, among `boxes` (one per finite collider,
    /// indexed by collider) whose boxes overlap and for which `keep(i, j)` holds.
    /// `finite` lists the colliders to consider.
    pub fn pairs(
        &mut self,
        boxes: &[Aabb],
        finite: &[u32],
        mut keep: impl FnMut(u32, u32) -> bool,
        out: &mut Vec<(u32, u32)>,
    ) {
        self.choose_axis(boxes, finite);
        self.last = self.bin(boxes, finite);
        let Some(grid) = self.last else { return };
        let mut push = |i: u32, j: u32| {
            let (lo, hi) = if i < j { (i, j) } else { (j, i) };
            if keep(lo, hi) {
                out.push((lo, hi));
            }
        };
        let axis = self.axis;
        for col in 0..self.starts.len() - 1 {
            let range = self.starts[col] as usize..self.starts[col + 1] as usize;
            if range.len() < 2 {
                continue;
            }
            // Sorted by key, not through the boxes: a sort that reads each
            // comparison's boxes from everywhere was most of a rebuild.
            self.keys.clear();
            self.keys.extend(self.entries[range].iter().map(|&i| (boxes[i as usize].min[axis], i)));
            self.keys.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            self.sorted.clear();
            self.sorted.extend(self.keys.iter().map(|&(_, i)| boxes[i as usize]));
            self.corners.clear();
            self.corners.extend(self.keys.iter().map(|&(_, i)| {
                let [u0, w0, _, _] = self.spans[i as usize];
                [u0, w0]
            }));
            // Each box meets the ones after it whose intervals start before its
            // own ends: exactly the pairs of the column that overlap on the axis.
            for (a, box_a) in self.sorted.iter().enumerate() {
                for (b, box_b) in self.sorted[a + 1..].iter().enumerate() {
                    if box_b.min[axis] > box_a.max[axis] {
                        break;
                    }
                    if box_a.overlaps(box_b) && grid.owner(self.corners[a], self.corners[a + 1 + b]) == col {
                        push(self.keys[a].1, self.keys[a + 1 + b].1);
                    }
                }
            }
        }
        for (k, &i) in self.wide.iter().enumerate() {
            let bi = &boxes[i as usize];
            // Two wide boxes meet once, from the first of them.
            for &j in self.narrow.iter().chain(&self.wide[k + 1..]) {
                if bi.overlaps(&boxes[j as usize]) {
                    push(i, j);
                }
            }
        }
    }

    /// Whether a last call's grid is known (see [`Self::near`]).
    pub fn has_grid(&self) -> bool {
        self.last.is_some()
    }

    /// Every box of the last call that may overlap box `b`, if none of them
    /// changed since (some more than once, some that do not overlap): those of
    /// the columns `b` spans and the wide ones. False, with nothing given, if
    /// there is no last call's grid or `b` spans more than `MAX_COLUMNS` of
    /// it.
    pub fn near(&self, b: &Aabb, mut give: impl FnMut(u32)) -> bool {
        let Some(grid) = self.last else { return false };
        let [(u0, u1), (w0, w1)] = grid.span(b);
        if u1 < u0 || w1 < w0 || (u1 - u0 + 1) * (w1 - w0 + 1) > MAX_COLUMNS {
            return false;
        }
        for cu in u0..=u1 {
            for cw in w0..=w1 {
                let col = cu * grid.n[1] + cw;
                let (a, z) = (self.starts[col] as usize, self.starts[col + 1] as usize);
                self.entries[a..z].iter().for_each(|&i| give(i));
            }
        }
        self.wide.iter().for_each(|&i| give(i));
        true
    }

    /// The sweep axis: the one along which the box centres spread most (with
    /// hysteresis), chosen afresh for a new set of boxes.
    fn choose_axis(&mut self, boxes: &[Aabb], finite: &[u32]) {
        let spread = spreads(boxes, finite);
        let widest = (0..3).fold(0, |best, k| if spread[k] > spread[best] { k } else { best });
        if self.count != finite.len() || spread[widest] > AXIS_SWITCH * spread[self.axis] {
            self.axis = widest;
        }
        self.count = finite.len();
    }

    /// Counting sort of the boxes into columns (`starts`, `entries`); the wide
    /// ones into `wide`. None if there is nothing to bin.
    fn bin(&mut self, boxes: &[Aabb], finite: &[u32]) -> Option<Grid> {
        let (u, w) = ((self.axis + 1) % 3, (self.axis + 2) % 3);
        let extent = |b: &Aabb| (b.max[u] - b.min[u]).max(b.max[w] - b.min[w]);
        let sane = |b: &Aabb| (0..3).all(|k| b.min[k].is_finite() && b.max[k].is_finite());
        self.extents.clear();
        self.extents.extend(finite.iter().map(|&i| &boxes[i as usize]).filter(|b| sane(b)).map(extent));
        self.starts.clear();
        self.entries.clear();
        self.wide.clear();
        self.narrow.clear();
        if self.extents.is_empty() {
            self.wide.extend(finite);
            self.starts.push(0);
            return None;
        }
        let nth = (self.extents.len() * 9 / 10).min(self.extents.len() - 1);
        let (_, p90, _) = self.extents.select_nth_unstable_by(nth, f64::total_cmp);
        let mut cell = CELL_OVER_EXTENT * *p90;
        let wide_extent = WIDE_CELLS * cell;
        let is_wide = |b: &Aabb| !sane(b) || extent(b) > wide_extent;
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for &i in finite {
            let b = &boxes[i as usize];
            if is_wide(b) {
                self.wide.push(i);
                continue;
            }
            self.narrow.push(i);
            for (k, a) in [u, w].into_iter().enumerate() {
                lo[k] = lo[k].min(b.min[a]);
                hi[k] = hi[k].max(b.min[a]);
            }
        }
        let normal = self.narrow.len();
        let span = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(0.0);
        if !(cell > 0.0) {
            // Boxes of no extent: cells from the spread instead.
            cell = if span > 0.0 { span / (normal as f64).sqrt() } else { 1.0 };
        }
        let columns = |cell: f64| [0, 1].map(|k| (((hi[k] - lo[k]).max(0.0) / cell) as usize).saturating_add(2));
        let mut n = columns(cell);
        while n[0].saturating_mul(n[1]) > COLUMNS_PER_BOX * normal + 64 {
            cell *= 2.0;
            n = columns(cell);
        }
        let grid = Grid { u, w, lo: if normal > 0 { lo } else { [0.0; 2] }, cell, n };
        self.count_into_columns(boxes, &grid);
        Some(grid)
    }

    /// `starts` and `entries` of the narrow boxes, column after column.
    fn count_into_columns(&mut self, boxes: &[Aabb], grid: &Grid) {
        let columns = grid.n[0] * grid.n[1];
        self.starts.resize(columns + 1, 0);
        let narrow = std::mem::take(&mut self.narrow);
        self.spans.resize(boxes.len(), [0; 4]);
        for &i in &narrow {
            let [(u0, u1), (w0, w1)] = grid.span(&boxes[i as usize]);
            self.spans[i as usize] = [u0 as u32, w0 as u32, u1 as u32, w1 as u32];
        }
        let spans = &self.spans;
        let each = |f: &mut dyn FnMut(usize, u32)| {
            for &i in &narrow {
                let [u0, w0, u1, w1] = spans[i as usize].map(|c| c as usize);
                for cu in u0..=u1 {
                    for cw in w0..=w1 {
                        f(cu * grid.n[1] + cw, i);
                    }
                }
            }
        };
        each(&mut |col, _| self.starts[col + 1] += 1);
        for c in 0..columns {
            self.starts[c + 1] += self.starts[c];
        }
        self.entries.resize(self.starts[columns] as usize, 0);
        let mut fill = self.starts.clone();
        each(&mut |col, i| {
            self.entries[fill[col] as usize] = i;
            fill[col] += 1;
        });
        self.narrow = narrow;
    }
}

/// Variance of the box centres along each axis: the widest has the fewest overlaps.
fn spreads(boxes: &[Aabb], ids: &[u32]) -> [f64; 3] {
    let n = ids.len().max(1) as f64;
    let centre = |i: u32, k: usize| 0.5 * (boxes[i as usize].min[k] + boxes[i as usize].max[k]);
    std::array::from_fn(|k| {
        let mean = ids.iter().map(|&i| centre(i, k)).sum::<f64>() / n;
        ids.iter().map(|&i| (centre(i, k) - mean).powi(2)).sum::<f64>() / n
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube(c: [f64; 3], h: f64) -> Aabb {
        Aabb { min: [c[0] - h, c[1] - h, c[2] - h], max: [c[0] + h, c[1] + h, c[2] + h] }
    }

    fn unit_box(c: [f64; 3]) -> Aabb {
        cube(c, 0.5)
    }

    fn brute_force(boxes: &[Aabb]) -> Vec<(u32, u32)> {
        let n = boxes.len() as u32;
        let mut want = Vec::new();
        for i in 0..n {
            for j in i + 1..n {
                if boxes[i as usize].overlaps(&boxes[j as usize]) {
                    want.push((i, j));
                }
            }
        }
        want
    }

    fn sweep(sap: &mut SweepAndPrune, boxes: &[Aabb]) -> Vec<(u32, u32)> {
        let ids: Vec<u32> = (0..boxes.len() as u32).collect();
        let mut got = Vec::new();
        sap.pairs(boxes, &ids, |_, _| true, &mut got);
        let n = got.len();
        got.sort();
        got.dedup();
        assert_eq!(got.len(), n, "a pair was reported twice");
        got
    }

    /// A small deterministic generator (splitmix64) for random scenes.
    fn random(seed: &mut u64) -> f64 {
        *seed = seed.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = *seed;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        (z ^ (z >> 31)) as f64 / u64::MAX as f64
    }

    #[test]
    fn finds_exactly_the_overlapping_pairs() {
        let boxes: Vec<Aabb> = (0..40).map(|i| unit_box([(i % 7) as f64 * 0.9, (i / 7) as f64 * 1.3, 0.0])).collect();
        assert_eq!(sweep(&mut SweepAndPrune::default(), &boxes), brute_force(&boxes));
    }

    #[test]
    fn follows_the_spread_to_another_axis_and_stays_exact() {
        // A column (spread along z) that collapses into a heap spread along x.
        let column: Vec<Aabb> = (0..30).map(|i| unit_box([0.1 * (i % 3) as f64, 0.0, 0.95 * i as f64])).collect();
        let heap: Vec<Aabb> = (0..30).map(|i| unit_box([0.95 * i as f64, 0.1 * (i % 4) as f64, 0.2 * (i % 2) as f64])).collect();
        let mut sap = SweepAndPrune::default();
        assert_eq!(sweep(&mut sap, &column), brute_force(&column));
        assert_eq!(sap.axis, 2);
        assert_eq!(sweep(&mut sap, &heap), brute_force(&heap));
        assert_eq!(sap.axis, 0);
    }

    #[test]
    fn random_boxes_of_every_size_give_exactly_the_overlapping_pairs() {
        let mut seed = 7;
        for scene in 0..40 {
            let n = 20 + scene * 10;
            let boxes: Vec<Aabb> = (0..n)
                .map(|k| {
                    let c = [random(&mut seed) * 10.0, random(&mut seed) * 10.0, random(&mut seed) * 3.0];
                    // Mostly small, some a few times larger, one in 40 a wall.
                    let h = if k % 40 == 0 { 6.0 } else { 0.1 + 0.5 * random(&mut seed).powi(3) };
                    cube(c, h)
                })
                .collect();
            assert_eq!(sweep(&mut SweepAndPrune::default(), &boxes), brute_force(&boxes), "scene {scene}");
        }
    }

    #[test]
    fn a_grid_of_touching_boxes_in_any_order() {
        // 6³ boxes of half size 0.5 at spacing 1: each meets its 26 neighbours.
        let mut boxes: Vec<Aabb> = Vec::new();
        for i in 0..6 {
            for j in 0..6 {
                for k in 0..6 {
                    boxes.push(unit_box([i as f64, j as f64, k as f64]));
                }
            }
        }
        let want = brute_force(&boxes);
        // Faces, edges (two diagonals in each of three planes), corners.
        assert_eq!(want.len(), 3 * 5 * 6 * 6 + 3 * 2 * 5 * 5 * 6 + 4 * 5 * 5 * 5);
        assert_eq!(sweep(&mut SweepAndPrune::default(), &boxes), want);
        boxes.reverse();
        assert_eq!(sweep(&mut SweepAndPrune::default(), &boxes), brute_force(&boxes));
    }

    #[test]
    fn degenerate_boxes_do_not_break_it() {
        // All at one point; boxes of no extent; a NaN box and an infinite one
        // (a diverging body the step guard has yet to catch) pair with nothing
        // they do not overlap.
        let same = vec![cube([1.0, 2.0, 3.0], 0.0); 5];
        assert_eq!(sweep(&mut SweepAndPrune::default(), &same).len(), 10);
        let mut odd = vec![unit_box([0.0; 3]), unit_box([0.5, 0.0, 0.0]), unit_box([9.0, 9.0, 9.0])];
        odd.push(Aabb { min: [f64::NAN; 3], max: [f64::NAN; 3] });
        odd.push(Aabb { min: [f64::NEG_INFINITY; 3], max: [f64::INFINITY; 3] });
        assert_eq!(sweep(&mut SweepAndPrune::default(), &odd), brute_force(&odd));
        assert_eq!(sweep(&mut SweepAndPrune::default(), &[]), vec![]);
    }
}
