//! Small geometric helpers: quaternions in the (x, y, z, w) storage order of the
//! state arrays, the SO(3) maps (hat, exp, log), and the polar decomposition.

pub mod polar;
pub mod quat;
pub mod so3;

pub type Vec3 = nalgebra::Vector3<f64>;
pub type Mat3 = nalgebra::Matrix3<f64>;
pub type Quat = nalgebra::Quaternion<f64>;
