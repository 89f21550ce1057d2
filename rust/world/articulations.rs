//! Articulations in the world: which joints become articulations (the joint
//! graph's trees, see [`crate::articulation::build`]; a tree falls back to XPBD
//! when a particle is attached to one of its links, or when one of its links
//! asks for continuous collision detection, which moves a body off its joints),
//! the `articulation` stage, and the joints' read-back arrays that the Python
//! views show: position, velocity, drive target and applied force per joint.
//! Contacts act on articulated links through the contact solver (see
//! [`super::link_contacts`]).

use super::joints::SolverChoice;
use super::{Scene, Settings, World};
use crate::articulation::build::{self, BodyInput, Component, JointInput};
use crate::articulation::{spatial, Articulations, Control, DriveMode, JointModel};
use crate::body::BodyKind;
use crate::error::{Error, Result};
use crate::math::{quat, Quat, Vec3};
use crate::xpbd::joints::{angles, JointKind};

/// The articulations of a scene and what they take over.
pub(crate) struct Compiled {
    pub articulations: Articulations,
    /// Per joint: whether an articulation carries it.
    pub articulated_joint: Vec<bool>,
    /// Per body: whether it is a link of an articulation.
    pub articulated_body: Vec<bool>,
}

fn model_of(kind: JointKind) -> JointModel {
    match kind {
        JointKind::Hinge => JointModel::Revolute,
        JointKind::Prismatic => JointModel::Prismatic,
        JointKind::Spherical => JointModel::Spherical,
        JointKind::Fixed | JointKind::Distance => JointModel::Fixed,
    }
}

fn inputs(scene: &Scene, settings: &Settings) -> (Vec<BodyInput>, Vec<JointInput>) {
    let bodies = scene
        .bodies()
        .iter()
        .map(|d| BodyInput {
            dynamic: d.init.kind == BodyKind::Dynamic,
            kinematic: d.init.kind == BodyKind::Kinematic,
            position: d.init.position,
            orientation: d.init.orientation,
            linear_velocity: d.init.linear_velocity,
            angular_velocity: d.init.angular_velocity,
            mass: d.init.mass,
            inertia: d.init.inertia,
        })
        .collect();
    let joints = scene
        .joints()
        .iter()
        .zip(scene.joint_options())
        .map(|(j, o)| {
            let mut control = o.control.clone();
            if matches!(j.kind, JointKind::Hinge | JointKind::Prismatic) {
                control.limits = j.limits;
            }
            let rigid = j.compliance == 0.0 && j.angular_compliance == 0.0;
            JointInput {
                model: model_of(j.kind),
                body_a: j.body_a,
                body_b: j.body_b,
                anchor_a: j.anchor_a,
                anchor_b: j.anchor_b,
                axis_a: j.axis_a,
                axis_b: j.axis_b,
                rest: j.rest,
                control,
                articulable: settings.articulation.enabled
                    && j.kind != JointKind::Distance
                    && rigid
                    && o.solver != SolverChoice::Xpbd,
            }
        })
        .collect();
    (bodies, joints)
}

/// Why a component stays XPBD, if it does.
fn fallback(scene: &Scene, comp: &Component, attached: &[bool]) -> Option<&'static str> {
    if !comp.tree {
        return Some("its joints form a loop, or include a distance, compliant or solver=\"xpbd\" joint");
    }
    if comp.bodies.iter().any(|&b| attached[b as usize]) {
        return Some("a particle is attached to one of its bodies");
    }
    let descs = scene.bodies();
    if comp.bodies.iter().any(|&b| descs[b as usize].ccd) {
        return Some("one of its bodies asks for continuous collision detection (ccd=True), which moves a body off its joints");
    }
    None
}

/// Converts what a joint's controls say about body a relative to b into what
/// the articulation's child sees when the child is b.
fn flip(control: &mut Control, rest: &Quat) {
    if let Some([lo, hi]) = control.limits {
        control.limits = Some([-hi, -lo]);
    }
    if let Some([lo, hi]) = control.twist {
        control.twist = Some([-hi, -lo]);
    }
    if let Some(d) = control.drive.as_mut() {
        match (d.mode, d.target.len()) {
            (DriveMode::Position, 4) => {
                let t = Quat::new(d.target[3], d.target[0], d.target[1], d.target[2]);
                let back = rest * t.conjugate() * rest.conjugate();
                d.target = quat::to_xyzw(&back).to_vec();
            }
            (DriveMode::Velocity, 3) => {
                let w = -quat::rotate(rest, &Vec3::new(d.target[0], d.target[1], d.target[2]));
                d.target = w.as_slice().to_vec();
            }
            _ => d.target[0] = -d.target[0],
        }
    }
}

