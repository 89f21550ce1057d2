//! A [`Scene`] (a plain description, validated as it is filled) compiles into a
//! [`World`] (state arrays plus the stages this scene needs).

pub mod articulations;
pub mod checksum;
pub mod collision;
pub mod diagnostics;
pub mod framing;
pub mod guard;
pub mod inputs;
pub mod joints;
pub mod link_contacts;
pub mod mesh_sides;
pub mod particles;
pub mod pipeline;
pub mod profile;
pub mod recipe;
pub mod runaway;
pub mod scene;
pub mod scene_bytes;
pub mod settings;
pub mod snapshot;
pub mod snapshot_bytes;
pub mod step;
pub mod threads;
pub mod batch;
pub mod validate;
#[allow(clippy::module_inception)]
pub mod world;

pub use pipeline::{Stage, StageKind};
pub use scene::{BodySpec, Inertia, Scene};
pub use settings::Settings;
pub use world::World;
