//! The compiled simulation: state arrays of fixed layout and the pipeline of stages
//! the scene needs.

use std::time::Instant;

use nalgebra::Isometry3;

use super::pipeline::{plan, Stage, StageKind};
use super::profile::Profile;
use super::{validate, Scene, Settings};
use crate::body::{Bodies, Shape};
use crate::error::{Error, Result};
use crate::integrate::kick::KickSources;
use crate::integrate::{
    drift, euler, free_rotation, implicit_gyro, kick, rk4, symplectic_euler, BodyLists, Gyroscopic, InertiaClass,
    Integrator, Rotation,
};
use crate::math::Vec3;

/// The stages for the current force sources, with their profile slots.
#[derive(Clone, Debug, Default)]
struct Plan {
    forces: bool,
    stages: Vec<(Stage, usize)>,
}

pub struct World {
    /// Body state (views of these arrays are what Python sees).
    pub bodies: Bodies,
    /// Each body's shape and its pose in the body's principal frame.
    pub shapes: Vec<Option<(Shape, Isometry3<f64>)>>,
    pub(crate) gravity: Vec3,
    settings: Settings,
    rotation: Rotation,
    lists: BodyLists,
    plan: Plan,
    steps: u64,
    /// Whether the derived arrays (rotation, angular momentum, world inertia) are
    /// kept fresh after each `step` call; set once a user reads one of them.
    pub keep_derived: bool,
    pub profile: Profile,
}

impl World {
    pub(crate) fn new(scene: &Scene, settings: Settings) -> Result<Self> {
        let descs = scene.bodies();
        let mut bodies = Bodies::with_capacity(descs.len());
        for d in descs {
            bodies.push(&d.init);
        }
        let shapes = descs.iter().map(|d| d.shape.clone().map(|s| (s, d.shape_pose))).collect();
        let lists = BodyLists::new(&bodies);
        let rotation = settings.integrator.splitting().map_or(Rotation::Free, |s| s.rotation);
        let mut world = World {
            bodies,
            shapes,
            gravity: Vec3::from(scene.gravity),
            settings,
            rotation,
            lists,
            plan: Plan::default(),
            steps: 0,
            keep_derived: false,
            profile: Profile::default(),
        };
        world.replan(true);
        world.bodies.update_derived();
        Ok(world)
    }

    pub fn dt(&self) -> f64 {
        self.settings.dt
    }

    pub fn settings(&self) -> &Settings {
        &self.settings
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
    fn kick_sources(&self) -> KickSources {
        let nonzero = |a: &[[f64; 3]]| self.lists.dynamic.iter().any(|&i| a[i as usize] != [0.0; 3]);
        KickSources { gravity: self.gravity, force: nonzero(&self.bodies.force), torque: nonzero(&self.bodies.torque) }
    }

    fn replan(&mut self, force: bool) {
        let forces = self.kick_sources().any();
        if !force && forces == self.plan.forces {
            return;
        }
        let stages = plan(self.settings.integrator, &self.lists, forces);
        let stages = stages.into_iter().map(|s| (s, self.profile.slot(s.name()))).collect();
        self.plan = Plan { forces, stages };
    }

    /// Names of the stages one (sub)step runs now, in order.
    pub fn stage_names(&mut self) -> Vec<&'static str> {
        self.replan(false);
        self.plan.stages.iter().map(|(s, _)| s.name()).collect()
    }

    /// Advances `n` steps. The state is checked first: if a body is invalid (NaN,
    /// non-unit quaternion written through a view) nothing moves and the error
    /// names the body.
    pub fn step(&mut self, n: u64) -> Result<()> {
        validate::check(&self.bodies)?;
        validate::normalize(&mut self.bodies);
        self.replan(false);
        let src = self.kick_sources();
        let h = self.settings.dt / self.settings.substeps as f64;
        let stages = std::mem::take(&mut self.plan.stages);
        for _ in 0..n {
            for _ in 0..self.settings.substeps {
                for &(stage, slot) in &stages {
                    if self.profile.enabled {
                        let t0 = Instant::now();
                        self.run(stage, h, &src);
                        self.profile.add(slot, t0);
                    } else {
                        self.run(stage, h, &src);
                    }
                }
            }
        }
        self.plan.stages = stages;
        self.steps += n;
        self.profile.count_steps(n);
        if self.keep_derived {
            self.bodies.update_derived();
        }
        Ok(())
    }

    fn run(&mut self, stage: Stage, h: f64, src: &KickSources) {
        let h = h * stage.frac;
        let (b, l) = (&mut self.bodies, &self.lists);
        match stage.kind {
            StageKind::Forces => kick::kick(b, &l.dynamic, h, src),
            StageKind::Translate => drift::translate(b, &l.dynamic, h),
            StageKind::Rk4 => rk4::step(b, &l.dynamic, h, src),
            StageKind::Gyroscopic(Gyroscopic::Explicit) => symplectic_euler::gyroscopic_explicit(b, &l.anisotropic_index, h),
            StageKind::Gyroscopic(Gyroscopic::Implicit) => implicit_gyro::gyroscopic_implicit(b, &l.anisotropic_index, h),
            StageKind::Rotate(class) => rotate(b, l, class, self.rotation, h),
        }
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
        if self.bodies.kind[i] != crate::body::BodyKind::Dynamic {
            return Err(Error::input(format!("body {i} is fixed: forces on it would have no effect")));
        }
        Ok(())
    }
}

fn rotate(b: &mut Bodies, l: &BodyLists, class: InertiaClass, method: Rotation, h: f64) {
    use InertiaClass::*;
    match (method, class) {
        (Rotation::Free, Isotropic) => free_rotation::rotate_isotropic(b, &l.isotropic, h),
        (Rotation::Free, Symmetric) => free_rotation::rotate_symmetric(b, &l.symmetric, h),
        (Rotation::Free, Asymmetric) => free_rotation::rotate_asymmetric(b, &l.asymmetric, h),
        (Rotation::Euler, Isotropic) => euler::rotate_isotropic(b, &l.isotropic, h),
        (Rotation::Euler, c) => euler::rotate(b, l.indices(c), h),
        (Rotation::Exp, c) => symplectic_euler::rotate_exp(b, l.indices(c), h),
    }
}
