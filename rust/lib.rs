//! rigidrs: rigid bodies and position-based bodies, integrated with methods whose
//! accuracy is measured against exact references.
//!
//! A [`world::Scene`] describes what is simulated; [`world::Scene::build`] validates
//! it and compiles a [`world::World`]: struct-of-arrays state plus the pipeline of
//! stages that this scene needs, and nothing else.

// `!(x > 0.0)` is how this crate says "not a positive number, NaN included":
// a bad input or a diverged state must fail such checks, which `x <= 0.0`
// would let through.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// The numeric kernels index several arrays in step (`v[i] += h * a[i]`): one
// index reads as the formula does, where zipped iterators would not.
#![allow(clippy::needless_range_loop)]

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
