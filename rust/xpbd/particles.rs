//! Particle state as a struct of arrays, one `Vec` per field. A world allocates
//! these once; they never reallocate, so NumPy views of them stay valid.
//!
//! A pinned particle has inverse mass 0: constraints and collisions never move it
//! (its position may still be written by the user between steps).

use crate::collide::Filter;
use crate::error::{finite3, non_negative, positive, Error, Result};

/// What `Scene::add_particle` takes, each field with its unit and default.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct ParticleSpec {
    /// Position, world (m). No default.
    pub position: [f64; 3],
    /// Velocity, world (m/s). Default 0.
    pub velocity: [f64; 3],
    /// Mass (kg), > 0. Default 1. A pinned particle keeps its mass for shape
    /// matching and diagnostics but is never moved.
    pub mass: f64,
    /// Collision radius (m), ≥ 0. Default 0: a point, which still collides with
    /// rigid colliders but not with other particles.
    pub radius: f64,
    /// Friction coefficient (–), ≥ 0, static and dynamic, against rigid
    /// colliders and other particles; combined with the other side's by the
    /// geometric mean, as between bodies. Default 0.5.
    pub friction: f64,
    /// Pinned: inverse mass 0, never moved by the simulation. Default false.
    pub fixed: bool,
    /// Collision filter against rigid colliders and other particles, as between
    /// bodies. Default: group 1, collides with all.
    pub filter: Filter,
}

impl ParticleSpec {
    pub fn at(position: [f64; 3]) -> Self {
        Self { position, velocity: [0.0; 3], mass: 1.0, radius: 0.0, friction: 0.5, fixed: false, filter: Filter::default() }
    }

    pub fn validate(&self) -> Result<()> {
        finite3("position", self.position)?;
        finite3("velocity", self.velocity)?;
        positive("mass", self.mass)?;
        // 1/mass must be finite and positive as well (a subnormal mass overflows).
        if !(1.0 / self.mass).is_finite() {
            return Err(Error::input(format!("mass {} is too small: 1/mass overflows", self.mass)));
        }
        non_negative("radius", self.radius)?;
        non_negative("friction", self.friction)?;
        Ok(())
    }
}

/// Per-particle arrays. Index `i` of every field is particle `i`.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Particles {
    /// Position, world (m). Writable through `world.particles.position`.
    pub position: Vec<[f64; 3]>,
    /// Velocity, world (m/s). Writable through `world.particles.velocity`.
    pub velocity: Vec<[f64; 3]>,
    /// 1 / mass (1/kg); 0 for pinned particles.
    pub inv_mass: Vec<f64>,
    /// Mass (kg), also of pinned particles.
    pub mass: Vec<f64>,
    /// Collision radius (m).
    pub radius: Vec<f64>,
    /// Friction coefficient against rigid colliders and other particles (–).
    pub friction: Vec<f64>,
    /// Collision filter.
    pub filter: Vec<Filter>,
    /// Position at the start of the current substep (m): `v = (x − prev) / h`.
    pub prev: Vec<[f64; 3]>,
    /// Position when added to the scene (m): particles that overlap there never
    /// collide with each other (neighbours in a cloth or a soft body).
    pub initial: Vec<[f64; 3]>,
}

impl Particles {
    pub fn len(&self) -> usize {
        self.position.len()
    }

    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    /// Appends a validated particle.
    pub fn push(&mut self, s: &ParticleSpec) {
        self.position.push(s.position);
        self.velocity.push(if s.fixed { [0.0; 3] } else { s.velocity });
        self.inv_mass.push(if s.fixed { 0.0 } else { 1.0 / s.mass });
        self.mass.push(s.mass);
        self.radius.push(s.radius);
        self.friction.push(s.friction);
        self.filter.push(s.filter);
        self.prev.push(s.position);
        self.initial.push(s.position);
    }

    /// Drops the particles from index `n` on.
    pub fn truncate(&mut self, n: usize) {
        self.position.truncate(n);
        self.velocity.truncate(n);
        self.inv_mass.truncate(n);
        self.mass.truncate(n);
        self.radius.truncate(n);
        self.friction.truncate(n);
        self.filter.truncate(n);
        self.prev.truncate(n);
        self.initial.truncate(n);
    }

    /// Checks the state written through views before a step, naming the particle.
    pub fn check(&self) -> Result<()> {
        for i in 0..self.len() {
            for (field, v) in [("position", &self.position[i]), ("velocity", &self.velocity[i])] {
                if !v.iter().all(|x| x.is_finite()) {
                    return Err(Error::state(format!("particle {i}: {field} is not finite: {v:?}")));
                }
            }
        }
        Ok(())
    }
}
