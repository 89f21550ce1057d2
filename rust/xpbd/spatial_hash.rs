//! A dense spatial hash for particle neighbours: cells of a fixed size hashed
//! into a table, particles sorted by bucket with a counting sort (two passes, no
//! allocation after the first build). A query visits the 27 cells around a
//! point; buckets two cells share are visited once.

#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct SpatialHash {
    /// Cell edge (m).
    cell: f64,
    /// `start[b]..start[b + 1]` indexes `entries` for bucket `b`.
    start: Vec<u32>,
    entries: Vec<u32>,
    bucket_of: Vec<u32>,
}

#[inline(always)]
fn hash(c: [i64; 3], n: usize) -> usize {
    let h = (c[0].wrapping_mul(92837111)) ^ (c[1].wrapping_mul(689287499)) ^ (c[2].wrapping_mul(283923481));
    (h.unsigned_abs() % n as u64) as usize
}

impl SpatialHash {
    #[inline(always)]
    fn cell_of(&self, p: &[f64; 3]) -> [i64; 3] {
        p.map(|v| (v / self.cell).floor() as i64)
    }

    /// Sorts the particles `ids` (positions `x`) into cells of edge `cell` (m > 0).
    pub fn build(&mut self, x: &[[f64; 3]], ids: &[u32], cell: f64) {
        self.cell = cell;
        let n = (2 * ids.len()).max(1);
        self.start.clear();
        self.start.resize(n + 1, 0);
        self.bucket_of.clear();
        for &i in ids {
            let b = hash(self.cell_of(&x[i as usize]), n);
            self.bucket_of.push(b as u32);
            self.start[b + 1] += 1;
        }
        for b in 0..n {
            self.start[b + 1] += self.start[b];
        }
        self.entries.clear();
        self.entries.resize(ids.len(), 0);
        let mut fill = self.start.clone();
        for (k, &i) in ids.iter().enumerate() {
            let b = self.bucket_of[k] as usize;
            self.entries[fill[b] as usize] = i;
            fill[b] += 1;
        }
    }

    /// Calls `f(j)` for every particle in the 27 cells around `p` (and possibly
    /// a few more sharing their buckets), each at most once.
    pub fn for_neighbours(&self, p: &[f64; 3], mut f: impl FnMut(u32)) {
        if self.entries.is_empty() || self.start.len() < 2 {
            return;
        }
        let n = self.start.len() - 1;
        let c = self.cell_of(p);
        let mut seen = [usize::MAX; 27];
        let mut k = 0;
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let b = hash([c[0] + dx, c[1] + dy, c[2] + dz], n);
                    if seen[..k].contains(&b) {
                        continue;
                    }
                    seen[k] = b;
                    k += 1;
                    for &j in &self.entries[self.start[b] as usize..self.start[b + 1] as usize] {
                        f(j);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_every_pair_within_a_cell() {
        let x: Vec<[f64; 3]> = (0..300).map(|i| {
            let t = i as f64;
            [(t * 0.37).sin() * 2.0, (t * 0.71).cos() * 2.0, (t * 0.13).sin()]
        }).collect();
        let ids: Vec<u32> = (0..300).collect();
        let mut h = SpatialHash::default();
        h.build(&x, &ids, 0.3);
        for i in 0..300 {
            let mut found = Vec::new();
            h.for_neighbours(&x[i], |j| found.push(j));
            let mut dedup = found.clone();
            dedup.sort();
            dedup.dedup();
            assert_eq!(dedup.len(), found.len(), "a particle was visited twice");
            for j in 0..300 {
                let d: f64 = (0..3).map(|k| (x[i][k] - x[j][k]).powi(2)).sum::<f64>().sqrt();
                if d < 0.3 {
                    assert!(found.contains(&(j as u32)), "{i} misses {j} at {d}");
                }
            }
        }
    }
}
