//! The stages a world runs, chosen from what the scene contains: a stage with
//! nothing to do is not in the plan and costs nothing.
//!
//! One step is `pre` (collision detection), then `substeps` times `sub`, then
//! `post` (sleep). Within a substep, bodies that touch something this step take a
//! velocity-level step (full kick, contact solve, drift, relax: first order, as in
//! every impulse-based engine; a body no contact pushed in the substep drifts
//! along its kick's parabola, `integrate::drift::translate_touching`, exact as in
//! free flight). Bodies in free flight keep the integrator's own
//! splitting and its order: in a world with contacts only, they take its whole
//! step once, in `pre` after the narrow phase, exactly as in a world without
//! colliders (substeps are for contacts); with joints or particles, which act on
//! bodies inside the substeps, they take it per substep. The drift (translation
//! and rotation) is the integrator's for all.
//!
//! Joints (XPBD, [`crate::xpbd::joints`]) are projected once per substep right
//! after the integrator's last drift, before CCD and the contact relax pass: the
//! contact solve of the substep (velocities, with position bias) has already
//! run, the joint projection then moves the bodies onto their joint constraints
//! and corrects their velocities by `Δx/h`, `Δθ/h`, and the relax pass (and, for
//! splittings that close with a kick, that kick) acts on the corrected state.
//! Contacts therefore see the joints' corrections in the relax pass and in the
//! next substep; joints see the contact impulses through the drift.
//!
//! Particles (XPBD) and shape matching run each substep after the joints
//! and before CCD, the contact relax pass and the closing kick: `xpbd`
//! (predict), `shape_matching` (only with clusters), `xpbd` (project constraints
//! and collisions, update velocities); see `crate::xpbd::solver`. Particles see
//! the bodies at their drifted poses, and what they do to bodies (attachments,
//! contacts) is then seen by the relax pass.

use crate::integrate::{BodyLists, Gyroscopic, InertiaClass, Integrator, Rotation};

/// Which dynamic bodies a kick applies to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Group {
    /// Every awake dynamic body (a world without contacts).
    All,
    /// Awake dynamic bodies in no contact this step.
    Free,
    /// Awake dynamic bodies in contact this step.
    Touching,
}

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum StageKind {
    BroadPhase,
    NarrowPhase,
    /// Velocity-level gyroscopic update of the non-isotropic bodies of a group.
    Gyroscopic(Gyroscopic, Group),
    /// Kick by gravity, applied forces and torques.
    Forces(Group),
    /// Restitution: pairwise impacts of approaching contacts, in time order.
    Impacts,
    /// Copies the touching bodies into the solver (`relax`: before the relax pass).
    Gather { relax: bool },
    /// Writes the solved velocities back.
    Scatter { relax: bool },
    /// Warm start of the contact impulses.
    WarmStart,
    /// Coulomb friction (true cone); `relax`: without position bias.
    Friction { relax: bool },
    /// Non-penetration; `relax`: without position bias.
    Normal { relax: bool },
    /// `p += h v` for a group.
    Translate(Group),
    /// Rotation of the bodies of one inertia class and group by the integrator's
    /// method; `first`: the first drift of its step, where the exact rotation of
    /// asymmetric bodies decides which turn too fast for one split per drift
    /// (they sit out every drift of the step but for their `RotateFast`).
    Rotate(InertiaClass, Group, bool),
    /// The whole step's rotation of the asymmetric bodies the first drift found
    /// too fast, in rotation substeps; planned in the middle drift of the
    /// integrator's (palindromic) composition, so that the kicks before it add up
    /// to half the step; runs only when there are such bodies.
    RotateFast(Group),
    /// The monolithic RK4 step of a group; `forces`: with its kick.
    Rk4 { group: Group, forces: bool },
    /// Kinematic bodies moved by their velocities.
    Kinematic,
    /// Continuous collision detection of fast bodies that asked for it.
    Ccd,
    /// Islands at rest go to sleep.
    Sleep,
    /// XPBD projection of the joints (after the last drift of a substep).
    Joints,
    /// Articulations in reduced coordinates: a whole step, substeps their own
    /// (those not in contact this step).
    Articulation,
    /// The kick of the articulations in contact, before the contact solve of a
    /// substep (see `crate::articulation::contact`).
    ArticulationKick,
    /// Their limits and drift, after the contact solve of a substep.
    ArticulationDrift,
    /// Particles: prediction by their velocities and gravity.
    ParticlePredict,
    /// Shape matching of the particle clusters.
    ShapeMatching,
    /// Particles: constraint and collision projection, then velocities.
    ParticleProject,
}

