//! Patches, cells and the global cell grid (paper §3.1, Fig. 2; DESIGN §2).
//!
//! Storage order: patch-major, cells row-major (z then x) inside a patch,
//! blades of a cell contiguous. Cells also have global grid coordinates
//! `(gx, gz)` that run across patch borders, so propagation (Eq. 4) crosses
//! patches.

use glam::Vec3;

/// Marks a missing neighbour (field border) in [`FieldLayout::neighbours`].
pub const NO_NEIGHBOUR: u32 = u32::MAX;

/// One patch: the unit of frustum culling.
#[derive(Clone, Debug, PartialEq)]
pub struct Patch {
    /// Patch coordinates (px, pz).
    pub coord: [u32; 2],
    /// Lower corner of the patch's box (includes terrain and maximum blade height).
    pub aabb_min: Vec3,
    /// Upper corner of the patch's box.
    pub aabb_max: Vec3,
    /// First blade of the patch in storage order; its blades are
    /// `first_blade .. first_blade + blades`.
    pub first_blade: u32,
    /// Number of blades in the patch.
    pub blades: u32,
    /// First cell of the patch in storage order.
    pub first_cell: u32,
}

/// Index arithmetic of the field: how patches, cells and blades are numbered.
#[derive(Clone, Debug)]
pub struct FieldLayout {
    /// Patches along x and z.
    pub patches: [u32; 2],
    /// Cells along a patch side.
    pub cells_per_patch: u32,
    /// Blades per cell.
    pub blades_per_cell: u32,
    /// Cell side, metres.
    pub cell_size: f32,
    /// World x, z of the field's lower corner (the field is centred on the origin).
    pub origin: [f32; 2],
    /// Every patch, in storage order.
    pub patch_list: Vec<Patch>,
    /// How far any patch's box reaches beyond the patch's square in x or z,
    /// metres (≥ 0; the blades' roots are jittered and their length is added
    /// sideways, see `generate::patch_boxes`). Lets the broad phase find the
    /// patches under an object by a grid lookup
    /// ([`crate::collision::broad_phase::patch_rect`]). Set with
    /// `patch_list`; a box changed later must stay within it.
    pub patch_overhang_m: f32,
    /// Per strip of patches ([`super::strips`]): the union of its patches'
    /// boxes, for frustum culling by strips ([`super::cull_patches`]).
    pub strip_aabbs: Vec<(Vec3, Vec3)>,
    /// For each blade: the blades in the same slot of the 4-neighbour cells
    /// (Definition 6), in the fixed order −x, +x, −z, +z; [`NO_NEIGHBOUR`] at
    /// the field border.
    pub neighbours: Vec<[u32; 4]>,
}

/// Index of the neighbour in −x direction inside a `neighbours` entry.
pub const NEG_X: usize = 0;
/// Index of the neighbour in +x direction.
pub const POS_X: usize = 1;
/// Index of the neighbour in −z direction.
pub const NEG_Z: usize = 2;
/// Index of the neighbour in +z direction.
pub const POS_Z: usize = 3;

impl FieldLayout {
    /// Cells along x and z of the whole field.
    #[must_use]
    pub fn grid_size(&self) -> [u32; 2] {
        [
            self.patches[0] * self.cells_per_patch,
            self.patches[1] * self.cells_per_patch,
        ]
    }

    /// Number of cells.
    #[must_use]
    pub fn cell_count(&self) -> usize {
        let [gx, gz] = self.grid_size();
        gx as usize * gz as usize
    }

    /// Side of a patch's square, metres.
    #[must_use]
    pub fn patch_size(&self) -> f32 {
        self.cells_per_patch as f32 * self.cell_size
    }

    /// Sets `patch_list` and what follows from it: [`Self::patch_overhang_m`]
    /// and [`Self::strip_aabbs`].
    pub fn set_patches(&mut self, patches: Vec<Patch>) {
        let size = self.patch_size();
        self.patch_overhang_m = patches.iter().fold(0.0f32, |m, p| {
            let lo = [
                self.origin[0] + p.coord[0] as f32 * size,
                self.origin[1] + p.coord[1] as f32 * size,
            ];
            let reach = [
                lo[0] - p.aabb_min.x,
                lo[1] - p.aabb_min.z,
                p.aabb_max.x - (lo[0] + size),
                p.aabb_max.z - (lo[1] + size),
            ];
            reach
                .iter()
                .fold(m, |m, &r| if r.is_finite() { m.max(r) } else { m })
        });
        self.strip_aabbs = super::strips::strip_bounds(self.patches, |i| {
            (patches[i].aabb_min, patches[i].aabb_max)
        });
        self.patch_list = patches;
    }

