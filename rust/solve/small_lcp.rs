//! The normals of a few contact points of one manifold solved together and
//! exactly: find impulses `x ≥ 0` with velocities `w = K x + b ≥ 0` and
//! `xᵀw = 0` (a point pushes only while it touches), by block principal
//! pivoting on the set of pushing points (Júdice & Pires 1994): solve the set
//! exactly, let go the points that pull, take back the ones left approaching,
//! until none changes side.
//!
//! Solved one at a time, Gauss–Seidel gives the point it meets first more than
//! its share. A cube landing square on an edge took 5 % more impulse on one
//! corner, tipped sideways and spun about the vertical; one slapping down on a
//! face after sliding off an edge took 216 and 42 N·s on two corners that
//! mirror each other, and flew off sideways at 1.2 m/s.

/// Largest manifold solved together (parry's manifolds between polyhedra have
/// up to this many points in practice; a larger one is left to Gauss–Seidel).
pub const MAX_POINTS: usize = 8;

/// Pivoting rounds before giving up (a point changes side once or twice).
const ROUNDS: usize = 8;

/// Added to the diagonal, relative to its largest entry: the points of a face
/// are dependent (four coplanar points hold three velocities), and the
/// regularized answer is the least-norm one (the load shared evenly between
/// points that mirror each other). It leaves this fraction of a velocity
/// unsolved, and round-off over it in how the load is shared (1e-10 gave
/// corners of a flat landing 3e-7 apart; 1e-8 balances the two).
const REGULARIZATION: f64 = 1e-8;

/// Approach speed, relative to the largest velocity asked of a problem, below
/// which a point let go counts as not approaching: round-off, not a reason to
/// take it back (shared with [`super::active_set`]).
pub const SLOW: f64 = 1e-9;

/// The set of points that pushed in the last answer of one face and the
/// Cholesky factor of their `K`, kept between the sweeps of a projected
/// Gauss–Seidel solve (whose `K` stays the same): a face whose points keep
/// their sides is solved again without factoring.
#[derive(Clone, Copy)]
pub struct Factor {
    push: u32,
    l: [f64; MAX_POINTS * MAX_POINTS],
    /// The reciprocals of `l`'s diagonal: the solves multiply by them (their
    /// divisions, each waiting on the one before, held up the tumbling
    /// 4000-cube pile: 18.4 s for 120 steps, 16.4 s multiplying).
    inv: [f64; MAX_POINTS],
}

impl Default for Factor {
    fn default() -> Self {
        Factor { push: NONE, l: [0.0; MAX_POINTS * MAX_POINTS], inv: [0.0; MAX_POINTS] }
    }
}

/// No set factored yet.
const NONE: u32 = u32::MAX;

impl Factor {
    /// Drops the factored set (for a new `K`).
    pub fn forget(&mut self) {
        self.push = NONE;
    }
}

/// Solves the problem for symmetric positive semi-definite `k` (`n × n`, row
/// major, `n = b.len()`). Returns whether it found `x`; if not, `x` is
/// unchanged.
pub fn small_lcp(k: &[f64], b: &[f64], x: &mut [f64]) -> bool {
    small_lcp_with(k, b, x, &mut Factor::default())
}

