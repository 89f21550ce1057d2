//! Joint controls: drives (position or velocity targets with stiffness, damping
//! and a force limit), joint damping, armature and Coulomb friction, each a
//! generalized force on the joint's dofs, solved implicitly over a kick.
//!
//! Over a kick of length `τ` that is followed by a drift of length `h`, a force
//! `φ(q, v) = k (q* − q) + c (v* − v)` is taken at the state the kick and drift
//! lead to, linearized: `φ ≈ φ(q, v) − h k v − (c + h k) τ q̈`. Its constant part
//! goes to the right-hand side, `τ (c + h k)` to the joint's diagonal in the
//! articulated-body solve, so a drive of any stiffness is stable at the step (a
//! stiff spring behaves like backward Euler's, not like an explicit one's). A
//! term that would exceed its `max` is solved again as the constant `±max`.
//! Friction is a velocity drive to rest with damping `friction / FRICTION_SPEED`
//! capped at `friction`: it holds the joint (creeping below `FRICTION_SPEED`)
//! until the load exceeds it, then slides against it.

use crate::math::{quat, Quat, Vec3};

/// Below this joint speed (rad/s or m/s) friction acts as a damper.
pub const FRICTION_SPEED: f64 = 1e-4;

#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum DriveMode {
    Position,
    Velocity,
}

#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Drive {
    pub mode: DriveMode,
    /// Hinge: angle (rad) or rate (rad/s); prismatic: slide (m) or rate (m/s);
    /// spherical: relative rotation (x, y, z, w) or angular velocity (3, rad/s,
    /// child frame).
    pub target: Vec<f64>,
    /// N·m/rad or N/m (position mode).
    pub stiffness: f64,
    /// N·m·s/rad or N·s/m.
    pub damping: f64,
    /// N·m or N; infinite by default.
    pub max_force: f64,
}

/// What acts on one joint besides the articulation's dynamics.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Control {
    pub drive: Option<Drive>,
    /// Viscous damping (N·m·s/rad or N·s/m).
    pub damping: f64,
    /// Added to the joint's inertia (kg·m² or kg).
    pub armature: f64,
    /// Coulomb friction (N·m or N).
    pub friction: f64,
    /// Hinge angle (rad) or slide (m) range.
    pub limits: Option<[f64; 2]>,
    /// Spherical: largest swing of the child's axis from its build direction (rad).
    pub cone: Option<f64>,
    /// Spherical: twist range about the child's axis (rad).
    pub twist: Option<[f64; 2]>,
}

impl Control {
    pub fn is_passive(&self) -> bool {
        self.drive.is_none() && self.damping == 0.0 && self.friction == 0.0
    }
}

/// One linearized term on `n` consecutive dofs from `at`.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct Term {
    pub at: usize,
    pub n: usize,
    /// `φ(q, v) − h k v` per dof.
    pub rhs: [f64; 3],
    /// `τ (c + h k)`, the same on every dof of the term.
    pub diag: f64,
    pub max: f64,
    pub saturated: bool,
    /// The solve's `q̈` times `weight / τ` is the velocity change the term
    /// sees: its right-hand side enters the solve times `weight`.
    pub weight: f64,
}

impl Term {
    /// The force this term applies for the solved accelerations `qdd`.
    pub fn force(&self, qdd: &[f64]) -> [f64; 3] {
        let mut f = [0.0; 3];
        for i in 0..self.n {
            f[i] = self.rhs[i] - self.diag * qdd[self.at + i] / self.weight;
        }
        f
    }
}

/// Position error of a spherical joint `q` towards `target`, as a rotation
/// vector in the child frame: `log(q⁻¹ q*)`.
fn rotation_error(q: &[f64], target: &[f64]) -> Vec3 {
    let (cur, want) = (Quat::new(q[3], q[0], q[1], q[2]), Quat::new(target[3], target[0], target[1], target[2]));
    let d = cur.conjugate() * want;
    let d = if d.w < 0.0 { -d } else { d };
    let s = (d.i * d.i + d.j * d.j + d.k * d.k).sqrt();
    if s < 1e-300 {
        return Vec3::zeros();
    }
    Vec3::new(d.i, d.j, d.k) * (2.0 * s.atan2(d.w) / s)
}

/// Appends the terms of one joint's controls (drive, damping, friction) for a
/// kick of length `tau` followed by a drift `h`, at coordinates `q`, `v` (the
/// joint's own slices; `at` its first dof). The caller sets `weight` when the
/// solve's kick is not `tau` long.
pub fn terms(c: &Control, q: &[f64], v: &[f64], at: usize, tau: f64, h: f64, out: &mut Vec<Term>) {
    let n = v.len();
    let linear = |k: f64, damp: f64, err: &[f64], vt: &[f64], max: f64| {
        let mut rhs = [0.0; 3];
        for i in 0..n {
            rhs[i] = k * err[i] + damp * (vt[i] - v[i]) - h * k * v[i];
        }
        Term { at, n, rhs, diag: tau * (damp + h * k), max, saturated: false, weight: 1.0 }
    };
    let zero = [0.0; 3];
    if let Some(d) = &c.drive {
        let t = match (d.mode, n) {
            (DriveMode::Position, 3) => {
                let e = rotation_error(q, &d.target);
                linear(d.stiffness, d.damping, e.as_slice(), &zero, d.max_force)
            }
            (DriveMode::Position, _) => linear(d.stiffness, d.damping, &[d.target[0] - q[0]], &zero, d.max_force),
            (DriveMode::Velocity, _) => linear(0.0, d.damping, &zero, &d.target, d.max_force),
        };
        out.push(t);
    }
    if c.damping > 0.0 {
        out.push(linear(0.0, c.damping, &zero, &zero, f64::INFINITY));
    }
    if c.friction > 0.0 {
        out.push(linear(0.0, c.friction / FRICTION_SPEED, &zero, &zero, c.friction));
    }
}

/// Marks the terms whose force for `qdd` exceeds their limit; returns whether
/// any changed (then the solve must run again with [`apply`]).
pub fn saturate(terms: &mut [Term], qdd: &[f64]) -> bool {
    let mut changed = false;
    for t in terms.iter_mut().filter(|t| !t.saturated && t.max.is_finite()) {
        let f = t.force(qdd);
        let norm = f[..t.n].iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm > t.max {
            let s = t.max / norm;
            for i in 0..t.n {
                t.rhs[i] = f[i] * s;
            }
            t.diag = 0.0;
            t.saturated = true;
            changed = true;
        }
    }
    changed
}

/// Adds the terms to the joint forces and the diagonal.
pub fn apply(terms: &[Term], tau: &mut [f64], extra: &mut [f64]) {
    for t in terms {
        for i in 0..t.n {
            tau[t.at + i] += t.weight * t.rhs[i];
            extra[t.at + i] += t.diag;
        }
    }
}

/// The identity rotation as spherical coordinates.
pub fn identity_target() -> Vec<f64> {
    let q = quat::to_xyzw(&Quat::identity());
    q.to_vec()
}
