//! The field's GPU buffers in the render world: blade vertices (the core's
//! layout, uploaded whole once, then only the runs of blades that
//! changed), per-blade shape, this frame's drawn cells and billboards, the
//! draw parameters; and their bind group (group 2 of `blades.wgsl`). On
//! the GPU path (feature `gpu`) the GPU's own buffers instead: its blade
//! vertices, one bind group for each chunk of them, and its lists.

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

/// Bytes of one indirect draw's arguments (`DrawIndirectArgs`: vertex
/// count, instance count, first vertex, first instance).
pub const DRAW_ARGS_BYTES: u64 = 16;

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
    /// The blades' chunk, `(first blade, blades, 0, 0)`: on the CPU path
    /// one chunk, `(0, blades)`.
    pub chunk: Buffer,
    /// Bind groups over all of them (made in `PrepareBindGroups`; empty
    /// until then): one, or on the GPU path one a chunk of blades (the
    /// billboards are drawn with the first).
    pub bind_groups: Vec<BindGroup>,
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
    /// `DrawIndirectArgs`: chunk k's blades at `16 k`, then the billboards'.
    pub args: Buffer,
    /// Per chunk its blade vertices and its `(first blade, blades)`.
    pub chunks: Vec<(Buffer, Buffer)>,
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

/// The largest storage buffer the device binds whole, bytes.
fn binding_limit(device: &RenderDevice) -> u64 {
    let l = device.limits();
    l.max_storage_buffer_binding_size.min(l.max_buffer_size)
}

/// `None` when `old` holds `bytes`, else a new buffer half as large again
/// (within `limit`, never below `bytes`).
fn grown(
    device: &RenderDevice,
    old: &Buffer,
    label: &'static str,
    bytes: u64,
    limit: u64,
) -> Option<Buffer> {
    (old.size() < bytes).then(|| {
        let size = (bytes + bytes / 2).min(limit).max(bytes);
        buffer(device, label, size, BufferUsages::STORAGE)
    })
}

/// The CPU path's buffer of this frame that the device cannot bind whole,
/// if one: its name and size.
fn too_large(frame: &GrassFrame, vertices: u64, limit: u64) -> Option<(&'static str, u64)> {
    [
        ("blade vertices", vertices * VERTEX_BYTES),
        ("drawn cells", frame.cells.len() as u64 * 4),
        (
            "billboards",
            (frame.billboards.len() * std::mem::size_of::<BillboardInstance>()) as u64,
        ),
    ]
    .into_iter()
    .find(|&(_, bytes)| bytes > limit)
}

/// Makes the buffers for a new field and uploads this frame's changes.
pub fn prepare_grass_buffers(
    mut commands: Commands,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    frame: Res<GrassFrame>,
    gpu: Option<ResMut<GrassGpu>>,
    mut refused: Local<Option<String>>,
) {
    let Some([blades, segments, per_cell]) = frame.layout else {
        if gpu.is_some() {
            commands.remove_resource::<GrassGpu>();
        }
        return;
    };
    let on_gpu = frame.on_gpu_path();
    // On the GPU path the vertices are the GPU's: no buffer of the CPU's.
    let vertices = if on_gpu {
        1
    } else {
        u64::from(blades) * u64::from(segments + 1)
    };
    let limit = binding_limit(&device);
    if let Some((what, bytes)) = too_large(&frame, vertices, limit).filter(|_| !on_gpu) {
        // Not drawn rather than a validation error that stops the app.
        let why = format!(
            "the field's {what} take {bytes} bytes, over the {limit} bytes the device binds \
             whole: the grass is not drawn on the CPU path (the GPU path, \
             TrampleField::on_gpu, draws a field in chunks)"
        );
        if refused.as_ref() != Some(&why) {
            warn!("bevy_trample: {why}");
            *refused = Some(why);
        }
        if gpu.is_some() {
            commands.remove_resource::<GrassGpu>();
        }
        return;
    }
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
                chunk: chunk_uniform(&device, 0, blades),
                bind_groups: Vec::new(),
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
            gpu.cells = Buffer::from(g.instances.clone());
            gpu.billboards = Buffer::from(g.billboards.clone());
            gpu.indirect = Some(Indirect {
                args: Buffer::from(g.args.clone()),
                chunks: g
                    .chunks
                    .iter()
                    .map(|(pos, first, blades)| {
                        (
                            Buffer::from(pos.clone()),
                            chunk_uniform(&device, *first, *blades),
                        )
                    })
                    .collect(),
                billboard_args: g.billboard_args,
                made: g.made,
            });
            gpu.bind_groups.clear();
        }
        queue.write_buffer(&gpu.params, 0, bytemuck::bytes_of(&frame.params));
        if let Some(gpu) = made {
            commands.insert_resource(gpu);
        }
        return;
    }
    let cell_bytes = (frame.cells.len() * 4) as u64;
    if let Some(b) = grown(
        &device,
        &gpu.cells,
        "trample drawn cells",
        cell_bytes,
        limit,
    ) {
        gpu.cells = b;
        gpu.bind_groups.clear();
    }
    queue.write_buffer(&gpu.cells, 0, bytemuck::cast_slice(&frame.cells));
    let bb_bytes = (frame.billboards.len() * std::mem::size_of::<BillboardInstance>()) as u64;
    if let Some(b) = grown(
        &device,
        &gpu.billboards,
        "trample billboards",
        bb_bytes,
        limit,
    ) {
        gpu.billboards = b;
        gpu.bind_groups.clear();
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

/// A chunk's `(first blade, blades, 0, 0)` uniform (`chunk` in blades.wgsl).
fn chunk_uniform(device: &RenderDevice, first: u32, blades: u32) -> Buffer {
    device.create_buffer_with_data(&bevy::render::render_resource::BufferInitDescriptor {
        label: Some("trample blade chunk"),
        contents: bytemuck::cast_slice(&[first, blades, 0, 0]),
        usage: BufferUsages::UNIFORM,
    })
}

/// (Re)makes the bind groups when a buffer was (re)made: one over the
/// uploads, or on the GPU path one a chunk of its blade vertices.
pub fn prepare_grass_bind_group(
    device: Res<RenderDevice>,
    cache: Res<PipelineCache>,
    pipeline: Option<Res<GrassPipeline>>,
    gpu: Option<ResMut<GrassGpu>>,
) {
    let (Some(pipeline), Some(mut gpu)) = (pipeline, gpu) else {
        return;
    };
    if !gpu.bind_groups.is_empty() {
        return;
    }
    let layout = cache.get_bind_group_layout(&pipeline.grass_layout);
    let group = |pos: &Buffer, chunk: &Buffer| {
        device.create_bind_group(
            "trample grass",
            &layout,
            &BindGroupEntries::sequential((
                pos.as_entire_binding(),
                gpu.shape.as_entire_binding(),
                gpu.cells.as_entire_binding(),
                gpu.params.as_entire_binding(),
                gpu.billboards.as_entire_binding(),
                chunk.as_entire_binding(),
            )),
        )
    };
    let groups = match &gpu.indirect {
        Some(indirect) => indirect
            .chunks
            .iter()
            .map(|(pos, chunk)| group(pos, chunk))
            .collect(),
        None => vec![group(&gpu.pos, &gpu.chunk)],
    };
    gpu.bind_groups = groups;
}
