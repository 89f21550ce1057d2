//! Energy and momentum of a world, over its dynamic bodies and movable particles.

use super::World;
use crate::body::BodyKind;
use crate::math::Vec3;

impl World {
    fn dynamic(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.bodies.len()).filter(|&i| self.bodies.kind[i] == BodyKind::Dynamic)
    }

    /// Translational plus rotational kinetic energy (J).
    pub fn kinetic_energy(&self) -> f64 {
        let b = &self.bodies;
        self.dynamic()
            .map(|i| {
                let v = Vec3::from(b.linear_velocity[i]);
                let w = Vec3::from(b.angular_velocity[i]);
                0.5 * b.mass[i] * v.norm_squared() + 0.5 * w.dot(&b.spin_momentum(i))
            })
            .sum::<f64>()
            + self.particle_sums().kinetic
    }

    /// Gravitational potential energy `−Σ m g·p` (J), zero at the origin.
    pub fn potential_energy(&self) -> f64 {
        let g = self.gravity;
        self.dynamic().map(|i| -self.bodies.mass[i] * g.dot(&Vec3::from(self.bodies.position[i]))).sum::<f64>()
            + self.particle_sums().potential
    }

    /// Total linear momentum `Σ m v` (kg·m/s).
    pub fn linear_momentum(&self) -> Vec3 {
        self.dynamic().map(|i| self.bodies.mass[i] * Vec3::from(self.bodies.linear_velocity[i])).sum::<Vec3>()
            + self.particle_sums().linear
    }

    /// Total angular momentum about the world origin, `Σ p × m v + I ω` (kg·m²/s).
    pub fn angular_momentum(&self) -> Vec3 {
        let b = &self.bodies;
        self.dynamic()
            .map(|i| {
                let p = Vec3::from(b.position[i]);
                p.cross(&(b.mass[i] * Vec3::from(b.linear_velocity[i]))) + b.spin_momentum(i)
            })
            .sum::<Vec3>()
            + self.particle_sums().angular
    }
}
