//! The default integrator: a time-reversible leapfrog (kick, drift, kick) in
//! joint coordinates, second order.
//!
//! ```text
//! v½   = v + h/2 q̈(q, v½)            implicit in v½ (fixed point), + controls over h
//! limits: impulses on v½ so that the drift stays within every limit
//! q'   = q ⊕ h v½                     each joint on its own manifold
//! v'   = v½ + h/2 q̈(q', v½)           explicit
//! ```
//!
//! The first half kick is the adjoint of the last, so without controls the
//! step is symmetric: reversible, second order, and for a pendulum (no
//! velocity-dependent force) it is Störmer–Verlet, symplectic: the amplitude
//! does not decay and the period error is (ωh)²/24. The velocity-dependent
//! forces (Coriolis, centrifugal, gyroscopic) are what the fixed point iterates
//! on; it starts from the last step's end acceleration, so two passes reach the
//! method's own accuracy when `h` times the largest joint rate is small (the
//! substep rule sees to it, [`super::substeps`]).
//!
//! Drives, damping and friction act in the first kick over the whole substep,
//! implicitly with a look-ahead over the drift (backward Euler on the control
//! forces: a stiff drive settles, never rings; first order in its own `ω h`).
//! Statics are exact (a drive or friction holding a load is a fixed point of
//! the step), and the drift moves at the controlled velocity `v½`; the velocity
//! a step ends with lags the controls by half a substep: a velocity drive
//! holding a load turns at `target − load/damping` exactly, and reads back
//! `h/2 · load/J` less.

use super::dynamics::{accelerations, record, Env, Kick, Scratch};
use super::model::Articulation;
use super::{joint, limits};

/// Fixed-point passes of the implicit half kick at most, and the change (m/s
/// or rad/s, relative to the velocities' size) below which it stops.
const PASSES: usize = 2;
const TOLERANCE: f64 = 1e-13;

/// Work arrays that outlive a substep.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Buffers {
    pub qdd: Vec<f64>,
    pub vh: Vec<f64>,
    pub next: Vec<f64>,
    /// `q̈` at the end of the last substep and whether it is valid (it seeds
    /// the fixed point, and without velocity dependence it is the next kick's).
    pub last: Vec<f64>,
    pub last_valid: bool,
}

/// One substep of length `h`; controls' and limits' impulses are added to `applied`.
pub fn substep(art: &mut Articulation, env: &Env<'_>, h: f64, s: &mut Scratch, b: &mut Buffers, applied: &mut [f64]) {
    let (mut q, mut v) = (std::mem::take(&mut art.q), std::mem::take(&mut art.v));
    let nv = v.len();
    b.qdd.resize(nv, 0.0);
    b.vh.resize(nv, 0.0);
    b.next.resize(nv, 0.0);
    b.last.resize(nv, 0.0);
    let controls = art.links.iter().any(|l| !l.control.is_passive());
    let kick = Kick { tau: h, h, weight: 2.0 };
    if !b.last_valid {
        accelerations(art, env, &q, &v, &v, Some(kick), s, &mut b.last);
    }
    for i in 0..nv {
        b.vh[i] = v[i] + 0.5 * h * b.last[i];
    }
    let passes = if art.velocity_dependent || controls { PASSES } else { 1 };
    let scale = v.iter().fold(0.0f64, |m, x| m.max(x.abs())) + 1.0;
    for pass in 0..passes {
        let fresh = pass > 0 || controls || art.velocity_dependent || !b.last_valid;
        if fresh {
            accelerations(art, env, &q, &b.vh, &v, Some(kick), s, &mut b.qdd);
        } else {
            b.qdd.copy_from_slice(&b.last);
        }
        let mut change = 0.0f64;
        for i in 0..nv {
            b.next[i] = v[i] + 0.5 * h * b.qdd[i];
            change = change.max((b.next[i] - b.vh[i]).abs());
        }
        std::mem::swap(&mut b.vh, &mut b.next);
        if change <= TOLERANCE * scale {
            break;
        }
    }
    if controls {
        record(s, &b.qdd, h, applied);
    }
    let mut rows = limits::active_rows(art, &q, &b.vh, h);
    if !rows.is_empty() {
        if !controls && !art.velocity_dependent {
            // The factorization must be at q: the pass above may have reused `last`.
            accelerations(art, env, &q, &b.vh, &v, Some(kick), s, &mut b.qdd);
        }
        limits::solve(art, &mut rows, &mut b.vh, applied);
    }
    for l in &art.links {
        let (qa, va) = (l.q_at, l.v_at);
        joint::drift(l.model, &mut q[qa..qa + l.model.nq()], &b.vh[va..va + l.model.nv()], h);
    }
    accelerations(art, env, &q, &b.vh, &b.vh, None, s, &mut b.last);
    for i in 0..nv {
        v[i] = b.vh[i] + 0.5 * h * b.last[i];
    }
    b.last_valid = true;
    art.q = q;
    art.v = v;
}
