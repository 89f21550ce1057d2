//! Rigid-body joints by extended position-based dynamics (Müller, Macklin,
//! Chentanez, Jeschke, Kim 2020, "Detailed Rigid Body Simulation with Extended
//! Position Based Dynamics").
//!
//! A joint ties body a to body b or to the world. Each substep, after the drift
//! has moved every body, the joint constraints are projected on the poses
//! (Gauss–Seidel, `iterations` passes in the order the joints were added), each
//! projection an XPBD update of a Lagrange multiplier with compliance (see
//! [`correction`]; two points held together and a kept relative orientation
//! are solved as 3×3 blocks, [`block`]); the multipliers start from zero every
//! substep. The velocities of the bodies a projection moves get `Δx/h` and `Δθ/h`.
//!
//! Kinds (one file each): [`spherical`] (points coincide), [`hinge`] (points
//! coincide, axes aligned, optional angle limits), [`fixed`] (points coincide,
//! relative orientation kept), [`prismatic`] (orientation kept, the point of a
//! slides along b's axis, optional limits), [`distance`] (a rest length between
//! the points, or a range). Positional constraints use the joint's `compliance`
//! (m/N), angular ones its `angular_compliance` (rad/(N·m)); limits are hard.
//!
//! What a joint did over the last substep is readable: the force on body a is
//! `Σ Δλ n / h²` of its positional corrections (N, world), the couple on a is
//! that of its angular corrections (N·m, world): together the wrench the joint
//! applies to a about a's anchor. Body b receives the opposite.

pub mod angles;
pub mod block;
pub mod correction;
pub mod distance;
pub mod fixed;
pub mod hinge;
pub mod prismatic;
pub mod spec;
pub mod spherical;

pub use spec::JointSpec;

use correction::{Multipliers, Pair};
use crate::body::Bodies;
use crate::error::{Error, Result};
use crate::math::{Quat, Vec3};

/// What a joint constrains.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum JointKind {
    Spherical,
    Hinge,
    Fixed,
    Prismatic,
    Distance,
}

impl JointKind {
    pub const ALL: [JointKind; 5] =
        [JointKind::Spherical, JointKind::Hinge, JointKind::Fixed, JointKind::Prismatic, JointKind::Distance];

    pub fn name(self) -> &'static str {
        match self {
            JointKind::Spherical => "spherical",
            JointKind::Hinge => "hinge",
            JointKind::Fixed => "fixed",
            JointKind::Prismatic => "prismatic",
            JointKind::Distance => "distance",
        }
    }

    pub fn from_name(name: &str) -> Result<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name).ok_or_else(|| {
            let names: Vec<&str> = Self::ALL.iter().map(|k| k.name()).collect();
            Error::input(format!("kind: unknown joint kind {name:?}; choose one of {}", names.join(", ")))
        })
    }
}

/// A joint as compiled: its frames in each body's principal frame (for the
/// world, in the world frame), taken from the bodies' initial poses.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Joint {
    pub kind: JointKind,
    pub body_a: u32,
    /// `None`: the world.
    pub body_b: Option<u32>,
    /// Anchor on a and on b, each in its body's frame (m).
    pub anchor_a: Vec3,
    pub anchor_b: Vec3,
    /// Unit joint axis in a's frame and in b's frame.
    pub axis_a: Vec3,
    pub axis_b: Vec3,
    /// A unit vector orthogonal to the axis, in a's and b's frames, equal in the
    /// world at build: the zero of a hinge's angle.
    pub ref_a: Vec3,
    pub ref_b: Vec3,
    /// Orientation of a relative to b at build, `q_b⁻¹ q_a`.
    pub rest: Quat,
    /// Positional compliance (m/N).
    pub compliance: f64,
    /// Angular compliance (rad/(N·m)).
    pub angular_compliance: f64,
    /// Hinge: angle range (rad); prismatic: slide range (m); distance: length range (m).
    pub limits: Option<[f64; 2]>,
    /// Distance joint without limits: the length it keeps (m).
    pub rest_length: f64,
}

