//! Joint models in reduced coordinates: what a joint's coordinates `q` (size
//! `nq`) and velocities `v` (size `nv`) are, the child's pose they give, the
//! joint's motion subspace `S` (world, spatial) and how `q` moves with `v`.
//!
//! | model | nq | nv | q | v |
//! |---|---|---|---|---|
//! | revolute | 1 | 1 | angle (rad) about the axis, right hand | rate (rad/s) |
//! | prismatic | 1 | 1 | slide (m) along the axis | rate (m/s) |
//! | spherical | 4 | 3 | relative rotation (x, y, z, w) since build, child frame | angular velocity relative to the parent, child frame (rad/s) |
//! | fixed | 0 | 0 | | |
//! | free (a floating root) | 7 | 6 | centre of mass (m), orientation (x, y, z, w) | angular velocity (rad/s), velocity of the centre of mass (m/s), world |
//!
//! A spherical joint's rotation lives on the unit quaternions: it moves by
//! `q ← q exp(h ω)`, exactly on the group, so it never leaves it.

use super::spatial::{join, rotation_about, translation_along, Vec6};
use crate::math::{quat, Mat3, Quat, Vec3};

#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum JointModel {
    Revolute,
    Prismatic,
    Spherical,
    Fixed,
    Free,
}

impl JointModel {
    pub fn nq(self) -> usize {
        match self {
            JointModel::Revolute | JointModel::Prismatic => 1,
            JointModel::Spherical => 4,
            JointModel::Fixed => 0,
            JointModel::Free => 7,
        }
    }

    pub fn nv(self) -> usize {
        match self {
            JointModel::Revolute | JointModel::Prismatic => 1,
            JointModel::Spherical => 3,
            JointModel::Fixed => 0,
            JointModel::Free => 6,
        }
    }
}

/// A pose: centre of mass (world, m) and principal-frame orientation.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct Pose {
    pub x: Vec3,
    pub q: Quat,
}

impl Pose {
    pub fn identity() -> Self {
        Self { x: Vec3::zeros(), q: Quat::identity() }
    }

    pub fn point(&self, local: &Vec3) -> Vec3 {
        self.x + quat::rotate(&self.q, local)
    }
}

/// Where a joint sits on its parent and its child, from the build poses.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct Frames {
    /// Anchor in the parent's frame (m; the world frame for the world).
    pub anchor_parent: Vec3,
    /// Anchor in the child's frame (m).
    pub anchor_child: Vec3,
    /// Unit axis in the parent's and in the child's frame.
    pub axis_parent: Vec3,
    pub axis_child: Vec3,
    /// Orientation of the child relative to the parent at build, `q_p⁻¹ q_c`.
    pub rest: Quat,
}

/// The child's pose for coordinates `q` of `model` under a parent at `parent`.
pub fn child_pose(model: JointModel, f: &Frames, parent: &Pose, q: &[f64]) -> Pose {
    let base = parent.q * f.rest;
    let orientation = match model {
        JointModel::Revolute => base * quat::exp(&(f.axis_child * q[0])),
        JointModel::Spherical => base * Quat::new(q[3], q[0], q[1], q[2]),
        JointModel::Prismatic | JointModel::Fixed => base,
        JointModel::Free => return Pose { x: Vec3::new(q[0], q[1], q[2]), q: Quat::new(q[6], q[3], q[4], q[5]) },
    };
    let mut anchor = parent.point(&f.anchor_parent);
    if model == JointModel::Prismatic {
        anchor += quat::rotate(&parent.q, &(f.axis_parent * q[0]));
    }
    Pose { x: anchor - quat::rotate(&orientation, &f.anchor_child), q: orientation }
}

/// The columns of the motion subspace (world), `nv` of them, for the child at
/// `child` under a parent at `parent`.
pub fn subspace(model: JointModel, f: &Frames, parent: &Pose, child: &Pose, out: &mut [Vec6; 6]) {
    match model {
        JointModel::Revolute => {
            let a = quat::rotate(&child.q, &f.axis_child);
            out[0] = rotation_about(&a, &child.point(&f.anchor_child));
        }
        JointModel::Prismatic => out[0] = translation_along(&quat::rotate(&parent.q, &f.axis_parent)),
        JointModel::Spherical => {
            let p = child.point(&f.anchor_child);
            let r = quat::to_matrix(&child.q);
            for k in 0..3 {
                out[k] = rotation_about(&r.column(k).into(), &p);
            }
        }
        JointModel::Fixed => {}
        JointModel::Free => {
            // v = (ω, v_c): the origin point moves at v_c + c × ω.
            for k in 0..3 {
                let mut e = Vec3::zeros();
                e[k] = 1.0;
                out[k] = join(&e, &child.x.cross(&e));
                out[k + 3] = translation_along(&e);
            }
        }
    }
}

