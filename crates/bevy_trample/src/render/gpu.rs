//! The field's GPU buffers in the render world: blade vertices (the core's
//! layout, uploaded whole once, then only the runs of blades that
//! changed; in chunks of patches when the field is over one storage
//! binding, [`trample::field::chunks`]), per-blade shape, this frame's
//! drawn cells and billboards, the draw parameters; and their bind groups
//! (group 2 of `blades.wgsl`, one a chunk). On the GPU path (feature
//! `gpu`) the GPU's own buffers instead: its blade vertices, in its own
//! chunks, and its lists.

use super::extract::{BillboardInstance, GrassFrame, GrassParams};
use super::pipeline::GrassPipeline;
use bevy::prelude::*;
use bevy::render::render_resource::{
    BindGroup, BindGroupEntries, Buffer, BufferDescriptor, BufferUsages, PipelineCache,
};
use bevy::render::renderer::{RenderDevice, RenderQueue};
use std::ops::Range;
use trample::field::{drawn_ranges, list_pieces, plan_chunks};

/// Bytes of one blade vertex on the GPU: `vec4<f32>` (the core's
/// [`trample::field::BladeVertex`], `[x, y, z, 0]`).
pub const VERTEX_BYTES: u64 = trample::field::chunks::VERTEX_BYTES;

/// Bytes of one indirect draw's arguments (`DrawIndirectArgs`: vertex
/// count, instance count, first vertex, first instance).
pub const DRAW_ARGS_BYTES: u64 = 16;

/// The field's buffers and what the draws need to know.
#[derive(Resource)]
pub struct GrassGpu {
    /// Blade vertices by chunk of patches (one chunk for a field within
    /// one storage binding): the chunk's vertices (vertex k of its blade l
    /// at `k * blades + l`) and its `(first blade, blades, 0, 0)` uniform.
    /// On the CPU path the uploads, on the GPU path its own buffers.
    pub chunks: Vec<(Buffer, Buffer)>,
    /// On the CPU path: each chunk's blades (global indices), as `chunks`.
    pub chunk_blades: Vec<Range<u32>>,
    /// On the CPU path: each chunk's blade instances drawn this frame (the
    /// drawn cells cut at the chunks' borders, × blades per cell × drawn
    /// copies; instance indices into the whole list).
    pub drawn: Vec<Range<u32>>,
    /// Per blade `[width, tint]`.
    pub shape: Buffer,
    /// Cells drawn as blades (grows as needed).
    pub cells: Buffer,
    /// Billboards, in pieces of at most one storage binding (each grows
    /// as needed; on the GPU path its one list).
    pub billboards: Vec<Buffer>,
    /// Billboards drawn this frame from each piece.
    pub billboard_counts: Vec<u32>,
    /// [`GrassParams`].
    pub params: Buffer,
    /// Bind groups over all of them (made in `PrepareBindGroups`; empty
    /// until then): one a chunk of blade vertices (with the first piece
    /// of billboards), then one a further piece of billboards (with the
    /// first chunk of blades).
    pub bind_groups: Vec<BindGroup>,
    /// Blade instances drawn this frame: cells × blades per cell × drawn
    /// copies per blade ([`super::look::GrassLook::copies`]).
    pub blades: u32,
    /// Billboards drawn this frame (all pieces).
    pub billboard_count: u32,
    /// Segments per blade (`n`).
    pub segments: u32,
    /// Bytes of vertex data uploaded this frame (for measurements).
    pub uploaded_bytes: u64,
    /// On the GPU path: its indirect draws (blades at 0, billboards at
    /// `billboard_args`), and which GPU field `chunks`, `cells` and
    /// `billboards` are the buffers of.
    pub indirect: Option<Indirect>,
}

