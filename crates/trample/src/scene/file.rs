//! The layout of a scene file: one table per area.

use crate::camera::CameraParams;
use crate::field::{FieldParams, LodParams};
use crate::object::ObjectParams;
use crate::step::SimParams;
use serde::{Deserialize, Serialize};

/// A whole scene file. Every table is optional; missing keys take their defaults.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Short name, shown by `trample check`.
    #[serde(default)]
    pub name: String,
    /// One-line description.
    #[serde(default)]
    pub description: String,
    /// `[field]`: the grass field.
    #[serde(default)]
    pub field: FieldParams,
    /// `[lod]`: level-of-detail distances.
    #[serde(default)]
    pub lod: LodParams,
    /// `[sim]`: method parameters.
    #[serde(default)]
    pub sim: SimParams,
    /// `[camera]`: viewpoint path.
    #[serde(default)]
    pub camera: CameraParams,
    /// `[run]`: how long the tools run the scene.
    #[serde(default)]
    pub run: RunParams,
    /// `[wind]`: wind drawn over the grass (draw time only). Default: none.
    #[serde(default)]
    pub wind: crate::wind::WindParams,
    /// `[[objects]]`: the moving objects.
    #[serde(default)]
    pub objects: Vec<ObjectParams>,
}

/// `[run]` table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RunParams {
    /// Frames `simulate` and `run` take when `--frames` is not given. Default 300.
    pub frames: u64,
}

impl Default for RunParams {
    fn default() -> Self {
        Self { frames: 300 }
    }
}
