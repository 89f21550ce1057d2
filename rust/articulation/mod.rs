//! Articulations in reduced coordinates: trees of bodies (and floating bases)
//! whose joints are coordinates `q`, `v` rather than constraints, so a joint
//! never opens. A world's `articulation` stage advances each articulation by
//! its integrator ([`ArticulationIntegrator`]: [`leapfrog`] by default,
//! [`euler`], [`rk4`]) with substeps chosen from its state ([`substeps`]), each
//! evaluation one articulated-body solve ([`aba`], O(links)); drives, damping,
//! armature and friction ([`control`]) are implicit in the kicks, limits are
//! impulses ([`limits`]). The links stay rows of the world's bodies: their poses
//! and velocities are written from `q`, `v` after every step ([`kinematics`]).
//!
//! Which joints become articulations is decided by [`build`] from the joint
//! graph; the world passes what it knows (bodies, joints, which links could
//! touch a collider).

pub mod aba;
pub mod build;
pub mod contact;
pub mod control;
pub mod dynamics;
pub mod euler;
pub mod joint;
pub mod kinematics;
pub mod leapfrog;
pub mod limits;
pub mod model;
pub mod momentum;
pub mod rk4;
pub mod single;
pub mod spatial;
pub mod substeps;

pub use control::{Control, Drive, DriveMode};
pub use joint::JointModel;
pub use model::Articulation;

use crate::body::Bodies;
use crate::error::{Error, Result};
use crate::math::Vec3;
use dynamics::{Env, Scratch};

/// How articulations are integrated in time.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum ArticulationIntegrator {
    /// Reversible leapfrog, second order; the default.
    Leapfrog,
    /// Semi-implicit Euler, first order.
    Euler,
    /// Classical Runge–Kutta on the joint charts, fourth order.
    Rk4,
}

impl ArticulationIntegrator {
    pub const ALL: [ArticulationIntegrator; 3] =
        [ArticulationIntegrator::Leapfrog, ArticulationIntegrator::Euler, ArticulationIntegrator::Rk4];

    pub fn name(self) -> &'static str {
        match self {
            ArticulationIntegrator::Leapfrog => "leapfrog",
            ArticulationIntegrator::Euler => "euler",
            ArticulationIntegrator::Rk4 => "rk4",
        }
    }

    pub fn order(self) -> u32 {
        match self {
            ArticulationIntegrator::Leapfrog => 2,
            ArticulationIntegrator::Euler => 1,
            ArticulationIntegrator::Rk4 => 4,
        }
    }

    /// The `h ω` each substep is held to when substeps are automatic.
    pub fn kappa(self) -> f64 {
        match self {
            ArticulationIntegrator::Leapfrog => KAPPA,
            ArticulationIntegrator::Euler => KAPPA,
            ArticulationIntegrator::Rk4 => 2.0 * KAPPA,
        }
    }

    pub fn from_name(name: &str) -> Result<Self> {
        Self::ALL.into_iter().find(|i| i.name() == name).ok_or_else(|| {
            let names: Vec<&str> = Self::ALL.iter().map(|i| i.name()).collect();
            Error::input(format!("articulation_integrator: unknown name {name:?}; choose one of {}", names.join(", ")))
        })
    }
}

/// `h ω` per substep for the second-order methods (see [`substeps`]).
pub const KAPPA: f64 = 0.25;

/// Build options of articulations.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ArticulationSettings {
    /// Whether tree-shaped joint systems become articulations. Default true;
    /// false keeps every joint XPBD.
    pub enabled: bool,
    pub integrator: ArticulationIntegrator,
    /// Substeps per step; `None`: chosen each step from the state.
    pub substeps: Option<u32>,
}

impl Default for ArticulationSettings {
    fn default() -> Self {
        Self { enabled: true, integrator: ArticulationIntegrator::Leapfrog, substeps: None }
    }
}

/// Every articulation of a world.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Articulations {
    pub list: Vec<Articulation>,
    pub settings: ArticulationSettings,
    scratch: Scratch,
    leap: Vec<leapfrog::Buffers>,
    rk: Vec<rk4::Buffers>,
    /// The closed form of each single hinge or slide on the world.
    single: Vec<Option<single::Single>>,
    /// Per articulation: it steps inside the contact substeps this step (see
    /// [`contact`]), not in the `articulation` stage.
    contact: Vec<bool>,
    /// Per articulation in contact: what this substep's kick did to its linear
    /// momentum beyond the external impulse (see [`momentum`]).
    momentum_error: Vec<Vec3>,
}

impl Articulations {
    pub fn new(list: Vec<Articulation>, settings: ArticulationSettings, gravity: Vec3) -> Self {
        let n = list.len();
        let single = list.iter().map(|a| single::Single::of(a).map(|s| s.with_gravity(&gravity, a.links[0].mass))).collect();
        Self { list, settings, scratch: Scratch::default(), leap: vec![Default::default(); n], rk: vec![Default::default(); n], single, contact: vec![false; n], momentum_error: vec![Vec3::zeros(); n] }
    }

    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// Forgets what the last step left for the next (call when the state, the
    /// targets or the applied forces may have changed).
    pub fn invalidate(&mut self) {
        for b in &mut self.leap {
            b.last_valid = false;
        }
        for a in &mut self.list {
            a.cached_qdd = None;
        }
    }

