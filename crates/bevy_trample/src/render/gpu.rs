//! The field's GPU buffers in the render world: blade vertices (the core's
//! layout, uploaded whole once, then only the runs of blades that
//! changed), per-blade shape, this frame's drawn cells and billboards, the
//! draw parameters; and their bind group (group 2 of `blades.wgsl`).

use super::extract::{BillboardInstance, GrassFrame, GrassParams};
use super::pipeline::GrassPipeline;
use bevy::prelude::*;
use bevy::render::render_resource::{
    BindGroup, BindGroupEntries, Buffer, BufferDescriptor, BufferUsages, PipelineCache,
};
use bevy::render::renderer::{RenderDevice, RenderQueue};

/// Bytes of one blade vertex on the GPU: `vec4<f32>` (the core's
/// [`trample::field::BladeVertex`], `[x, y, z, 0]`).
pub const VERTEX_BYTES: u64 = 16;

/// The field's buffers and what the draws need to know.
#[derive(Resource)]
pub struct GrassGpu {
    /// Blade vertices, `pos[k * blades + b]`.
    pub pos: Buffer,
    /// Per blade `[width, tint]`.
    pub shape: Buffer,
    /// Cells drawn as blades (grows as needed).
    pub cells: Buffer,
    /// Billboards (grows as needed).
    pub billboards: Buffer,
    /// [`GrassParams`].
    pub params: Buffer,
    /// Bind group over all of them (made in `PrepareBindGroups`).
    pub bind_group: Option<BindGroup>,
    /// Blade instances drawn this frame: cells × blades per cell × drawn
    /// copies per blade ([`super::look::GrassLook::copies`]).
    pub blades: u32,
    /// Billboards drawn this frame.
    pub billboard_count: u32,
    /// Segments per blade (`n`).
    pub segments: u32,
    /// Bytes of vertex data uploaded this frame (for measurements).
    pub uploaded_bytes: u64,
    /// On the GPU path: its indirect draws (blades at 0, billboards at
    /// `billboard_args`), and which GPU field `pos`, `cells` and
    /// `billboards` are the buffers of.
    pub indirect: Option<Indirect>,
}

/// The GPU path's indirect draws.
pub struct Indirect {
    /// `DrawIndirectArgs`, the blades' first.
    pub args: Buffer,
    /// Byte offset of the billboards' draw.
    pub billboard_args: u64,
    /// The GPU field they belong to.
    pub made: u64,
}

