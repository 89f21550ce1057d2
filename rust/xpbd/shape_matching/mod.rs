//! Shape matching (Müller, Heidelberger, Teschner, Gross 2005, "Meshless
//! deformations based on shape matching") on XPBD particles: clusters in rigid,
//! linear and quadratic modes, volume preservation for the linear mode,
//! overlapping clusters and plasticity.
//!
//! Each substep, after the particles' prediction and before their constraint
//! projection (so collisions have the last word), every cluster computes the goal
//! positions of its particles from their predicted positions ([`goal`]); each
//! particle moves by the average over its clusters of `stiffness·(g − x)`. A
//! particle's mass is shared among the `c` clusters that hold it (weight `m/c`
//! in each), so every cluster's correction keeps the linear and angular momentum
//! (see [`goal`]) and so does their average. Pinned particles are matched with
//! their mass but never moved. The stiffness acts per substep: more substeps make
//! a cluster with stiffness < 1 stiffer.

pub mod cluster;
pub mod goal;
pub mod plasticity;
pub mod rotation;

pub use cluster::{Cluster, ClusterSpec, Mode};
pub use plasticity::Plasticity;

use super::particles::Particles;
use crate::error::Result;
use crate::math::Vec3;

/// The clusters of a world and the scratch space of their stage.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct ShapeMatching {
    pub clusters: Vec<Cluster>,
    /// Particles in at least one cluster, and per particle the number of clusters.
    members: Vec<u32>,
    count: Vec<u32>,
    /// Sum of the corrections of each particle (m), and one cluster's goals.
    sum: Vec<Vec3>,
    goals: Vec<Vec3>,
}

impl ShapeMatching {
    /// Shares each particle's mass among its clusters and prepares their rest
    /// shapes from the particles' positions as added.
    pub fn new(mut clusters: Vec<Cluster>, p: &Particles) -> Result<Self> {
        let mut count = vec![0u32; p.len()];
        for c in &clusters {
            for &i in &c.particles {
                count[i as usize] += 1;
            }
        }
        for (k, c) in clusters.iter_mut().enumerate() {
            let w = c.particles.iter().map(|&i| p.mass[i as usize] / count[i as usize] as f64).collect();
            let x: Vec<Vec3> = c.particles.iter().map(|&i| Vec3::from(p.initial[i as usize])).collect();
            c.set_weights(w, &x).map_err(|e| e.context(format!("cluster {k}")))?;
        }
        let members = (0..p.len() as u32).filter(|&i| count[i as usize] > 0).collect();
        Ok(Self { clusters, members, count, sum: vec![Vec3::zeros(); p.len()], goals: Vec::new() })
    }

    pub fn is_empty(&self) -> bool {
        self.clusters.is_empty()
    }

    /// One substep of `h` seconds: goals, averaged corrections, plastic flow.
    pub fn apply(&mut self, p: &mut Particles, h: f64) {
        for &i in &self.members {
            self.sum[i as usize] = Vec3::zeros();
        }
        for c in &mut self.clusters {
            let fit = goal::goals(c, &p.position, &mut self.goals);
            let s = c.spec.stiffness;
            for (&i, g) in c.particles.iter().zip(&self.goals) {
                self.sum[i as usize] += (g - Vec3::from(p.position[i as usize])) * s;
            }
            if let Some(pl) = c.spec.plasticity {
                let elastic = fit.rotation.transpose() * fit.linear;
                if plasticity::flow(&pl, &mut c.plastic, &elastic, h) {
                    c.rest = c.rest0.iter().map(|q| c.plastic * q).collect();
                    // A unit-volume Sp keeps the moments invertible.
                    let _ = c.update_moments();
                }
            }
        }
        for &i in &self.members {
            let i = i as usize;
            if p.inv_mass[i] > 0.0 {
                let dx = self.sum[i] / self.count[i] as f64;
                p.position[i] = (Vec3::from(p.position[i]) + dx).into();
            }
        }
    }
}
