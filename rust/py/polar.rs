//! `polar_decomposition(M, method="svd", *, initial=None)` on one 3×3 matrix or a
//! batch `(N, 3, 3)`.

use numpy::{PyArray1, PyArrayDyn, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use super::convert::float_array;
use super::errors::IntoPy;
use crate::error::{Error, Result};
use crate::math::polar::{polar, PolarMethod};
use crate::math::{quat, Mat3, Quat};

/// How far from orthonormal (max entry of `RᵀR − I`) a warm start may be.
const ROTATION_TOL: f64 = 1e-6;

/// `(R, S)`, each shaped as the input.
type Factors<'py> = (Bound<'py, PyArrayDyn<f64>>, Bound<'py, PyArrayDyn<f64>>);

/// `(R, S)` with `M = R S`: see the stub for the parameters.
#[pyfunction]
#[pyo3(signature = (m, method="svd", *, initial=None))]
pub fn polar_decomposition<'py>(
    py: Python<'py>,
    m: &Bound<'py, PyAny>,
    method: &str,
    initial: Option<&Bound<'py, PyAny>>,
) -> PyResult<Factors<'py>> {
    let method = PolarMethod::from_name(method).py_err()?;
    let (values, shape) = float_array(m, "M")?;
    let single = batch_shape(&shape, "M")?.is_none();
    let mats = matrices(&values);
    let warm = match initial {
        None => None,
        Some(_) if method != PolarMethod::Muller => {
            return Err(PyValueError::new_err(format!("initial: only method=\"muller\" takes a warm start, got method={:?}", method.name())))
        }
        Some(obj) => Some(warm_starts(obj, mats.len())?),
    };
    let out = py.detach(|| decompose(&mats, method, warm.as_deref(), single)).py_err()?;
    let r = array(py, out.iter().map(|p| p.0), &shape)?;
    let s = array(py, out.iter().map(|p| p.1), &shape)?;
    Ok((r, s))
}

/// `None` for one matrix `(3, 3)`, `Some(N)` for `(N, 3, 3)`.
fn batch_shape(shape: &[usize], name: &str) -> PyResult<Option<usize>> {
    match shape {
        [3, 3] => Ok(None),
        [n, 3, 3] => Ok(Some(*n)),
        _ => Err(PyValueError::new_err(format!("{name} must have shape (3, 3) or (N, 3, 3), got {shape:?}"))),
    }
}

/// Row-major 3×3 blocks.
fn matrices(values: &[f64]) -> Vec<Mat3> {
    values.chunks_exact(9).map(Mat3::from_row_slice).collect()
}

/// One warm start per matrix: `initial` of shape (3, 3) (shared) or (N, 3, 3).
fn warm_starts(obj: &Bound<'_, PyAny>, n: usize) -> PyResult<Vec<Quat>> {
    let (values, shape) = float_array(obj, "initial")?;
    let count = batch_shape(&shape, "initial")?;
    if count.is_some_and(|k| k != n) {
        return Err(PyValueError::new_err(format!("initial: has {} matrices for {n} in M", shape[0])));
    }
    let rots = matrices(&values);
    let quats = rots.iter().enumerate().map(|(k, r)| rotation(r).map_err(|e| e.context(format!("initial[{k}]"))));
    let quats: Result<Vec<Quat>> = quats.collect();
    let quats = quats.py_err()?;
    Ok(if count.is_none() { vec![quats[0]; n] } else { quats })
}

/// The unit quaternion of a rotation matrix, after checking that it is one.
fn rotation(r: &Mat3) -> Result<Quat> {
    let ortho = (r.transpose() * r - Mat3::identity()).amax();
    if !(ortho <= ROTATION_TOL && r.determinant() > 0.0) {
        return Err(Error::input(format!("initial must be a rotation matrix (orthonormal, det +1), got {r}")));
    }
    Ok(quat::from_matrix(r))
}

/// Every matrix's factors; an error names the matrix (`M`, or `M[k]` in a batch).
fn decompose(mats: &[Mat3], method: PolarMethod, warm: Option<&[Quat]>, single: bool) -> Result<Vec<(Mat3, Mat3)>> {
    mats.iter()
        .enumerate()
        .map(|(k, m)| {
            let name = if single { "M".to_string() } else { format!("M[{k}]") };
            let p = polar(m, method, warm.map(|w| &w[k])).map_err(|e| e.context(name))?;
            Ok((p.r, p.s))
        })
        .collect()
}

/// Row-major blocks as an array of `shape`.
fn array<'py>(py: Python<'py>, mats: impl Iterator<Item = Mat3>, shape: &[usize]) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    // nalgebra stores columns: the transpose's storage is the row-major order.
    let flat: Vec<f64> = mats.flat_map(|m| m.transpose().as_slice().to_vec()).collect();
    PyArray1::from_vec(py, flat).reshape(shape.to_vec())
}
