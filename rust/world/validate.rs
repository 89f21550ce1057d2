//! The check at the start of every `step` call: state written through views must
//! still be a valid state, or the step is refused before anything moves.

use crate::body::{BodyKind, Bodies};
use crate::error::{Error, Result};

/// How far from unit length a written quaternion may be before it is an error
/// rather than round-off to be normalised away.
pub const UNIT_TOL: f64 = 1e-6;

fn finite3(b: usize, field: &str, v: &[f64; 3]) -> Result<()> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(Error::state(format!("body {b}: {field} is not finite: {v:?}")))
    }
}

/// Checks every body without changing anything.
pub fn check(bodies: &Bodies) -> Result<()> {
    if all_valid(bodies) {
        return Ok(());
    }
    (0..bodies.len()).try_for_each(|i| check_body(bodies, i))
}

/// Whether [`check_body`] passes every body: one branch-free pass (the
/// body-by-body check, with its early returns, was 5 % of a step of 2000
/// free boxes), which names no body; the slow check then finds it.
fn all_valid(bodies: &Bodies) -> bool {
    let b = bodies;
    let unit = b.orientation.iter().fold(true, |ok, q| ok & unit(norm2(q)));
    unit && finite3s(&[&b.position, &b.linear_velocity, &b.angular_velocity, &b.force, &b.torque])
}

/// Whether every number of the arrays is finite.
pub fn finite3s(arrays: &[&[[f64; 3]]]) -> bool {
    arrays.iter().all(|a| finite(a.as_flattened()))
}

/// Whether every number of `v` is finite: sums of `x · 0`, which is 0 for a
/// finite x and NaN for NaN or infinity (a sum of the values themselves could
/// overflow while each is finite), in eight independent lanes (one running
/// sum waited on its previous addition at every number: 2 % of a step of
/// 2000 free boxes).
pub fn finite(v: &[f64]) -> bool {
    let mut lanes = [0.0f64; 8];
    let chunks = v.chunks_exact(8);
    let rest = chunks.remainder().iter().map(|x| x * 0.0).sum::<f64>();
    for c in chunks {
        for (l, x) in lanes.iter_mut().zip(c) {
            *l += x * 0.0;
        }
    }
    lanes.iter().sum::<f64>() + rest == 0.0
}

/// `|q|²` of a written quaternion: the one sum both checks judge (the fast
/// pass must pass exactly what the body-by-body one does).
fn norm2(q: &[f64; 4]) -> f64 {
    q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]
}

/// Whether `|q|²` is unit within what round-off explains (NaN is not).
fn unit(n2: f64) -> bool {
    (n2 - 1.0).abs() <= 2.0 * UNIT_TOL
}

/// Checks body `i` (an index below `bodies.len()`).
pub fn check_body(bodies: &Bodies, i: usize) -> Result<()> {
    finite3(i, "position", &bodies.position[i])?;
    finite3(i, "linear_velocity", &bodies.linear_velocity[i])?;
    finite3(i, "angular_velocity", &bodies.angular_velocity[i])?;
    finite3(i, "force", &bodies.force[i])?;
    finite3(i, "torque", &bodies.torque[i])?;
    let q = bodies.orientation[i];
    let n2 = norm2(&q);
    if !unit(n2) {
        return Err(Error::state(format!(
            "body {i}: orientation {q:?} is not a unit quaternion (norm {}); write a normalised (x, y, z, w)",
            n2.sqrt()
        )));
    }
    Ok(())
}

/// After a successful [`check`]: removes round-off from the quaternions and the
/// velocities of fixed bodies (which never move).
pub fn normalize(bodies: &mut Bodies) {
    for i in 0..bodies.len() {
        let q = &mut bodies.orientation[i];
        let n2 = norm2(q);
        // Steps keep quaternions unit to a few ulp; only a written one needs this.
        if (n2 - 1.0).abs() > 8.0 * f64::EPSILON {
            let n = n2.sqrt();
            q.iter_mut().for_each(|x| *x /= n);
        }
        if bodies.kind[i] == BodyKind::Fixed {
            bodies.linear_velocity[i] = [0.0; 3];
            bodies.angular_velocity[i] = [0.0; 3];
        }
    }
}

/// Whether every position, velocity and orientation is finite.
pub fn all_finite(bodies: &Bodies) -> bool {
    let b = bodies;
    finite3s(&[&b.position, &b.linear_velocity, &b.angular_velocity]) && finite(b.orientation.as_flattened())
}
