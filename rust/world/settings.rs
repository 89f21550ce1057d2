//! Parameters of [`super::Scene::build`], each with its unit and default.

use crate::error::{non_negative, positive, Error, Result};
use crate::integrate::Integrator;
use crate::solve::islands::SleepSettings;
use crate::solve::SolverSettings;

#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Settings {
    /// Time step of one `World::step` (s). No default: the caller chooses it.
    pub dt: f64,
    /// The time integrator. Default: [`Integrator::Strang`].
    pub integrator: Integrator,
    /// Substeps per step: each runs the substep stages with `dt / substeps`.
    /// Default (`None`): 1 without contacts, 4 with them; with XPBD joints at
    /// least half the joints of the largest jointed system (at most 64); and at
    /// least what the scene's particle links ask for
    /// ([`crate::xpbd::substeps::for_links`]: a particle travels at most 0.1 of its
    /// structure's shortest link per substep).
    pub substeps: Option<u32>,
    /// Contact solver iterations per substep (and as many relax iterations),
    /// Gauss–Seidel passes over the joints per substep, and symmetric passes over
    /// the particle constraints per substep. Default 1; a step of a settling
    /// pile takes at least 2 contact iterations (see `solve::second_pass`).
    pub iterations: u32,
    /// Largest angle (rad) a body may turn by per rotation substep of the split
    /// integrators (`strang`, `yoshida4`, `suzuki4`) and of `rk4`, taken at the
    /// largest `|ω|` of its free orbit: a body over it has its rotation
    /// subdivided, alone (`integrate::free_rotation::Substeps`). Default
    /// (`None`): the integrator's own, [`Integrator::max_split_angle`] (0.2,
    /// 0.5, 0.6, 0.03 rad);
    /// `f64::INFINITY` never subdivides (the bare method, for convergence studies).
    pub max_rotation_angle: Option<f64>,
    pub solver: SolverSettings,
    pub sleep: SleepSettings,
    /// Articulations: on/off, integrator, substeps (see [`crate::articulation`]).
    pub articulation: crate::articulation::ArticulationSettings,
    /// Worker threads the world's own parallel work may use (≥ 1): the free
    /// rotation of large groups, the contact solve of many contact islands,
    /// and then (or with many contact pairs) the narrow phase and constraint
    /// build. Default (`None`): every core
    /// (`available_parallelism`). The result is bitwise the same for every count
    /// (see [`super::threads`]).
    pub threads: Option<u32>,
}

impl Settings {
    pub fn new(dt: f64) -> Self {
        Self {
            dt,
            integrator: Integrator::Strang,
            substeps: None,
            iterations: 1,
            max_rotation_angle: None,
            solver: SolverSettings::default(),
            sleep: SleepSettings::default(),
            articulation: Default::default(),
            threads: None,
        }
    }

    /// The largest split angle per rotation substep (rad) this world uses.
    pub fn rotation_angle(&self) -> f64 {
        self.max_rotation_angle.unwrap_or(self.integrator.max_split_angle())
    }

    pub fn validate(&self) -> Result<()> {
        positive("dt", self.dt)?;
        if self.substeps == Some(0) {
            return Err(Error::input("substeps must be at least 1, got 0"));
        }
        if self.articulation.substeps == Some(0) {
            return Err(Error::input("articulation_substeps must be at least 1, got 0"));
        }
        if self.threads == Some(0) {
            return Err(Error::input("threads must be at least 1, got 0"));
        }
        if self.iterations == 0 {
            return Err(Error::input("iterations must be at least 1, got 0"));
        }
        if let Some(a) = self.max_rotation_angle {
            if a.is_nan() || a <= 0.0 {
                return Err(Error::input(format!(
                    "max_rotation_angle must be positive (rad; inf turns rotation substeps off), got {a}"
                )));
            }
        }
        let s = &self.solver;
        non_negative("contact_hertz", s.contact_hertz)?;
        non_negative("contact_damping_ratio", s.contact_damping_ratio)?;
        positive("max_push_velocity", s.max_push_velocity)?;
        if let Some(t) = s.restitution_threshold {
            non_negative("restitution_threshold", t)?;
        }
        non_negative("slop", s.slop)?;
        non_negative("sleep linear threshold", self.sleep.linear)?;
        non_negative("sleep angular threshold", self.sleep.angular)?;
        non_negative("sleep time", self.sleep.time)?;
        Ok(())
    }
}
