//! The whole grass field: layout, terrain, blades and per-cell state.

use super::blades::Blades;
use super::cells::Cells;
use super::layout::FieldLayout;
use super::params::FieldParams;
use super::terrain::Terrain;

/// A generated grass field (see [`Field::generate`](super::generate)).
#[derive(Clone, Debug)]
pub struct Field {
    /// What it was generated from.
    pub params: FieldParams,
    /// Patch/cell/blade numbering and neighbours.
    pub layout: FieldLayout,
    /// The ground.
    pub terrain: Terrain,
    /// Every blade's vertices (SoA, Eq. 1).
    pub blades: Blades,
    /// Per-cell level of detail and billboard state.
    pub cells: Cells,
    /// Length of the longest blade, metres: how far a blade can reach from its root.
    pub max_blade_length: f32,
}
