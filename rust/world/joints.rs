//! Joints in the scene and the world: `Scene::add_joint` validates and compiles a
//! [`JointSpec`]; the world's `joints` stage projects them each substep (see
//! [`crate::xpbd::joints`] and, for where the stage sits in a substep,
//! [`super::pipeline`]); the forces they applied are read back per joint.

use super::{Scene, World};
use crate::articulation::{Control, DriveMode};
use crate::error::{non_negative, Error, Result};
use crate::xpbd::joints::{Joint, JointKind, JointSpec};

/// Which solver a joint asks for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum SolverChoice {
    /// An articulation where the joint graph allows it, else XPBD.
    #[default]
    Auto,
    /// Always XPBD.
    Xpbd,
    /// An articulation, or an error when the world is built.
    Articulation,
}

impl SolverChoice {
    pub fn from_name(name: &str) -> Result<Self> {
        match name {
            "auto" => Ok(Self::Auto),
            "xpbd" => Ok(Self::Xpbd),
            "articulation" => Ok(Self::Articulation),
            _ => Err(Error::input(format!("solver: unknown solver {name:?}; choose auto, xpbd or articulation"))),
        }
    }
}

/// What `add_joint` takes besides the geometry: a name, the solver, controls.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct JointOptions {
    pub name: Option<String>,
    pub solver: SolverChoice,
    /// Drive, damping, armature, friction, cone and twist limits (the hinge or
    /// slide range is the spec's `limits`).
    pub control: Control,
}

impl JointOptions {
    /// Checks the controls against the joint kind.
    fn validate(&self, kind: JointKind) -> Result<()> {
        let c = &self.control;
        let name = kind.name();
        non_negative("damping", c.damping)?;
        non_negative("armature", c.armature)?;
        non_negative("friction", c.friction)?;
        let controlled = c.drive.is_some() || c.damping > 0.0 || c.armature > 0.0 || c.friction > 0.0;
        let dofs = matches!(kind, JointKind::Hinge | JointKind::Prismatic | JointKind::Spherical);
        if controlled && !dofs {
            return Err(Error::input(format!("drive: a {name} joint has no free motion to drive, damp or brake")));
        }
        if (c.cone.is_some() || c.twist.is_some()) && kind != JointKind::Spherical {
            return Err(Error::input(format!("cone_limit: cone and twist limits are for spherical joints, not {name}")));
        }
        if let Some(cone) = c.cone {
            if !(cone.is_finite() && cone > 0.0 && cone <= std::f64::consts::PI) {
                return Err(Error::input(format!("cone_limit must be in (0, pi] rad, got {cone}")));
            }
        }
        if let Some([lo, hi]) = c.twist {
            let pi = std::f64::consts::PI;
            if !(lo.is_finite() && hi.is_finite() && -pi <= lo && lo <= hi && hi <= pi) {
                return Err(Error::input(format!("twist_limits must satisfy -pi <= lo <= hi <= pi rad, got [{lo}, {hi}]")));
            }
        }
        if let Some(d) = &c.drive {
            non_negative("drive stiffness", d.stiffness)?;
            non_negative("drive damping", d.damping)?;
            if !(d.max_force > 0.0) || d.max_force.is_nan() {
                return Err(Error::input(format!("drive max_force must be positive (inf: no limit), got {}", d.max_force)));
            }
            if d.mode == DriveMode::Velocity && d.stiffness != 0.0 {
                return Err(Error::input("drive stiffness: a velocity drive has no stiffness (give damping)"));
            }
            let want = match (kind, d.mode) {
                (JointKind::Spherical, DriveMode::Position) => 4,
                (JointKind::Spherical, DriveMode::Velocity) => 3,
                _ => 1,
            };
            if d.target.len() != want || !d.target.iter().all(|x| x.is_finite()) {
                return Err(Error::input(format!(
                    "drive target: a {name} joint's {} drive takes {want} finite value(s), got {:?}",
                    if d.mode == DriveMode::Position { "position" } else { "velocity" },
                    d.target
                )));
            }
        }
        if self.solver == SolverChoice::Xpbd && (controlled || c.cone.is_some() || c.twist.is_some()) {
            return Err(Error::input(
                "solver: drives, damping, armature, friction and cone/twist limits need an articulation, not solver=\"xpbd\"",
            ));
        }
        Ok(())
    }
}

impl Scene {
    /// Validates `spec` against the bodies added so far and adds the joint;
    /// returns its index. On error (naming the joint and the field) the scene is
    /// unchanged.
    pub fn add_joint(&mut self, spec: JointSpec) -> Result<usize> {
        self.add_joint_with(spec, JointOptions::default())
    }

