//! Rigid-body storage (struct of arrays), mass properties and shapes.

pub mod density;
pub mod mass;
pub mod shape;
pub mod storage;

pub use mass::{MassProps, Principal};
pub use shape::Shape;
pub use storage::{BodyKind, Bodies};
