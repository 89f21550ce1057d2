//! What a scene was given, call by call: the inputs of `add_body`, `add_joint`
//! and the particle methods as the Python API received them (after argument
//! conversion, before anything is derived from them). A scene file is written
//! from this and rebuilt by replaying the calls, so a rebuilt scene holds the same
//! bits: the compiled bodies (principal frames), joints and particle model are
//! derived data, and deriving them again from the same inputs is deterministic.
//! `Scene::build` never reads it.

use super::joints::JointOptions;
use super::BodySpec;
use crate::body::Shape;
use crate::xpbd::builders::Material;
use crate::xpbd::joints::JointSpec;
use crate::xpbd::shape_matching::ClusterSpec;
use crate::xpbd::{Compliance, ParticleSpec};

#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Recipe {
    /// One per body, in index order, without its shape: that is the compiled
    /// body's (`BodyDesc::shape`, the given shape unchanged), kept once.
    pub bodies: Vec<BodySpec>,
    /// One per joint, in index order: the geometry and the options as given.
    pub joints: Vec<(JointSpec, JointOptions)>,
    /// Particle-side calls in the order they were made (they share the particle,
    /// constraint and cluster numbering, so the order matters).
    pub particles: Vec<ParticleCall>,
    /// `Scene.build` keyword arguments kept with the scene (`Scene.build_settings`).
    pub build: Vec<(String, Setting)>,
}

/// A build setting's value, as plain data.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Setting {
    None,
    Bool(bool),
    Int(i64),
    Float(f64),
    Str(String),
}

/// Where a shape-matched body's particles come from.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub enum Source {
    /// Filled on a grid of `spacing`.
    Shape(Shape),
    /// Given points (m).
    Points(Vec<[f64; 3]>),
}

/// One particle-side call.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub enum ParticleCall {
    Particle(ParticleSpec),
    Distance { p: i64, q: i64, k: Compliance, rest_length: Option<f64> },
    Bending { p: [i64; 4], k: Compliance },
    Volume { p: [i64; 4], k: Compliance },
    MeshVolume { triangles: Vec<[i64; 3]>, pressure: f64, k: Compliance },
    Attachment { particle: i64, body: i64, point: Option<[f64; 3]>, rest_length: f64, k: Compliance },
    ShapeMatching { particles: Vec<i64>, spec: ClusterSpec },
    Rope { start: [f64; 3], end: [f64; 3], segments: i64, mat: Material, k: Compliance, pinned: Vec<i64> },
    Cloth {
        origin: [f64; 3],
        u: [f64; 3],
        v: [f64; 3],
        resolution: [i64; 2],
        mat: Material,
        k: Compliance,
        bending: Option<Compliance>,
        pinned: Vec<i64>,
    },
    SoftBox { center: [f64; 3], half_extents: [f64; 3], cells: [i64; 3], mat: Material, k: Compliance, volume: Option<Compliance> },
    ShapeMatchedBody {
        source: Source,
        spacing: Option<f64>,
        position: Option<[f64; 3]>,
        orientation: Option<[f64; 4]>,
        mat: Material,
        spec: ClusterSpec,
        cluster_size: Option<f64>,
    },
}
