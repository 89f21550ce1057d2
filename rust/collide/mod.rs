//! Collision detection: colliders, the broad phase (sweep and prune in columns), the narrow
//! phase (parry's persistent contact manifolds) and continuous collision detection.

mod approach;
pub mod broad_phase;
pub mod ccd;
mod coincident_points;
pub mod cylinder_cap;
pub mod collider;
pub mod corners;
mod face_clip;
pub mod fat_pairs;
mod internal_edges;
pub mod face_points;
pub mod manifolds;
pub mod material;
pub mod mesh_side;
pub mod narrow_phase;
mod passing;
pub mod sweep_and_prune;
pub mod plane_hull;
mod touching_axial;
mod touching_polyhedra;

pub use collider::{Collider, Filter};
pub use material::Material;
