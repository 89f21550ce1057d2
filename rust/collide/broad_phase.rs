//! Sweep and prune: colliders sorted by the lower bound of their box on one axis
//! (kept sorted by insertion sort, nearly linear since order changes little from
//! step to step), swept once; only boxes whose intervals overlap on that axis are
//! compared on the other two. Half-spaces are infinite and tested apart, against
//! each finite box.

/// An axis-aligned box (m).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Aabb {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

impl Aabb {
    #[inline(always)]
    pub fn overlaps(&self, o: &Aabb) -> bool {
        (0..3).all(|k| self.min[k] <= o.max[k] && o.min[k] <= self.max[k])
    }

    pub fn from_parry(a: &parry3d_f64::bounding_volume::Aabb) -> Self {
        Self { min: a.mins.coords.into(), max: a.maxs.coords.into() }
    }

    /// Whether this box lies within `o`.
    #[inline(always)]
    pub fn inside(&self, o: &Aabb) -> bool {
        (0..3).all(|k| self.min[k] >= o.min[k] && self.max[k] <= o.max[k])
    }

    /// The largest gap (m) between this box and `inner`, a box inside it: a box
    /// grown while its body moved fast and kept after it slowed down would pair
    /// it with every neighbour it no longer reaches.
    #[inline(always)]
    pub fn slack(&self, inner: &Aabb) -> f64 {
        (0..3).map(|k| (inner.min[k] - self.min[k]).max(self.max[k] - inner.max[k])).fold(0.0, f64::max)
    }

    /// The smallest box holding both.
    pub fn union(mut self, o: &Aabb) -> Self {
        for k in 0..3 {
            self.min[k] = self.min[k].min(o.min[k]);
            self.max[k] = self.max[k].max(o.max[k]);
        }
        self
    }

    /// Grows the box by `margin` on every side.
    pub fn loosened(mut self, margin: f64) -> Self {
        for k in 0..3 {
            self.min[k] -= margin;
            self.max[k] += margin;
        }
        self
    }

    /// Extends the box along the displacement `d`.
    pub fn swept(mut self, d: [f64; 3]) -> Self {
        for k in 0..3 {
            if d[k] < 0.0 {
                self.min[k] += d[k];
            } else {
                self.max[k] += d[k];
            }
        }
        self
    }
}

/// A half-space `n·x ≤ offset` (world).
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct HalfSpace {
    pub normal: [f64; 3],
    pub offset: f64,
}

impl HalfSpace {
    /// Whether the box reaches within `margin` of the half-space.
    pub fn touches(&self, a: &Aabb, margin: f64) -> bool {
        let lowest: f64 = (0..3).map(|k| self.normal[k] * if self.normal[k] > 0.0 { a.min[k] } else { a.max[k] }).sum();
        lowest <= self.offset + margin
    }
}

#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct SweepAndPrune {
    axis: usize,
    order: Vec<u32>,
    /// The boxes in sweep order, packed: the sweep reads them front to back.
    sorted: Vec<Aabb>,
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
        // The finite colliders of a world never change: set the order up once, and
        // keep it sorted by insertion (it changes little between calls). The axis
        // follows the scene's spread: a pile that has settled is wider than high.
        let spread = spreads(boxes, finite);
        let widest = (0..3).fold(0, |best, k| if spread[k] > spread[best] { k } else { best });
        if self.order.len() != finite.len() {
            self.order = finite.to_vec();
            self.axis = widest;
        } else if spread[widest] > AXIS_SWITCH * spread[self.axis] {
            self.axis = widest;
        }
        let axis = self.axis;
        insertion_sort(&mut self.order, |i| boxes[i as usize].min[axis]);
        self.sorted.clear();
        self.sorted.extend(self.order.iter().map(|&i| boxes[i as usize]));
        // Each box meets the ones after it whose intervals start before its own
        // ends: exactly the pairs that overlap on the sweep axis, no more.
        for (a, box_a) in self.sorted.iter().enumerate() {
            for (b, box_b) in self.sorted[a + 1..].iter().enumerate() {
                if box_b.min[axis] > box_a.max[axis] {
                    break;
                }
                if box_a.overlaps(box_b) {
                    let (i, j) = (self.order[a], self.order[a + 1 + b]);
                    let (lo, hi) = if i < j { (i, j) } else { (j, i) };
                    if keep(lo, hi) {
                        out.push((lo, hi));
                    }
                }
            }
        }
    }
}

/// How much more the box centres must spread along another axis before the sweep
/// moves to it (and sorts anew): no flip-flopping between two similar axes.
const AXIS_SWITCH: f64 = 1.5;

/// Variance of the box centres along each axis: the widest has the fewest overlaps.
fn spreads(boxes: &[Aabb], ids: &[u32]) -> [f64; 3] {
    let n = ids.len().max(1) as f64;
    let centre = |i: u32, k: usize| 0.5 * (boxes[i as usize].min[k] + boxes[i as usize].max[k]);
    std::array::from_fn(|k| {
        let mean = ids.iter().map(|&i| centre(i, k)).sum::<f64>() / n;
        ids.iter().map(|&i| (centre(i, k) - mean).powi(2)).sum::<f64>() / n
    })
}

fn insertion_sort(v: &mut [u32], key: impl Fn(u32) -> f64) {
    for i in 1..v.len() {
        let x = v[i];
        let kx = key(x);
        let mut j = i;
        while j > 0 && key(v[j - 1]) > kx {
            v[j] = v[j - 1];
            j -= 1;
        }
        v[j] = x;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box(c: [f64; 3]) -> Aabb {
        Aabb { min: [c[0] - 0.5, c[1] - 0.5, c[2] - 0.5], max: [c[0] + 0.5, c[1] + 0.5, c[2] + 0.5] }
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
        got.sort();
        got
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
    fn half_space_touch() {
        let h = HalfSpace { normal: [0.0, 0.0, 1.0], offset: 0.0 };
        assert!(h.touches(&unit_box([0.0, 0.0, 0.4]), 0.0));
        assert!(!h.touches(&unit_box([0.0, 0.0, 0.6]), 0.05));
        assert!(h.touches(&unit_box([0.0, 0.0, 0.6]), 0.2));
    }
}
