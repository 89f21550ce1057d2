//! Conversions from Python values, each failing with a message that names the field.

use numpy::{PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

/// Any array-like as a flat `f64` buffer and its shape.
pub fn float_array(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<(Vec<f64>, Vec<usize>)> {
    let np = obj.py().import("numpy")?;
    let arr = np
        .call_method1("asarray", (obj, "float64"))
        .map_err(|e| PyTypeError::new_err(format!("{name} must be numeric: {e}")))?;
    let arr = arr.cast::<PyArrayDyn<f64>>().map_err(|e| PyTypeError::new_err(format!("{name}: {e}")))?;
    let ro = arr.try_readonly().map_err(|e| PyValueError::new_err(format!("{name}: {e}")))?;
    let shape = ro.shape().to_vec();
    Ok((ro.as_array().iter().copied().collect(), shape))
}

fn shape_error(name: &str, want: &str, got: &[usize]) -> PyErr {
    PyValueError::new_err(format!("{name} must have shape {want}, got {got:?}"))
}

pub fn vec3(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<[f64; 3]> {
    let (v, shape) = float_array(obj, name)?;
    if shape != [3] {
        return Err(shape_error(name, "(3,)", &shape));
    }
    Ok([v[0], v[1], v[2]])
}

pub fn vec4(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<[f64; 4]> {
    let (v, shape) = float_array(obj, name)?;
    if shape != [4] {
        return Err(shape_error(name, "(4,)", &shape));
    }
    Ok([v[0], v[1], v[2], v[3]])
}

/// An `(N, 3)` array as rows.
pub fn rows3(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<[f64; 3]>> {
    let (v, shape) = float_array(obj, name)?;
    if shape.len() != 2 || shape[1] != 3 {
        return Err(shape_error(name, "(N, 3)", &shape));
    }
    Ok(v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
}

/// A scalar broadcast to `n` entries, or an `(n,)` array.
pub fn scalar_or_vector(obj: &Bound<'_, PyAny>, name: &str, n: usize) -> PyResult<Vec<f64>> {
    let (v, shape) = float_array(obj, name)?;
    match shape.as_slice() {
        [] => Ok(vec![v[0]; n]),
        [m] if *m == n => Ok(v),
        _ => Err(shape_error(name, &format!("() or ({n},)"), &shape)),
    }
}

/// An `(T, 3)` array of vertex indices.
pub fn triangles(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<[u32; 3]>> {
    let (v, shape) = float_array(obj, name)?;
    if shape.len() != 2 || shape[1] != 3 {
        return Err(shape_error(name, "(T, 3)", &shape));
    }
    v.chunks_exact(3)
        .enumerate()
        .map(|(t, c)| {
            let mut tri = [0u32; 3];
            for k in 0..3 {
                let x = c[k];
                if !(x >= 0.0 && x <= u32::MAX as f64 && x.fract() == 0.0) {
                    return Err(PyValueError::new_err(format!("{name}[{t}] must hold vertex indices, got {x}")));
                }
                tri[k] = x as u32;
            }
            Ok(tri)
        })
        .collect()
}

/// A non-negative integer argument (a body index, a count), as a clear
/// `ValueError` when negative instead of an `OverflowError`.
pub fn non_negative_int(x: i64, name: &str) -> PyResult<u64> {
    u64::try_from(x).map_err(|_| PyValueError::new_err(format!("{name} must be a non-negative integer, got {x}")))
}
