//! The scene: a plain description of what is simulated, validated as it is filled
//! so that every error names the body it is about. [`Scene::build`] compiles it.

use nalgebra::{Isometry3, Translation3, UnitQuaternion};

use super::{Settings, World};
use crate::body::mass::{inertia_matrix, validate_inertia};
use crate::collide::{Filter, Material};
use crate::body::storage::BodyInit;
use crate::body::{BodyKind, MassProps, Shape};
use crate::error::{finite3, positive, Error, Result};
use crate::math::{quat, Mat3, Quat, Vec3};

/// Explicit inertia: principal moments about the body axes, or a full tensor
/// (kg·m², about the centre of mass, in the frame of `position`/`orientation`).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub enum Inertia {
    Principal([f64; 3]),
    Tensor([[f64; 3]; 3]),
}

/// What `add_body` takes. Mass comes from exactly one of: `shape` + `density`,
/// `shape` + `mass` (uniform density scaled to that mass), `mass` + `inertia`
/// (with or without a shape), or `mass_properties` (e.g. from sampled density).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct BodySpec {
    pub shape: Option<Shape>,
    /// Uniform density (kg/m³).
    pub density: Option<f64>,
    /// Mass (kg).
    pub mass: Option<f64>,
    pub inertia: Option<Inertia>,
    pub mass_properties: Option<MassProps>,
    /// Position of the shape's (or mass properties') frame origin, world (m). Default 0.
    pub position: [f64; 3],
    /// Orientation of that frame, quaternion (x, y, z, w); normalised. Default identity.
    pub orientation: [f64; 4],
    /// Velocity of the centre of mass, world (m/s). Default 0.
    pub linear_velocity: [f64; 3],
    /// Angular velocity, world (rad/s). Default 0.
    pub angular_velocity: [f64; 3],
    /// A fixed body never moves and needs no mass. Default false.
    pub fixed: bool,
    /// A kinematic body moves with the velocities the user gives it, has infinite
    /// mass and needs none. Default false.
    pub kinematic: bool,
    /// Surface material of the shape. Default: friction 0.5, restitution 0.
    pub material: Material,
    /// Collision filter of the shape. Default: group 1, collides with all.
    pub filter: Filter,
    /// Continuous collision detection for this body. Default false.
    pub ccd: bool,
    /// A name for read-back (`world.bodies.names`). Default none.
    pub name: Option<String>,
}

impl Default for BodySpec {
    fn default() -> Self {
        Self {
            shape: None,
            density: None,
            mass: None,
            inertia: None,
            mass_properties: None,
            position: [0.0; 3],
            orientation: [0.0, 0.0, 0.0, 1.0],
            linear_velocity: [0.0; 3],
            angular_velocity: [0.0; 3],
            fixed: false,
            kinematic: false,
            material: Material::default(),
            filter: Filter::default(),
            ccd: false,
            name: None,
        }
    }
}

/// A body as compiled into a world: its initial state in the principal frame, and
/// where its shape sits in that frame.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct BodyDesc {
    pub init: BodyInit,
    pub shape: Option<Shape>,
    /// Pose of the shape's frame in the body's principal frame.
    pub shape_pose: Isometry3<f64>,
    pub material: Material,
    pub filter: Filter,
    pub ccd: bool,
    pub name: Option<String>,
}

#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Scene {
    /// Gravitational acceleration (m/s²). Default (0, 0, −9.81).
    pub gravity: [f64; 3],
    bodies: Vec<BodyDesc>,
    /// Joints, validated and compiled by `add_joint` (see `super::joints`).
    pub(crate) joints: Vec<crate::xpbd::joints::Joint>,
    /// Per joint: name, solver choice and controls (see `super::joints`).
    pub(crate) joint_options: Vec<super::joints::JointOptions>,
    /// Particles, their constraints and clusters (see `world::particles`).
    pub(crate) xpbd: crate::xpbd::XpbdModel,
    /// The calls that filled the scene, as given (see `super::recipe`): what a
    /// scene file holds. Filled by the Python bindings.
    pub recipe: super::recipe::Recipe,
}

