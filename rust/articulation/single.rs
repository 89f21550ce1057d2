//! The articulation of one body on one hinge or slide to the ground, in closed
//! form: its axis is fixed in the world, so the inertia about it is a constant
//! and an evaluation is a few dozen flops (the general recursion costs ~20 times
//! more). Same integrators, controls and limits as the general path, same
//! results to round-off; a thousand pendulums step at the cost of their state.

use super::control::{self, Term};
use super::joint::{self, JointModel, Pose};
use super::model::{Articulation, Parent};
use super::spatial::join;
use crate::body::Bodies;
use crate::math::{quat, Mat3, Vec3};

/// What is constant about a single hinge or slide on the ground.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Single {
    pub slide: bool,
    /// World axis, the anchor (a point of the axis), the inertia about the axis
    /// (kg·m², with armature) or the mass (kg, with armature).
    pub axis: Vec3,
    pub anchor: Vec3,
    pub inertia: f64,
    /// Hinge: the centre of mass at angle θ is `anchor + par + cos θ perp +
    /// sin θ (axis × perp)`; gravity's moment about the axis is then
    /// `m g-terms = c0 + c1 cos θ + c2 sin θ` (one sine and cosine per evaluation).
    pub moment: [f64; 3],
    pub par: Vec3,
    pub perp: Vec3,
}

impl Single {
    /// The closed form of `art`, if it is one 1-dof link on the world.
    pub fn of(art: &Articulation) -> Option<Self> {
        let [l] = art.links.as_slice() else { return None };
        if l.parent != Parent::World || !matches!(l.model, JointModel::Revolute | JointModel::Prismatic) {
            return None;
        }
        let f = &l.frames;
        let slide = l.model == JointModel::Prismatic;
        let axis = if slide { f.axis_parent } else { quat::rotate(&f.rest, &f.axis_child) };
        let inertia = if slide {
            l.mass + l.control.armature
        } else {
            // I about the axis through the anchor, at q = 0 (it does not change).
            let pose = joint::child_pose(l.model, f, &Pose::identity(), &[0.0]);
            let r = quat::to_matrix(&pose.q);
            let ic = r * Mat3::from_diagonal(&Vec3::from(l.inertia)) * r.transpose();
            let arm = (pose.x - f.anchor_parent).cross(&axis);
            axis.dot(&(ic * axis)) + l.mass * arm.norm_squared() + l.control.armature
        };
        let x0 = joint::child_pose(l.model, f, &Pose::identity(), &[0.0]).x - f.anchor_parent;
        let par = axis * axis.dot(&x0);
        let perp = x0 - par;
        Some(Self { slide, axis, anchor: f.anchor_parent, inertia, moment: [0.0; 3], par, perp })
    }

    /// Sets the gravity terms of the hinge's moment (`g` in m/s²).
    pub fn with_gravity(mut self, g: &Vec3, mass: f64) -> Self {
        let w = mass * g;
        let side = self.axis.cross(&self.perp);
        self.moment = [self.axis.dot(&self.par.cross(&w)), self.axis.dot(&self.perp.cross(&w)), self.axis.dot(&side.cross(&w))];
        self
    }

    /// Generalized force of gravity and the body's applied force and torque at `q`.
    fn natural(&self, art: &Articulation, q: f64, gravity: &Vec3, bodies: &Bodies) -> f64 {
        let l = &art.links[0];
        let b = l.body as usize;
        let f = l.mass * gravity + Vec3::from(bodies.force[b]);
        if self.slide {
            return self.axis.dot(&f);
        }
        let (fe, te) = (Vec3::from(bodies.force[b]), Vec3::from(bodies.torque[b]));
        let (sh, ch) = half_sin_cos(art, q);
        let (sn, cs) = (2.0 * sh * ch, ch * ch - sh * sh);
        let [c0, c1, c2] = self.moment;
        let mut m = c0 + c1 * cs + c2 * sn;
        if fe != Vec3::zeros() || te != Vec3::zeros() {
            let r = self.par + cs * self.perp + sn * self.axis.cross(&self.perp);
            m += self.axis.dot(&(r.cross(&fe) + te));
        }
        let _ = f;
        m
    }

    /// `q̈` with the controls' terms (built at `q`, `v_ctrl`) over a kick.
    #[allow(clippy::too_many_arguments)]
    fn accel(&self, art: &Articulation, q: f64, v_ctrl: f64, kick: Option<(f64, f64, f64)>, gravity: &Vec3, bodies: &Bodies, terms: &mut Vec<Term>) -> f64 {
        let nat = self.natural(art, q, gravity, bodies);
        terms.clear();
        if let Some((tau, h, weight)) = kick {
            control::terms(&art.links[0].control, &[q], &[v_ctrl], 0, tau, h, terms);
            terms.iter_mut().for_each(|t| t.weight = weight);
        }
        let solve = |terms: &[Term]| {
            let (mut f, mut m) = (nat, self.inertia);
            for t in terms {
                f += t.weight * t.rhs[0];
                m += t.diag;
            }
            f / m
        };
        let a = solve(terms);
        if control::saturate(terms, &[a]) {
            return solve(terms);
        }
        a
    }

