//! The grass field: patches (culling unit), cells (LOD unit) and blades
//! (structure-of-arrays, patch-major), terrain and level of detail (DESIGN §2).

pub mod blades;
pub mod frustum;
pub mod generate;
pub mod layout;
pub mod lod;
pub mod params;
pub mod terrain;

pub use blades::{Blades, MAX_SEGMENTS};
pub use layout::{FieldLayout, Patch, NO_NEIGHBOUR};
pub use lod::{Lod, LodParams};
pub use params::{FieldParams, TerrainParams};
pub use terrain::Terrain;
