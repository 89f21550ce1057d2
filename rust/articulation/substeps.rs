//! How many substeps a step of an articulation takes when the user leaves it to
//! the engine: enough that `h ω ≤ κ` for the fastest rate the state shows.
//!
//! Explicit kicks are stable only while `h ω < 2` for every mode, and a chain's
//! fastest modes are not its pendulum swing: two neighbouring links turning
//! against each other under the tension `F` their joint carries oscillate at
//! `ω² = F r / J` (`r` the lever from the joint to the link's centre of mass, `J`
//! the link's own inertia about the joint), which for a hanging chain of N links
//! grows like N² g / L; a whipping chain adds its joint rates `|q̇|` (the
//! velocity-product forces scale with them). The estimate takes, over the links,
//! `ω = |q̇| + sqrt(F r / J)` (plus `sqrt(k / J)` for a drive when the
//! integrator treats drives explicitly) from the state and the reactions of the
//! last solve, and the substep count `⌈dt ω / κ⌉`, capped at [`MAX_SUBSTEPS`].
//! A single pendulum gets one substep: its `ω` is its own swing frequency.

use super::joint::JointModel;
use super::model::Articulation;
use super::spatial::lin;
use crate::math::Vec3;

/// The most substeps one step of one articulation takes.
pub const MAX_SUBSTEPS: u32 = 4096;

/// The fastest rate (rad/s) of the articulation's state.
pub fn fastest_rate(art: &Articulation, drives: bool) -> f64 {
    let mut worst = 0.0f64;
    for (l, w) in art.links.iter().zip(&art.work) {
        let v = &art.v[l.v_at..l.v_at + l.model.nv()];
        let rate = match l.model {
            JointModel::Revolute => v[0].abs(),
            JointModel::Spherical => Vec3::new(v[0], v[1], v[2]).norm(),
            JointModel::Free => Vec3::new(v[0], v[1], v[2]).norm(),
            JointModel::Prismatic | JointModel::Fixed => 0.0,
        };
        let r = l.frames.anchor_child.norm();
        let small = l.inertia.iter().fold(f64::INFINITY, |m, &x| m.min(x));
        let j = l.mass * r * r + small + l.control.armature;
        let mut stiff = 0.0;
        if l.model != JointModel::Free && j > 0.0 {
            stiff = lin(&w.reaction).norm() * r / j;
            if l.model == JointModel::Prismatic {
                stiff = 0.0;
            }
            if drives {
                if let Some(d) = &l.control.drive {
                    stiff += d.stiffness / j;
                }
            }
        }
        worst = worst.max(rate + stiff.sqrt());
    }
    worst
}

/// Substeps for a step `dt` at the rate `omega` with `h ω ≤ kappa`.
pub fn count(dt: f64, omega: f64, kappa: f64) -> u32 {
    let n = (dt * omega / kappa).ceil();
    if n.is_finite() && n >= 1.0 {
        (n as u32).min(MAX_SUBSTEPS)
    } else if n.is_nan() {
        MAX_SUBSTEPS
    } else {
        1
    }
}
