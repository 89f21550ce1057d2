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
    for i in 0..bodies.len() {
        finite3(i, "position", &bodies.position[i])?;
        finite3(i, "linear_velocity", &bodies.linear_velocity[i])?;
        finite3(i, "angular_velocity", &bodies.angular_velocity[i])?;
        finite3(i, "force", &bodies.force[i])?;
        finite3(i, "torque", &bodies.torque[i])?;
        let q = bodies.orientation[i];
        let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
        if !((n - 1.0).abs() <= UNIT_TOL) {
            return Err(Error::state(format!(
                "body {i}: orientation {q:?} is not a unit quaternion (norm {n}); write a normalised (x, y, z, w)"
            )));
        }
    }
    Ok(())
}

/// After a successful [`check`]: removes round-off from the quaternions and the
/// velocities of fixed bodies (which never move).
pub fn normalize(bodies: &mut Bodies) {
    for i in 0..bodies.len() {
        let q = &mut bodies.orientation[i];
        let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
        if n != 1.0 {
            q.iter_mut().for_each(|x| *x /= n);
        }
        if bodies.kind[i] == BodyKind::Fixed {
            bodies.linear_velocity[i] = [0.0; 3];
            bodies.angular_velocity[i] = [0.0; 3];
        }
    }
}
