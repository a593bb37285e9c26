//! The grass field: patches (culling unit), cells (LOD unit) and blades
//! (structure-of-arrays, patch-major), terrain and level of detail (DESIGN §2).

pub mod blades;
pub mod cells;
pub mod changes;
pub mod chunks;
pub mod drawn;
pub mod frustum;
pub mod generate;
pub mod grid_image;
// Named after its module so that `Field` is found where it is looked for.
#[allow(clippy::module_inception)]
pub mod field;
pub mod layout;
pub mod lod;
pub mod maps;
pub mod params;
pub mod rng;
pub mod strips;
pub mod terrain;

pub use blades::{BladeVertex, Blades, MAX_SEGMENTS};
pub use cells::Cells;
pub use changes::ChangeSet;
pub use chunks::{ChunkError, drawn_ranges, list_pieces, plan_chunks, split_at_chunks};
pub use drawn::{drawn_blade_cells, drawn_blade_cells_by_cell, drawn_cells, drawn_cells_by_cell};
pub use field::Field;
pub use frustum::{Frustum, cull_patches, cull_patches_each};
pub use layout::{FieldLayout, NO_NEIGHBOUR, Patch};
pub use lod::{
    Lod, LodChange, LodCounts, LodError, LodParams, classify_cells, classify_cells_by_patch,
};
pub use maps::{GrassMap, GrassMapParams, GrassMaps, MapError};
pub use params::{FieldError, FieldParams, TerrainParams};
pub use terrain::{Terrain, TerrainError};
