//! The per-cell stages on the GPU: level of detail (Fig. 1), billboards
//! (Eq. 8) and their recovery (the paper's mode), transitions (Eq. 9–13),
//! and (ours, track everywhere) billboards and flatness that follow the
//! blades. One WGSL file per stage (`classify.wgsl`, `billboards.wgsl`,
//! `slopes.wgsl`, `transitions.wgsl`, `follow.wgsl`), each with the
//! bindings it uses (at most 9 storage buffers). `classify` runs first in a
//! sub-step (the narrow phase needs the levels), and, with the transitions,
//! only when the viewpoint or the distances changed (`lod_settle.rs`, as
//! the CPU); the others after the blades bend, as in
//! `trample::step::stages::substep`. The transitions run in two dispatches
//! a chunk: Eq. 12 over every cell, listing the cells coming back to
//! geometry, then Eq. 13 over that list (`transitions.wgsl` says why).
//!
//! Differences from the CPU path, by design: every cell is classified (the
//! CPU skips patches whose cells all keep one level: same result); every
//! billboard cell tests every object's root box (the CPU first keeps the
//! patches under the box: a conservative filter, same result); `follow`
//! computes every cell of the active patches that may hold a displaced
//! blade ([`crate::active_patches`]) whose blades are away from rest or
//! were when it last computed it (the CPU only those whose blades moved:
//! the others already hold these values).

use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use trample::field::FieldLayout;
use trample::obb::Obb;

use crate::active_patches::List;
use crate::broad_phase::BroadPhase;
use crate::field::GpuField;
use crate::kernel::{Kernel, Slot, args_buffer, begin_pass};

/// `transitions.wgsl`'s entry points: the pass over every cell (Eq. 12,
/// and the list of the cells coming back to geometry), the indirect
/// dispatch of that list, and Eq. 13 over it.
const TRANSITIONS: usize = 0;
const BACK_ARGS: usize = 1;
const TRANSITIONS_BACK: usize = 2;

/// The per-cell stages, one WGSL file each.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// `classify.wgsl`: level of detail per cell.
    Classify,
    /// `billboards.wgsl`: Eq. 8 (the paper's mode).
    Billboards,
    /// `transitions.wgsl`: Eq. 9–13.
    Transitions,
    /// `slopes.wgsl`: recovery of bent billboards (the paper's mode).
    Slopes,
    /// `follow.wgsl`: billboards and flatness from the blades (ours).
    Follow,
}

/// The WGSL source of `stage` as compiled (`segment_obb.wgsl`,
/// `blade.wgsl`, `chunk.wgsl` and `cell.wgsl` prepended; `guard.wgsl` and
/// `billboard.wgsl` too for the stages that move blades or billboards).
#[must_use]
pub fn source(stage: Stage) -> String {
    let (own, guard) = match stage {
        Stage::Classify => (include_str!("classify.wgsl"), false),
        Stage::Billboards => (include_str!("billboards.wgsl"), true),
        Stage::Transitions => (include_str!("transitions.wgsl"), true),
        Stage::Slopes => (include_str!("slopes.wgsl"), false),
        Stage::Follow => (include_str!("follow.wgsl"), false),
    };
    let guard = if guard {
        format!("{}\n{}", crate::GUARD_WGSL, crate::BILLBOARD_WGSL)
    } else {
        String::new()
    };
    // `follow` runs over the active patches' recover lists.
    let active = if stage == Stage::Follow {
        format!(
            "{}\n{}",
            include_str!("broad_params.wgsl"),
            include_str!("active_chunk.wgsl")
        )
    } else {
        String::new()
    };
    format!(
        "{}\n{}\n{}\n{}\n{}\n{}\n{}",
        crate::SEGMENT_OBB_WGSL,
        crate::BLADE_WGSL,
        guard,
        crate::CHUNK_WGSL,
        crate::CELL_WGSL,
        active,
        own
    )
}

