//! The broad phase's boxes: axis-aligned boxes of the finite colliders (paired
//! by [`SweepAndPrune`]) and half-spaces, which are infinite and tested apart,
//! against each finite box.

/// An axis-aligned box (m).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Aabb {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

impl Aabb {
    /// Whether the boxes meet, judged on all six comparisons at once: the
    /// broad phase asks it of every pair of fat boxes each step, and whether
    /// two settling balls' boxes still meet is a coin toss that the
    /// comparisons' early exits turned into up to six mispredicted branches
    /// (a fifth of the 1000-ball pit's mispredictions in its first 150 steps).
    #[inline(always)]
    pub fn overlaps(&self, o: &Aabb) -> bool {
        let k = |k: usize| (self.min[k] <= o.max[k]) & (o.min[k] <= self.max[k]);
        k(0) & k(1) & k(2)
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

pub use super::sweep_and_prune::SweepAndPrune;

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box(c: [f64; 3]) -> Aabb {
        Aabb { min: [c[0] - 0.5, c[1] - 0.5, c[2] - 0.5], max: [c[0] + 0.5, c[1] + 0.5, c[2] + 0.5] }
    }

    #[test]
    fn half_space_touch() {
        let h = HalfSpace { normal: [0.0, 0.0, 1.0], offset: 0.0 };
        assert!(h.touches(&unit_box([0.0, 0.0, 0.4]), 0.0));
        assert!(!h.touches(&unit_box([0.0, 0.0, 0.6]), 0.05));
        assert!(h.touches(&unit_box([0.0, 0.0, 0.6]), 0.2));
    }
}
