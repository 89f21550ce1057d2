//! An articulation in contact: stepped inside the world's contact substeps, so
//! that its joints and its contacts see each other every substep.
//!
//! A step of an articulation whose links touch something (the narrow phase
//! found a contact for one of them) is not the whole-step integration of the
//! `articulation` stage: each contact substep `h` is a semi-implicit Euler step,
//! as for the bodies in contact (and as MuJoCo's `Euler` and PhysX's
//! articulations take with contacts):
//!
//! ```text
//! kick:   v* = v + h (M + A)⁻¹ (τ − C(q, v))     controls implicit over the kick (A: their diagonal)
//! solve:  v* += (M + A)⁻¹ Jᵀ λ                      contact impulses, in the contact solver
//! limits: impulses on v* so the drift stays within every limit
//! drift:  q' = q ⊕ h v*
//! relax:  v' = v* + (M + A)⁻¹ Jᵀ λ'                the contact relax pass, at q'
//! ```
//!
//! `J` is a contact row's Jacobian over the articulation's dofs ([`add_jacobian`],
//! the motion subspaces on the path from the link to the root) and `(M + A)⁻¹ Jᵀ`
//! the articulated-body algorithm's joint-space response ([`super::aba::response`],
//! O(links)), so a contact impulse moves the whole articulation as the joints
//! transmit it, and a stiff drive resists it as it resists gravity (implicitly).
//! The factorization the solver needs is left by the kick (at `q`) and by the
//! drift (at `q'`, for the relax pass). First order, like every body in contact,
//! and at the world's contact substeps; free of contacts the articulation keeps
//! its own integrator and substeps. (The leapfrog's kick–contacts–drift–kick was
//! tried: its last half kick leaves each link resting on the ground with `g h/2`
//! of fall, so a chain never comes to rest; the Euler step ends at rest.)

use super::dynamics::{accelerations, record, Env, Kick};
use super::model::{Articulation, Parent};
use super::spatial::Vec6;
use super::{joint, kinematics, limits, momentum, substeps, Articulations};
use crate::body::Bodies;
use crate::math::Vec3;

/// Fixed-point passes of the kick's velocity-dependent forces at the midpoint.
const MIDPOINT_PASSES: usize = 2;

/// The most substeps the articulations in contact raise a step to.
pub const MAX_CONTACT_SUBSTEPS: u32 = 256;

impl Articulations {
    /// Marks the articulations that step inside the contact substeps this step
    /// (`contact[a]`), clears their applied-force accumulators and forgets what
    /// their own integrator kept from its last step.
    pub fn set_contact(&mut self, contact: impl Fn(usize) -> bool) {
        self.contact.resize(self.list.len(), false);
        self.momentum_error.resize(self.list.len(), Vec3::zeros());
        for a in 0..self.list.len() {
            let on = contact(a);
            self.contact[a] = on;
            if on {
                let art = &mut self.list[a];
                art.applied.fill(0.0);
                art.cached_qdd = None;
                self.leap[a].last_valid = false;
            }
        }
    }

    /// Whether some articulation steps inside the contact substeps this step.
    pub fn any_contact(&self) -> bool {
        self.contact.iter().any(|&c| c)
    }

    /// Whether articulation `a` steps inside the contact substeps this step.
    pub fn in_contact(&self, a: usize) -> bool {
        self.contact.get(a).copied().unwrap_or(false)
    }

    /// The kick of a contact substep `h` (see the module docs); leaves each
    /// articulation's factorization at `q`, with the controls' diagonal, for the
    /// contact rows.
    pub fn contact_kick(&mut self, bodies: &Bodies, gravity: &Vec3, h: f64) {
        for a in 0..self.list.len() {
            if !self.in_contact(a) {
                continue;
            }
            let art = &mut self.list[a];
            let env = Env { bodies, gravity: *gravity, external: external(art, bodies) };
            let (q, mut v) = (std::mem::take(&mut art.q), std::mem::take(&mut art.v));
            let (b, s) = (&mut self.leap[a], &mut self.scratch);
            b.qdd.resize(v.len(), 0.0);
            b.vh.resize(v.len(), 0.0);
            let kick = Some(Kick { tau: h, h, weight: 1.0 });
            accelerations(art, &env, &q, &v, &v, kick, s, &mut b.qdd);
            let floating = momentum::floating(art);
            let p0 = if floating { momentum::linear_momentum(art, &v) } else { Vec3::zeros() };
            // The velocity-dependent forces at the midpoint velocity (fixed point).
            for _ in 0..if art.velocity_dependent { MIDPOINT_PASSES } else { 0 } {
                for ((m, x), a) in b.vh.iter_mut().zip(&v).zip(&b.qdd) {
                    *m = x + 0.5 * h * a;
                }
                accelerations(art, &env, &q, &b.vh, &v, kick, s, &mut b.qdd);
            }
            record(s, &b.qdd, h, &mut art.applied);
            for (x, a) in v.iter_mut().zip(&b.qdd) {
                *x += h * a;
            }
            if floating {
                // What the kick did to the momentum beyond the external impulse.
                let exact = momentum::external_impulse(art, bodies, gravity, h);
                self.momentum_error[a] = momentum::linear_momentum(art, &v) - p0 - exact;
            }
            art.q = q;
            art.v = v;
        }
    }

