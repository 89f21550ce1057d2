//! The compiled simulation: state arrays of fixed layout, the colliders and the
//! plan of stages the scene needs.

use super::collision::Collision;
use super::pipeline::{plan, Plan, PlanInputs};
use super::profile::Profile;
use super::{Scene, Settings};
use crate::body::{BodyKind, Bodies, Shape};
use crate::error::{Error, Result};
use crate::integrate::kick::KickSources;
use crate::integrate::{BodyLists, Integrator, Rotation};
use crate::math::Vec3;
use nalgebra::Isometry3;

#[derive(serde::Serialize, serde::Deserialize)]
pub struct World {
    /// Body state (views of these arrays are what Python sees).
    pub bodies: Bodies,
    /// Each body's shape and its pose in the body's principal frame.
    pub shapes: Vec<Option<(Shape, Isometry3<f64>)>>,
    pub(crate) gravity: Vec3,
    pub(crate) settings: Settings,
    /// Substeps per step, resolved from the settings and the scene.
    pub(crate) substeps: u32,
    /// Contact substeps the last step took (see `solve::rocking`).
    pub(crate) last_substeps: u32,
    /// Worker threads the contact stages of the current step may use: more
    /// than one only while the step runs on the pool (see `World::one_step`).
    #[serde(skip)]
    pub(crate) contact_threads: usize,
    pub(crate) rotation: Rotation,
    /// Awake dynamic bodies by class (rebuilt when bodies sleep or wake).
    pub(crate) lists: BodyLists,
    /// This step's awake dynamic bodies in free flight and in contact, by class.
    pub(crate) split: [BodyLists; 2],
    /// The touching mask `split` was made from, `None` once `lists` changed
    /// (re-splitting unchanged lists was 2 % of a step of 2000 free boxes).
    #[serde(skip)]
    pub(crate) split_mask: Option<Vec<bool>>,
    pub(crate) kinematic: Vec<u32>,
    pub collision: Option<Collision>,
    /// The scene's joints and what they did over the last substep.
    pub joints: crate::xpbd::joints::Joints,
    /// Particles, their constraints and clusters (none without particles).
    pub xpbd: Option<crate::xpbd::Xpbd>,
    /// Tree-shaped joint systems in reduced coordinates.
    pub articulations: crate::articulation::Articulations,
    /// Per body: whether it is an articulation's link (the body integrator
    /// leaves it alone; its pose and velocity are written from the joints).
    pub articulated_body: Vec<bool>,
    /// Per joint (the views `world.joints.*`): angle (rad) or slide (m), its
    /// rate, the drive target (writable), the generalized force applied over
    /// the last step (N·m or N). NaN where a joint has no single coordinate.
    pub joint_position: Vec<f64>,
    pub joint_velocity: Vec<f64>,
    pub joint_target: Vec<f64>,
    pub joint_force: Vec<f64>,
    /// Names given to `add_body` and `add_joint` (empty when none).
    pub body_names: Vec<String>,
    pub joint_names: Vec<String>,
    pub(crate) plan: Plan,
    pub(crate) plan_inputs: PlanInputs,
    /// Asymmetric bodies the first drift of this step found too fast for one
    /// split per drift (they take the whole step in `RotateFast`).
    pub(crate) fast: Vec<crate::integrate::Aniso>,
    /// The asymmetric bodies of the group but those in `fast`, for the other
    /// drifts of a composition, and a scratch mark per body to build it.
    pub(crate) slow: Vec<crate::integrate::Aniso>,
    pub(crate) fast_mark: Vec<bool>,
    /// Per body in contact, its linear velocity right after this substep's
    /// kick: a body the contact solve left at it drifts along its kick's
    /// parabola (see [`crate::integrate::drift::translate_touching`]).
    #[serde(skip)]
    pub(crate) kicked: Vec<[f64; 3]>,
    /// Drift fractions of the integrator's composition, which each rotation
    /// substep of a fast body repeats (`[1.0]` for strang).
    pub(crate) fast_weights: Vec<f64>,
    pub(crate) steps: u64,
    /// Whether the derived arrays (rotation, angular momentum, world inertia) are
    /// kept fresh after each `step` call; set once a user reads one of them.
    pub keep_derived: bool,
    /// Stage timings: not state; a world read from bytes starts a new window.
    #[serde(skip)]
    pub profile: Profile,
    /// Set only while a failed step is run again to find its stage (`guard`).
    #[serde(skip)]
    pub(crate) watch: Option<super::guard::Watch>,
    /// Tests only: the step count at which a step panics (inside a stage).
    #[cfg(test)]
    #[serde(skip)]
    pub(crate) fail_at: Option<u64>,
}

clone_in_place!(World {
    bodies,
    shapes,
    gravity,
    settings,
    substeps,
    last_substeps,
    contact_threads,
    rotation,
    lists,
    split,
    split_mask,
    kinematic,
    collision,
    joints,
    xpbd,
    articulations,
    articulated_body,
    joint_position,
    joint_velocity,
    joint_target,
    joint_force,
    body_names,
    joint_names,
    plan,
    plan_inputs,
    fast,
    slow,
    fast_mark,
    kicked,
    fast_weights,
    steps,
    keep_derived,
    profile,
    watch,
    #[cfg(test)] fail_at,
});

