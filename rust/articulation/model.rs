//! One articulation: a tree of links (each a row of the world's bodies) joined
//! to its parent by a joint model, its coordinates `q`, `v`, and the work arrays
//! the recursions fill. Links are stored parent before child.

use super::control::Control;
use super::joint::{Frames, JointModel, Pose};
use super::spatial::{Mat6, Vec6};

/// What a link hangs from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Parent {
    /// The world frame.
    World,
    /// A fixed body (its current pose is read each step).
    Fixed(u32),
    /// An earlier link of the same articulation.
    Link(usize),
}

#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Link {
    /// Row in the world's bodies.
    pub body: u32,
    pub parent: Parent,
    /// Index of the scene joint that makes this link's joint; `None` for a
    /// floating root's free joint.
    pub joint: Option<usize>,
    /// Whether the scene joint's body a is this link (else it is the parent).
    pub child_is_a: bool,
    pub model: JointModel,
    pub frames: Frames,
    /// Offsets of this joint's coordinates in `q` and `v`.
    pub q_at: usize,
    pub v_at: usize,
    /// Mass (kg) and principal moments (kg·m²).
    pub mass: f64,
    pub inertia: [f64; 3],
    /// Drive, damping, armature, friction and limits of the joint.
    pub control: Control,
}

/// Per-link results of the recursions (world frame, about the origin).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct LinkWork {
    pub pose: Pose,
    /// Motion subspace columns (the first `nv`).
    pub s: [Vec6; 6],
    /// Spatial velocity and the velocity-product acceleration `Ṡ v`.
    pub vel: Vec6,
    pub c: Vec6,
    /// Spatial inertia, articulated inertia and articulated bias force.
    pub inertia: Mat6,
    /// `v ×* I v − f_ext` from the first pass (the accumulators start from it).
    pub bias: Vec6,
    pub ia: Mat6,
    pub pa: Vec6,
    /// `U = I^A S`, `D⁻¹` (top-left `nv × nv`) and `u = τ − Sᵀ p^A`.
    pub u_mat: [Vec6; 6],
    pub d_inv: Mat6,
    pub u: [f64; 6],
    /// Spatial acceleration (gravity offset: the base accelerates at −g).
    pub acc: Vec6,
    /// Spatial force the parent transmits to this link's subtree.
    pub reaction: Vec6,
}

impl Default for LinkWork {
    fn default() -> Self {
        Self {
            pose: Pose::identity(),
            s: [Vec6::zeros(); 6],
            vel: Vec6::zeros(),
            c: Vec6::zeros(),
            inertia: Mat6::zeros(),
            bias: Vec6::zeros(),
            ia: Mat6::zeros(),
            pa: Vec6::zeros(),
            u_mat: [Vec6::zeros(); 6],
            d_inv: Mat6::zeros(),
            u: [0.0; 6],
            acc: Vec6::zeros(),
            reaction: Vec6::zeros(),
        }
    }
}

#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Articulation {
    pub links: Vec<Link>,
    pub nq: usize,
    pub nv: usize,
    pub q: Vec<f64>,
    pub v: Vec<f64>,
    pub work: Vec<LinkWork>,
    /// Generalized force (N·m or N per dof) the joint controls applied over the
    /// last step, averaged over its substeps.
    pub applied: Vec<f64>,
    /// Substeps the last step took.
    pub last_substeps: u32,
    /// Whether `q̈` depends on `v` (anything but a single 1-dof link).
    pub velocity_dependent: bool,
    /// A single passive hinge or slide: `q̈` at the end of its last substep.
    pub cached_qdd: Option<f64>,
    /// A single hinge: `(q, sin q/2, cos q/2)` of its last evaluation.
    pub cached_half: Option<(f64, f64, f64)>,
}

impl Articulation {
    pub fn new(links: Vec<Link>, q: Vec<f64>, v: Vec<f64>) -> Self {
        let nq = links.iter().map(|l| l.model.nq()).sum();
        let nv = links.iter().map(|l| l.model.nv()).sum();
        let work = vec![LinkWork::default(); links.len()];
        use super::joint::JointModel::{Fixed, Prismatic, Revolute};
        let single = links.len() == 1 && matches!(links[0].model, Revolute | Prismatic | Fixed);
        Self { links, nq, nv, q, v, work, applied: vec![0.0; nv], last_substeps: 0, velocity_dependent: !single, cached_qdd: None, cached_half: None }
    }
}
