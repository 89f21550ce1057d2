//! Semi-implicit (symplectic) Euler in joint coordinates, first order: the
//! velocities take the whole kick, then the coordinates drift with the new
//! velocities (MuJoCo's `Euler`). One solve per substep; controls implicit
//! over the kick as in the leapfrog. Kept for comparison and as the cheapest
//! option: for a pendulum it is symplectic (period error (ωh)²/24, amplitude
//! kept), but it is only first order for chains.

use super::dynamics::{accelerations, record, Env, Kick, Scratch};
use super::leapfrog::Buffers;
use super::model::Articulation;
use super::{joint, limits};

pub fn substep(art: &mut Articulation, env: &Env<'_>, h: f64, s: &mut Scratch, b: &mut Buffers, applied: &mut [f64]) {
    let (mut q, mut v) = (std::mem::take(&mut art.q), std::mem::take(&mut art.v));
    let nv = v.len();
    b.qdd.resize(nv, 0.0);
    let kick = Kick { tau: h, h, weight: 1.0 };
    accelerations(art, env, &q, &v, &v, Some(kick), s, &mut b.qdd);
    record(s, &b.qdd, h, applied);
    for i in 0..nv {
        v[i] += h * b.qdd[i];
    }
    let mut rows = limits::active_rows(art, &q, &v, h);
    if !rows.is_empty() {
        limits::solve(art, &mut rows, &mut v, applied);
    }
    for l in &art.links {
        let (qa, va) = (l.q_at, l.v_at);
        joint::drift(l.model, &mut q[qa..qa + l.model.nq()], &v[va..va + l.model.nv()], h);
    }
    art.q = q;
    art.v = v;
}