/// The GPU path's indirect draws.
pub struct Indirect {
    /// `DrawIndirectArgs`: chunk k's blades at `16 k`, then the billboards'.
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

/// The largest storage buffer the device binds whole, bytes.
fn binding_limit(device: &RenderDevice) -> u64 {
    let l = device.limits();
    l.max_storage_buffer_binding_size.min(l.max_buffer_size)
}

/// `None` when `old` holds `bytes`, else a new buffer half as large again
/// (within `limit`, never below `bytes`), its size a multiple of 4 bytes
/// (a storage binding's must be: half again of 4 · an odd count was not).
fn grown(
    device: &RenderDevice,
    old: &Buffer,
    label: &'static str,
    bytes: u64,
    limit: u64,
) -> Option<Buffer> {
    (old.size() < bytes).then(|| {
        buffer(
            device,
            label,
            grown_size(bytes, limit),
            BufferUsages::STORAGE,
        )
    })
}

/// The size [`grown`] gives a buffer that must hold `bytes` (a multiple of
/// 4) within a binding of `limit` bytes.
fn grown_size(bytes: u64, limit: u64) -> u64 {
    (bytes + bytes / 2)
        .next_multiple_of(16)
        .min(limit & !3)
        .max(bytes)
}

/// How the CPU path's buffers of this frame fit the device: the chunks of
/// the blade vertices (`blades` blades of `verts` vertices, cut at
/// `unit` blades), or why the field cannot be drawn (a whole-field array
/// over one binding, or one patch's vertices). The billboards are drawn
/// in pieces ([`list_pieces`]).
fn fit(
    frame: &GrassFrame,
    [blades, verts, unit]: [u32; 3],
    limit: u64,
) -> Result<Vec<Range<u32>>, String> {
    let whole = [
        ("blade shapes", u64::from(blades) * 8),
        ("drawn cells", frame.cells.len() as u64 * 4),
    ];
    if let Some((what, bytes)) = whole.into_iter().find(|&(_, bytes)| bytes > limit) {
        return Err(format!(
            "the field's {what} take {bytes} bytes, over the {limit} bytes the device binds whole"
        ));
    }
    plan_chunks(blades, verts, unit, limit).map_err(|e| format!("{e}"))
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
    let Some([blades, segments, per_cell, unit]) = frame.layout else {
        if gpu.is_some() {
            commands.remove_resource::<GrassGpu>();
        }
        return;
    };
    let on_gpu = frame.on_gpu_path();
    let limit = binding_limit(&device);
    // On the GPU path the vertices and lists are the GPU's, in its chunks.
    let plan = if on_gpu {
        Ok(Vec::new())
    } else {
        fit(&frame, [blades, segments + 1, unit], limit)
    };
    let plan = match plan {
        Ok(plan) => plan,
        Err(why) => {
            // Not drawn rather than a validation error that stops the app.
            let why = format!("{why}: the grass is not drawn");
            if refused.as_ref() != Some(&why) {
                warn!("bevy_trample: {why}");
                *refused = Some(why);
            }
            if gpu.is_some() {
                commands.remove_resource::<GrassGpu>();
            }
            return;
        }
    };
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
            let chunks = plan
                .iter()
                .map(|r| {
                    let vertices = u64::from(r.len() as u32) * u64::from(segments + 1);
                    (
                        buffer(
                            &device,
                            "trample blade vertices",
                            vertices * VERTEX_BYTES,
                            BufferUsages::STORAGE,
                        ),
                        chunk_uniform(&device, r.start, r.len() as u32),
                    )
                })
                .collect();
            made = Some(GrassGpu {
                chunks,
                chunk_blades: plan.clone(),
                drawn: Vec::new(),
                shape,
                cells: buffer(&device, "trample drawn cells", 4096, BufferUsages::STORAGE),
                billboards: vec![buffer(
                    &device,
                    "trample billboards",
                    48 * 1024,
                    BufferUsages::STORAGE,
                )],
                billboard_counts: Vec::new(),
                params: buffer(
                    &device,
                    "trample grass params",
                    std::mem::size_of::<GrassParams>() as u64,
                    BufferUsages::UNIFORM,
                ),
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
    #[cfg(feature = "gpu")]
    if let Some(g) = &frame.gpu {
        // The GPU path's own buffers, bound in place of the uploads.
        if gpu.indirect.as_ref().map(|i| i.made) != Some(g.made) {
            gpu.cells = Buffer::from(g.instances.clone());
            gpu.billboards = vec![Buffer::from(g.billboards.clone())];
            gpu.chunks = g
                .chunks
                .iter()
                .map(|(pos, first, blades)| {
                    (
                        Buffer::from(pos.clone()),
                        chunk_uniform(&device, *first, *blades),
                    )
                })
                .collect();
            gpu.chunk_blades.clear();
            gpu.indirect = Some(Indirect {
                args: Buffer::from(g.args.clone()),
                billboard_args: g.billboard_args,
                made: g.made,
            });
            gpu.bind_groups.clear();
        }
        gpu.uploaded_bytes = 0;
        queue.write_buffer(&gpu.params, 0, bytemuck::bytes_of(&frame.params));
        if let Some(gpu) = made {
            commands.insert_resource(gpu);
        }
        return;
    }
    gpu.uploaded_bytes = upload_runs(&queue, gpu, &frame, blades);
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
    let pieces = list_pieces(
        frame.billboards.len(),
        std::mem::size_of::<BillboardInstance>() as u64,
        limit,
    );
    gpu.billboard_counts.clear();
    for (k, piece) in pieces.into_iter().enumerate() {
        let data = &frame.billboards[piece];
        let bytes = std::mem::size_of_val(data) as u64;
        if k == gpu.billboards.len() {
            gpu.billboards.push(buffer(
                &device,
                "trample billboards",
                bytes,
                BufferUsages::STORAGE,
            ));
            gpu.bind_groups.clear();
        }
        if let Some(b) = grown(
            &device,
            &gpu.billboards[k],
            "trample billboards",
            bytes,
            limit,
        ) {
            gpu.billboards[k] = b;
            gpu.bind_groups.clear();
        }
        queue.write_buffer(&gpu.billboards[k], 0, bytemuck::cast_slice(data));
        gpu.billboard_counts.push(data.len() as u32);
    }
    queue.write_buffer(&gpu.params, 0, bytemuck::bytes_of(&frame.params));
    // Each chunk draws the listed cells whose blades it holds (the list is
    // ascending, so they are one run of it).
    let instances_a_cell = per_cell.saturating_mul(frame.params.counts[3].max(1));
    let at = |i: usize| (i as u32).saturating_mul(instances_a_cell);
    gpu.drawn = drawn_ranges(&frame.cells, &gpu.chunk_blades, per_cell)
        .into_iter()
        .map(|r| at(r.start)..at(r.end))
        .collect();
    gpu.blades = at(frame.cells.len());
    gpu.billboard_count = frame.billboards.len() as u32;
    if let Some(gpu) = made {
        commands.insert_resource(gpu);
    }
}

/// Writes the frame's runs of changed vertices (the core's layout over
/// all `blades`: vertex k of blade b at `k * blades + b`) into the chunks
/// that hold them; the bytes written.
fn upload_runs(queue: &RenderQueue, gpu: &GrassGpu, frame: &GrassFrame, blades: u32) -> u64 {
    let mut at = 0usize;
    let mut bytes = 0;
    for &(first, len) in &frame.runs {
        let data = &frame.staging[at..at + len as usize];
        at += len as usize;
        // A run lies within one vertex level k (the extract cuts them so).
        let (k, b0) = (first / blades.max(1), first % blades.max(1));
        for ((pos, _), chunk) in gpu.chunks.iter().zip(&gpu.chunk_blades) {
            let lo = b0.max(chunk.start);
            let hi = (b0 + len).min(chunk.end);
            if lo >= hi {
                continue;
            }
            let in_chunk =
                u64::from(k) * u64::from(chunk.len() as u32) + u64::from(lo - chunk.start);
            let part = &data[(lo - b0) as usize..(hi - b0) as usize];
            queue.write_buffer(pos, in_chunk * VERTEX_BYTES, bytemuck::cast_slice(part));
            bytes += u64::from(hi - lo) * VERTEX_BYTES;
        }
    }
    bytes
}

/// A chunk's `(first blade, blades, 0, 0)` uniform (`chunk` in blades.wgsl).
fn chunk_uniform(device: &RenderDevice, first: u32, blades: u32) -> Buffer {
    device.create_buffer_with_data(&bevy::render::render_resource::BufferInitDescriptor {
        label: Some("trample blade chunk"),
        contents: bytemuck::cast_slice(&[first, blades, 0, 0]),
        usage: BufferUsages::UNIFORM,
    })
}

/// (Re)makes the bind groups when a buffer was (re)made: one a chunk of
/// blade vertices (the uploads', or the GPU path's own), then one a
/// further piece of billboards.
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
    let group = |(pos, chunk): &(Buffer, Buffer), billboards: &Buffer| {
        device.create_bind_group(
            "trample grass",
            &layout,
            &BindGroupEntries::sequential((
                pos.as_entire_binding(),
                gpu.shape.as_entire_binding(),
                gpu.cells.as_entire_binding(),
                gpu.params.as_entire_binding(),
                billboards.as_entire_binding(),
                chunk.as_entire_binding(),
            )),
        )
    };
    let (Some(first_chunk), Some(first_piece)) = (gpu.chunks.first(), gpu.billboards.first())
    else {
        return;
    };
    let groups = gpu
        .chunks
        .iter()
        .map(|c| group(c, first_piece))
        .chain(gpu.billboards[1..].iter().map(|b| group(first_chunk, b)))
        .collect();
    gpu.bind_groups = groups;
}

#[cfg(test)]
mod tests {
    use super::grown_size;

    #[test]
    fn a_grown_buffer_binds_whole() {
        // 4,959 drawn cells: 19,836 bytes; half again was 29,754, which a
        // storage binding refuses (not a multiple of 4).
        for bytes in [4, 19_836, 48 * 7, 1 << 20] {
            let size = grown_size(bytes, 1 << 27);
            assert!(
                size >= bytes + bytes / 2 && size.is_multiple_of(4),
                "{bytes}: {size}"
            );
        }
        // Within the limit (a multiple of 4 below it), never below the bytes.
        assert_eq!(grown_size(1000, 1202), 1200);
        assert_eq!(grown_size(1000, 1000), 1000);
    }
}
