//! A point of a rigid body in XPBD (Müller et al. 2020, "Detailed rigid body
//! simulation with extended position based dynamics"): its generalized inverse
//! mass along a direction, and the positional impulse that moves the body.
//!
//! A positional impulse `p` (N·s², i.e. kg·m) at world offset `r` from the centre
//! of mass moves the body by `Δx = p / m` and turns it by `Δθ = I⁻¹ (r × p)`
//! (`q ← q + ½ [Δθ, 0] q`, renormalised). Its velocities change by `Δx / h` and
//! `Δθ / h`, as `v = (x − x_prev) / h` would give: the body feels the pull.
//! Fixed, kinematic and sleeping bodies are immovable here (inverse mass 0).

use crate::body::Bodies;
use crate::math::{quat, Quat, Vec3};

/// World offset of the body-frame point `local` (m) from the centre of mass,
/// and the world point itself.
#[inline]
pub fn world_point(b: &Bodies, body: usize, local: &Vec3) -> (Vec3, Vec3) {
    let r = quat::rotate(&b.q(body), local);
    (r, Vec3::from(b.position[body]) + r)
}

/// Generalized inverse mass `1/m + (r × n)ᵀ I⁻¹ (r × n)` of the body point at
/// world offset `r` along the unit direction `n` (1/kg); 0 for a body that does
/// not move under impulses.
#[inline]
pub fn inverse_mass(b: &Bodies, body: usize, r: &Vec3, n: &Vec3) -> f64 {
    if !b.awake(body) {
        return 0.0;
    }
    let rn = r.cross(n);
    b.inv_mass[body] + rn.dot(&b.inv_inertia_world_mul(body, &rn))
}

/// Applies the positional impulse `p` (kg·m, world) at world offset `r` over a
/// substep of `h` seconds; does nothing to a body that does not move under
/// impulses.
#[inline]
pub fn apply(b: &mut Bodies, body: usize, r: &Vec3, p: &Vec3, h: f64) {
    if !b.awake(body) {
        return;
    }
    let dx = p * b.inv_mass[body];
    let dtheta = b.inv_inertia_world_mul(body, &r.cross(p));
    b.position[body] = (Vec3::from(b.position[body]) + dx).into();
    b.linear_velocity[body] = (Vec3::from(b.linear_velocity[body]) + dx / h).into();
    b.angular_velocity[body] = (Vec3::from(b.angular_velocity[body]) + dtheta / h).into();
    let q = b.q(body);
    let dq = Quat::new(0.0, dtheta.x, dtheta.y, dtheta.z) * q * 0.5;
    b.orientation[body] = quat::to_xyzw(&quat::normalize(&(q + dq)));
}

/// Velocity of the body point at world offset `r` (m/s); 0 for a fixed body.
#[inline]
pub fn point_velocity(b: &Bodies, body: usize, r: &Vec3) -> Vec3 {
    Vec3::from(b.linear_velocity[body]) + Vec3::from(b.angular_velocity[body]).cross(r)
}
