//! Lists of indices kept in one array (the blocks of each island, the contacts
//! of each group), and a slice split into the runs its owners lay out one
//! after another (a block's rows, a constraint's points) for the threads.

/// One list of indices per owner, in one array (compressed rows).
#[derive(Clone, Default)]
pub struct Lists {
    start: Vec<u32>,
    items: Vec<u32>,
}

impl Lists {
    /// The lists of `n` owners from `(owner, item)` pairs, each list in the
    /// order of the pairs; a pair whose owner is `n` or more is left out.
    pub fn fill(&mut self, n: usize, pairs: impl Iterator<Item = (u32, u32)> + Clone) {
        self.start.clear();
        self.start.resize(n + 1, 0);
        for (owner, _) in pairs.clone() {
            if let Some(c) = self.start.get_mut(owner as usize + 1).filter(|_| (owner as usize) < n) {
                *c += 1;
            }
        }
        for k in 0..n {
            self.start[k + 1] += self.start[k];
        }
        let mut at = self.start.clone();
        self.items.clear();
        self.items.resize(self.start[n] as usize, 0);
        for (owner, item) in pairs {
            if let Some(a) = at.get_mut(owner as usize).filter(|_| (owner as usize) < n) {
                self.items[*a as usize] = item;
                *a += 1;
            }
        }
    }

    /// The list of owner `k` (empty for an owner that does not exist).
    pub fn of(&self, k: usize) -> &[u32] {
        match (self.start.get(k), self.start.get(k + 1)) {
            (Some(&a), Some(&b)) => self.items.get(a as usize..b as usize).unwrap_or(&[]),
            _ => &[],
        }
    }

    /// Number of owners.
    pub fn len(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// `v` cut into the runs `(start, len)`, which must come in order without
/// overlapping (gaps allowed); `None` if they do not.
pub fn runs<T>(v: &mut [T], runs: impl Iterator<Item = (usize, usize)>) -> Option<Vec<&mut [T]>> {
    let mut out = Vec::new();
    let (mut rest, mut at) = (v, 0usize);
    for (start, len) in runs {
        let tail = std::mem::take(&mut rest).get_mut(start.checked_sub(at)?..)?;
        if len > tail.len() {
            return None;
        }
        let (mine, tail) = tail.split_at_mut(len);
        out.push(mine);
        (rest, at) = (tail, start + len);
    }
    Some(out)
}