/// An object's root box in the world, and the cells the CPU path tests for
/// billboards under it. Layout-compatible with `WorldObb` in `cells.wgsl`.
/// The w components hold that cell rectangle in global cell coordinates:
/// x from `center[3]` to `u[3]`, z from `v[3]` to `w[3]` (inclusive).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct GpuWorldObb {
    /// Centre (w unused).
    pub center: [f32; 4],
    /// Axis u.
    pub u: [f32; 4],
    /// Axis v.
    pub v: [f32; 4],
    /// Axis w.
    pub w: [f32; 4],
    /// Half extents.
    pub half: [f32; 4],
}
const _: () = assert!(std::mem::size_of::<GpuWorldObb>() == 80);

impl GpuWorldObb {
    /// `o` with the rectangle of cells whose square overlaps its (x, z)
    /// extent grown by `reach` (a blade's greatest length): the cells
    /// `trample::step::stages::bend_billboards` tests (`reach_rect(obb,
    /// reach)` and `FieldLayout::patch_cells_overlapping`), with the same
    /// float steps, so both paths test the same billboards.
    #[must_use]
    pub fn new(o: &Obb, layout: &FieldLayout, reach: f32) -> Self {
        let corners = o.corners();
        let lo = corners.iter().fold(Vec3::INFINITY, |a, c| a.min(*c)) - Vec3::splat(reach);
        let hi = corners.iter().fold(Vec3::NEG_INFINITY, |a, c| a.max(*c)) + Vec3::splat(reach);
        // An empty rectangle for NaN boxes.
        let cell =
            |x: f32, origin: f32| ((x - origin) / layout.cell_size).floor().clamp(-2.0, 1.0e7);
        let ok = lo.is_finite() && hi.is_finite();
        let (x0, x1) = if ok {
            (cell(lo.x, layout.origin[0]), cell(hi.x, layout.origin[0]))
        } else {
            (1.0, 0.0)
        };
        let (z0, z1) = if ok {
            (cell(lo.z, layout.origin[1]), cell(hi.z, layout.origin[1]))
        } else {
            (1.0, 0.0)
        };
        let v = |a: Vec3, w: f32| [a.x, a.y, a.z, w];
        Self {
            center: v(o.center, x0),
            u: v(o.axes[0], x1),
            v: v(o.axes[1], z0),
            w: v(o.axes[2], z1),
            half: v(o.half, 0.0),
        }
    }
}

/// Global cell coordinates (gx, gz) of cell `c` packed as `gx | gz << 16`
/// in the bits of an f32 (`billboards.wgsl` takes them apart): fields up
/// to 65,536 cells a side, past any field the memory limit lets through
/// (2^28 blades).
#[must_use]
pub fn packed_cell_coords(layout: &FieldLayout, c: usize) -> f32 {
    let cpp = layout.cells_per_patch as usize;
    let (p, l) = (c / layout.cells_in_patch(), c % layout.cells_in_patch());
    let px = p % layout.patches[0] as usize;
    let pz = p / layout.patches[0] as usize;
    let (gx, gz) = (px * cpp + l % cpp, pz * cpp + l / cpp);
    f32::from_bits((gx as u32 & 0xffff) | ((gz as u32 & 0xffff) << 16))
}

/// The compiled per-cell kernels.
pub struct Cells {
    classify: Kernel,
    billboards: Kernel,
    transitions: Kernel,
    slopes: Kernel,
    follow: Kernel,
    /// `transitions_back`'s indirect dispatch (written by `back_args`).
    back_args: wgpu::Buffer,
    /// Bound in `back_args`'s slot while `transitions_back` reads the
    /// arguments (a buffer is not both an indirect source and writable
    /// storage in one dispatch).
    unused_args: wgpu::Buffer,
}

