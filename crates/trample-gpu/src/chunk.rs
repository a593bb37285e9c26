//! Chunks of patches (issue 4, item 2): a field's blade vertices are split
//! into chunks of whole patches, each chunk's `pos` and `rest` within one
//! storage binding (128 MiB on the software drivers: ≈ 1.6 M blades of five
//! vertices). The stages that touch vertices (narrow phase, bending,
//! recovery, the per-cell stages) run one dispatch per chunk over its own
//! buffers (`chunk.wgsl`); the small per-blade and per-cell arrays (forces,
//! generations, classes, neighbours, cell states: ≤ 16 bytes a blade) stay
//! whole-field, so propagation crosses chunk borders as it crosses patch
//! borders. Those whole-field arrays bound the field at one binding of 16
//! bytes a blade (≈ 8.4 M blades on the software drivers;
//! [`GpuError::TooLarge`] beyond).
//!
//! An unchunked field is one chunk; a chunked field gives the same result
//! (`tests/chunking.rs`).

use bytemuck::{Pod, Zeroable};
use std::ops::Range;

use crate::error::GpuError;
use crate::kernel::grid;
use trample::field::ChunkError;

/// The uniform of one chunk. Layout-compatible with `Chunk` in `chunk.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq, Eq)]
pub struct GpuChunkParams {
    /// First blade, blades, first cell, cells.
    pub range: [u32; 4],
    /// Workgroups in x of the blade dispatch and of the cell dispatch; the
    /// entry of the chunk's count in the broad phase's lists (patches +
    /// chunk index); blades per chunking unit (a patch).
    pub groups: [u32; 4],
}
const _: () = assert!(std::mem::size_of::<GpuChunkParams>() == 32);

/// One chunk of patches on the GPU.
pub struct GpuChunk {
    /// Global blades `first_blade .. first_blade + blades`.
    pub first_blade: u32,
    /// Blades in the chunk.
    pub blades: u32,
    /// Global cells `first_cell .. first_cell + cells`.
    pub first_cell: u32,
    /// Cells in the chunk.
    pub cells: u32,
    /// Vertex positions of the chunk's blades, vertex-major over the chunk
    /// (`pos[k * blades + (b - first_blade)]`), `vec4<f32>` (w unused).
    /// Usable as a vertex or storage buffer by a renderer.
    pub pos: wgpu::Buffer,
    /// Rest positions, same layout; vertex 0 carries the segment length in w.
    pub rest: wgpu::Buffer,
    pub(crate) uniform: wgpu::Buffer,
    /// Workgroups (x, y) of a dispatch over the chunk's blades.
    pub(crate) groups: (u32, u32),
    /// Workgroups (x, y) of a dispatch over the chunk's cells.
    pub(crate) cell_groups: (u32, u32),
}

impl GpuChunk {
    /// The uniform's contents for a device allowing `max_groups`
    /// workgroups per dimension.
    pub(crate) fn params(
        first_blade: u32,
        blades: u32,
        blades_per_cell: u32,
        max_groups: u32,
        count_entry: u32,
        unit: u32,
    ) -> (GpuChunkParams, (u32, u32), (u32, u32)) {
        let cells = blades / blades_per_cell.max(1);
        let groups = grid(blades, max_groups);
        let cell_groups = grid(cells, max_groups);
        (
            GpuChunkParams {
                range: [
                    first_blade,
                    blades,
                    first_blade / blades_per_cell.max(1),
                    cells,
                ],
                groups: [groups.0, cell_groups.0, count_entry, unit],
            },
            groups,
            cell_groups,
        )
    }

    /// The chunk's global blades.
    #[must_use]
    pub fn blade_range(&self) -> Range<usize> {
        self.first_blade as usize..(self.first_blade + self.blades) as usize
    }
}

/// The blade ranges of the chunks of a field of `count` blades of `verts`
/// vertices, cut at multiples of `unit` blades (a patch; `count` is a
/// multiple of it), each chunk's positions (16 bytes a vertex) within
/// `max_bytes`: the core's [`trample::field::plan_chunks`] (a renderer on
/// the CPU path cuts a field the same way), its refusals as [`GpuError`]s.
///
/// # Errors
/// [`GpuError::TooLarge`] when one unit alone is over `max_bytes`;
/// [`GpuError::Layout`] when `unit` is 0 or does not divide `count`.
pub fn plan_chunks(
    count: u32,
    verts: u32,
    unit: u32,
    max_bytes: u64,
) -> Result<Vec<Range<u32>>, GpuError> {
    trample::field::plan_chunks(count, verts, unit, max_bytes).map_err(|e| match e {
        ChunkError::UnitTooLarge { bytes, limit } => GpuError::TooLarge {
            what: "the blade positions of one patch (the smallest chunk)",
            bytes,
            limit,
        },
        ChunkError::Layout { .. } => GpuError::Layout(e.to_string()),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_patch_over_the_limit_is_refused_by_name() {
        // The plan itself is the core's (`trample::field::chunks`); here
        // its refusals as the GPU path's errors.
        assert_eq!(plan_chunks(640, 5, 64, 3 * 5_120).unwrap().len(), 4);
        let e = plan_chunks(640, 5, 64, 5_000).unwrap_err();
        assert!(
            matches!(
                e,
                GpuError::TooLarge {
                    bytes: 5_120,
                    limit: 5_000,
                    ..
                }
            ),
            "{e}"
        );
        assert!(e.to_string().contains("one patch"), "{e}");
        assert!(plan_chunks(640, 5, 0, 1 << 20).is_err());
        assert!(plan_chunks(650, 5, 64, 1 << 20).is_err());
    }

    #[test]
    fn chunk_params_index_cells_and_workgroups() {
        let (p, g, cg) = GpuChunk::params(128, 200, 8, 2, 7, 40);
        assert_eq!(p.range, [128, 200, 16, 25]);
        // 200 blades = 4 groups of 64, at most 2 in x.
        assert_eq!(g, (2, 2));
        assert_eq!(cg, (1, 1));
        assert_eq!(p.groups, [2, 1, 7, 40]);
    }
}
