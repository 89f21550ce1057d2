//! Featherstone's articulated-body algorithm, O(n) in the links, in world
//! coordinates (see [`super::spatial`]). [`forward`](super::kinematics::forward)
//! is its first pass; [`accelerations`] runs the other two: articulated inertias
//! and bias forces from the leaves to the root, then accelerations from the root
//! to the leaves. Gravity enters as an acceleration −g of the base, so the link
//! accelerations it leaves are offset by −g and the reactions include weight.
//!
//! `extra` adds to each joint's `D = Sᵀ I^A S` diagonal: armature, and the
//! implicit part of drives, damping and friction over a kick (see
//! [`super::control`]): a term `A` there makes the solve `(M + A) q̈ = τ − C`.
//! [`response`] reuses the factorization for joint-space impulses: `Δv = (M + A)⁻¹ J`.

use super::model::{Articulation, Parent};
use super::spatial::{join, Mat6, Vec6};
use crate::math::Vec3;

/// `D⁻¹` of an `n × n` symmetric positive definite block (top-left of `d`).
fn invert(d: &Mat6, n: usize) -> Mat6 {
    let mut out = Mat6::zeros();
    match n {
        0 => {}
        1 => out[(0, 0)] = 1.0 / d[(0, 0)],
        3 => {
            let m = d.fixed_view::<3, 3>(0, 0).into_owned();
            let inv = m.try_inverse().unwrap_or_else(nalgebra::Matrix3::zeros);
            out.fixed_view_mut::<3, 3>(0, 0).copy_from(&inv);
        }
        _ => out = d.try_inverse().unwrap_or_else(Mat6::zeros),
    }
    out
}

/// Passes 2 and 3: `qdd` for joint forces `tau` and the diagonal additions
/// `extra` (both per dof). Needs pass 1 at the current state. Also leaves each
/// link's spatial acceleration and the reaction its joint transmits.
pub fn accelerations(art: &mut Articulation, tau: &[f64], extra: &[f64], gravity: &Vec3, qdd: &mut [f64]) {
    for w in art.work.iter_mut() {
        w.ia = w.inertia;
        w.pa = w.bias;
    }
    for k in (0..art.links.len()).rev() {
        let (n, at, parent) = (art.links[k].model.nv(), art.links[k].v_at, art.links[k].parent);
        let w = &mut art.work[k];
        let mut d = Mat6::zeros();
        for j in 0..n {
            w.u_mat[j] = w.ia * w.s[j];
        }
        for i in 0..n {
            for j in 0..n {
                d[(i, j)] = w.s[i].dot(&w.u_mat[j]);
            }
            d[(i, i)] += extra[at + i];
            w.u[i] = tau[at + i] - w.s[i].dot(&w.pa);
        }
        w.d_inv = invert(&d, n);
        let Parent::Link(p) = parent else { continue };
        let mut ia = w.ia;
        let mut pa = w.pa;
        for i in 0..n {
            for j in 0..n {
                let dij = w.d_inv[(i, j)];
                if dij != 0.0 {
                    ia -= (w.u_mat[i] * dij) * w.u_mat[j].transpose();
                    pa += w.u_mat[i] * (dij * w.u[j]);
                }
            }
        }
        pa += ia * w.c;
        let pw = &mut art.work[p];
        pw.ia += ia;
        pw.pa += pa;
    }
    let base = join(&Vec3::zeros(), &(-gravity));
    for k in 0..art.links.len() {
        let (n, at) = (art.links[k].model.nv(), art.links[k].v_at);
        let a_parent = match art.links[k].parent {
            Parent::Link(p) => art.work[p].acc,
            _ => base,
        };
        let w = &mut art.work[k];
        let a = a_parent + w.c;
        let mut rhs = [0.0; 6];
        for i in 0..n {
            rhs[i] = w.u[i] - w.u_mat[i].dot(&a);
        }
        let mut acc = a;
        for i in 0..n {
            let x: f64 = (0..n).map(|j| w.d_inv[(i, j)] * rhs[j]).sum();
            qdd[at + i] = x;
            acc += w.s[i] * x;
        }
        w.acc = acc;
        w.reaction = w.ia * acc + w.pa;
    }
}

/// `Δv = (M + A)⁻¹ j` for a joint-space impulse `j` (per dof), with the
/// factorization of the last [`accelerations`] (same `q`, same `extra`).
/// Overwrites the links' bias accumulators and accelerations.
pub fn response(art: &mut Articulation, j: &[f64], dv: &mut [f64]) {
    for w in art.work.iter_mut() {
        w.pa = Vec6::zeros();
    }
    for k in (0..art.links.len()).rev() {
        let (n, at, parent) = (art.links[k].model.nv(), art.links[k].v_at, art.links[k].parent);
        let w = &mut art.work[k];
        for i in 0..n {
            w.u[i] = j[at + i] - w.s[i].dot(&w.pa);
        }
        let Parent::Link(p) = parent else { continue };
        let mut pa = w.pa;
        for i in 0..n {
            for jj in 0..n {
                pa += w.u_mat[i] * (w.d_inv[(i, jj)] * w.u[jj]);
            }
        }
        art.work[p].pa += pa;
    }
    for k in 0..art.links.len() {
        let (n, at) = (art.links[k].model.nv(), art.links[k].v_at);
        let a = match art.links[k].parent {
            Parent::Link(p) => art.work[p].acc,
            _ => Vec6::zeros(),
        };
        let w = &mut art.work[k];
        let mut rhs = [0.0; 6];
        for i in 0..n {
            rhs[i] = w.u[i] - w.u_mat[i].dot(&a);
        }
        let mut acc = a;
        for i in 0..n {
            let x: f64 = (0..n).map(|jj| w.d_inv[(i, jj)] * rhs[jj]).sum();
            dv[at + i] = x;
            acc += w.s[i] * x;
        }
        w.acc = acc;
    }
}
