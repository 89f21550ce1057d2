//! Constraint solvers: the impulse-based contact solver (sequential impulses on
//! soft constraints with substeps and relaxation), restitution by impacts, Coulomb
//! friction on a true cone, islands and sleeping.

pub mod active_set;
pub mod block;
pub mod block_assembly;
pub mod contact;
pub mod contact_groups;
pub mod coplanar;
pub mod flush_pairs;
pub mod friction;
pub mod generalized;
pub mod impacts;
pub mod impulse;
pub mod island_sweeps;
pub mod islands;
pub mod ldlt;
pub mod limit_surface;
pub mod lists;
pub mod overshoot;
pub mod patch_polygon;
pub mod position;
pub mod prepare;
pub mod projected_gauss_seidel;
pub mod quiet;
pub mod support;
pub(crate) mod team;
pub mod soft;
pub mod solver_body;
pub mod pair;
pub mod refresh;
pub mod warm_start;
pub mod gather;
pub mod warm_guard;
pub mod release;
pub mod reuse;
mod rounded_curve;
pub mod seams;
pub mod second_pass;
pub mod rocking;
pub mod small_lcp;

pub use contact::{ContactSolver, SolverSettings};