pub(crate) fn compile(scene: &Scene, settings: &Settings) -> Result<Compiled> {
    let (bodies, joints) = inputs(scene, settings);
    let n = bodies.len();
    let mut attached = vec![false; n];
    for a in &scene.xpbd.attachments {
        attached[a.body as usize] = true;
    }
    let mut out = Compiled {
        articulations: Articulations::default(),
        articulated_joint: vec![false; joints.len()],
        articulated_body: vec![false; n],
    };
    let mut list = Vec::new();
    let comps = build::components(&bodies, &joints);
    for comp in &comps {
        if let Some(reason) = fallback(scene, comp, &attached) {
            check_xpbd_ok(scene, comp, reason)?;
            continue;
        }
        let mut art = build::articulation(comp, &bodies, &joints);
        for l in art.links.iter_mut().filter(|l| !l.child_is_a) {
            let rest = l.frames.rest.conjugate();
            flip(&mut l.control, &rest);
        }
        for l in &art.links {
            out.articulated_body[l.body as usize] = true;
            if let Some(j) = l.joint {
                out.articulated_joint[j] = true;
            }
        }
        list.push(art);
    }
    out.articulations = Articulations::new(list, settings.articulation, Vec3::from(scene.gravity));
    Ok(out)
}

/// A component that stays XPBD must not hold a joint that needs an articulation.
fn check_xpbd_ok(scene: &Scene, comp: &Component, reason: &str) -> Result<()> {
    for &k in &comp.joints {
        let o = &scene.joint_options()[k];
        let c = &o.control;
        let needs = c.drive.is_some() || c.damping > 0.0 || c.armature > 0.0 || c.friction > 0.0 || c.cone.is_some() || c.twist.is_some();
        if o.solver == SolverChoice::Articulation || (needs && o.solver == SolverChoice::Auto) {
            let what = if o.solver == SolverChoice::Articulation { "solver=\"articulation\"" } else { "its drive, damping, armature, friction or cone/twist limits" };
            return Err(Error::input(format!("joint {k}: {what} needs an articulation, but its system stays XPBD: {reason}")));
        }
    }
    Ok(())
}

impl World {
    /// The `articulation` stage.
    pub(crate) fn step_articulations(&mut self) {
        let g = self.gravity;
        self.articulations.step(&mut self.bodies, &g, self.settings.dt);
    }

    /// Poses articulated 1-dof joints: `q[j]` (rad or m, NaN: keep), `v[j]`
    /// (rad/s or m/s, NaN: keep; `None`: 0 where a position is given). Every
    /// entry is checked before anything changes; errors name the joint.
    pub fn set_joint_positions(&mut self, q: &[f64], v: Option<&[f64]>) -> Result<()> {
        let n = self.joint_position.len();
        if q.len() != n || v.is_some_and(|v| v.len() != n) {
            return Err(Error::input(format!("positions and velocities must have one entry per joint ({n})")));
        }
        let mut link_of = vec![None; n];
        for (a, art) in self.articulations.list.iter().enumerate() {
            for (k, l) in art.links.iter().enumerate() {
                if let Some(j) = l.joint {
                    link_of[j] = Some((a, k));
                }
            }
        }
        let mut changes = Vec::new();
        for j in 0..n {
            let (qj, vj) = (q[j], v.map_or(f64::NAN, |v| v[j]));
            if qj.is_nan() && vj.is_nan() {
                continue;
            }
            let kind = self.joints.joints[j].kind.name();
            let Some((a, k)) = link_of[j] else {
                return Err(Error::input(format!(
                    "joint {j}: a {kind} joint that XPBD solves has no coordinates to set (move its bodies, or give NaN)"
                )));
            };
            let l = &self.articulations.list[a].links[k];
            if l.model.nv() != 1 {
                return Err(Error::input(format!("joint {j}: a {kind} joint has no single coordinate (give NaN)")));
            }
            if qj.is_infinite() || vj.is_infinite() {
                return Err(Error::input(format!("joint {j}: position and velocity must be finite or NaN, got {qj}, {vj}")));
            }
            let s = if l.child_is_a { 1.0 } else { -1.0 };
            if let (Some([lo, hi]), false) = (l.control.limits, qj.is_nan()) {
                if !(lo <= s * qj && s * qj <= hi) {
                    return Err(Error::input(format!("joint {j}: position {qj} is outside its limits")));
                }
            }
            let vj = if v.is_none() && !qj.is_nan() { 0.0 } else { vj };
            changes.push((a, l.q_at, l.v_at, s * qj, s * vj));
        }
        let moved: Vec<usize> = changes.iter().map(|c| c.0).collect();
        self.wake_articulations(&moved);
        for (a, qa, va, qj, vj) in changes {
            let art = &mut self.articulations.list[a];
            if !qj.is_nan() {
                art.q[qa] = qj;
            }
            if !vj.is_nan() {
                art.v[va] = vj;
            }
        }
        self.articulations.invalidate();
        self.place_links();
        self.read_joints();
        self.bodies.update_derived();
        Ok(())
    }

    /// Writes the links' poses and velocities from the joints' coordinates.
    pub(crate) fn place_links(&mut self) {
        self.articulations.write_bodies(&mut self.bodies);
    }