    /// Limits and drift of a contact substep `h`, then the factorization at the
    /// new pose, with the controls' diagonal (for the relax pass), and the links
    /// written to `bodies`.
    pub fn contact_drift(&mut self, bodies: &mut Bodies, gravity: &Vec3, h: f64) {
        for a in 0..self.list.len() {
            if !self.in_contact(a) {
                continue;
            }
            let art = &mut self.list[a];
            let (mut q, mut v) = (std::mem::take(&mut art.q), std::mem::take(&mut art.v));
            let mut rows = limits::active_rows(art, &q, &v, h);
            if !rows.is_empty() {
                // The factorization of the kick, at this q, is still current.
                let mut applied = std::mem::take(&mut art.applied);
                limits::solve(art, &mut rows, &mut v, &mut applied);
                art.applied = applied;
            }
            let floating = momentum::floating(art);
            // The contacts' and limits' impulses, at the kick's pose.
            let solved = if floating { momentum::linear_momentum(art, &v) } else { Vec3::zeros() };
            for l in &art.links {
                let (qa, va) = (l.q_at, l.v_at);
                joint::drift(l.model, &mut q[qa..qa + l.model.nq()], &v[va..va + l.model.nv()], h);
            }
            let env = Env { bodies, gravity: *gravity, external: external(art, bodies) };
            let kick = Some(Kick { tau: h, h, weight: 1.0 });
            accelerations(art, &env, &q, &v, &v, kick, &mut self.scratch, &mut self.leap[a].qdd);
            if floating {
                // The drift is free of forces: the momentum it ends with is the
                // solve's, less what the kick added beyond the external impulse.
                let drifted = momentum::linear_momentum(art, &v);
                momentum::restore(art, &mut v, &(solved - self.momentum_error[a]), &drifted);
                momentum::linear_momentum(art, &v);
            }
            art.q = q;
            art.v = v;
            kinematics::write_bodies(art, bodies);
        }
    }

    /// Substeps a step `dt` of the articulations in contact needs (at least
    /// `base`): each holds `h ω ≤ κ` for its fastest rate as in free flight
    /// (see [`super::substeps`]), or takes its fixed `articulation_substeps`.
    pub fn contact_substeps(&self, dt: f64, base: u32) -> u32 {
        let mut n = base;
        for (a, art) in self.list.iter().enumerate() {
            if !self.in_contact(a) {
                continue;
            }
            let need = match self.settings.substeps {
                Some(fixed) => fixed,
                None => substeps::count(dt, substeps::fastest_rate(art, false), self.settings.integrator.kappa()),
            };
            n = n.max(need.min(MAX_CONTACT_SUBSTEPS));
        }
        n
    }

    /// Writes the links' velocities (from `v`, at the current pose) of the
    /// articulations in contact into `bodies`.
    pub fn write_contact_velocities(&mut self, bodies: &mut Bodies) {
        for a in 0..self.list.len() {
            if self.in_contact(a) {
                let art = &mut self.list[a];
                link_velocities(art);
                kinematics::write_bodies(art, bodies);
            }
        }
    }

    /// Ends a step of `substeps` contact substeps of length `dt / substeps`: the
    /// applied forces averaged over the step.
    pub fn finish_contact(&mut self, dt: f64, substeps: u32) {
        for a in 0..self.list.len() {
            if self.in_contact(a) {
                let art = &mut self.list[a];
                art.applied.iter_mut().for_each(|x| *x /= dt);
                art.last_substeps = substeps;
            }
        }
    }
}

/// Whether some link of `art` has an applied force or torque.
fn external(art: &Articulation, bodies: &Bodies) -> bool {
    art.links.iter().any(|l| {
        let b = l.body as usize;
        bodies.force[b] != [0.0; 3] || bodies.torque[b] != [0.0; 3]
    })
}

/// Each link's spatial velocity from `v` and the motion subspaces of the last
/// pass 1 (root to leaves).
pub fn link_velocities(art: &mut Articulation) {
    for k in 0..art.links.len() {
        let l = &art.links[k];
        let mut vel = match l.parent {
            Parent::Link(p) => art.work[p].vel,
            _ => Vec6::zeros(),
        };
        for d in 0..l.model.nv() {
            vel += art.work[k].s[d] * art.v[l.v_at + d];
        }
        art.work[k].vel = vel;
    }
}

/// Adds `sign ×` the Jacobian row of a spatial force `f` (world, about the
/// origin) acting on link `k` to `out` (one entry per dof): `Sᵀ f` on every dof
/// of the path from `k` to the root, zero elsewhere. The row's velocity is
/// `out · v`, the work of `f` on link `k`'s motion; `outᵀ λ` is the generalized
/// impulse of `f λ`. Needs the subspaces of the last pass 1. O(depth).
pub fn add_jacobian(art: &Articulation, k: usize, f: &Vec6, sign: f64, out: &mut [f64]) {
    let mut link = Some(k);
    while let Some(i) = link {
        let l = &art.links[i];
        for d in 0..l.model.nv() {
            out[l.v_at + d] += sign * art.work[i].s[d].dot(f);
        }
        link = match l.parent {
            Parent::Link(p) => Some(p),
            _ => None,
        };
    }
}
