//! The high-order option: classical Runge–Kutta, fourth order, on the joint
//! coordinates in the chart `q = q₀ ⊕ δ` around the substep's start (Munthe-Kaas:
//! rotations advance through the inverse differential of the exponential, so
//! spherical joints and a floating root keep fourth order and stay on their
//! groups). Controls are explicit here (the substep rule accounts for their
//! stiffness); limits are applied as impulses before the substep, so that its
//! first-order drift would stay within them.

use super::dynamics::{accelerations, record, Env, Kick, Scratch};
use super::model::Articulation;
use super::{joint, limits};

#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Buffers {
    k_delta: [Vec<f64>; 4],
    k_v: [Vec<f64>; 4],
    delta: Vec<f64>,
    vs: Vec<f64>,
    qs: Vec<f64>,
    rate: Vec<f64>,
}

/// `q₀ ⊕ δ` for every joint.
fn retract(art: &Articulation, q0: &[f64], delta: &[f64], out: &mut [f64]) {
    for l in &art.links {
        let (qa, va, nq, nv) = (l.q_at, l.v_at, l.model.nq(), l.model.nv());
        joint::retract(l.model, &q0[qa..qa + nq], &delta[va..va + nv], &mut out[qa..qa + nq]);
    }
}

fn chart_rate(art: &Articulation, delta: &[f64], v: &[f64], out: &mut [f64]) {
    for l in &art.links {
        let (va, nv) = (l.v_at, l.model.nv());
        joint::chart_rate(l.model, &delta[va..va + nv], &v[va..va + nv], &mut out[va..va + nv]);
    }
}

pub fn substep(art: &mut Articulation, env: &Env<'_>, h: f64, s: &mut Scratch, b: &mut Buffers, applied: &mut [f64]) {
    let (q0, mut v0) = (std::mem::take(&mut art.q), std::mem::take(&mut art.v));
    let (nq, nv) = (q0.len(), v0.len());
    for k in 0..4 {
        b.k_delta[k].resize(nv, 0.0);
        b.k_v[k].resize(nv, 0.0);
    }
    b.delta.resize(nv, 0.0);
    b.vs.resize(nv, 0.0);
    b.rate.resize(nv, 0.0);
    b.qs.resize(nq, 0.0);
    let passive = art.links.iter().all(|l| l.control.is_passive());
    let ctrl = if passive { None } else { Kick::EXPLICIT };
    accelerations(art, env, &q0, &v0, &v0, ctrl, s, &mut b.k_v[0]);
    let mut rows = limits::active_rows(art, &q0, &v0, h);
    if !rows.is_empty() {
        limits::solve(art, &mut rows, &mut v0, applied);
        accelerations(art, env, &q0, &v0, &v0, ctrl, s, &mut b.k_v[0]);
    }
    record(s, &b.k_v[0], h / 6.0, applied);
    b.k_delta[0].copy_from_slice(&v0);
    for (k, c) in [(1usize, 0.5), (2, 0.5), (3, 1.0)] {
        for i in 0..nv {
            b.delta[i] = c * h * b.k_delta[k - 1][i];
            b.vs[i] = v0[i] + c * h * b.k_v[k - 1][i];
        }
        retract(art, &q0, &b.delta, &mut b.qs);
        let (qs, vs) = (std::mem::take(&mut b.qs), std::mem::take(&mut b.vs));
        let mut kv = std::mem::take(&mut b.k_v[k]);
        accelerations(art, env, &qs, &vs, &vs, ctrl, s, &mut kv);
        record(s, &kv, h * if k == 3 { 1.0 } else { 2.0 } / 6.0, applied);
        chart_rate(art, &b.delta, &vs, &mut b.rate);
        b.k_delta[k].copy_from_slice(&b.rate);
        b.k_v[k] = kv;
        b.qs = qs;
        b.vs = vs;
    }
    let mut v = v0;
    for i in 0..nv {
        b.delta[i] = h / 6.0 * (b.k_delta[0][i] + 2.0 * b.k_delta[1][i] + 2.0 * b.k_delta[2][i] + b.k_delta[3][i]);
        v[i] += h / 6.0 * (b.k_v[0][i] + 2.0 * b.k_v[1][i] + 2.0 * b.k_v[2][i] + b.k_v[3][i]);
    }
    let mut q = vec![0.0; nq];
    retract(art, &q0, &b.delta, &mut q);
    art.q = q;
    art.v = v;
}
