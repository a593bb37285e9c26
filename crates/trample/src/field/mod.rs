//! The grass field: patches (culling unit), cells (LOD unit) and blades
//! (structure-of-arrays, patch-major), terrain and level of detail (DESIGN §2).

pub mod blades;
pub mod cells;
pub mod frustum;
pub mod generate;
pub mod grass;
pub mod layout;
pub mod lod;
pub mod params;
pub mod rng;
pub mod terrain;

pub use blades::{Blades, MAX_SEGMENTS};
pub use cells::Cells;
pub use frustum::{Frustum, cull_patches};
pub use grass::Field;
pub use layout::{FieldLayout, NO_NEIGHBOUR, Patch};
pub use lod::{Lod, LodChange, LodCounts, LodParams, classify_cells};
pub use params::{FieldError, FieldParams, TerrainParams};
pub use terrain::Terrain;