impl World {
    pub(crate) fn new(scene: &Scene, settings: Settings) -> Result<Self> {
        let descs = scene.bodies();
        let mut bodies = Bodies::with_capacity(descs.len());
        for d in descs {
            bodies.push(&d.init);
        }
        let shapes = descs.iter().map(|d| d.shape.clone().map(|s| (s, d.shape_pose))).collect();
        let compiled = super::articulations::compile(scene, &settings)?;
        // Links of one articulation collide, as any bodies do, unless a joint
        // ties them.
        let joint_pairs = World::joint_pairs(scene);
        let mut collision = Collision::new(descs, &bodies, &settings, &joint_pairs)?;
        if let Some(c) = collision.as_mut() {
            let links: Vec<(Vec<u32>, usize)> =
                compiled.articulations.list.iter().map(|a| (a.links.iter().map(|l| l.body).collect(), a.nv)).collect();
            c.solver.gen.set_links(bodies.len(), &links);
        }
        let articulated_contacts = collision.is_some()
            && super::link_contacts::links_may_touch(descs, &compiled.articulated_body);
        let xpbd_joints = compiled.articulated_joint.iter().any(|&a| !a);
        let base = if collision.is_some() { 4 } else { 1 };
        let xpbd_base = if xpbd_joints { super::joints::xpbd_substeps(scene, &compiled.articulated_joint) } else { 1 };
        // Default: 4 with contacts, else 1; what XPBD joints and particle links ask for.
        let substeps = settings.substeps.unwrap_or_else(|| {
            let links = crate::xpbd::substeps::for_links(&scene.xpbd, Vec3::from(scene.gravity), settings.dt);
            base.max(xpbd_base).max(links)
        });
        let lists = BodyLists::new(&bodies).without(&compiled.articulated_body);
        let kinematic = (0..bodies.len() as u32).filter(|&i| bodies.kind[i as usize] == BodyKind::Kinematic).collect();
        let rotation = settings.integrator.splitting().map_or(Rotation::Free, |s| s.rotation);
        let fast_weights = settings.integrator.splitting().map_or(vec![1.0], |s| s.drifts);
        let plan_inputs = PlanInputs {
            integrator: settings.integrator,
            forces: false,
            collisions: collision.is_some(),
            impacts: collision.as_ref().is_some_and(|c| c.bouncy),
            friction: collision.as_ref().is_some_and(|c| c.frictional),
            ccd: collision.as_ref().is_some_and(|c| !c.ccd.is_empty()),
            kinematic: descs.iter().any(|d| d.init.kind == BodyKind::Kinematic),
            sleep: collision.is_some() && settings.sleep.enabled,
            iterations: settings.iterations,
            joints: xpbd_joints,
            articulations: !compiled.articulations.is_empty(),
            articulated_contacts,
            particles: !scene.xpbd.is_empty(),
            clusters: !scene.xpbd.clusters.is_empty(),
        };
        let xpbd = super::particles::compile(scene, &settings)?;
        let mut world = World {
            bodies,
            shapes,
            gravity: Vec3::from(scene.gravity),
            settings,
            substeps,
            last_substeps: substeps,
            contact_threads: 1,
            rotation,
            split: [lists.clone(), BodyLists::default()],
            split_mask: None,
            lists,
            kinematic,
            collision,
            joints: {
                let mut j = crate::xpbd::joints::Joints::new(scene.joints().to_vec());
                j.articulated = compiled.articulated_joint.clone();
                j
            },
            xpbd,
            articulations: compiled.articulations,
            articulated_body: compiled.articulated_body,
            joint_position: vec![f64::NAN; scene.joints().len()],
            joint_velocity: vec![f64::NAN; scene.joints().len()],
            joint_target: scene.joint_options().iter().map(initial_target).collect(),
            joint_force: vec![0.0; scene.joints().len()],
            body_names: descs.iter().map(|d| d.name.clone().unwrap_or_default()).collect(),
            joint_names: scene.joint_options().iter().map(|o| o.name.clone().unwrap_or_default()).collect(),
            plan: Plan::default(),
            plan_inputs,
            fast: Vec::new(),
            slow: Vec::new(),
            fast_mark: Vec::new(),
            kicked: Vec::new(),
            fast_weights,
            steps: 0,
            keep_derived: false,
            watch: None,
            #[cfg(test)]
            fail_at: None,
            profile: Profile::default(),
        };
        world.replan(true);
        world.sync_targets();
        world.place_links();
        world.read_joints();
        world.bodies.update_derived();
        Ok(world)
    }

    pub fn dt(&self) -> f64 {
        self.settings.dt
    }

    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    pub fn substeps(&self) -> u32 {
        self.substeps
    }

