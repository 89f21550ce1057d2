//! One evaluation of the articulation's accelerations `q̈(q, v)` with its joint
//! controls linearized over a kick (see [`super::control`]): the first pass of
//! the recursions, the controls' terms, then the articulated-body solve, once
//! more if a force limit was reached.

use super::control::{self, Term};
use super::model::Articulation;
use super::{aba, kinematics};
use crate::body::Bodies;
use crate::math::Vec3;

/// What an evaluation reads from the world.
pub struct Env<'a> {
    pub bodies: &'a Bodies,
    pub gravity: Vec3,
    /// Whether some link has an applied force or torque.
    pub external: bool,
}

/// Reusable buffers.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Scratch {
    pub tau: Vec<f64>,
    pub extra: Vec<f64>,
    pub terms: Vec<Term>,
}

/// How the controls enter a solve: over a kick of length `tau` followed by a
/// drift `h` (both 0: explicitly), their right-hand side times `weight` (the
/// control kick over the solve's own kick); `None`: no controls at all.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct Kick {
    pub tau: f64,
    pub h: f64,
    pub weight: f64,
}

impl Kick {
    pub const EXPLICIT: Option<Kick> = Some(Kick { tau: 0.0, h: 0.0, weight: 1.0 });
}

/// `q̈` at `(q, v)`, the controls taken at `(q, v_ctrl)` (the velocity the kick
/// starts from). Adds the controls' generalized forces to `applied` if given.
#[allow(clippy::too_many_arguments)]
pub fn accelerations(
    art: &mut Articulation,
    env: &Env<'_>,
    q: &[f64],
    v: &[f64],
    v_ctrl: &[f64],
    kick: Option<Kick>,
    s: &mut Scratch,
    qdd: &mut [f64],
) {
    kinematics::forward(art, q, v, env.bodies, env.external);
    s.terms.clear();
    if let Some(kick) = kick {
        for l in art.links.iter().filter(|l| !l.control.is_passive()) {
            let (qs, n) = (&q[l.q_at..l.q_at + l.model.nq()], l.model.nv());
            control::terms(&l.control, qs, &v_ctrl[l.v_at..l.v_at + n], l.v_at, kick.tau, kick.h, &mut s.terms);
        }
        for t in s.terms.iter_mut() {
            t.weight = kick.weight;
        }
    }
    solve(art, env, s, qdd);
    if control::saturate(&mut s.terms, qdd) {
        solve(art, env, s, qdd);
    }
}

fn solve(art: &mut Articulation, env: &Env<'_>, s: &mut Scratch, qdd: &mut [f64]) {
    s.tau.clear();
    s.tau.resize(art.nv, 0.0);
    s.extra.clear();
    s.extra.resize(art.nv, 0.0);
    for l in &art.links {
        for i in 0..l.model.nv() {
            s.extra[l.v_at + i] = l.control.armature;
        }
    }
    control::apply(&s.terms, &mut s.tau, &mut s.extra);
    aba::accelerations(art, &s.tau, &s.extra, &env.gravity, qdd);
}

/// Adds `weight ×` the controls' forces of the last evaluation to `applied`.
pub fn record(s: &Scratch, qdd: &[f64], weight: f64, applied: &mut [f64]) {
    for t in &s.terms {
        let f = t.force(qdd);
        for i in 0..t.n {
            applied[t.at + i] += weight * f[i];
        }
    }
}