    /// [`Scene::add_joint`] with a name, a solver choice and controls.
    pub fn add_joint_with(&mut self, spec: JointSpec, mut options: JointOptions) -> Result<usize> {
        let index = self.joints.len();
        let context = |e: Error| e.context(format!("joint {index}"));
        let bodies = self.bodies();
        let joint = spec.compile(bodies.len(), |i| &bodies[i].init).map_err(context)?;
        options.validate(spec.kind).map_err(context)?;
        if let Some(name) = &options.name {
            if self.joint_options.iter().any(|o| o.name.as_ref() == Some(name)) {
                return Err(context(Error::input(format!("name {name:?} is taken by another joint"))));
            }
        }
        if spec.kind == JointKind::Spherical && options.control.drive.as_ref().is_some_and(|d| d.mode == DriveMode::Position) {
            if let Some(d) = options.control.drive.as_mut() {
                let n = d.target.iter().map(|x| x * x).sum::<f64>().sqrt();
                if !(n > 1e-12) {
                    return Err(context(Error::input("drive target: a spherical position target must be a non-zero quaternion")));
                }
                d.target.iter_mut().for_each(|x| *x /= n);
            }
        }
        self.joints.push(joint);
        self.joint_options.push(options);
        Ok(index)
    }

    pub fn joint_options(&self) -> &[JointOptions] {
        &self.joint_options
    }

    pub fn joints(&self) -> &[Joint] {
        &self.joints
    }
}

impl World {
    /// The `joints` stage: one substep's projection of every joint.
    pub(crate) fn project_joints(&mut self, h: f64) {
        self.joints.project(&mut self.bodies, h, self.settings.iterations);
    }

    /// Force (N, world) each joint applied to its body a over the last substep
    /// (an articulated joint: the force it transmits at the step's end); body b
    /// received the opposite.
    pub fn joint_forces(&mut self) -> &[[f64; 3]] {
        self.read_joint_wrenches();
        &self.joints.force
    }

    /// Couple (N·m, world) each joint's angular constraints applied to body a
    /// over the last substep: with the force, the wrench about a's anchor.
    pub fn joint_torques(&mut self) -> &[[f64; 3]] {
        self.read_joint_wrenches();
        &self.joints.torque
    }

    /// Body pairs tied by a joint, smaller index first (the world left out).
    pub(crate) fn joint_pairs(scene: &Scene) -> Vec<(u32, u32)> {
        let mut pairs: Vec<(u32, u32)> =
            scene.joints().iter().filter_map(|j| j.body_b.map(|b| (j.body_a.min(b), j.body_a.max(b)))).collect();
        pairs.sort_unstable();
        pairs.dedup();
        pairs
    }
}

/// The substeps a world with XPBD joints takes by default: half the joints of
/// its largest connected system of XPBD joints (rounded up), at most
/// [`XPBD_MAX_SUBSTEPS`]. XPBD hands a load along a chain one joint per
/// Gauss–Seidel pass and is first order in the substep: measured at dt = 1/60,
/// chains of 2 cm links released horizontally explode below 8 substeps (50 and
/// 100 links) and hold with ~N/2 (50 links at 25: largest gap ~1.6 mm; 100 links
/// at 50: ~2 mm over 5 s).
pub(crate) fn xpbd_substeps(scene: &Scene, articulated: &[bool]) -> u32 {
    let n = scene.bodies().len();
    let mut parent: Vec<usize> = (0..=n).collect();
    fn find(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    let node = |b: Option<u32>| b.map_or(n, |b| b as usize);
    let mut count = vec![0u32; n + 1];
    let live: Vec<&Joint> = scene.joints().iter().zip(articulated).filter(|(_, &a)| !a).map(|(j, _)| j).collect();
    for j in &live {
        let (a, b) = (find(&mut parent, node(Some(j.body_a))), find(&mut parent, node(j.body_b)));
        if a != b {
            parent[a] = b;
        }
    }
    for j in &live {
        let r = find(&mut parent, node(Some(j.body_a)));
        count[r] += 1;
    }
    let largest = count.into_iter().max().unwrap_or(0);
    largest.div_ceil(2).clamp(1, XPBD_MAX_SUBSTEPS)
}

/// The most substeps [`xpbd_substeps`] chooses.
pub const XPBD_MAX_SUBSTEPS: u32 = 64;

/// Whether bodies `a` and `b` are tied by a joint (`pairs` sorted, smaller first).
pub(crate) fn jointed(pairs: &[(u32, u32)], a: u32, b: u32) -> bool {
    !pairs.is_empty() && pairs.binary_search(&(a.min(b), a.max(b))).is_ok()
}

/// Beyond this many colliders the exact search below is skipped (it is O(n²) in
/// the worst case) and the collision stages stay.
const EXACT_SEARCH_LIMIT: usize = 2000;

/// Whether some pair of colliders that filters, kinds and shapes let touch is not
/// tied by a joint: a pendulum or a chain whose only possible contacts are
/// between jointed bodies needs no collision stage at all. Called after the
/// cheaper per-filter test said some pair can touch.
pub(crate) fn some_pair_unjointed(
    cols: &[crate::collide::Collider],
    kinds: &[crate::body::BodyKind],
    pairs: &[(u32, u32)],
) -> bool {
    if pairs.is_empty() || cols.len() > EXACT_SEARCH_LIMIT {
        return true;
    }
    let movable = |c: &crate::collide::Collider| kinds[c.body as usize] != crate::body::BodyKind::Fixed;
    cols.iter().enumerate().any(|(k, ci)| {
        cols[k + 1..].iter().any(|cj| {
            ci.body != cj.body
                && ci.filter.allows(&cj.filter)
                && (movable(ci) || movable(cj))
                && !(ci.infinite && cj.infinite)
                && !jointed(pairs, ci.body, cj.body)
        })
    })
}
