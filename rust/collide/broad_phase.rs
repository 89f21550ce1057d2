//! Sweep and prune: colliders sorted by the lower bound of their box on one axis
//! (kept sorted by insertion sort, nearly linear since order changes little from
//! step to step), swept once; only boxes whose intervals overlap on that axis are
//! compared on the other two. Half-spaces are infinite and tested apart, against
//! each finite box.

/// An axis-aligned box (m).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
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
#[derive(Clone, Copy, Debug)]
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

#[derive(Clone, Debug, Default)]
pub struct SweepAndPrune {
    axis: usize,
    order: Vec<u32>,
    active: Vec<u32>,
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
        // The finite colliders of a world never change: set the order up once.
        if self.order.len() != finite.len() {
            self.order = finite.to_vec();
            self.axis = widest_axis(boxes, finite);
        }
        let axis = self.axis;
        insertion_sort(&mut self.order, |i| boxes[i as usize].min[axis]);
        self.active.clear();
        for &i in &self.order {
            let a = &boxes[i as usize];
            self.active.retain(|&j| boxes[j as usize].max[axis] >= a.min[axis]);
            for &j in &self.active {
                if a.overlaps(&boxes[j as usize]) {
                    let (lo, hi) = if i < j { (i, j) } else { (j, i) };
                    if keep(lo, hi) {
                        out.push((lo, hi));
                    }
                }
            }
            self.active.push(i);
        }
    }
}

/// The axis along which the box centres spread most: the fewest overlaps in it.
fn widest_axis(boxes: &[Aabb], ids: &[u32]) -> usize {
    let n = ids.len().max(1) as f64;
    let mut best = (0, -1.0);
    for k in 0..3 {
        let c: Vec<f64> = ids.iter().map(|&i| 0.5 * (boxes[i as usize].min[k] + boxes[i as usize].max[k])).collect();
        let mean = c.iter().sum::<f64>() / n;
        let var = c.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / n;
        if var > best.1 {
            best = (k, var);
        }
    }
    best.0
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

    #[test]
    fn finds_exactly_the_overlapping_pairs() {
        let boxes: Vec<Aabb> = (0..40).map(|i| unit_box([(i % 7) as f64 * 0.9, (i / 7) as f64 * 1.3, 0.0])).collect();
        let ids: Vec<u32> = (0..40).collect();
        let mut sap = SweepAndPrune::default();
        let mut got = Vec::new();
        sap.pairs(&boxes, &ids, |_, _| true, &mut got);
        got.sort();
        let mut want = Vec::new();
        for i in 0..40u32 {
            for j in i + 1..40 {
                if boxes[i as usize].overlaps(&boxes[j as usize]) {
                    want.push((i, j));
                }
            }
        }
        assert_eq!(got, want);
    }

    #[test]
    fn half_space_touch() {
        let h = HalfSpace { normal: [0.0, 0.0, 1.0], offset: 0.0 };
        assert!(h.touches(&unit_box([0.0, 0.0, 0.4]), 0.0));
        assert!(!h.touches(&unit_box([0.0, 0.0, 0.6]), 0.05));
        assert!(h.touches(&unit_box([0.0, 0.0, 0.6]), 0.2));
    }
}
