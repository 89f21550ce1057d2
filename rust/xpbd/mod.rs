//! Extended position-based dynamics (XPBD): constraints projected on positions
//! with compliance, Lagrange multipliers per substep, velocities corrected from
//! the projection. Rigid-body joints ([`joints`]) and particles with their
//! constraints, collisions, builders and shape matching.
//!
//! A scene holds an [`XpbdModel`] (what was added, validated); a world compiles
//! it into an [`Xpbd`] whose stages run each substep after the rigid bodies'
//! drift and before the contact relax pass: `xpbd` (predict), `shape_matching`
//! (when there are clusters), `xpbd` (project constraints and collisions, update
//! velocities). See [`solver`] for the order inside a substep.

pub mod attachment;
pub mod bending;
pub mod body_point;
pub mod builders;
pub mod collision;
pub mod compliance;
pub mod distance;
pub mod joints;
pub mod model;
pub mod particles;
pub mod shape_matching;
pub mod solver;
pub mod spatial_hash;
pub mod substeps;
pub mod volume;

pub use compliance::Compliance;
pub use model::{ConstraintKind, XpbdModel};
pub use particles::{ParticleSpec, Particles};
pub use solver::Xpbd;