    /// Writes every link's pose and velocity from `q`, `v` into `bodies`.
    pub fn write_bodies(&mut self, bodies: &mut Bodies) {
        for (art, single) in self.list.iter_mut().zip(&self.single) {
            if let Some(s) = single {
                s.write(art, bodies);
                continue;
            }
            let (q, v) = (std::mem::take(&mut art.q), std::mem::take(&mut art.v));
            kinematics::forward(art, &q, &v, bodies, false);
            art.q = q;
            art.v = v;
            kinematics::write_bodies(art, bodies);
        }
    }

    /// Refreshes the joint reactions of the closed-form articulations (the
    /// general ones leave theirs from their last solve).
    pub fn refresh_reactions(&mut self, bodies: &Bodies, gravity: &Vec3) {
        for (art, single) in self.list.iter_mut().zip(&self.single) {
            if let Some(s) = single {
                s.reaction(art, gravity, bodies);
            }
        }
    }

    /// The `articulation` stage: one step `dt` of every articulation not in
    /// contact this step, then the links' poses and velocities written to `bodies`.
    pub fn step(&mut self, bodies: &mut Bodies, gravity: &Vec3, dt: f64) {
        for k in 0..self.list.len() {
            if self.in_contact(k) {
                continue;
            }
            let art = &mut self.list[k];
            if art.links.iter().all(|l| bodies.sleeping[l.body as usize]) {
                art.v.fill(0.0);
                continue;
            }
            if let (Some(s), false) = (&self.single[k], self.settings.integrator == ArticulationIntegrator::Rk4) {
                step_single(s, art, &self.settings, dt, gravity, bodies, &mut self.scratch.terms);
                continue;
            }
            let external = art.links.iter().any(|l| {
                let b = l.body as usize;
                bodies.force[b] != [0.0; 3] || bodies.torque[b] != [0.0; 3]
            });
            let integrator = self.settings.integrator;
            let env = Env { bodies, gravity: *gravity, external };
            if art.work.first().is_some_and(|w| w.inertia[(3, 3)] == 0.0) {
                let mut qdd = vec![0.0; art.nv];
                let (q, v) = (art.q.clone(), art.v.clone());
                dynamics::accelerations(art, &env, &q, &v, &v, None, &mut self.scratch, &mut qdd);
            }
            let mut applied = std::mem::take(&mut art.applied);
            applied.fill(0.0);
            let drives = integrator == ArticulationIntegrator::Rk4;
            // Automatic substeps: the rate is estimated again before every substep
            // (from the state and the reactions of the last solve), so a chain
            // that starts to whip within a step gets shorter substeps at once.
            let floating = momentum::floating(art);
            let mut p = if floating { momentum::measure(art, bodies) } else { Vec3::zeros() };
            let (mut left, mut n) = (dt, 0u32);
            while left > 0.0 {
                let remaining = match self.settings.substeps {
                    Some(fixed) => fixed.saturating_sub(n).max(1),
                    None => substeps::count(left, substeps::fastest_rate(art, drives), integrator.kappa())
                        .min(substeps::MAX_SUBSTEPS.saturating_sub(n).max(1)),
                };
                let h = if remaining <= 1 { left } else { left / remaining as f64 };
                match integrator {
                    ArticulationIntegrator::Leapfrog => {
                        leapfrog::substep(art, &env, h, &mut self.scratch, &mut self.leap[k], &mut applied)
                    }
                    ArticulationIntegrator::Euler => {
                        euler::substep(art, &env, h, &mut self.scratch, &mut self.leap[k], &mut applied)
                    }
                    ArticulationIntegrator::Rk4 => rk4::substep(art, &env, h, &mut self.scratch, &mut self.rk[k], &mut applied),
                }
                if floating {
                    p += momentum::external_impulse(art, bodies, gravity, h);
                    momentum::settle(art, bodies, &p);
                }
                left = if remaining <= 1 { 0.0 } else { left - h };
                n += 1;
            }
            for x in applied.iter_mut() {
                *x /= dt;
            }
            art.applied = applied;
            art.last_substeps = n;
            let (q, v) = (std::mem::take(&mut art.q), std::mem::take(&mut art.v));
            kinematics::forward(art, &q, &v, bodies, false);
            art.q = q;
            art.v = v;
            kinematics::write_bodies(art, bodies);
        }
    }
}

/// One step of a single hinge or slide on the world, by its closed form.
fn step_single(
    s: &single::Single,
    art: &mut Articulation,
    settings: &ArticulationSettings,
    dt: f64,
    gravity: &Vec3,
    bodies: &mut Bodies,
    terms: &mut Vec<control::Term>,
) {
    let euler = settings.integrator == ArticulationIntegrator::Euler;
    let mut applied = [0.0];
    let (mut left, mut n) = (dt, 0u32);
    while left > 0.0 {
        let remaining = match settings.substeps {
            Some(fixed) => fixed.saturating_sub(n).max(1),
            None => substeps::count(left, s.fastest_rate(art, gravity), settings.integrator.kappa())
                .min(substeps::MAX_SUBSTEPS.saturating_sub(n).max(1)),
        };
        let h = if remaining <= 1 { left } else { left / remaining as f64 };
        s.substep(art, euler, h, gravity, bodies, terms, &mut applied);
        left = if remaining <= 1 { 0.0 } else { left - h };
        n += 1;
    }
    art.applied[0] = applied[0] / dt;
    art.last_substeps = n;
    s.write(art, bodies);
}
