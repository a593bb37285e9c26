//! The per-cell stages on the GPU: level of detail (Fig. 1), billboards
//! (Eq. 8), transitions (Eq. 9–13) and billboard recovery; dispatches
//! `cells.wgsl`. `classify` runs first in a sub-step (the narrow phase needs
//! the levels); the others after the blades bend, as in
//! `trample::step::stages::substep`.
//!
//! Differences from the CPU path, by design: every cell is classified (the
//! CPU skips patches whose cells all keep one level: same result), and
//! every billboard cell tests every object's root box (the CPU first keeps
//! the patches under the box: a conservative filter, same result).

use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use trample::field::FieldLayout;
use trample::obb::Obb;

use crate::field::GpuField;
use crate::kernel::{Kernel, Slot};

/// The WGSL source as compiled (`segment_obb.wgsl`, `blade.wgsl`,
/// `guard.wgsl`, `billboard.wgsl` and `chunk.wgsl` prepended).
#[must_use]
pub fn source() -> String {
    format!(
        "{}\n{}\n{}\n{}\n{}\n{}",
        crate::SEGMENT_OBB_WGSL,
        crate::BLADE_WGSL,
        crate::GUARD_WGSL,
        crate::BILLBOARD_WGSL,
        crate::CHUNK_WGSL,
        include_str!("cells.wgsl")
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

/// Global cell coordinates (gx, gz) of cell `c` packed as `gx + 4096 gz`
/// in an f32 (exact below 2^24: fields up to 4096 cells a side).
#[must_use]
pub fn packed_cell_coords(layout: &FieldLayout, c: usize) -> f32 {
    let cpp = layout.cells_per_patch as usize;
    let (p, l) = (c / layout.cells_in_patch(), c % layout.cells_in_patch());
    let px = p % layout.patches[0] as usize;
    let pz = p / layout.patches[0] as usize;
    let (gx, gz) = (px * cpp + l % cpp, pz * cpp + l / cpp);
    (gx + 4096 * gz) as f32
}

const CLASSIFY: usize = 0;
const BILLBOARDS: usize = 1;
const TRANSITIONS: usize = 2;
const RECOVER_SLOPES: usize = 3;

/// The compiled per-cell kernels.
pub struct Cells {
    kernel: Kernel,
}

impl Cells {
    /// Compiles the kernels on `device`.
    #[must_use]
    pub fn new(device: &wgpu::Device) -> Self {
        use Slot::{Read, ReadWrite, Uniform};
        Self {
            kernel: Kernel::new(
                device,
                "trample-gpu cells",
                &source(),
                &[
                    Uniform, ReadWrite, ReadWrite, Read, ReadWrite, Read, ReadWrite, Read,
                    ReadWrite, Uniform, Read,
                ],
                &["classify", "billboards", "transitions", "recover_slopes"],
            ),
        }
    }

    /// The bind groups over `field`, one per chunk, with the step
    /// uniform, the counters and the objects' world root boxes.
    pub fn bind(
        &self,
        device: &wgpu::Device,
        field: &GpuField,
        params: &wgpu::Buffer,
        state: &wgpu::Buffer,
        world_roots: &wgpu::Buffer,
    ) -> CellGroups {
        CellGroups(
            field
                .chunks
                .iter()
                .map(|chunk| {
                    let group = self.kernel.bind(
                        device,
                        &[
                            params,
                            state,
                            &field.cell_state,
                            &field.cell_rest,
                            &field.slope,
                            world_roots,
                            &chunk.pos,
                            &chunk.rest,
                            &field.displaced,
                            &chunk.uniform,
                            &field.ground,
                        ],
                    );
                    (group, chunk.cell_groups)
                })
                .collect(),
        )
    }

    /// Records `entry` over every chunk's cells.
    fn record(&self, encoder: &mut wgpu::CommandEncoder, entry: usize, groups: &CellGroups) {
        for (group, size) in &groups.0 {
            self.kernel.dispatch(encoder, entry, group, *size);
        }
    }

    /// Records the level of detail of every cell (before the narrow phase).
    pub fn record_classify(&self, encoder: &mut wgpu::CommandEncoder, groups: &CellGroups) {
        self.record(encoder, CLASSIFY, groups);
    }

    /// Records billboards (Eq. 8), after the blades bend.
    pub fn record_billboards(&self, encoder: &mut wgpu::CommandEncoder, groups: &CellGroups) {
        self.record(encoder, BILLBOARDS, groups);
    }

    /// Records transitions (Eq. 9–13), after the billboards.
    pub fn record_transitions(&self, encoder: &mut wgpu::CommandEncoder, groups: &CellGroups) {
        self.record(encoder, TRANSITIONS, groups);
    }

    /// Records the recovery of bent billboards (after the blades recover).
    pub fn record_recover_slopes(&self, encoder: &mut wgpu::CommandEncoder, groups: &CellGroups) {
        self.record(encoder, RECOVER_SLOPES, groups);
    }
}

/// The per-chunk bind groups of [`Cells`] and their workgroup counts.
pub struct CellGroups(Vec<(wgpu::BindGroup, (u32, u32))>);
