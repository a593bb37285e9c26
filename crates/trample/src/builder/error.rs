//! Why a simulation could not be built: one enum for every check, each
//! message naming the key (as in a scene file) and what is allowed. A scene
//! file's errors are these, prefixed with the file's name
//! ([`crate::scene::SceneError::Invalid`]).

use crate::camera::CameraError;
use crate::field::{FieldError, LodError, MapError, TerrainError};
use crate::object::ObjectError;
use crate::step::{SimError, ViewError};

/// A value a [`super::SimulationBuilder`] or [`super::BodyBuilder`] refused.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    /// A `field` value out of range.
    #[error(transparent)]
    Field(#[from] FieldError),
    /// A `sim` value out of range.
    #[error(transparent)]
    Sim(#[from] SimError),
    /// A `wind` value out of range (the message names the key).
    #[error("{0}")]
    Wind(String),
    /// A `lod` value out of range.
    #[error(transparent)]
    Lod(#[from] LodError),
    /// A `camera` value out of range.
    #[error(transparent)]
    Camera(#[from] CameraError),
    /// The camera looks at an object no body is named after.
    #[error("camera.look_at.name = \"{name}\": no object has that name (objects: {names:?})")]
    CameraTarget {
        /// The name looked for.
        name: String,
        /// The bodies' names.
        names: Vec<String>,
    },
    /// Two bodies with one name.
    #[error("objects[{index}].name = \"{name}\": another object already has this name")]
    DuplicateName {
        /// Index of the second one.
        index: usize,
        /// The name.
        name: String,
    },
    /// The field would need more memory than `sim.memory_limit_gib`.
    #[error(
        "field needs about {:.1} GiB ({blades} blades); sim.memory_limit_gib = {limit_gib} allows less",
        *need_bytes as f64 / 1024f64.powi(3)
    )]
    Memory {
        /// The estimate, bytes ([`crate::field::FieldParams::memory_estimate_bytes_for`]).
        need_bytes: u64,
        /// Blades of the field.
        blades: u64,
        /// The limit, GiB.
        limit_gib: f32,
    },
    /// The terrain could not be made (height map).
    #[error(transparent)]
    Terrain(#[from] TerrainError),
    /// A grass map could not be read.
    #[error(transparent)]
    Maps(#[from] MapError),
    /// A body could not be made (shape, mesh, path, motion).
    #[error(transparent)]
    Object(#[from] ObjectError),
    /// The host view is not usable.
    #[error(transparent)]
    View(#[from] ViewError),
}