/// One stage: what it does, the fraction of the substep (or, `whole`, of the
/// step) it covers, and its accumulator in the world's profile.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Stage {
    pub kind: StageKind,
    pub frac: f64,
    pub whole: bool,
    pub slot: usize,
}

impl Stage {
    fn new(kind: StageKind, frac: f64) -> Self {
        Self { kind, frac, whole: false, slot: 0 }
    }

    /// A stage that covers `frac` of the whole step, run once per step.
    fn whole(kind: StageKind, frac: f64) -> Self {
        Self { kind, frac, whole: true, slot: 0 }
    }

    pub fn name(&self) -> &'static str {
        match self.kind {
            StageKind::BroadPhase => "broad_phase",
            StageKind::NarrowPhase => "narrow_phase",
            StageKind::Gyroscopic(..) => "gyroscopic",
            StageKind::Forces(_) => "forces",
            StageKind::Impacts => "impacts",
            StageKind::WarmStart
            | StageKind::Normal { relax: false }
            | StageKind::Gather { relax: false }
            | StageKind::Scatter { relax: false } => "contact_solve",
            StageKind::Friction { .. } => "friction",
            StageKind::Normal { relax: true }
            | StageKind::Gather { relax: true }
            | StageKind::Scatter { relax: true } => "contact_relax",
            StageKind::Translate(_) => "translate",
            StageKind::Rotate(InertiaClass::Isotropic, ..) => "rotate_isotropic",
            StageKind::Rotate(InertiaClass::Symmetric, ..) => "rotate_symmetric",
            StageKind::Rotate(InertiaClass::Asymmetric, ..) => "rotate_asymmetric",
            StageKind::RotateFast(_) => "rotate_fast",
            StageKind::Rk4 { .. } => "rk4",
            StageKind::Kinematic => "kinematic",
            StageKind::Ccd => "ccd",
            StageKind::Sleep => "sleep",
            StageKind::Joints => "joints",
            StageKind::Articulation => "articulation",
            StageKind::ArticulationKick | StageKind::ArticulationDrift => "articulation_contact",
            StageKind::ParticlePredict | StageKind::ParticleProject => "xpbd",
            StageKind::ShapeMatching => "shape_matching",
        }
    }
}

/// What the plan depends on.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct PlanInputs {
    pub integrator: Integrator,
    /// Gravity, an applied force or an applied torque acts.
    pub forces: bool,
    /// Some pair of colliders can touch.
    pub collisions: bool,
    /// Some pair that can touch has restitution > 0.
    pub impacts: bool,
    /// Some pair that can touch has friction > 0.
    pub friction: bool,
    /// Some body asked for continuous collision detection.
    pub ccd: bool,
    pub kinematic: bool,
    pub sleep: bool,
    /// Solver iterations per substep (≥ 1), contacts and joints alike.
    pub iterations: u32,
    /// The scene has joints that XPBD projects.
    pub joints: bool,
    /// The scene has articulations.
    pub articulations: bool,
    /// Some articulated link has a collider that another collider's filter
    /// allows: articulations may step inside the contact substeps.
    pub articulated_contacts: bool,
    /// The scene has particles / shape-matching clusters.
    pub particles: bool,
    pub clusters: bool,
}

#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Plan {
    pub pre: Vec<Stage>,
    pub sub: Vec<Stage>,
    pub post: Vec<Stage>,
}

impl Plan {
    pub fn stages(&self) -> impl Iterator<Item = &Stage> {
        self.pre.iter().chain(&self.sub).chain(&self.post)
    }

    /// Gives every stage its profile accumulator.
    pub fn assign_slots(&mut self, profile: &mut super::profile::Profile) {
        for s in self.pre.iter_mut().chain(self.sub.iter_mut()).chain(self.post.iter_mut()) {
            s.slot = profile.slot(s.name());
        }
    }
}

