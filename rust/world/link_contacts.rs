//! The world's side of contacts on articulated links: which articulations step
//! inside the contact substeps this step (those with a link in some contact the
//! narrow phase found), their kick and drift stages, and the hand-over of their
//! joint velocities to and from the contact solver around each solve pass (see
//! [`crate::articulation::contact`] and [`crate::solve::generalized`]).

use super::scene::BodyDesc;
use super::World;

impl World {
    /// After the narrow phase: the articulations with a link in a contact step
    /// inside the contact substeps this step; the others take their whole step
    /// in the `articulation` stage.
    pub(crate) fn mark_articulation_contacts(&mut self) {
        if self.articulations.is_empty() {
            return;
        }
        let gen = self.collision.as_ref().map(|c| &c.solver.gen);
        self.articulations.set_contact(|a| gen.is_some_and(|g| g.in_contact(a)));
    }

    /// The `articulation_contact` stage before the contact solve.
    pub(crate) fn articulation_kick(&mut self, h: f64) {
        let g = self.gravity;
        self.articulations.contact_kick(&self.bodies, &g, h);
    }

    /// The `articulation_contact` stage after the contact solve: limits, drift,
    /// the links written at their new poses.
    pub(crate) fn articulation_drift(&mut self, h: f64) {
        let g = self.gravity;
        self.articulations.contact_drift(&mut self.bodies, &g, h);
    }

    /// After the solver's gather: the joint velocities and rows of the
    /// articulations in contact.
    pub(crate) fn gather_links(&mut self) {
        if let Some(c) = self.collision.as_mut() {
            c.solver.gather_links(&mut self.articulations);
        }
    }

    /// After the solver's scatter: the solved joint velocities back to the
    /// articulations, and their links' velocities to the bodies.
    pub(crate) fn scatter_links(&mut self) {
        let Some(c) = self.collision.as_mut() else { return };
        if c.solver.gen.slots.is_empty() {
            return;
        }
        c.solver.scatter_links(&mut self.articulations);
        self.articulations.write_contact_velocities(&mut self.bodies);
    }

    /// The substeps of this step and their length, after the narrow phase:
    /// `base` (the world's, or the rocking substeps; `h` each), or more if an
    /// articulation in contact needs them (the contact solver then takes the
    /// shorter substep).
    pub(crate) fn step_substeps(&mut self, base: u32, h: f64) -> (u32, f64) {
        if !self.articulations.any_contact() {
            return (base, h);
        }
        let dt = self.settings.dt;
        let n = self.articulations.contact_substeps(dt, base);
        if n == base {
            return (n, h);
        }
        let h = dt / n as f64;
        if let Some(c) = self.collision.as_mut() {
            c.solver.set_substep(h);
        }
        (n, h)
    }

    /// After the substeps of a step: the applied forces of the articulations in
    /// contact averaged over the step.
    pub(crate) fn finish_link_contacts(&mut self, substeps: u32) {
        if self.articulations.any_contact() {
            self.articulations.finish_contact(self.settings.dt, substeps);
        }
    }
}

/// Whether some articulated link (`articulated[b]`) has a collider that
/// another body's collider allows by filter.
pub(crate) fn links_may_touch(descs: &[BodyDesc], articulated: &[bool]) -> bool {
    descs.iter().enumerate().any(|(i, link)| {
        articulated[i]
            && link.shape.is_some()
            && descs.iter().enumerate().any(|(k, d)| k != i && d.shape.is_some() && link.filter.allows(&d.filter))
    })
}