impl Default for Scene {
    fn default() -> Self {
        Self {
            gravity: [0.0, 0.0, -9.81],
            bodies: Vec::new(),
            joints: Vec::new(),
            joint_options: Vec::new(),
            xpbd: Default::default(),
            recipe: Default::default(),
        }
    }
}

impl Scene {
    pub fn new(gravity: [f64; 3]) -> Result<Self> {
        finite3("gravity", gravity)?;
        Ok(Self { gravity, ..Self::default() })
    }

    pub fn bodies(&self) -> &[BodyDesc] {
        &self.bodies
    }

    /// The compiled bodies, to change per copy of a batch (`world::batch`),
    /// which validates what it writes.
    pub(crate) fn bodies_mut(&mut self) -> &mut [BodyDesc] {
        &mut self.bodies
    }

    /// Validates `spec` and adds the body; returns its index. On error the scene
    /// is unchanged.
    pub fn add_body(&mut self, spec: BodySpec) -> Result<usize> {
        let index = self.bodies.len();
        if let Some(name) = &spec.name {
            if self.bodies.iter().any(|b| b.name.as_ref() == Some(name)) {
                return Err(Error::input(format!("body {index}: name {name:?} is taken by another body")));
            }
        }
        let desc = describe(spec).map_err(|e| e.context(format!("body {index}")))?;
        self.bodies.push(desc);
        Ok(index)
    }

    /// Compiles the scene into a world.
    pub fn build(&self, settings: &Settings) -> Result<World> {
        settings.validate()?;
        World::new(self, settings.clone())
    }
}

/// A validated pose from a position (m) and an (x, y, z, w) quaternion (normalised).
pub fn pose(p: [f64; 3], q: [f64; 4]) -> Result<Isometry3<f64>> {
    finite3("position", p)?;
    let q = unit_quaternion(q)?;
    Ok(Isometry3::from_parts(Translation3::from(Vec3::from(p)), UnitQuaternion::new_unchecked(q)))
}

fn unit_quaternion(q: [f64; 4]) -> Result<Quat> {
    if !q.iter().all(|x| x.is_finite()) {
        return Err(Error::input(format!("orientation must be finite, got {q:?}")));
    }
    // Scaled by the largest component first: |q|² of (1e200, 1e200, 0, 0) overflows.
    let scale = q.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let qq = if scale > 0.0 { quat::from_xyzw(q.map(|x| x / scale)) } else { quat::from_xyzw(q) };
    let n = qq.norm();
    if !(n > 1e-12) {
        return Err(Error::input(format!("orientation must be a non-zero quaternion (x, y, z, w), got {q:?}")));
    }
    Ok(qq / n)
}

/// What a fixed or kinematic body is given must make sense too, though its mass
/// is infinite: a NaN or negative inertia is a mistake the user should hear about,
/// and a `Plane` (a half-space) can only be fixed.
fn check_static_body(spec: &BodySpec) -> Result<()> {
    let is_plane = spec.shape.as_ref().is_some_and(|s| s.name() == "Plane");
    if is_plane && !spec.fixed {
        let how = if spec.kinematic { "kinematic=True" } else { "a dynamic body" };
        return Err(Error::input(format!("a Plane is a half-space with no finite mass: it must be fixed=True, not {how}")));
    }
    if (spec.fixed || spec.kinematic) && (spec.inertia.is_some() || spec.mass_properties.is_some()) {
        mass_of(spec)?;
    }
    Ok(())
}

/// The mass properties `spec` asks for, in the frame of its position/orientation.
fn mass_of(spec: &BodySpec) -> Result<MassProps> {
    let given = |b: bool, n: &'static str| if b { Some(n) } else { None };
    let sources: Vec<&str> = [
        given(spec.density.is_some(), "density"),
        given(spec.mass_properties.is_some(), "mass_properties"),
        given(spec.mass.is_some() && spec.inertia.is_none(), "mass"),
        given(spec.inertia.is_some(), "mass with inertia"),
    ]
    .into_iter()
    .flatten()
    .collect();
    if sources.len() > 1 {
        return Err(Error::input(format!("give only one source of mass, got {}", sources.join(" and "))));
    }
    let props = mass_from_sources(spec)?;
    props.validate("mass")?;
    Ok(props)
}

