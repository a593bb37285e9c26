//! Draw lists for a renderer that draws straight from the GPU path's
//! buffers (DESIGN §7: "keeps its buffers on the GPU so the renderer draws
//! straight from them"): dispatches `draw_lists.wgsl` over the cells of the
//! visible patches and writes the blade and billboard instance lists and
//! their indirect-draw arguments, on the GPU, after a step. The renderer
//! (`trample-render`'s `Renderer::encode_gpu`) supplies what is its own (the
//! vertex counts, the billboard width, the debug palette) in
//! [`GpuDrawParams`]; nothing is read back.

use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use crate::field::GpuField;
use crate::kernel::{Kernel, Slot, grid};

/// The WGSL source as compiled (`segment_obb.wgsl`, `blade.wgsl`,
/// `guard.wgsl` and `billboard.wgsl` prepended).
#[must_use]
pub fn source() -> String {
    format!(
        "{}\n{}\n{}\n{}\n{}",
        crate::SEGMENT_OBB_WGSL,
        crate::BLADE_WGSL,
        crate::GUARD_WGSL,
        crate::BILLBOARD_WGSL,
        include_str!("draw_lists.wgsl")
    )
}

/// The draw lists' uniform. Layout-compatible with `DrawParams` in
/// `draw_lists.wgsl`; [`DrawLists::record`] fills `counts`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct GpuDrawParams {
    /// Cells, cells per patch, cells per chunk, chunks (set by [`DrawLists::record`]).
    pub counts: [u32; 4],
    /// Vertices of a blade, of a billboard; 1 to colour blades by class;
    /// the billboards' debug colour (RGBA8, 0 = textured).
    pub draw: [u32; 4],
    /// Billboard half width (m); drawn blades per listed blade (the
    /// renderer's render density: the blade draws' instance counts are the
    /// listed blades times this, at least 1; 0 reads as 1); the near blend
    /// band (m: Billboard-LOD cells nearer to the viewpoint than
    /// `geometry_m` plus this list their blades too, untouched ones in the
    /// billboards' debug colour; 0: none); unused.
    pub size: [f32; 4],
    /// Debug colours (RGBA8): DBG this step, DBG earlier, PBG earlier, untouched.
    pub palette: [u32; 4],
    /// PBG this step: colour at generation 1 (rgb), fade per generation (w).
    pub pbg: [f32; 4],
}

/// `wgpu::util::DrawIndirectArgs`' size: one per chunk, then the billboards'.
pub const DRAW_ARGS_BYTES: u64 = 16;

/// The largest binding the draw lists of a field of `blades` blades in
/// `cells` cells make, bytes, and what it is: the billboard instances (48
/// bytes a cell) or the blade instances (8 bytes a blade).
#[must_use]
pub fn largest_binding(blades: u64, cells: u64) -> (u64, &'static str) {
    if cells * 48 >= blades * 8 {
        (
            cells * 48,
            "the draw lists' billboard instances (48 bytes a cell)",
        )
    } else {
        (
            blades * 8,
            "the draw lists' blade instances (8 bytes a blade)",
        )
    }
}

/// The compiled kernels and the lists they fill, for one field.
pub struct DrawLists {
    kernel: Kernel,
    uniform: wgpu::Buffer,
    visible: wgpu::Buffer,
    counts: wgpu::Buffer,
    /// Blade instances: `(blade, debug colour)`; chunk k's at its first blade.
    pub blade_instances: wgpu::Buffer,
    /// Billboard instances, 48 bytes each (base + half width, top, extra).
    pub billboards: wgpu::Buffer,
    /// Indirect draw arguments: chunk k's blades at `16 k`, the billboards'
    /// after the last chunk's.
    pub args: wgpu::Buffer,
    chunks: u32,
}

const LIST_CELLS: usize = 0;
const LIST_ARGS: usize = 1;