/// The part of the child's spatial acceleration that `q̈ = 0` leaves: `Ṡ v`.
/// For joints whose subspace is fixed in the child (or, for a slide, in the
/// parent, which gives the same here) it is `v_child × S v`.
pub fn bias(model: JointModel, v_child: &Vec6, s_v: &Vec6, v: &[f64]) -> Vec6 {
    match model {
        JointModel::Free => {
            let (w, vc) = (Vec3::new(v[0], v[1], v[2]), Vec3::new(v[3], v[4], v[5]));
            join(&Vec3::zeros(), &vc.cross(&w))
        }
        JointModel::Fixed => Vec6::zeros(),
        _ => super::spatial::cross_motion(v_child, s_v),
    }
}

/// `q ← q ⊕ h v`: the coordinates moved by the velocity `v` held for `h`.
pub fn drift(model: JointModel, q: &mut [f64], v: &[f64], h: f64) {
    match model {
        JointModel::Revolute | JointModel::Prismatic => q[0] += h * v[0],
        JointModel::Spherical => {
            let r = Quat::new(q[3], q[0], q[1], q[2]) * quat::exp(&(Vec3::new(v[0], v[1], v[2]) * h));
            store_quat(&quat::normalize(&r), &mut q[0..4]);
        }
        JointModel::Fixed => {}
        JointModel::Free => {
            for k in 0..3 {
                q[k] += h * v[3 + k];
            }
            let r = quat::exp(&(Vec3::new(v[0], v[1], v[2]) * h)) * Quat::new(q[6], q[3], q[4], q[5]);
            store_quat(&quat::normalize(&r), &mut q[3..7]);
        }
    }
}

/// `q ⊕ δ` for a tangent vector `δ` (the chart around `q` that [`drift`] uses).
pub fn retract(model: JointModel, q0: &[f64], delta: &[f64], out: &mut [f64]) {
    out.copy_from_slice(q0);
    drift(model, out, delta, 1.0);
}

/// In the chart `q = q0 ⊕ δ`, the rate of `δ` for the velocity `v`: the inverse
/// differential of the exponential for rotations, the identity otherwise.
pub fn chart_rate(model: JointModel, delta: &[f64], v: &[f64], out: &mut [f64]) {
    match model {
        JointModel::Revolute | JointModel::Prismatic => out[0] = v[0],
        JointModel::Spherical => {
            // q = q0 exp(δ): ω_body = J_r(δ) δ̇, δ̇ = J_r⁻¹ ω.
            let r = dexp_inv(&(-Vec3::new(delta[0], delta[1], delta[2])), &Vec3::new(v[0], v[1], v[2]));
            out[..3].copy_from_slice(r.as_slice());
        }
        JointModel::Fixed => {}
        JointModel::Free => {
            // R = exp(δ) R0: ω_world = J_l(δ) δ̇.
            let r = dexp_inv(&Vec3::new(delta[0], delta[1], delta[2]), &Vec3::new(v[0], v[1], v[2]));
            out[..3].copy_from_slice(r.as_slice());
            out[3..6].copy_from_slice(&v[3..6]);
        }
    }
}

/// `J_l(θ)⁻¹ ω = ω − ½ θ × ω + (1/|θ|²)(1 − (|θ|/2) cot(|θ|/2)) θ × (θ × ω)`.
fn dexp_inv(theta: &Vec3, w: &Vec3) -> Vec3 {
    let a2 = theta.norm_squared();
    let c = if a2 < 1e-8 {
        1.0 / 12.0 + a2 / 720.0
    } else {
        let a = a2.sqrt();
        (1.0 - 0.5 * a / (0.5 * a).tan()) / a2
    };
    let tw = theta.cross(w);
    w - 0.5 * tw + c * theta.cross(&tw)
}

pub fn store_quat(q: &Quat, out: &mut [f64]) {
    out.copy_from_slice(&[q.i, q.j, q.k, q.w]);
}

/// The neutral coordinates (the build pose) of `model`.
pub fn neutral(model: JointModel, out: &mut [f64]) {
    out.fill(0.0);
    if model == JointModel::Spherical {
        out[3] = 1.0;
    }
}

/// The rotation matrix of a world quaternion.
pub fn matrix(q: &Quat) -> Mat3 {
    quat::to_matrix(q)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dexp_inv_undoes_the_differential_of_exp() {
        let theta = Vec3::new(0.4, -0.9, 1.3);
        let rate = Vec3::new(0.2, 0.5, -0.7);
        let eps = 1e-6;
        // ω_world from the finite difference of exp(θ + ε θ̇) exp(θ)⁻¹.
        let d = quat::exp(&(theta + eps * rate)) * quat::exp(&(theta - eps * rate)).conjugate();
        let w = Vec3::new(d.i, d.j, d.k) * (2.0 / (2.0 * eps)) * d.w.signum();
        assert!((dexp_inv(&theta, &w) - rate).norm() < 1e-8);
    }
}