pub fn plan(inp: &PlanInputs, lists: &BodyLists) -> Plan {
    let mut p = Plan::default();
    let dynamic = !lists.dynamic.is_empty();
    if inp.collisions {
        p.pre.push(Stage::new(StageKind::BroadPhase, 1.0));
        p.pre.push(Stage::new(StageKind::NarrowPhase, 1.0));
    }
    if inp.articulations {
        // An articulation touching nothing this step takes its whole step on its
        // own, once per step; one in contact steps inside the contact substeps.
        p.pre.push(Stage::whole(StageKind::Articulation, 1.0));
    }
    if dynamic && inp.collisions && !inp.joints && !inp.particles {
        return plan_free_and_touching(p, inp, lists);
    }
    let free = if inp.collisions { Group::Free } else { Group::All };
    let split = inp.integrator.splitting();
    let exact = split.as_ref().is_some_and(|s| s.rotation == Rotation::Free);
    let drift =
        |sub: &mut Vec<Stage>, frac: f64, pos: [usize; 2]| drift(sub, lists, Group::All, Stage::new, frac, pos, exact);
    if dynamic {
        if let Some(g) = split.as_ref().and_then(|s| s.gyroscopic) {
            if !lists.anisotropic_index.is_empty() {
                p.sub.push(Stage::new(StageKind::Gyroscopic(g, Group::All), 1.0));
            }
        }
        if inp.collisions && inp.forces {
            p.sub.push(Stage::new(StageKind::Forces(Group::Touching), 1.0));
        }
    }
    if inp.collisions {
        articulation_stage(&mut p.sub, inp, StageKind::ArticulationKick);
        p.sub.push(Stage::new(StageKind::Gather { relax: false }, 1.0));
        if inp.impacts {
            p.sub.push(Stage::new(StageKind::Impacts, 1.0));
        }
        p.sub.push(Stage::new(StageKind::WarmStart, 1.0));
        solve(&mut p.sub, inp, false);
        articulation_stage(&mut p.sub, inp, StageKind::ArticulationDrift);
    }
    if inp.kinematic {
        p.sub.push(Stage::new(StageKind::Kinematic, 1.0));
    }
    if dynamic {
        match &split {
            None => {
                p.sub.push(Stage::new(StageKind::Rk4 { group: free, forces: inp.forces }, 1.0));
                if inp.collisions {
                    p.sub.push(Stage::new(StageKind::Rk4 { group: Group::Touching, forces: false }, 1.0));
                }
                joints(&mut p.sub, inp);
                particles(&mut p.sub, inp);
            }
            Some(s) => {
                for (j, &d) in s.drifts.iter().enumerate() {
                    if inp.forces && s.kicks[j] != 0.0 {
                        p.sub.push(Stage::new(StageKind::Forces(free), s.kicks[j]));
                    }
                    drift(&mut p.sub, d, [j, s.drifts.len()]);
                }
                joints(&mut p.sub, inp);
                particles(&mut p.sub, inp);
                let last = s.kicks[s.drifts.len()];
                if inp.forces && last != 0.0 {
                    // The closing kick goes after the relax so resting bodies end at rest.
                    if inp.ccd {
                        p.sub.push(Stage::new(StageKind::Ccd, 1.0));
                    }
                    if inp.collisions {
                        solve(&mut p.sub, inp, true);
                    }
                    p.sub.push(Stage::new(StageKind::Forces(free), last));
                    return finish(p, inp);
                }
            }
        }
    }
    if !dynamic {
        particles(&mut p.sub, inp);
    }
    if inp.ccd && dynamic {
        p.sub.push(Stage::new(StageKind::Ccd, 1.0));
    }
    if inp.collisions {
        solve(&mut p.sub, inp, true);
    }
    finish(p, inp)
}