    /// Copies the writable 1-dof drive targets into the articulations (their
    /// sign turned where the articulation's child is the joint's body b); an
    /// articulation asleep wakes when a target of it changed.
    pub(crate) fn sync_targets(&mut self) {
        let mut moved = Vec::new();
        for (a, art) in self.articulations.list.iter_mut().enumerate() {
            for l in &mut art.links {
                let (Some(j), Some(d)) = (l.joint, l.control.drive.as_mut()) else { continue };
                if d.target.len() == 1 {
                    let t = self.joint_target[j];
                    let t = if l.child_is_a { t } else { -t };
                    if d.target[0] != t {
                        d.target[0] = t;
                        moved.push(a);
                    }
                }
            }
        }
        moved.dedup();
        self.wake_articulations(&moved);
    }

    /// Wakes the articulations `list` (indices) if they sleep.
    pub(crate) fn wake_articulations(&mut self, list: &[usize]) {
        let Some(c) = self.collision.as_mut() else { return };
        let mut woke = false;
        for &a in list {
            if let Some(l) = self.articulations.list.get(a).and_then(|art| art.links.first()) {
                woke |= c.islands.wake(&mut self.bodies, l.body as usize);
            }
        }
        if woke {
            self.relist();
        }
    }

    /// Refreshes the joints' position, velocity and force arrays.
    pub(crate) fn read_joints(&mut self) {
        for art in &self.articulations.list {
            for l in &art.links {
                let Some(j) = l.joint else { continue };
                let s = if l.child_is_a { 1.0 } else { -1.0 };
                let one = l.model.nv() == 1;
                self.joint_position[j] = if one { s * art.q[l.q_at] } else { f64::NAN };
                self.joint_velocity[j] = if one { s * art.v[l.v_at] } else { f64::NAN };
                self.joint_force[j] = if one { s * art.applied[l.v_at] } else { f64::NAN };
            }
        }
        self.read_xpbd_joints();
    }

    /// The wrench each articulated joint transmits, into the joints' force and
    /// torque read-back (computed when asked: `joint_forces`, `joint_torques`).
    pub(crate) fn read_joint_wrenches(&mut self) {
        let g = self.gravity;
        self.articulations.refresh_reactions(&self.bodies, &g);
        for art in &self.articulations.list {
            for (l, w) in art.links.iter().zip(&art.work) {
                let Some(j) = l.joint else { continue };
                let s = if l.child_is_a { 1.0 } else { -1.0 };
                // The wrench the joint transmits to the child, about the anchor;
                // body a is the child or receives the opposite.
                let (f, n) = (spatial::lin(&w.reaction), spatial::ang(&w.reaction));
                let anchor = w.pose.point(&l.frames.anchor_child);
                let couple = n - anchor.cross(&f);
                self.joints.force[j] = (s * f).into();
                self.joints.torque[j] = (s * couple).into();
            }
        }
    }

    /// XPBD hinges and slides: angle and slide from the bodies' poses; the
    /// force is the joint's couple (or force) along its axis.
    fn read_xpbd_joints(&mut self) {
        let b = &self.bodies;
        for (k, j) in self.joints.joints.iter().enumerate() {
            if self.joints.articulated.get(k).copied().unwrap_or(false) {
                continue;
            }
            let (a, other) = (j.body_a as usize, j.body_b.map(|x| x as usize));
            let qa = b.q(a);
            let (xb, qb, wb, vb) = match other {
                Some(o) => (Vec3::from(b.position[o]), b.q(o), Vec3::from(b.angular_velocity[o]), Vec3::from(b.linear_velocity[o])),
                None => (Vec3::zeros(), Quat::identity(), Vec3::zeros(), Vec3::zeros()),
            };
            let axis = quat::rotate(&qb, &j.axis_b);
            let wa = Vec3::from(b.angular_velocity[a]);
            let (pos, vel, force) = match j.kind {
                JointKind::Hinge => (
                    angles::signed_angle(&quat::rotate(&qb, &j.ref_b), &quat::rotate(&qa, &j.ref_a), &axis),
                    (wa - wb).dot(&axis),
                    Vec3::from(self.joints.torque[k]).dot(&axis),
                ),
                JointKind::Prismatic => {
                    let xa = Vec3::from(b.position[a]);
                    let (pa, pb) = (xa + quat::rotate(&qa, &j.anchor_a), xb + quat::rotate(&qb, &j.anchor_b));
                    let va = Vec3::from(b.linear_velocity[a]) + wa.cross(&(pa - xa));
                    let vpb = vb + wb.cross(&(pa - xb));
                    ((pa - pb).dot(&axis), (va - vpb).dot(&axis), Vec3::from(self.joints.force[k]).dot(&axis))
                }
                _ => (f64::NAN, f64::NAN, f64::NAN),
            };
            self.joint_position[k] = pos;
            self.joint_velocity[k] = vel;
            self.joint_force[k] = force;
        }
    }
}
