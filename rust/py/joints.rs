//! Joints from Python: the argument conversion of `Scene.add_joint` and the
//! `(J, 3)` arrays of `World.joint_forces` / `World.joint_torques`.

use numpy::{PyArray1, PyArrayDyn, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use super::convert::{float_array, non_negative_int, vec3};
use crate::articulation::Control;
use crate::error::Error;
use crate::world::joints::{JointOptions, SolverChoice};
use crate::xpbd::joints::{JointKind, JointSpec};

/// The arguments of `Scene.add_joint`, as Python gave them.
pub struct JointArgs<'a, 'py> {
    pub kind: &'a str,
    pub body_a: i64,
    pub body_b: Option<i64>,
    pub anchor: Option<&'a Bound<'py, PyAny>>,
    pub anchor_b: Option<&'a Bound<'py, PyAny>>,
    pub axis: Option<&'a Bound<'py, PyAny>>,
    pub compliance: f64,
    pub angular_compliance: f64,
    pub limits: Option<&'a Bound<'py, PyAny>>,
    pub rest_length: Option<f64>,
    pub name: Option<String>,
    pub solver: &'a str,
    pub drive: Option<crate::articulation::Drive>,
    pub damping: f64,
    pub armature: f64,
    pub friction: f64,
    pub cone_limit: Option<f64>,
    pub twist_limits: Option<&'a Bound<'py, PyAny>>,
}

/// The options of `add_joint` besides the geometry.
pub fn options(args: &JointArgs<'_, '_>, index: usize) -> PyResult<JointOptions> {
    let field = |name: &str| format!("joint {index}: {name}");
    let solver = SolverChoice::from_name(args.solver).map_err(|e| to_py(e, index))?;
    let control = Control {
        drive: args.drive.clone(),
        damping: args.damping,
        armature: args.armature,
        friction: args.friction,
        limits: None,
        cone: args.cone_limit,
        twist: args.twist_limits.map(|l| pair(l, &field("twist_limits"))).transpose()?,
    };
    Ok(JointOptions { name: args.name.clone(), solver, control })
}

/// A [`JointSpec`] from the arguments; errors name joint `index` and the field.
pub fn spec(args: &JointArgs<'_, '_>, index: usize) -> PyResult<JointSpec> {
    let field = |name: &str| format!("joint {index}: {name}");
    let kind = JointKind::from_name(args.kind).map_err(|e| to_py(e, index))?;
    let body_a = non_negative_int(args.body_a, &field("body_a"))? as usize;
    let body_b = args.body_b.map(|b| non_negative_int(b, &field("body_b"))).transpose()?.map(|b| b as usize);
    let mut s = JointSpec::new(kind, body_a, body_b);
    s.anchor = args.anchor.map(|p| vec3(p, &field("anchor"))).transpose()?;
    s.anchor_b = args.anchor_b.map(|p| vec3(p, &field("anchor_b"))).transpose()?;
    if let Some(a) = args.axis {
        s.axis = vec3(a, &field("axis"))?;
    }
    s.compliance = args.compliance;
    s.angular_compliance = args.angular_compliance;
    s.limits = args.limits.map(|l| pair(l, &field("limits"))).transpose()?;
    s.rest_length = args.rest_length;
    Ok(s)
}

fn to_py(e: Error, index: usize) -> PyErr {
    super::errors::to_py(e.context(format!("joint {index}")))
}

/// A `(lo, hi)` pair.
fn pair(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<[f64; 2]> {
    let (v, shape) = float_array(obj, name)?;
    if shape != [2] {
        return Err(PyValueError::new_err(format!("{name} must be a pair (lo, hi), got shape {shape:?}")));
    }
    Ok([v[0], v[1]])
}

/// Rows of three as a `(J, 3)` array (a copy).
pub fn rows<'py>(py: Python<'py>, rows: &[[f64; 3]]) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let flat: Vec<f64> = rows.iter().flatten().copied().collect();
    PyArray1::from_vec(py, flat).reshape(vec![rows.len(), 3])
}
