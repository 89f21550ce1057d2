//! Forward kinematics, the first pass of every recursion: from `q` and `v`, each
//! link's pose, motion subspace, spatial velocity, velocity-product acceleration
//! and spatial inertia (root to leaves), and its bias force `v ×* I v − f_ext`.
//! [`write_bodies`] copies poses and velocities into the world's body rows.

use super::joint::{self, Pose};
use super::model::{Articulation, Parent};
use super::spatial::{self, cross_force, Vec6};
use crate::body::Bodies;
use crate::math::{quat, Vec3};

/// The pose of a link's parent (a fixed body's pose is read from `bodies`).
fn parent_pose(art: &Articulation, parent: Parent, bodies: &Bodies) -> (Pose, Vec6) {
    match parent {
        Parent::World => (Pose::identity(), Vec6::zeros()),
        Parent::Fixed(b) => {
            let b = b as usize;
            (Pose { x: Vec3::from(bodies.position[b]), q: bodies.q(b) }, Vec6::zeros())
        }
        Parent::Link(k) => (art.work[k].pose, art.work[k].vel),
    }
}

/// Pass 1 at coordinates `q`, velocities `v`. With `external`, the bodies'
/// applied forces and torques enter the bias forces.
pub fn forward(art: &mut Articulation, q: &[f64], v: &[f64], bodies: &Bodies, external: bool) {
    for k in 0..art.links.len() {
        let link = &art.links[k];
        let (model, nv) = (link.model, link.model.nv());
        let (pp, pv) = parent_pose(art, link.parent, bodies);
        let qk = &q[link.q_at..link.q_at + model.nq()];
        let vk = &v[link.v_at..link.v_at + nv];
        let pose = joint::child_pose(model, &link.frames, &pp, qk);
        let mut s = [Vec6::zeros(); 6];
        joint::subspace(model, &link.frames, &pp, &pose, &mut s);
        let mut s_v = Vec6::zeros();
        for (col, &x) in s.iter().zip(vk) {
            s_v += col * x;
        }
        let vel = pv + s_v;
        let c = joint::bias(model, &vel, &s_v, vk);
        let r = quat::to_matrix(&pose.q);
        let ic = r * nalgebra::Matrix3::from_diagonal(&Vec3::from(link.inertia)) * r.transpose();
        let inertia = spatial::inertia(link.mass, &pose.x, &ic);
        let mut pa = cross_force(&vel, &(inertia * vel));
        if external {
            let b = link.body as usize;
            let f = Vec3::from(bodies.force[b]);
            let t = Vec3::from(bodies.torque[b]);
            pa -= spatial::force_at(&f, &pose.x) + spatial::join(&t, &Vec3::zeros());
        }
        let w = &mut art.work[k];
        w.pose = pose;
        w.s = s;
        w.vel = vel;
        w.c = c;
        w.inertia = inertia;
        w.bias = pa;
    }
}

/// Poses only (no velocities, inertias or forces): for read-back and building.
pub fn poses(art: &mut Articulation, q: &[f64], bodies: &Bodies) {
    for k in 0..art.links.len() {
        let link = &art.links[k];
        let (pp, _) = parent_pose(art, link.parent, bodies);
        let qk = &q[link.q_at..link.q_at + link.model.nq()];
        art.work[k].pose = joint::child_pose(link.model, &link.frames, &pp, qk);
    }
}

/// Copies each link's pose (centre of mass, principal frame) and velocity
/// (centre of mass, angular; world) into its body row. Needs [`forward`] (or
/// [`poses`] and the velocities) at the current state.
pub fn write_bodies(art: &Articulation, bodies: &mut Bodies) {
    for (link, w) in art.links.iter().zip(&art.work) {
        let b = link.body as usize;
        bodies.position[b] = w.pose.x.into();
        bodies.orientation[b] = quat::to_xyzw(&w.pose.q);
        let omega = spatial::ang(&w.vel);
        bodies.angular_velocity[b] = omega.into();
        bodies.linear_velocity[b] = spatial::point_velocity(&w.vel, &w.pose.x).into();
    }
}
