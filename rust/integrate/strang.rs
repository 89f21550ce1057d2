//! Strang splitting, the default integrator: `kick(h/2) drift(h) kick(h/2)` where
//! the drift moves bodies in a straight line and rotates them by the exact
//! torque-free flow of [`super::free_rotation`].
//!
//! Second order and symmetric; `|L|` is conserved exactly without torque, energy
//! stays bounded with no drift (the method is symplectic), and a projectile under
//! constant gravity follows its parabola exactly.

use super::{Rotation, Splitting};

pub fn splitting() -> Splitting {
    Splitting { gyroscopic: None, kicks: vec![0.5, 0.5], drifts: vec![1.0], rotation: Rotation::Free }
}
