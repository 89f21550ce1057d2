//! rigidrs: rigid bodies and position-based bodies, integrated with methods whose
//! accuracy is measured against exact references.
//!
//! A [`world::Scene`] describes what is simulated; [`world::Scene::build`] validates
//! it and compiles a [`world::World`]: struct-of-arrays state plus the pipeline of
//! stages that this scene needs, and nothing else.

#[macro_use]
mod clone_in_place;

pub mod articulation;
pub mod body;
pub mod collide;
pub mod error;
pub mod integrate;
pub mod math;
pub mod solve;
pub mod world;
pub mod xpbd;

#[cfg(feature = "python")]
mod py;

pub use error::{Error, ErrorKind, Result};