impl Cells {
    /// Compiles the kernels on `device`.
    #[must_use]
    pub fn new(device: &wgpu::Device) -> Self {
        use Slot::{Read, ReadWrite, Uniform};
        let k = |stage, label, slots: &[Slot], entry| {
            Kernel::new(device, label, &source(stage), slots, &[entry])
        };
        Self {
            classify: k(
                Stage::Classify,
                "trample-gpu classify",
                &[Uniform, ReadWrite, ReadWrite, Read, Uniform],
                "classify",
            ),
            billboards: k(
                Stage::Billboards,
                "trample-gpu billboards",
                &[Uniform, ReadWrite, Read, ReadWrite, Read, Uniform, Read],
                "billboards",
            ),
            transitions: Kernel::new(
                device,
                "trample-gpu transitions",
                &source(Stage::Transitions),
                &[
                    Uniform, ReadWrite, Read, ReadWrite, ReadWrite, Read, ReadWrite, Uniform, Read,
                    ReadWrite, ReadWrite,
                ],
                &["transitions", "back_args", "transitions_back"],
            ),
            slopes: k(
                Stage::Slopes,
                "trample-gpu billboard recovery",
                &[Uniform, ReadWrite, Read, ReadWrite, Uniform],
                "recover_slopes",
            ),
            follow: k(
                Stage::Follow,
                "trample-gpu follow",
                &[
                    Uniform, ReadWrite, Read, ReadWrite, ReadWrite, Read, Read, Uniform, Read,
                    Uniform, ReadWrite,
                ],
                "follow",
            ),
            back_args: args_buffer(
                device,
                "trample-gpu transitions back dispatch",
                wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT,
            ),
            unused_args: args_buffer(
                device,
                "trample-gpu transitions back dispatch (unused)",
                wgpu::BufferUsages::STORAGE,
            ),
        }
    }

    /// The bind groups of every stage over `field`, one per chunk, with the
    /// step uniform, the counters and the objects' world root boxes.
    pub fn bind(
        &self,
        device: &wgpu::Device,
        field: &GpuField,
        params: &wgpu::Buffer,
        state: &wgpu::Buffer,
        world_roots: &wgpu::Buffer,
        broad: &BroadPhase,
    ) -> CellGroups {
        let transitions = |chunk: &crate::chunk::GpuChunk, args| {
            self.transitions.bind(
                device,
                &[
                    params,
                    &field.cell_state,
                    &field.cell_rest,
                    &field.slope,
                    &chunk.pos,
                    &chunk.rest,
                    &field.displaced,
                    &chunk.uniform,
                    &field.ground,
                    &field.back_cells,
                    args,
                ],
            )
        };
        CellGroups {
            back_cells: field.back_cells.clone(),
            chunks: field
                .chunks
                .iter()
                .map(|chunk| ChunkGroups {
                    classify: self.classify.bind(
                        device,
                        &[
                            params,
                            state,
                            &field.cell_state,
                            &field.cell_rest,
                            &chunk.uniform,
                        ],
                    ),
                    billboards: self.billboards.bind(
                        device,
                        &[
                            params,
                            &field.cell_state,
                            &field.cell_rest,
                            &field.slope,
                            world_roots,
                            &chunk.uniform,
                            &field.ground,
                        ],
                    ),
                    transitions: transitions(chunk, &self.back_args),
                    transitions_back: transitions(chunk, &self.unused_args),
                    slopes: self.slopes.bind(
                        device,
                        &[
                            params,
                            &field.cell_state,
                            &field.cell_rest,
                            &field.slope,
                            &chunk.uniform,
                        ],
                    ),
                    follow: self.follow.bind(
                        device,
                        &[
                            params,
                            &field.cell_state,
                            &field.cell_rest,
                            &field.slope,
                            &field.flatness,
                            &chunk.pos,
                            &chunk.rest,
                            &chunk.uniform,
                            &field.displaced,
                            &broad.params,
                            &broad.lists,
                        ],
                    ),
                    size: chunk.cell_groups,
                })
                .collect(),
        }
    }

    /// Records the level of detail of every cell (before the narrow phase).
    pub fn record_classify(&self, encoder: &mut wgpu::CommandEncoder, groups: &CellGroups) {
        for g in &groups.chunks {
            self.classify.dispatch(encoder, 0, &g.classify, g.size);
        }
    }

