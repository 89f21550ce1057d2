//! What `Scene::add_joint` takes, its validation, and its compilation into a
//! [`Joint`] from the bodies' initial poses.

use std::f64::consts::PI;

use super::{Joint, JointKind};
use crate::body::storage::BodyInit;
use crate::body::BodyKind;
use crate::error::{finite3, non_negative, Error, Result};
use crate::math::{quat, Quat, Vec3};

/// A joint to add. Points and directions are in the world frame at the bodies'
/// initial poses (as given to `add_body`).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct JointSpec {
    pub kind: JointKind,
    /// Index of body a.
    pub body_a: usize,
    /// Index of body b; `None`: the world.
    pub body_b: Option<usize>,
    /// The joined point on a (m). Default: a's centre of mass.
    pub anchor: Option<[f64; 3]>,
    /// The joined point on b (m). Default: `anchor`. Distance joints keep these
    /// two points apart; the other kinds pull them together.
    pub anchor_b: Option<[f64; 3]>,
    /// Hinge or slide axis (any length but zero). Default (0, 0, 1).
    pub axis: [f64; 3],
    /// Positional compliance (m/N), ≥ 0. Default 0 (rigid).
    pub compliance: f64,
    /// Angular compliance (rad/(N·m)), ≥ 0. Default 0 (rigid).
    pub angular_compliance: f64,
    /// `[lo, hi]`: hinge angle (rad, −π ≤ lo ≤ hi ≤ π, 0 at build), prismatic
    /// slide (m, lo ≤ hi) or distance range (m, 0 ≤ lo ≤ hi). Default none.
    pub limits: Option<[f64; 2]>,
    /// Distance joint: the length kept (m, ≥ 0). Default: the anchors' initial
    /// distance. Not with `limits`.
    pub rest_length: Option<f64>,
}

impl JointSpec {
    /// A joint of `kind` between `body_a` and `body_b` with every default.
    pub fn new(kind: JointKind, body_a: usize, body_b: Option<usize>) -> Self {
        Self {
            kind,
            body_a,
            body_b,
            anchor: None,
            anchor_b: None,
            axis: [0.0, 0.0, 1.0],
            compliance: 0.0,
            angular_compliance: 0.0,
            limits: None,
            rest_length: None,
        }
    }

    /// Validates against the scene's bodies (`body(i)`: the initial state of body
    /// `i` of `count`) and compiles.
    pub fn compile<'b>(&self, count: usize, body: impl Fn(usize) -> &'b BodyInit) -> Result<Joint> {
        self.check_bodies(count, &body)?;
        non_negative("compliance", self.compliance)?;
        non_negative("angular_compliance", self.angular_compliance)?;
        let axis = unit_axis(self.axis)?;
        self.check_limits()?;
        let a = body(self.body_a);
        let (xb, qb) = self.body_b.map_or((Vec3::zeros(), Quat::identity()), |i| (body(i).position, body(i).orientation));
        let anchor = Vec3::from(finite3("anchor", self.anchor.unwrap_or(a.position.into()))?);
        let anchor_b = match self.anchor_b {
            Some(p) => Vec3::from(finite3("anchor_b", p)?),
            None => anchor,
        };
        let rest_length = match self.rest_length {
            Some(l) => non_negative("rest_length", l)?,
            None => (anchor - anchor_b).norm(),
        };
        let reference = crate::solve::contact::orthonormal(&axis);
        let local = |q: &Quat, v: &Vec3| quat::rotate_inv(q, v);
        Ok(Joint {
            kind: self.kind,
            body_a: self.body_a as u32,
            body_b: self.body_b.map(|i| i as u32),
            anchor_a: local(&a.orientation, &(anchor - a.position)),
            anchor_b: local(&qb, &(anchor_b - xb)),
            axis_a: local(&a.orientation, &axis),
            axis_b: local(&qb, &axis),
            ref_a: local(&a.orientation, &reference),
            ref_b: local(&qb, &reference),
            rest: qb.conjugate() * a.orientation,
            compliance: self.compliance,
            angular_compliance: self.angular_compliance,
            limits: self.limits,
            rest_length,
        })
    }

    fn check_bodies<'b>(&self, count: usize, body: &impl Fn(usize) -> &'b BodyInit) -> Result<()> {
        let range = |name: &str, i: usize| {
            if i < count {
                Ok(())
            } else {
                Err(Error::input(format!("{name}: body index {i} is out of range: the scene has {count} bodies")))
            }
        };
        range("body_a", self.body_a)?;
        if let Some(b) = self.body_b {
            range("body_b", b)?;
            if b == self.body_a {
                return Err(Error::input(format!("body_b: a joint needs two different bodies, got body {b} twice")));
            }
        }
        let moves = |i: usize| body(i).kind == BodyKind::Dynamic;
        if !moves(self.body_a) && !self.body_b.is_some_and(moves) {
            let other = self.body_b.map_or("the world".to_string(), |b| format!("body {b} ({})", kind_name(body(b).kind)));
            return Err(Error::input(format!(
                "body_a: body {} ({}) and {other} cannot move: a joint needs a dynamic body",
                self.body_a,
                kind_name(body(self.body_a).kind)
            )));
        }
        Ok(())
    }

    fn check_limits(&self) -> Result<()> {
        let kind = self.kind.name();
        if self.rest_length.is_some() && self.kind != JointKind::Distance {
            return Err(Error::input(format!("rest_length: a {kind} joint has no rest length")));
        }
        let Some([lo, hi]) = self.limits else { return Ok(()) };
        if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
            return Err(Error::input(format!("limits must be finite with lo <= hi, got [{lo}, {hi}]")));
        }
        match self.kind {
            JointKind::Hinge if !(-PI <= lo && hi <= PI) => {
                Err(Error::input(format!("limits: hinge angles must lie in [-pi, pi] rad, got [{lo}, {hi}]")))
            }
            JointKind::Distance if lo < 0.0 => Err(Error::input(format!("limits: distances must be >= 0 m, got [{lo}, {hi}]"))),
            JointKind::Distance if self.rest_length.is_some() => {
                Err(Error::input("rest_length: give either rest_length or limits to a distance joint, not both"))
            }
            JointKind::Spherical | JointKind::Fixed => Err(Error::input(format!("limits: a {kind} joint takes no limits"))),
            _ => Ok(()),
        }
    }
}

fn kind_name(k: BodyKind) -> &'static str {
    match k {
        BodyKind::Dynamic => "dynamic",
        BodyKind::Fixed => "fixed",
        BodyKind::Kinematic => "kinematic",
    }
}

/// `axis` normalised; an error if it is not finite or zero.
fn unit_axis(axis: [f64; 3]) -> Result<Vec3> {
    let v = Vec3::from(finite3("axis", axis)?);
    let scale = v.amax();
    if scale == 0.0 {
        return Err(Error::input(format!("axis must be a non-zero vector, got {axis:?}")));
    }
    // Scaled first: the norm of (1e-200, 0, 0) underflows.
    Ok((v / scale).normalize())
}
