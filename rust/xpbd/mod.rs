//! Extended position-based dynamics (XPBD): constraints projected on positions
//! with compliance, Lagrange multipliers per substep, velocities corrected from
//! the projection.

pub mod joints;
