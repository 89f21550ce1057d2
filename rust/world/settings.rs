//! Parameters of [`super::Scene::build`], each with its unit and default.

use crate::error::{positive, Error, Result};
use crate::integrate::Integrator;

#[derive(Clone, Debug)]
pub struct Settings {
    /// Time step of one `World::step` (s). No default: the caller chooses it.
    pub dt: f64,
    /// The time integrator. Default: [`Integrator::Strang`].
    pub integrator: Integrator,
    /// Substeps per step: each runs the pipeline with `dt / substeps`. Default: 1.
    pub substeps: u32,
}

impl Settings {
    pub fn new(dt: f64) -> Self {
        Self { dt, integrator: Integrator::Strang, substeps: 1 }
    }

    pub fn validate(&self) -> Result<()> {
        positive("dt", self.dt)?;
        if self.substeps == 0 {
            return Err(Error::input("substeps must be at least 1, got 0"));
        }
        Ok(())
    }
}