    /// Number of blades.
    #[must_use]
    pub fn blade_count(&self) -> usize {
        self.cell_count() * self.blades_per_cell as usize
    }

    /// Cells per patch.
    #[must_use]
    pub fn cells_in_patch(&self) -> usize {
        (self.cells_per_patch * self.cells_per_patch) as usize
    }

    /// Storage index of the cell at global grid coordinates `(gx, gz)`.
    #[must_use]
    pub fn cell_index(&self, gx: u32, gz: u32) -> usize {
        let cpp = self.cells_per_patch;
        let (px, lx) = (gx / cpp, gx % cpp);
        let (pz, lz) = (gz / cpp, gz % cpp);
        let patch = (pz * self.patches[0] + px) as usize;
        patch * self.cells_in_patch() + (lz * cpp + lx) as usize
    }

    /// Global grid coordinates of the cell with storage index `cell`.
    #[must_use]
    pub fn cell_coord(&self, cell: usize) -> [u32; 2] {
        let cpp = self.cells_per_patch as usize;
        let per_patch = self.cells_in_patch();
        let patch = cell / per_patch;
        let local = cell % per_patch;
        let (px, pz) = (
            patch % self.patches[0] as usize,
            patch / self.patches[0] as usize,
        );
        let (lx, lz) = (local % cpp, local / cpp);
        [(px * cpp + lx) as u32, (pz * cpp + lz) as u32]
    }

    /// Cell that holds blade `b`.
    #[must_use]
    pub fn cell_of_blade(&self, b: usize) -> usize {
        b / self.blades_per_cell as usize
    }

    /// World (x, z) of the centre of cell `(gx, gz)`.
    #[must_use]
    pub fn cell_centre(&self, gx: u32, gz: u32) -> [f32; 2] {
        [
            self.origin[0] + (gx as f32 + 0.5) * self.cell_size,
            self.origin[1] + (gz as f32 + 0.5) * self.cell_size,
        ]
    }

    /// Cells of patch `p` whose square overlaps the world rectangle
    /// `min ..= max` (x, z), in storage order. A finer broad phase than the
    /// patch box: it keeps the narrow phase to the blades under an object.
    pub fn patch_cells_overlapping(
        &self,
        p: usize,
        min: [f32; 2],
        max: [f32; 2],
    ) -> impl Iterator<Item = usize> + '_ {
        let ([x0, x1], [z0, z1]) = self.patch_cell_range(p, min, max);
        let first = p * self.cells_in_patch();
        let cpp = self.cells_per_patch as usize;
        (z0..=z1).flat_map(move |lz| (x0..=x1).map(move |lx| first + lz * cpp + lx))
    }

    /// The cells of [`FieldLayout::patch_cells_overlapping`] as ranges of
    /// patch-local columns and rows, `([x0, x1], [z0, z1])` inclusive
    /// (empty, `x0 > x1` or `z0 > z1`, when none): cell `(lx, lz)` is
    /// stored at `p · cells_in_patch + lz · cells_per_patch + lx`.
    #[must_use]
    pub fn patch_cell_range(
        &self,
        p: usize,
        min: [f32; 2],
        max: [f32; 2],
    ) -> ([usize; 2], [usize; 2]) {
        let cpp = self.cells_per_patch as i64;
        let (px, pz) = (
            (p % self.patches[0] as usize) as i64,
            (p / self.patches[0] as usize) as i64,
        );
        let range = |lo: f32, hi: f32, origin: f32, first: i64| {
            if lo.is_nan() || hi.is_nan() || lo > hi {
                return [1, 0]; // NaN or inverted: no cells.
            }
            let a = ((lo - origin) / self.cell_size).floor();
            let b = ((hi - origin) / self.cell_size).floor();
            // Saturating float→int casts keep absurd rectangles harmless.
            let (a, b) = ((a as i64).max(first), (b as i64).min(first + cpp - 1));
            if a > b {
                return [1, 0];
            }
            [(a - first) as usize, (b - first) as usize]
        };
        (
            range(min[0], max[0], self.origin[0], px * cpp),
            range(min[1], max[1], self.origin[1], pz * cpp),
        )
    }

    /// Global cell coordinates containing world point (x, z), if inside the field.
    #[must_use]
    pub fn cell_at(&self, x: f32, z: f32) -> Option<[u32; 2]> {
        let fx = (x - self.origin[0]) / self.cell_size;
        let fz = (z - self.origin[1]) / self.cell_size;
        let [gx, gz] = self.grid_size();
        if fx < 0.0 || fz < 0.0 || !fx.is_finite() || !fz.is_finite() {
            return None;
        }
        let (ix, iz) = (fx as u32, fz as u32);
        (ix < gx && iz < gz).then_some([ix, iz])
    }
}
