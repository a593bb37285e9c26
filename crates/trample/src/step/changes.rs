//! What the last step changed, for a host that uploads only that (issue 14,
//! item 2): the blades whose vertices and the cells whose level of detail
//! or billboard slope a step wrote. The writes record themselves
//! ([`crate::field::changes`]); these are the host's view of the record.

use super::simulation::Simulation;

impl Simulation {
    /// Blades whose vertices the last [`Simulation::step`] wrote, ascending,
    /// each once; every blade whose position bits changed is in it. Vertex
    /// k of blade b is `field.blades.pos[k * count + b]`
    /// ([`crate::field::Blades::pos_bytes`]). Runs of consecutive blades:
    /// [`crate::field::Field::changed_blades`]`.ranges()`.
    pub fn changed_blades(&self) -> impl Iterator<Item = u32> + '_ {
        self.field.changed_blades().iter()
    }

    /// Cells whose level of detail or billboard slope the last
    /// [`Simulation::step`] set, ascending, each once.
    pub fn changed_cells(&self) -> impl Iterator<Item = u32> + '_ {
        self.field.changed_cells().iter()
    }
}