/// [`small_lcp`] starting from the pushing set of `f` (if any) and reusing its
/// factor while the set holds (`k` must be the one `f` was made for).
pub fn small_lcp_with(k: &[f64], b: &[f64], x: &mut [f64], f: &mut Factor) -> bool {
    let n = b.len();
    if n == 0 || n > MAX_POINTS || k.len() < n * n || x.len() < n {
        return false;
    }
    let scale = (0..n).map(|i| k[i * n + i]).fold(0.0f64, f64::max);
    if !(scale > 0.0 && scale.is_finite()) {
        return false;
    }
    let eps = REGULARIZATION * scale;
    let slow = SLOW * b.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let mut push = if f.push == NONE { (0..n).filter(|&i| b[i] < 0.0).fold(0u32, |m, i| m | 1 << i) } else { f.push };
    let mut y = [0.0; MAX_POINTS];
    for _ in 0..ROUNDS {
        if push != f.push {
            if !factor_pushing(k, n, push, eps, f) {
                f.push = NONE;
                return false;
            }
            f.push = push;
        }
        solve_pushing(k, b, push, f, &mut y[..n]);
        let mut next = push;
        for i in 0..n {
            if push & 1 << i != 0 && y[i] < 0.0 {
                next &= !(1 << i);
            }
        }
        if next == push {
            for i in (0..n).filter(|&i| push & 1 << i == 0) {
                let w: f64 = (0..n).map(|j| k[i * n + j] * y[j]).sum::<f64>() + b[i];
                if w < -slow {
                    next |= 1 << i;
                }
            }
        }
        if next == push {
            x[..n].copy_from_slice(&y[..n]);
            return true;
        }
        push = next;
    }
    false
}

/// The pushing points of `push` (a bit each) in order.
fn pushing(n: usize, push: u32, idx: &mut [usize; MAX_POINTS]) -> usize {
    let mut m = 0;
    for i in 0..n {
        if push & 1 << i != 0 {
            idx[m] = i;
            m += 1;
        }
    }
    m
}

/// Cholesky factor `f.l` of the pushing points' `K + eps I`; false if it is
/// not positive definite.
fn factor_pushing(k: &[f64], n: usize, push: u32, eps: f64, f: &mut Factor) -> bool {
    let mut idx = [0usize; MAX_POINTS];
    let m = pushing(n, push, &mut idx);
    let (l, inv) = (&mut f.l, &mut f.inv);
    for p in 0..m {
        for q in 0..=p {
            let mut v = k[idx[p] * n + idx[q]] + if p == q { eps } else { 0.0 };
            for r in 0..q {
                v -= l[p * MAX_POINTS + r] * l[q * MAX_POINTS + r];
            }
            if p == q {
                if !(v > 0.0) {
                    return false;
                }
                l[p * MAX_POINTS + p] = v.sqrt();
                inv[p] = 1.0 / l[p * MAX_POINTS + p];
            } else {
                l[p * MAX_POINTS + q] = v * inv[q];
            }
        }
    }
    true
}

/// `y` with the points not pushing at zero and the pushing ones at `w = 0`.
fn solve_pushing(k: &[f64], b: &[f64], push: u32, f: &Factor, y: &mut [f64]) {
    let n = b.len();
    let mut idx = [0usize; MAX_POINTS];
    let m = pushing(n, push, &mut idx);
    y.iter_mut().for_each(|v| *v = 0.0);
    // The regularized answer, then refined against the exact `K`: each round
    // leaves eps / (eps + λ) of the error along an eigenvalue λ of the face,
    // so the velocities come out exact to round-off while the load between
    // dependent points stays shared as the regularization shares it.
    // The first round starts from zero, whose residual is `−b` itself.
    let mut z = [0.0; MAX_POINTS];
    for p in 0..m {
        z[p] = -b[idx[p]];
    }
    cholesky_solve(f, m, &mut z);
    let mut r = [0.0; MAX_POINTS];
    for p in 0..m {
        let kz: f64 = (0..m).map(|q| k[idx[p] * n + idx[q]] * z[q]).sum();
        r[p] = -b[idx[p]] - kz;
    }
    cholesky_solve(f, m, &mut r);
    for p in 0..m {
        z[p] += r[p];
    }
    for p in 0..m {
        y[idx[p]] = z[p];
    }
}