    /// Contact substeps the last step took: [`Self::substeps`], or more while a
    /// slow body rocks on its supports (`solve::rocking`) or an articulation in
    /// contact asks for more.
    pub fn last_substeps(&self) -> u32 {
        self.last_substeps
    }

    pub fn integrator(&self) -> Integrator {
        self.settings.integrator
    }

    /// Simulated time (s): steps taken times `dt`, so it does not drift.
    pub fn time(&self) -> f64 {
        self.steps as f64 * self.settings.dt
    }

    pub fn steps(&self) -> u64 {
        self.steps
    }

    pub fn lists(&self) -> &BodyLists {
        &self.lists
    }

    /// What the kick stage would apply now.
    pub(crate) fn kick_sources(&self) -> KickSources {
        let nonzero = |a: &[[f64; 3]]| self.lists.dynamic.iter().any(|&i| a[i as usize] != [0.0; 3]);
        KickSources { gravity: self.gravity, force: nonzero(&self.bodies.force), torque: nonzero(&self.bodies.torque) }
    }

    /// Rebuilds the plan if the force sources changed (or `always`).
    pub(crate) fn replan(&mut self, always: bool) {
        let src = self.kick_sources();
        self.replan_for(&src, always);
    }

    /// [`Self::replan`] for the force sources `src` of the current state.
    pub(crate) fn replan_for(&mut self, src: &KickSources, always: bool) {
        let forces = src.any();
        if !always && forces == self.plan_inputs.forces {
            return;
        }
        self.plan_inputs.forces = forces;
        self.plan = plan(&self.plan_inputs, &self.lists);
        self.plan.assign_slots(&mut self.profile);
    }

    /// Rebuilds the class lists after bodies fell asleep or woke.
    pub(crate) fn relist(&mut self) {
        self.lists = BodyLists::new(&self.bodies).without(&self.articulated_body);
        self.split_mask = None;
        self.plan = plan(&self.plan_inputs, &self.lists);
        self.plan.assign_slots(&mut self.profile);
    }

    /// Names of the stages one step runs now, in order (pre, one substep, post),
    /// with repeats in a row shown once. `rotate_fast` is listed when some body
    /// turns too fast for one split of its rotation per step (it takes substeps).
    pub fn stage_names(&mut self) -> Vec<&'static str> {
        self.replan(false);
        let mut names: Vec<&'static str> =
            self.plan.stages().filter(|s| self.stage_active(s)).map(|s| s.name()).collect();
        names.dedup();
        names
    }

    /// Adds a force (N, world) to body `i`; with `point` (world, m) it also adds the
    /// torque `(point − p) × f` about the centre of mass at the current position.
    pub fn apply_force(&mut self, i: usize, f: [f64; 3], point: Option<[f64; 3]>) -> Result<()> {
        self.check_dynamic(i)?;
        crate::error::finite3("force", f).map_err(|e| e.context(format!("body {i}")))?;
        let tau = match point {
            Some(pt) => {
                crate::error::finite3("point", pt).map_err(|e| e.context(format!("body {i}")))?;
                Some((Vec3::from(pt) - Vec3::from(self.bodies.position[i])).cross(&Vec3::from(f)))
            }
            None => None,
        };
        self.bodies.force[i] = (Vec3::from(self.bodies.force[i]) + Vec3::from(f)).into();
        if let Some(t) = tau {
            self.bodies.torque[i] = (Vec3::from(self.bodies.torque[i]) + t).into();
        }
        Ok(())
    }

    /// Adds a torque (N·m, world) to body `i`.
    pub fn apply_torque(&mut self, i: usize, t: [f64; 3]) -> Result<()> {
        self.check_dynamic(i)?;
        crate::error::finite3("torque", t).map_err(|e| e.context(format!("body {i}")))?;
        self.bodies.torque[i] = (Vec3::from(self.bodies.torque[i]) + Vec3::from(t)).into();
        Ok(())
    }

    /// This step's contact points (empty without a collision stage).
    pub fn contacts(&self) -> Vec<crate::collide::narrow_phase::ContactReport> {
        self.collision.as_ref().map_or_else(Vec::new, |c| c.reports())
    }

    /// Sets every applied force and torque to zero.
    pub fn clear_forces(&mut self) {
        self.bodies.force.fill([0.0; 3]);
        self.bodies.torque.fill([0.0; 3]);
    }

    fn check_dynamic(&self, i: usize) -> Result<()> {
        let n = self.bodies.len();
        if i >= n {
            return Err(Error::input(format!("body index {i} is out of range: the world has {n} bodies")));
        }
        let kind = match self.bodies.kind[i] {
            BodyKind::Dynamic => return Ok(()),
            BodyKind::Fixed => "fixed",
            BodyKind::Kinematic => "kinematic",
        };
        Err(Error::input(format!("body {i} is {kind}: forces on it would have no effect")))
    }
}

/// A 1-dof drive's target at build (0 for joints without one).
fn initial_target(o: &super::joints::JointOptions) -> f64 {
    match &o.control.drive {
        Some(d) if d.target.len() == 1 => d.target[0],
        _ => 0.0,
    }
}