fn buffer(device: &RenderDevice, label: &'static str, size: u64, usage: BufferUsages) -> Buffer {
    device.create_buffer(&BufferDescriptor {
        label: Some(label),
        size: size.max(16),
        usage: usage | BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// A buffer of at least `bytes`, `old` when it is large enough (then
/// `false`), else a new one half as large again (then `true`).
fn grown(device: &RenderDevice, old: &Buffer, label: &'static str, bytes: u64) -> Option<Buffer> {
    (old.size() < bytes).then(|| buffer(device, label, bytes + bytes / 2, BufferUsages::STORAGE))
}

/// Makes the buffers for a new field and uploads this frame's changes.
pub fn prepare_grass_buffers(
    mut commands: Commands,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    frame: Res<GrassFrame>,
    gpu: Option<ResMut<GrassGpu>>,
) {
    let Some([blades, segments, per_cell]) = frame.layout else {
        if gpu.is_some() {
            commands.remove_resource::<GrassGpu>();
        }
        return;
    };
    let vertices = u64::from(blades) * u64::from(segments + 1);
    let mut made;
    let gpu = match (gpu, &frame.full) {
        (Some(gpu), None) => {
            made = None;
            gpu.into_inner()
        }
        (_, full) => {
            let Some(shape_data) = full else { return };
            let shape = buffer(
                &device,
                "trample blade shape",
                u64::from(blades) * 8,
                BufferUsages::STORAGE,
            );
            queue.write_buffer(&shape, 0, bytemuck::cast_slice(shape_data));
            made = Some(GrassGpu {
                pos: buffer(
                    &device,
                    "trample blade vertices",
                    vertices * VERTEX_BYTES,
                    BufferUsages::STORAGE,
                ),
                shape,
                cells: buffer(&device, "trample drawn cells", 4096, BufferUsages::STORAGE),
                billboards: buffer(
                    &device,
                    "trample billboards",
                    48 * 1024,
                    BufferUsages::STORAGE,
                ),
                params: buffer(
                    &device,
                    "trample grass params",
                    std::mem::size_of::<GrassParams>() as u64,
                    BufferUsages::UNIFORM,
                ),
                bind_group: None,
                blades: 0,
                billboard_count: 0,
                segments,
                uploaded_bytes: 0,
                indirect: None,
            });
            made.as_mut().unwrap_or_else(|| unreachable!())
        }
    };
    // Only the runs of changed blades.
    let mut at = 0usize;
    gpu.uploaded_bytes = 0;
    for &(first, len) in &frame.runs {
        let data = &frame.staging[at..at + len as usize];
        at += len as usize;
        queue.write_buffer(
            &gpu.pos,
            u64::from(first) * VERTEX_BYTES,
            bytemuck::cast_slice(data),
        );
        gpu.uploaded_bytes += u64::from(len) * VERTEX_BYTES;
    }
    #[cfg(feature = "gpu")]
    if let Some(g) = &frame.gpu {
        // The GPU path's own buffers, bound in place of the uploads.
        if gpu.indirect.as_ref().map(|i| i.made) != Some(g.made) {
            gpu.pos = Buffer::from(g.pos.clone());
            gpu.cells = Buffer::from(g.instances.clone());
            gpu.billboards = Buffer::from(g.billboards.clone());
            gpu.indirect = Some(Indirect {
                args: Buffer::from(g.args.clone()),
                billboard_args: g.billboard_args,
                made: g.made,
            });
            gpu.bind_group = None;
        }
        queue.write_buffer(&gpu.params, 0, bytemuck::bytes_of(&frame.params));
        if let Some(gpu) = made {
            commands.insert_resource(gpu);
        }
        return;
    }
    let cell_bytes = (frame.cells.len() * 4) as u64;
    if let Some(b) = grown(&device, &gpu.cells, "trample drawn cells", cell_bytes) {
        gpu.cells = b;
        gpu.bind_group = None;
    }
    queue.write_buffer(&gpu.cells, 0, bytemuck::cast_slice(&frame.cells));
    let bb_bytes = (frame.billboards.len() * std::mem::size_of::<BillboardInstance>()) as u64;
    if let Some(b) = grown(&device, &gpu.billboards, "trample billboards", bb_bytes) {
        gpu.billboards = b;
        gpu.bind_group = None;
    }
    queue.write_buffer(&gpu.billboards, 0, bytemuck::cast_slice(&frame.billboards));
    queue.write_buffer(&gpu.params, 0, bytemuck::bytes_of(&frame.params));
    gpu.blades = (frame.cells.len() as u32)
        .saturating_mul(per_cell)
        .saturating_mul(frame.params.counts[3].max(1));
    gpu.billboard_count = frame.billboards.len() as u32;
    if let Some(gpu) = made {
        commands.insert_resource(gpu);
    }
}

/// (Re)makes the bind group when a buffer was (re)made.
pub fn prepare_grass_bind_group(
    device: Res<RenderDevice>,
    cache: Res<PipelineCache>,
    pipeline: Option<Res<GrassPipeline>>,
    gpu: Option<ResMut<GrassGpu>>,
) {
    let (Some(pipeline), Some(mut gpu)) = (pipeline, gpu) else {
        return;
    };
    if gpu.bind_group.is_some() {
        return;
    }
    let layout = cache.get_bind_group_layout(&pipeline.grass_layout);
    let group = device.create_bind_group(
        "trample grass",
        &layout,
        &BindGroupEntries::sequential((
            gpu.pos.as_entire_binding(),
            gpu.shape.as_entire_binding(),
            gpu.cells.as_entire_binding(),
            gpu.params.as_entire_binding(),
            gpu.billboards.as_entire_binding(),
        )),
    );
    gpu.bind_group = Some(group);
}