    /// Records billboards (Eq. 8), after the blades bend (the paper's mode).
    pub fn record_billboards(&self, encoder: &mut wgpu::CommandEncoder, groups: &CellGroups) {
        for g in &groups.chunks {
            self.billboards.dispatch(encoder, 0, &g.billboards, g.size);
        }
    }

    /// Records transitions (Eq. 9–13), after the billboards: per chunk,
    /// Eq. 12 and the list of the cells coming back to geometry over every
    /// cell, then Eq. 13 over that list (`transitions.wgsl` says why).
    pub fn record_transitions(&self, encoder: &mut wgpu::CommandEncoder, groups: &CellGroups) {
        for g in &groups.chunks {
            encoder.clear_buffer(&groups.back_cells, 0, Some(4));
            let mut pass = begin_pass(encoder);
            self.transitions
                .dispatch_in(&mut pass, TRANSITIONS, &g.transitions, g.size);
            self.transitions
                .dispatch_in(&mut pass, BACK_ARGS, &g.transitions, (1, 1));
            self.transitions.dispatch_indirect_in(
                &mut pass,
                TRANSITIONS_BACK,
                &g.transitions_back,
                &self.back_args,
            );
        }
    }

    /// Records the recovery of bent billboards (after the blades recover;
    /// the paper's mode).
    pub fn record_recover_slopes(&self, encoder: &mut wgpu::CommandEncoder, groups: &CellGroups) {
        for g in &groups.chunks {
            self.slopes.dispatch(encoder, 0, &g.slopes, g.size);
        }
    }

    /// Records billboards and flatness that follow the blades (track
    /// everywhere), last in a sub-step: over the cells of `broad`'s active
    /// recover lists (made in this sub-step: the active patches'
    /// `record_lists`).
    pub fn record_follow(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        groups: &CellGroups,
        broad: &BroadPhase,
    ) {
        for (c, g) in groups.chunks.iter().enumerate() {
            self.follow.dispatch_indirect_at(
                &mut begin_pass(encoder),
                0,
                &g.follow,
                &broad.args,
                broad.list_args_offset(List::Recover(c as u32)),
            );
        }
    }
}

/// One chunk's bind groups of every per-cell stage, and its workgroup counts.
struct ChunkGroups {
    classify: wgpu::BindGroup,
    billboards: wgpu::BindGroup,
    transitions: wgpu::BindGroup,
    /// `transitions`' buffers with the unused arguments buffer in
    /// `back_args`' slot (`transitions_back` reads the real one).
    transitions_back: wgpu::BindGroup,
    slopes: wgpu::BindGroup,
    follow: wgpu::BindGroup,
    size: (u32, u32),
}

/// The per-chunk bind groups of [`Cells`] and their workgroup counts.
pub struct CellGroups {
    chunks: Vec<ChunkGroups>,
    /// The field's list of the cells coming back to geometry
    /// (`GpuField::back_cells`), cleared before each chunk's transitions.
    back_cells: wgpu::Buffer,
}

#[cfg(test)]
mod tests {
    use super::*;
    use trample::field::{Field, FieldParams, Terrain};

    /// Issue 12: cell coordinates were packed as `gx + 4096 gz` in a float
    /// (wrong past 4,096 cells a side). They now take 16 bits each: the
    /// billboards kernel reads them back for fields up to 65,536 a side.
    #[test]
    fn cell_coordinates_round_trip_past_4096_cells_a_side() {
        let params = FieldParams {
            patches: [160, 1],
            cells_per_patch: 32,
            ..FieldParams::default()
        };
        let field = Field::generate(&params, Terrain::Flat(0.0)).unwrap();
        let layout = &field.layout;
        assert!(layout.grid_size()[0] > 4096);
        for c in [
            0,
            31,
            32 * 32,
            layout.cell_count() - 1,
            layout.cell_count() / 2 + 17,
        ] {
            let packed = packed_cell_coords(layout, c).to_bits();
            let [gx, gz] = layout.cell_coord(c);
            assert_eq!((packed & 0xffff, packed >> 16), (gx, gz), "cell {c}");
        }
    }
}
