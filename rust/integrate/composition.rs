//! Fourth-order compositions of the Strang step `S(h)`:
//! Yoshida (1990) `S(w₁h) S(w₀h) S(w₁h)` with `w₁ = 1/(2 − 2^{1/3})`, `w₀ = 1 − 2w₁`,
//! and Suzuki (1990) `S(ph)² S((1−4p)h) S(ph)²` with `p = 1/(4 − 4^{1/3})`.
//! Adjacent half kicks merge, so a composition of `s` Strang steps has `s + 1` kicks.

use super::{Rotation, Splitting};

/// The splitting of the composition `S(w₁h) S(w₂h) …` of Strang steps.
pub fn compose(weights: &[f64]) -> Splitting {
    let mut kicks = vec![0.5 * weights[0]];
    for pair in weights.windows(2) {
        kicks.push(0.5 * (pair[0] + pair[1]));
    }
    kicks.push(0.5 * weights[weights.len() - 1]);
    Splitting { gyroscopic: None, kicks, drifts: weights.to_vec(), rotation: Rotation::Free }
}

pub fn yoshida4() -> Splitting {
    let w1 = 1.0 / (2.0 - 2f64.cbrt());
    compose(&[w1, 1.0 - 2.0 * w1, w1])
}

pub fn suzuki4() -> Splitting {
    let p = 1.0 / (4.0 - 4f64.cbrt());
    compose(&[p, p, 1.0 - 4.0 * p, p, p])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fractions_sum_to_one() {
        for s in [yoshida4(), suzuki4()] {
            assert!((s.kicks.iter().sum::<f64>() - 1.0).abs() < 1e-15);
            assert!((s.drifts.iter().sum::<f64>() - 1.0).abs() < 1e-15);
            assert_eq!(s.kicks.len(), s.drifts.len() + 1);
        }
    }
}
