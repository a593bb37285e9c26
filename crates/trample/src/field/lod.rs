//! Level of detail per cell (paper §3.1, Fig. 1; DESIGN §2).

use serde::{Deserialize, Serialize};

/// Distances that choose each cell's representation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LodParams {
    /// Cells nearer than this (metres, from the viewpoint to the cell centre)
    /// are geometric blades. Default 12: close enough that a 2-core CPU can
    /// simulate them, far enough to see the track form.
    pub geometry_m: f32,
    /// Cells nearer than this (and not geometric) are billboards; beyond, the
    /// ground texture. Default 30.
    pub billboard_m: f32,
}

impl Default for LodParams {
    fn default() -> Self {
        Self { geometry_m: 12.0, billboard_m: 30.0 }
    }
}

/// Representation of a cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u8)]
pub enum Lod {
    /// Geometric blades (DBG/PBG can happen here).
    Geometry = 0,
    /// One billboard (BBG).
    Billboard = 1,
    /// Ground texture only: no animation.
    Texture = 2,
}