    /// One leapfrog (or, `euler`, semi-implicit Euler) substep; impulses of the
    /// controls and the limits go to `applied[0]`.
    #[allow(clippy::too_many_arguments)]
    pub fn substep(&self, art: &mut Articulation, euler: bool, h: f64, gravity: &Vec3, bodies: &Bodies, terms: &mut Vec<Term>, applied: &mut [f64]) {
        let (q, v) = (art.q[0], art.v[0]);
        let passive = art.links[0].control.is_passive();
        let kick = (!passive).then_some(if euler { (h, h, 1.0) } else { (h, h, 2.0) });
        // Without controls the end of the last substep's evaluation is this one's.
        let a = match (passive, art.cached_qdd) {
            (true, Some(a)) => a,
            _ => self.accel(art, q, v, kick, gravity, bodies, terms),
        };
        if passive {
            terms.clear();
        }
        let mut vh = v + if euler { h } else { 0.5 * h } * a;
        for t in terms.iter() {
            applied[0] += h * t.force(&[a])[0];
        }
        if let Some([lo, hi]) = art.links[0].control.limits {
            let m = self.inertia + terms.iter().map(|t| t.diag).sum::<f64>();
            let want = if q + h * vh < lo { (lo - q) / h } else if q + h * vh > hi { (hi - q) / h } else { vh };
            applied[0] += (want - vh) * m;
            vh = want;
        }
        let q1 = q + h * vh;
        if !self.slide {
            // One sine and cosine per substep: the evaluation below and the
            // pose written after the last substep both take them from here.
            let (sh, ch) = (0.5 * q1).sin_cos();
            art.cached_half = Some((q1, sh, ch));
        }
        let a1 = self.accel(art, q1, vh, None, gravity, bodies, terms);
        let v1 = if euler { vh } else { vh + 0.5 * h * a1 };
        art.q[0] = q1;
        art.v[0] = v1;
        art.cached_qdd = (passive && !euler).then_some(a1);
    }

    /// The fastest rate of the state (see [`super::substeps`]): the joint rate and
    /// the swing frequency under gravity and the centripetal load.
    pub fn fastest_rate(&self, art: &Articulation, gravity: &Vec3) -> f64 {
        if self.slide {
            return 0.0;
        }
        let l = &art.links[0];
        let r = l.frames.anchor_child.norm();
        let v = art.v[0].abs();
        v + (l.mass * (gravity.norm() + v * v * r) * r / self.inertia).sqrt()
    }

    /// Pose and velocity into the link's work record and its body row.
    pub fn write(&self, art: &mut Articulation, bodies: &mut Bodies) {
        let l = &art.links[0];
        let (q, v) = (art.q[0], art.v[0]);
        let pose = if self.slide {
            joint::child_pose(l.model, &l.frames, &Pose::identity(), &[q])
        } else {
            // One sine and cosine of the half angle give the quaternion and the
            // centre of mass (double-angle formulas).
            let (sh, ch) = half_sin_cos(art, q);
            let (sn, cs) = (2.0 * sh * ch, ch * ch - sh * sh);
            let a = l.frames.axis_child * sh;
            let turn = crate::math::Quat::new(ch, a.x, a.y, a.z);
            let x = self.anchor + self.par + cs * self.perp + sn * self.axis.cross(&self.perp);
            Pose { x, q: l.frames.rest * turn }
        };
        let omega = if self.slide { Vec3::zeros() } else { self.axis * v };
        let vel = if self.slide { self.axis * v } else { omega.cross(&(pose.x - self.anchor)) };
        let b = l.body as usize;
        let w = &mut art.work[0];
        w.pose = pose;
        w.vel = join(&omega, &(vel - omega.cross(&pose.x)));
        bodies.position[b] = pose.x.into();
        bodies.orientation[b] = quat::to_xyzw(&pose.q);
        bodies.angular_velocity[b] = omega.into();
        bodies.linear_velocity[b] = vel.into();
    }

    /// The reaction the joint transmits now (spatial, about the origin), for
    /// read-back: what the body's motion needs beyond gravity and its applied load.
    pub fn reaction(&self, art: &mut Articulation, gravity: &Vec3, bodies: &Bodies) {
        let l = &art.links[0];
        let (q, v) = (art.q[0], art.v[0]);
        let pose = joint::child_pose(l.model, &l.frames, &Pose::identity(), &[q]);
        let a = self.accel(art, q, v, None, gravity, bodies, &mut Vec::new());
        let (omega, alpha) = if self.slide { (Vec3::zeros(), Vec3::zeros()) } else { (self.axis * v, self.axis * a) };
        let r = pose.x - self.anchor;
        let acc = if self.slide { self.axis * a } else { alpha.cross(&r) + omega.cross(&omega.cross(&r)) };
        let b = l.body as usize;
        let (fe, te) = (Vec3::from(bodies.force[b]), Vec3::from(bodies.torque[b]));
        let f = l.mass * (acc - gravity) - fe;
        let rot = quat::to_matrix(&pose.q);
        let ic = rot * Mat3::from_diagonal(&Vec3::from(l.inertia)) * rot.transpose();
        let couple = ic * alpha + omega.cross(&(ic * omega)) - te;
        art.work[0].reaction = join(&(pose.x.cross(&f) + couple), &f);
    }
}

/// `sin(q/2)`, `cos(q/2)`, from the cache when it holds this `q`.
fn half_sin_cos(art: &Articulation, q: f64) -> (f64, f64) {
    match art.cached_half {
        Some((qc, s, c)) if qc == q => (s, c),
        _ => (0.5 * q).sin_cos(),
    }
}