/// Every joint of a world, what each did over the last substep.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Joints {
    pub joints: Vec<Joint>,
    /// The body pairs joints tie together (the world left out).
    pairs: Vec<(u32, u32)>,
    state: Vec<Multipliers>,
    /// Force (N) and couple (N·m) on body a over the last substep, world frame.
    pub force: Vec<[f64; 3]>,
    pub torque: Vec<[f64; 3]>,
    /// Joints an articulation carries: never projected here.
    pub articulated: Vec<bool>,
}

impl Joints {
    pub fn new(joints: Vec<Joint>) -> Self {
        let n = joints.len();
        let pairs = joints.iter().filter_map(|j| j.body_b.map(|b| (j.body_a, b))).collect();
        Self {
            joints,
            pairs,
            state: vec![Multipliers::default(); n],
            force: vec![[0.0; 3]; n],
            torque: vec![[0.0; 3]; n],
            articulated: vec![false; n],
        }
    }

    pub fn is_empty(&self) -> bool {
        self.joints.is_empty()
    }

    /// Whether some joint is projected here (not carried by an articulation).
    pub fn any_projected(&self) -> bool {
        self.articulated.iter().any(|&a| !a)
    }

    /// The body pairs joints tie together, (a, b); the world is left out.
    pub fn pairs(&self) -> &[(u32, u32)] {
        &self.pairs
    }

    /// One substep's projection: multipliers reset, `iterations` Gauss–Seidel
    /// passes over the joints, then the forces read back from `λ / h²`. A joint
    /// whose bodies are both asleep (or cannot move) is skipped and keeps the
    /// force it last read.
    pub fn project(&mut self, bodies: &mut Bodies, h: f64, iterations: u32) {
        self.state.fill(Multipliers::default());
        let moving = |j: &Joint| bodies.awake(j.body_a as usize) || j.body_b.is_some_and(|b| bodies.awake(b as usize));
        let active: Vec<bool> = self.joints.iter().zip(&self.articulated).map(|(j, &art)| !art && moving(j)).collect();
        for _ in 0..iterations.max(1) {
            for ((j, state), _) in self.joints.iter().zip(self.state.iter_mut()).zip(&active).filter(|(_, &on)| on) {
                let (a, b) = (j.body_a as usize, j.body_b.map(|b| b as usize));
                let mut pair = Pair { bodies: &mut *bodies, a, b, h, state };
                match j.kind {
                    JointKind::Spherical => spherical::project(j, &mut pair),
                    JointKind::Hinge => hinge::project(j, &mut pair),
                    JointKind::Fixed => fixed::project(j, &mut pair),
                    JointKind::Prismatic => prismatic::project(j, &mut pair),
                    JointKind::Distance => distance::project(j, &mut pair),
                }
            }
        }
        let inv_h2 = 1.0 / (h * h);
        for (k, s) in self.state.iter().enumerate().filter(|&(k, _)| active[k]) {
            self.force[k] = (s.linear * inv_h2).into();
            self.torque[k] = (s.angular * inv_h2).into();
        }
    }
}

/// Slots of the multipliers, shared by the kinds (each uses up to three).
pub(crate) mod slot {
    /// The attachment (or the perpendicular part of a prismatic joint's).
    pub const POSITION: usize = 0;
    /// The orientation (fixed, prismatic) or the alignment of the axes (hinge).
    pub const ORIENTATION: usize = 1;
    /// A limit.
    pub const LIMIT: usize = 2;
}

/// The attachment: the anchors of a and b coincide (compliance `compliance`),
/// by the block update.
pub(crate) fn attach(j: &Joint, pair: &mut Pair<'_>) {
    let (pa, pb) = (pair.pose_a(), pair.pose_b());
    let (ra, rb) = (pa.offset(&j.anchor_a), pb.offset(&j.anchor_b));
    let gap = (pa.x + ra) - (pb.x + rb);
    pair.point(&ra, &rb, &gap, j.compliance);
}

/// The relative orientation of a and b stays `rest` (compliance
/// `angular_compliance`), by the block update.
pub(crate) fn keep_orientation(j: &Joint, pair: &mut Pair<'_>) {
    let (pa, pb) = (pair.pose_a(), pair.pose_b());
    let turn = angles::turn_from(&(pb.q * j.rest), &pa.q);
    pair.orientation(&turn, j.angular_compliance);
}

#[cfg(test)]
mod tests;