impl DrawLists {
    /// Compiles the kernels and makes the lists for `field`.
    #[must_use]
    pub fn new(device: &wgpu::Device, field: &GpuField, patches: usize) -> Self {
        use Slot::{Read, ReadWrite, Uniform};
        use wgpu::BufferUsages as U;
        let chunks = field.chunks.len() as u32;
        let buffer = |label: &str, size: u64, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size.max(16),
                usage,
                mapped_at_creation: false,
            })
        };
        Self {
            kernel: Kernel::new(
                device,
                "trample-gpu draw lists",
                &source(),
                &[
                    Uniform, Uniform, Read, Read, Read, Read, Read, Read, ReadWrite, ReadWrite,
                    ReadWrite, ReadWrite, Read,
                ],
                &["list_cells", "list_args"],
            ),
            uniform: buffer(
                "trample-gpu draw params",
                std::mem::size_of::<GpuDrawParams>() as u64,
                U::UNIFORM | U::COPY_DST,
            ),
            visible: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("trample-gpu visible patches"),
                contents: bytemuck::cast_slice(&vec![1u32; patches.max(1)]),
                usage: U::STORAGE | U::COPY_DST,
            }),
            counts: buffer(
                "trample-gpu draw counts",
                u64::from(chunks + 1) * 4,
                U::STORAGE | U::COPY_DST | U::COPY_SRC,
            ),
            blade_instances: buffer(
                "trample-gpu blade instances",
                u64::from(field.count) * 8,
                U::STORAGE | U::COPY_SRC,
            ),
            billboards: buffer(
                "trample-gpu billboard instances",
                u64::from(field.cell_count) * 48,
                U::STORAGE | U::COPY_SRC,
            ),
            args: buffer(
                "trample-gpu draw arguments",
                u64::from(chunks + 1) * DRAW_ARGS_BYTES,
                U::STORAGE | U::INDIRECT | U::COPY_SRC,
            ),
            chunks,
        }
    }

    /// Records the lists of the cells of the `visible` patches (one flag a
    /// patch) into `encoder`, after the step that produced the state.
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        field: &GpuField,
        step_params: &wgpu::Buffer,
        cells_per_patch: u32,
        visible: &[bool],
        mut draw: GpuDrawParams,
    ) {
        let cells_per_chunk = field.chunks.first().map_or(0, |c| c.cells);
        draw.counts = [
            field.cell_count,
            cells_per_patch,
            cells_per_chunk,
            self.chunks,
        ];
        queue.write_buffer(&self.uniform, 0, bytemuck::bytes_of(&draw));
        let flags: Vec<u32> = visible.iter().map(|&v| u32::from(v)).collect();
        if !flags.is_empty() && (flags.len() * 4) as u64 <= self.visible.size() {
            queue.write_buffer(&self.visible, 0, bytemuck::cast_slice(&flags));
        }
        encoder.clear_buffer(&self.counts, 0, None);
        let group = self.kernel.bind(
            device,
            &[
                step_params,
                &self.uniform,
                &field.cell_state,
                &field.cell_rest,
                &field.slope,
                &self.visible,
                &field.generation,
                &field.class,
                &self.blade_instances,
                &self.billboards,
                &self.counts,
                &self.args,
                &field.ground,
            ],
        );
        let max = device.limits().max_compute_workgroups_per_dimension;
        self.kernel
            .dispatch(encoder, LIST_CELLS, &group, grid(field.cell_count, max));
        self.kernel
            .dispatch(encoder, LIST_ARGS, &group, grid(self.chunks + 1, max));
    }

    /// Reads back the instance counts of the last lists: blades per chunk,
    /// then billboards (tests, stats; not per frame).
    ///
    /// # Errors
    /// [`crate::GpuError::ReadBack`] when mapping fails.
    pub fn read_counts(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<u32>, crate::GpuError> {
        let mut v: Vec<u32> =
            crate::readback::read_buffer(device, queue, &self.counts, "draw counts")?;
        v.truncate(self.chunks as usize + 1);
        Ok(v)
    }
}