fn mass_from_sources(spec: &BodySpec) -> Result<MassProps> {
    if let Some(mp) = &spec.mass_properties {
        mp.validate("mass_properties")?;
        return Ok(mp.clone());
    }
    if let Some(inertia) = &spec.inertia {
        let mass = spec.mass.ok_or_else(|| Error::input("inertia needs mass= as well"))?;
        positive("mass", mass)?;
        let tensor = match inertia {
            Inertia::Principal(m) => inertia_matrix(m, &Quat::identity()),
            Inertia::Tensor(t) => Mat3::from_fn(|r, c| t[r][c]),
        };
        validate_inertia(&tensor, "inertia")?;
        let com = match &spec.shape {
            Some(s) => s.mass_properties(1.0)?.com,
            None => Vec3::zeros(),
        };
        return Ok(MassProps { mass, com, inertia: tensor });
    }
    let Some(shape) = &spec.shape else {
        return Err(Error::input("a dynamic body needs a shape with density= or mass=, mass= with inertia=, or mass_properties="));
    };
    match (spec.density, spec.mass) {
        (Some(rho), _) => shape.mass_properties(rho),
        (None, Some(m)) => {
            positive("mass", m)?;
            Ok(shape.mass_properties(1.0)?.with_mass(m))
        }
        (None, None) => Err(Error::input(format!("a dynamic {} needs density= or mass=", shape.name()))),
    }
}

fn describe(spec: BodySpec) -> Result<BodyDesc> {
    finite3("position", spec.position)?;
    finite3("linear_velocity", spec.linear_velocity)?;
    finite3("angular_velocity", spec.angular_velocity)?;
    let q_frame = unit_quaternion(spec.orientation)?;
    let p_frame = Vec3::from(spec.position);
    if let Some(rho) = spec.density {
        positive("density", rho)?;
    }
    if let Some(m) = spec.mass {
        positive("mass", m)?;
    }
    if spec.fixed && spec.kinematic {
        return Err(Error::input("a body cannot be both fixed and kinematic"));
    }
    if spec.ccd && spec.shape.is_none() {
        return Err(Error::input("ccd=True needs a shape to sweep"));
    }
    check_static_body(&spec)?;
    let (kind, props) = if spec.fixed {
        (BodyKind::Fixed, None)
    } else if spec.kinematic {
        (BodyKind::Kinematic, None)
    } else {
        (BodyKind::Dynamic, Some(mass_of(&spec)?))
    };
    // The body frame is the principal frame at the centre of mass; a fixed or
    // kinematic body keeps the frame it was given.
    let (com, principal) = match &props {
        Some(mp) => (mp.com, mp.principal()),
        None => (Vec3::zeros(), crate::body::Principal { moments: [f64::INFINITY; 3], frame: Quat::identity() }),
    };
    let init = BodyInit {
        kind,
        position: p_frame + quat::rotate(&q_frame, &com),
        orientation: q_frame * principal.frame,
        linear_velocity: Vec3::from(spec.linear_velocity),
        angular_velocity: Vec3::from(spec.angular_velocity),
        mass: props.as_ref().map_or(f64::INFINITY, |m| m.mass),
        inertia: principal.moments,
    };
    let inv_frame = principal.frame.conjugate();
    let shape_pose = Isometry3::from_parts(
        Translation3::from(-quat::rotate(&inv_frame, &com)),
        UnitQuaternion::new_unchecked(inv_frame),
    );
    Ok(BodyDesc { init, shape: spec.shape, shape_pose, material: spec.material, filter: spec.filter, ccd: spec.ccd, name: spec.name })
}
