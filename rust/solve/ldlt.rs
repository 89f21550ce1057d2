//! `K = L D Lᵀ` of a symmetric positive semi-definite matrix, the rows that
//! depend on the ones before it left out: the exact solves of the support
//! blocks ([`super::block`], [`super::active_set`]), whose points of one face
//! are dependent (four coplanar points hold three velocities).

/// A pivot below this fraction of the largest diagonal of `K` marks a row that
/// depends on the ones before it.
const PIVOT_TOLERANCE: f64 = 1e-10;

/// `K = L D Lᵀ` of a symmetric positive semi-definite `m × m` matrix: `L` below
/// the diagonal of `out`, `D` on it. A row that depends on the ones before it
/// (pivot below [`PIVOT_TOLERANCE`] of the largest diagonal) gets `D = 0` and
/// is left out of every solve.
pub fn factor(k: &[f64], out: &mut [f64], m: usize) {
    let scale = (0..m).map(|i| k[i * m + i]).fold(0.0f64, f64::max);
    let tol = PIVOT_TOLERANCE * scale;
    for j in 0..m {
        let mut d = k[j * m + j];
        for p in 0..j {
            d -= out[j * m + p] * out[j * m + p] * out[p * m + p];
        }
        if d <= tol {
            out[j * m + j] = 0.0;
            for i in j + 1..m {
                out[i * m + j] = 0.0;
            }
            continue;
        }
        out[j * m + j] = d;
        for i in j + 1..m {
            let mut v = k[i * m + j];
            for p in 0..j {
                v -= out[i * m + p] * out[j * m + p] * out[p * m + p];
            }
            out[i * m + j] = v / d;
        }
    }
}

/// Solves `K y = r` with the factor of [`factor`]; dependent rows get `y = 0`.
pub fn solve_factored(fac: &[f64], r: &[f64], y: &mut [f64]) {
    let m = r.len();
    y.copy_from_slice(r);
    for i in 0..m {
        for p in 0..i {
            y[i] -= fac[i * m + p] * y[p];
        }
    }
    for i in 0..m {
        let d = fac[i * m + i];
        y[i] = if d > 0.0 { y[i] / d } else { 0.0 };
    }
    for i in (0..m).rev() {
        if fac[i * m + i] == 0.0 {
            continue;
        }
        for p in i + 1..m {
            y[i] -= fac[p * m + i] * y[p];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dependent_row_is_left_out_and_the_rest_solved_exactly() {
        // Rows 0, 1 independent, row 2 = row 0 + row 1: K = A Aᵀ is rank 2.
        let a = [[1.0, 0.0, 2.0], [0.0, 1.0, -1.0], [1.0, 1.0, 1.0]];
        let mut k = [0.0; 9];
        for i in 0..3 {
            for j in 0..3 {
                k[i * 3 + j] = (0..3).map(|c| a[i][c] * a[j][c]).sum();
            }
        }
        let mut fac = [0.0; 9];
        factor(&k, &mut fac, 3);
        assert_eq!(fac[8], 0.0);
        let r = [1.0, 2.0, 3.0]; // consistent: r2 = r0 + r1
        let mut y = [0.0; 3];
        solve_factored(&fac, &r, &mut y);
        for i in 0..3 {
            let ky: f64 = (0..3).map(|j| k[i * 3 + j] * y[j]).sum();
            assert!((ky - r[i]).abs() < 1e-12, "{ky} vs {}", r[i]);
        }
    }
}
