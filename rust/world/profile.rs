//! Time spent per stage, accumulated by stage name since the last reset.

use std::time::Instant;

#[derive(Clone, Debug)]
pub struct Profile {
    /// Whether stages are timed (two clock reads per stage run).
    pub enabled: bool,
    names: Vec<&'static str>,
    seconds: Vec<f64>,
    runs: Vec<u64>,
    steps: u64,
}

impl Default for Profile {
    fn default() -> Self {
        Self { enabled: true, names: Vec::new(), seconds: Vec::new(), runs: Vec::new(), steps: 0 }
    }
}

impl Profile {
    /// The accumulator slot of a stage name, created on first use; slots stay valid
    /// across resets.
    pub fn slot(&mut self, name: &'static str) -> usize {
        if let Some(k) = self.names.iter().position(|&n| n == name) {
            return k;
        }
        self.names.push(name);
        self.seconds.push(0.0);
        self.runs.push(0);
        self.names.len() - 1
    }

    #[inline(always)]
    pub fn add(&mut self, slot: usize, since: Instant) {
        self.seconds[slot] += since.elapsed().as_secs_f64();
        self.runs[slot] += 1;
    }

    pub fn count_steps(&mut self, n: u64) {
        self.steps += n;
    }

    /// `(stage name, seconds)` of the stages that ran since the last reset, in
    /// first-run order, and the number of steps covered.
    pub fn report(&self) -> (Vec<(&'static str, f64)>, u64) {
        let rows = (0..self.names.len()).filter(|&k| self.runs[k] > 0).map(|k| (self.names[k], self.seconds[k]));
        (rows.collect(), self.steps)
    }

    pub fn reset(&mut self) {
        self.seconds.fill(0.0);
        self.runs.fill(0);
        self.steps = 0;
    }
}