/// A world with collisions (and neither joints nor particles, which act on
/// bodies within the substeps): bodies in free flight this step take the
/// integrator's whole step once, exactly as in a world without colliders; only
/// the bodies in contact are substepped. A body is free when no contact is
/// predicted for it within the step, so nothing touches it before the next.
fn plan_free_and_touching(mut p: Plan, inp: &PlanInputs, lists: &BodyLists) -> Plan {
    let split = inp.integrator.splitting();
    let exact = split.as_ref().is_some_and(|s| s.rotation == Rotation::Free);
    match &split {
        None => p.pre.push(Stage::whole(StageKind::Rk4 { group: Group::Free, forces: inp.forces }, 1.0)),
        Some(s) => {
            if let Some(g) = s.gyroscopic.filter(|_| !lists.anisotropic_index.is_empty()) {
                p.pre.push(Stage::whole(StageKind::Gyroscopic(g, Group::Free), 1.0));
            }
            for (j, &d) in s.drifts.iter().enumerate() {
                if inp.forces && s.kicks[j] != 0.0 {
                    p.pre.push(Stage::whole(StageKind::Forces(Group::Free), s.kicks[j]));
                }
                drift(&mut p.pre, lists, Group::Free, Stage::whole, d, [j, s.drifts.len()], exact);
            }
            let last = s.kicks[s.drifts.len()];
            if inp.forces && last != 0.0 {
                p.pre.push(Stage::whole(StageKind::Forces(Group::Free), last));
            }
        }
    }
    // The bodies in contact: a velocity-level step per substep (full kick, contact
    // solve, the integrator's drifts, relax).
    if let Some(g) = split.as_ref().and_then(|s| s.gyroscopic).filter(|_| !lists.anisotropic_index.is_empty()) {
        p.sub.push(Stage::new(StageKind::Gyroscopic(g, Group::Touching), 1.0));
    }
    if inp.forces {
        p.sub.push(Stage::new(StageKind::Forces(Group::Touching), 1.0));
    }
    articulation_stage(&mut p.sub, inp, StageKind::ArticulationKick);
    p.sub.push(Stage::new(StageKind::Gather { relax: false }, 1.0));
    if inp.impacts {
        p.sub.push(Stage::new(StageKind::Impacts, 1.0));
    }
    p.sub.push(Stage::new(StageKind::WarmStart, 1.0));
    solve(&mut p.sub, inp, false);
    articulation_stage(&mut p.sub, inp, StageKind::ArticulationDrift);
    if inp.kinematic {
        p.sub.push(Stage::new(StageKind::Kinematic, 1.0));
    }
    match &split {
        None => p.sub.push(Stage::new(StageKind::Rk4 { group: Group::Touching, forces: false }, 1.0)),
        Some(s) => {
            for (j, &d) in s.drifts.iter().enumerate() {
                drift(&mut p.sub, lists, Group::Touching, Stage::new, d, [j, s.drifts.len()], exact);
            }
        }
    }
    if inp.ccd {
        p.sub.push(Stage::new(StageKind::Ccd, 1.0));
    }
    solve(&mut p.sub, inp, true);
    finish(p, inp)
}

/// Drift `pos = [j, s]` (the `j`-th of `s`) of `frac` for a group: translation,
/// then the rotation of each inertia class the world has; with the exact free
/// rotation, in the middle drift, the whole step's rotation of the asymmetric
/// bodies too fast for one split per drift (a stage that does nothing, and is
/// not listed by `World::stage_names`, while no body needs it).
fn drift(
    stages: &mut Vec<Stage>,
    lists: &BodyLists,
    group: Group,
    make: fn(StageKind, f64) -> Stage,
    frac: f64,
    [j, s]: [usize; 2],
    exact_rotation: bool,
) {
    stages.push(make(StageKind::Translate(group), frac));
    for c in [InertiaClass::Isotropic, InertiaClass::Symmetric, InertiaClass::Asymmetric] {
        if lists.count(c) > 0 {
            stages.push(make(StageKind::Rotate(c, group, j == 0), frac));
        }
    }
    if exact_rotation && lists.count(InertiaClass::Asymmetric) > 0 && j == s / 2 {
        stages.push(make(StageKind::RotateFast(group), 1.0));
    }
}

/// A stage of the articulations in contact, if the scene may have any.
fn articulation_stage(sub: &mut Vec<Stage>, inp: &PlanInputs, kind: StageKind) {
    if inp.articulated_contacts {
        sub.push(Stage::new(kind, 1.0));
    }
}

/// The joint projection, if the scene has joints.
fn joints(sub: &mut Vec<Stage>, inp: &PlanInputs) {
    if inp.joints {
        sub.push(Stage::new(StageKind::Joints, 1.0));
    }
}

/// The particle stages of a substep (see the module docs).
fn particles(sub: &mut Vec<Stage>, inp: &PlanInputs) {
    if inp.particles {
        sub.push(Stage::new(StageKind::ParticlePredict, 1.0));
        if inp.clusters {
            sub.push(Stage::new(StageKind::ShapeMatching, 1.0));
        }
        sub.push(Stage::new(StageKind::ParticleProject, 1.0));
    }
}

/// Solver iterations; the relax pass gathers first, and each pass scatters after.
fn solve(sub: &mut Vec<Stage>, inp: &PlanInputs, relax: bool) {
    if relax {
        sub.push(Stage::new(StageKind::Gather { relax }, 1.0));
    }
    // Normal first: friction's cone is then that of this pass's normal impulse, so
    // a body set down at rest is held by static friction from its first substep.
    for _ in 0..inp.iterations.max(1) {
        sub.push(Stage::new(StageKind::Normal { relax }, 1.0));
        if inp.friction {
            sub.push(Stage::new(StageKind::Friction { relax }, 1.0));
        }
    }
    sub.push(Stage::new(StageKind::Scatter { relax }, 1.0));
}

fn finish(mut p: Plan, inp: &PlanInputs) -> Plan {
    if inp.sleep {
        p.post.push(Stage::new(StageKind::Sleep, 1.0));
    }
    p
}