/// Solves `L Lᵀ u = r` in place (`L` of [`factor_pushing`], `m` rows).
fn cholesky_solve(f: &Factor, m: usize, r: &mut [f64; MAX_POINTS]) {
    let (l, inv) = (&f.l, &f.inv);
    for p in 0..m {
        for q in 0..p {
            r[p] -= l[p * MAX_POINTS + q] * r[q];
        }
        r[p] *= inv[p];
    }
    for p in (0..m).rev() {
        for q in p + 1..m {
            r[p] -= l[q * MAX_POINTS + p] * r[q];
        }
        r[p] *= inv[p];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `K = A M⁻¹ Aᵀ` of the normals of points `(x, y)` under a unit cube face
    /// (mass 1, inertia I about x and y), rows `[1, y, −x]` in (v_z, ω_x, ω_y).
    fn face(points: &[(f64, f64)], inertia: f64) -> Vec<f64> {
        let n = points.len();
        let mut k = vec![0.0; n * n];
        for (i, a) in points.iter().enumerate() {
            for (j, b) in points.iter().enumerate() {
                k[i * n + j] = 1.0 + (a.1 * b.1 + a.0 * b.0) / inertia;
            }
        }
        k
    }

    #[test]
    fn a_face_landing_flat_loads_its_four_corners_equally() {
        let c = [(0.5, 0.5), (-0.5, 0.5), (-0.5, -0.5), (0.5, -0.5)];
        let k = face(&c, 1.0 / 6.0);
        // Falling at 2 m/s: stopping it takes an impulse of 2 (mass 1), a
        // quarter at each corner; nothing turns it.
        let b = [-2.0; 4];
        let mut x = [0.0; 4];
        assert!(small_lcp(&k, &b, &mut x));
        for xi in x {
            // Regularization 1e-8 of the diagonal: the answer within 1e-6.
            assert!((xi - 0.5).abs() < 1e-6, "{x:?}");
        }
    }

    #[test]
    fn a_face_landing_on_one_edge_lets_the_other_go() {
        // Falling at 1 m/s and turning at ω_y = 6 rad/s about the face centre:
        // corners at x = +0.5 approach at 1 + 6·0.5 = 4 m/s, those at −0.5
        // separate at 2 m/s.
        let c = [(0.5, 0.5), (-0.5, 0.5), (-0.5, -0.5), (0.5, -0.5)];
        let inertia = 1.0 / 6.0;
        let k = face(&c, inertia);
        let b: Vec<f64> = c.iter().map(|p| -1.0 - 6.0 * p.0).collect();
        let mut x = [0.0; 4];
        assert!(small_lcp(&k, &b, &mut x));
        // The edge at x = +0.5 stops as a pivot: an impulse P at arm 0.5,
        // 4 − P (1 + 0.25/I) = 0, its two corners sharing it; the other edge
        // then separates at 2 + P (1 − 0.25/I) > 0 and takes nothing.
        let p = 4.0 / (1.0 + 0.25 / inertia);
        assert!(2.0 + p * (1.0 - 0.25 / inertia) > 0.0);
        assert!((x[0] - p / 2.0).abs() < 1e-6 && (x[3] - p / 2.0).abs() < 1e-6, "{x:?}");
        assert!(x[1] == 0.0 && x[2] == 0.0, "{x:?}");
    }

    #[test]
    fn a_face_turning_slowly_onto_its_edge_is_stopped_whole() {
        // At ω_y = 2 rad/s the far edge would meet the floor at 0 m/s but is
        // pushed into it by the near edge's impulse: all four push and the
        // face stops, vertical speed and turn.
        let c = [(0.5, 0.5), (-0.5, 0.5), (-0.5, -0.5), (0.5, -0.5)];
        let k = face(&c, 1.0 / 6.0);
        let b: Vec<f64> = c.iter().map(|p| -1.0 - 2.0 * p.0).collect();
        let mut x = [0.0; 4];
        assert!(small_lcp(&k, &b, &mut x));
        for i in 0..4 {
            let w: f64 = (0..4).map(|j| k[i * 4 + j] * x[j]).sum::<f64>() + b[i];
            assert!(w.abs() < 1e-6 && x[i] > 0.0, "point {i}: w {w}, x {x:?}");
        }
    }

    #[test]
    fn points_moving_apart_take_nothing() {
        let k = face(&[(0.5, 0.0), (-0.5, 0.0)], 1.0 / 6.0);
        let mut x = [7.0; 2];
        assert!(small_lcp(&k, &[0.3, 0.1], &mut x));
        assert_eq!(x, [0.0, 0.0]);
    }
}
