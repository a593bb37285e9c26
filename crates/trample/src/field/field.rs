//! The whole grass field: layout, terrain, blades and per-cell state.

use super::blades::Blades;
use super::cells::Cells;
use super::changes::ChangeSet;
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
    /// Blades the grass maps left out ([`Blades::is_present`]); 0 for a
    /// field without maps, which lets the step skip the presence test.
    pub absent_blades: u64,
}

impl Field {
    /// Blades whose vertices the last step wrote ([`Blades::store`]),
    /// ascending, each once: every blade whose position changed is in it
    /// (one written back to the same value may be too). A host uploads
    /// vertex k of these blades only (`pos[k * count + b]`);
    /// [`ChangeSet::ranges`] groups them into runs. See also
    /// [`crate::Simulation::changed_blades`].
    #[must_use]
    pub fn changed_blades(&self) -> &ChangeSet {
        &self.blades.changed
    }

    /// Cells whose state the last step set, ascending, each once: a new
    /// level of detail ([`Cells::lod`]) or billboard slope ([`Cells::slope`],
    /// [`Cells::set_slope`]; the flatness, [`Cells::flatness`], is only set
    /// with the slope). Every cell whose level, slope or flatness changed is
    /// in it.
    #[must_use]
    pub fn changed_cells(&self) -> &ChangeSet {
        &self.cells.changed
    }

    /// Forgets which blades and cells were written; a step calls it when it
    /// begins.
    pub fn clear_changes(&mut self) {
        self.blades.changed.clear();
        self.cells.changed.clear();
    }

    /// Puts the blades and cells written in ascending order; a step calls
    /// it when it ends.
    pub fn sort_changes(&mut self) {
        self.blades.changed.sort();
        self.cells.changed.sort();
    }
}
