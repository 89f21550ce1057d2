//! The force stage: a velocity kick by gravity, the applied force and the applied
//! torque over a fraction of the step.

use crate::body::Bodies;
use crate::math::Vec3;

/// What the kick has to apply; decided per `step` call from the scene and the
/// applied-force arrays, so a scene without forces never runs this stage.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct KickSources {
    /// Gravitational acceleration (m/s²).
    pub gravity: Vec3,
    /// Whether any dynamic body has a non-zero applied force.
    pub force: bool,
    /// Whether any dynamic body has a non-zero applied torque.
    pub torque: bool,
}

impl KickSources {
    pub fn any(&self) -> bool {
        self.force || self.torque || self.gravity != Vec3::zeros()
    }

    /// The linear acceleration (m/s²) the kick gives dynamic body `i`: `g + F/m`.
    #[inline(always)]
    pub fn acceleration(&self, b: &Bodies, i: usize) -> Vec3 {
        if self.force {
            self.gravity + Vec3::from(b.force[i]) * b.inv_mass[i]
        } else {
            self.gravity
        }
    }
}

/// `v += h (g + F/m)`, `ω += h I⁻¹ τ` (world inertia) for the bodies in `list`.
pub fn kick(b: &mut Bodies, list: &[u32], h: f64, src: &KickSources) {
    for &i in list {
        let i = i as usize;
        let a = src.acceleration(b, i);
        b.linear_velocity[i] = (Vec3::from(b.linear_velocity[i]) + h * a).into();
    }
    if src.torque {
        for &i in list {
            let i = i as usize;
            let tau = Vec3::from(b.torque[i]);
            if tau != Vec3::zeros() {
                let dw = b.inv_inertia_world_mul(i, &tau) * h;
                b.angular_velocity[i] = (Vec3::from(b.angular_velocity[i]) + dw).into();
            }
        }
    }
}
