//! The stages a world runs each (sub)step, chosen from what the scene contains:
//! a stage with nothing to do is not in the list and costs nothing.

use crate::integrate::{BodyLists, Gyroscopic, InertiaClass, Integrator};

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StageKind {
    /// Velocity-level gyroscopic update of the non-isotropic bodies.
    Gyroscopic(Gyroscopic),
    /// Kick by gravity, applied forces and torques.
    Forces,
    /// `p += h v`.
    Translate,
    /// Rotation of the bodies of one inertia class by the integrator's method.
    Rotate(InertiaClass),
    /// The monolithic RK4 step.
    Rk4,
}

/// One stage: what it does and the fraction of the (sub)step it covers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stage {
    pub kind: StageKind,
    pub frac: f64,
}

impl Stage {
    pub fn name(&self) -> &'static str {
        match self.kind {
            StageKind::Gyroscopic(_) => "gyroscopic",
            StageKind::Forces => "forces",
            StageKind::Translate => "translate",
            StageKind::Rotate(InertiaClass::Isotropic) => "rotate_isotropic",
            StageKind::Rotate(InertiaClass::Symmetric) => "rotate_symmetric",
            StageKind::Rotate(InertiaClass::Asymmetric) => "rotate_asymmetric",
            StageKind::Rk4 => "rk4",
        }
    }
}

/// The stages of one (sub)step for `integrator`, given the bodies by class and
/// whether any force or torque acts.
pub fn plan(integrator: Integrator, lists: &BodyLists, forces: bool) -> Vec<Stage> {
    let mut stages = Vec::new();
    if lists.dynamic.is_empty() {
        return stages;
    }
    let Some(split) = integrator.splitting() else {
        stages.push(Stage { kind: StageKind::Rk4, frac: 1.0 });
        return stages;
    };
    let classes = [InertiaClass::Isotropic, InertiaClass::Symmetric, InertiaClass::Asymmetric];
    let anisotropic = lists.symmetric.len() + lists.asymmetric.len();
    if let (Some(g), true) = (split.gyroscopic, anisotropic > 0) {
        stages.push(Stage { kind: StageKind::Gyroscopic(g), frac: 1.0 });
    }
    let kick = |stages: &mut Vec<Stage>, frac: f64| {
        if forces && frac != 0.0 {
            stages.push(Stage { kind: StageKind::Forces, frac });
        }
    };
    for (j, &drift) in split.drifts.iter().enumerate() {
        kick(&mut stages, split.kicks[j]);
        stages.push(Stage { kind: StageKind::Translate, frac: drift });
        for class in classes.into_iter().filter(|&c| lists.count(c) > 0) {
            stages.push(Stage { kind: StageKind::Rotate(class), frac: drift });
        }
    }
    kick(&mut stages, split.kicks[split.drifts.len()]);
    stages
}
