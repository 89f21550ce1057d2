//! How two shapes move toward each other over a step, from what each of
//! their bodies does ([`Motion`], found once a step for every body its pairs
//! share).

use super::collider::Collider;
use super::narrow_phase::Prediction;
use crate::body::Bodies;
use crate::math::Vec3;

/// What one body brings to the approach of its pairs over a step: its
/// acceleration from gravity and applied forces (m/s²; none asleep or not
/// dynamic) and how fast it can turn, torques included (rad/s).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Motion {
    accel: Vec3,
    spin: f64,
}

impl Motion {
    pub(super) fn of(b: &Bodies, i: usize, pred: &Prediction) -> Self {
        let awake = b.awake(i);
        let accel = if awake { pred.gravity + Vec3::from(b.force[i]) * b.inv_mass[i] } else { Vec3::zeros() };
        let mut spin = Vec3::from(b.angular_velocity[i]).norm();
        if awake {
            spin += pred.dt * Vec3::from(b.torque[i]).norm() * b.inv_inertia[i].iter().fold(0.0, |m: f64, &x| m.max(x));
        }
        Self { accel, spin }
    }

    /// How fast collider `c` of the body can move its surface by turning (m/s).
    fn turning(&self, c: &Collider) -> f64 {
        // A half-space never turns (its reach is infinite): no 0·∞ here.
        if self.spin > 0.0 { self.spin * c.reach } else { 0.0 }
    }
}

/// How two shapes move toward each other over a step: their relative velocity
/// (body 1's minus body 2's, m/s), the relative acceleration from gravity and
/// applied forces (gravity cancels between two free bodies, m/s²) and how fast
/// each one's surface can turn, torques included (m/s).
pub(super) struct Approach {
    pub velocity: Vec3,
    pub accel: Vec3,
    pub turning: f64,
}

impl Approach {
    /// The approach of colliders `c1`, `c2` at the bodies `b`, their
    /// [`Motion`]s read from `motions` (per body) if it has them, else found.
    pub(super) fn of(c1: &Collider, c2: &Collider, (b, motions): (&Bodies, &[Motion]), pred: &Prediction) -> Self {
        let (i1, i2) = (c1.body as usize, c2.body as usize);
        let motion = |i: usize| motions.get(i).copied().unwrap_or_else(|| Motion::of(b, i, pred));
        let (m1, m2) = (motion(i1), motion(i2));
        Approach {
            velocity: Vec3::from(b.linear_velocity[i1]) - Vec3::from(b.linear_velocity[i2]),
            accel: m1.accel - m2.accel,
            turning: m1.turning(c1) + m2.turning(c2),
        }
    }

    /// An upper bound of the speed at which the two shapes approach over the step
    /// (m/s). Bodies falling side by side do not approach, whatever their speed.
    pub(super) fn bound(&self, dt: f64) -> f64 {
        self.velocity_after(dt).norm() + self.turning
    }

    /// The relative velocity at the end of the step (m/s).
    pub(super) fn velocity_after(&self, dt: f64) -> Vec3 {
        self.velocity + self.accel * dt
    }
}
