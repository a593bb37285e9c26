//! Geometric blades: the vertex buffer (the core's layout, uploaded each
//! frame; a field over one storage binding in chunks,
//! [`trample::field::chunks`], one draw a chunk), per-blade width and
//! tint, and a compact instance list of the blades of visible Geometry-LOD
//! cells (built on the CPU each frame). With the GPU path
//! ([`BladePass::draw_gpu`]) nothing is uploaded: one indirect draw per
//! chunk of the field, straight from trample-gpu's buffers.

use crate::globals::shader_module;
use std::ops::Range;
use trample::Simulation;
use trample::field::chunks::VERTEX_BYTES;
use trample::field::{Lod, drawn_blade_cells, plan_chunks, split_at_chunks};

/// One drawn blade. Layout-compatible with `vec2<u32>` of `instances` in blades.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct BladeInstance {
    /// Blade index in storage order.
    pub blade: u32,
    /// Debug colour, RGBA8 packed as by WGSL `unpack4x8unorm`; 0 = normal shading.
    pub debug_rgba: u32,
}

const _: () = assert!(std::mem::size_of::<BladeInstance>() == 8);

/// The blade pass: pipeline and buffers.
pub struct BladePass {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    /// The CPU path's vertex buffers, one a chunk of blades (one for a
    /// field within one storage binding); empty for a pass drawing the GPU
    /// path's buffers ([`BladePass::new_gpu`]) until a CPU frame needs them.
    cpu_chunks: Vec<CpuChunk>,
    shape: wgpu::Buffer,
    instances: wgpu::Buffer,
    /// Per chunk of the GPU path: `(first blade, blades, first blade)`.
    gpu_chunks: Vec<wgpu::Buffer>,
    list: Vec<BladeInstance>,
    /// Per CPU chunk, the run of `list` it draws this frame.
    drawn: Vec<Range<usize>>,
    segments: u32,
}

/// One chunk of the CPU path's blade vertices.
struct CpuChunk {
    /// Its vertices, the core's layout over its blades.
    pos: wgpu::Buffer,
    /// Its blades (global indices).
    blades: Range<u32>,
    /// `(first blade, blades, first listed instance, 0)`: z rewritten each
    /// frame.
    uniform: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
}

impl BladePass {
    /// Creates the pass for `sim`'s field.
    ///
    /// # Errors
    /// The adapter cannot read storage buffers in vertex shaders, or one
    /// of the field's whole arrays (the blades' shapes, 8 bytes a blade)
    /// exceeds one storage binding.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        globals: &wgpu::BindGroupLayout,
        sim: &Simulation,
        target: &crate::TargetFormat,
    ) -> Result<Self, crate::RenderError> {
        let mut pass = Self::new_gpu(device, queue, globals, sim, target)?;
        pass.make_cpu_chunks(device, sim)?;
        Ok(pass)
    }

    /// The CPU path's vertex buffers for `sim`'s field: as few chunks as
    /// fit one storage binding each, cut at any blade (the list drawn is
    /// of blades), bound with the shapes and the instance list.
    fn make_cpu_chunks(
        &mut self,
        device: &wgpu::Device,
        sim: &Simulation,
    ) -> Result<(), crate::RenderError> {
        let allowed = check_whole_arrays(device, sim)?;
        let blades = &sim.field.blades;
        let verts = blades.segments as u32 + 1;
        let plan = plan_chunks(blades.count as u32, verts, 1, allowed).map_err(|e| match e {
            trample::field::ChunkError::UnitTooLarge { bytes, limit } => {
                crate::RenderError::BladesTooLarge {
                    needed: bytes,
                    allowed: limit,
                }
            }
            // A unit of one blade divides every count.
            trample::field::ChunkError::Layout { .. } => unreachable!("{e}"),
        })?;
        self.cpu_chunks = plan
            .into_iter()
            .map(|r| {
                let size = (u64::from(r.end - r.start) * u64::from(verts) * VERTEX_BYTES).max(16);
                let pos = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("blade vertices"),
                    size,
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                let uniform = chunk_uniform(device, r.start, r.end - r.start, 0);
                let bind_group = self.bind(device, &pos, &self.instances, &uniform);
                CpuChunk {
                    pos,
                    blades: r,
                    uniform,
                    bind_group,
                }
            })
            .collect();
        Ok(())
    }

    /// Binds the CPU path's chunks again (the instance list was remade).
    fn rebind_cpu(&mut self, device: &wgpu::Device) {
        let groups: Vec<_> = self
            .cpu_chunks
            .iter()
            .map(|c| self.bind(device, &c.pos, &self.instances, &c.uniform))
            .collect();
        for (chunk, group) in self.cpu_chunks.iter_mut().zip(groups) {
            chunk.bind_group = group;
        }
    }

    /// Creates the pass for drawing `sim`'s field from the GPU path's
    /// buffers ([`BladePass::draw_gpu`]): no vertex buffer of its own.
    ///
    /// # Errors
    /// The adapter cannot read storage buffers in vertex shaders.
    pub fn new_gpu(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        globals: &wgpu::BindGroupLayout,
        sim: &Simulation,
        target: &crate::TargetFormat,
    ) -> Result<Self, crate::RenderError> {
        let limits = device.limits();
        if limits.max_storage_buffers_per_shader_stage < 3 {
            return Err(crate::RenderError::NoVertexStorage);
        }
        let blades = &sim.field.blades;
        let buffer = |label, size: u64| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let shape = buffer("blade shape", (blades.count.max(1) * 8) as u64);
        let shape_data: Vec<[f32; 2]> = blades
            .width
            .iter()
            .zip(&blades.tint)
            .map(|(&w, &t)| [w, t])
            .collect();
        queue.write_buffer(&shape, 0, bytemuck::cast_slice(&shape_data));
        // 1,024 blades to start with, fewer on a device binding less.
        let binding = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        let instances = buffer("blade instances", (8 * 1024).min(binding & !7).max(16));
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("blades"),
            entries: &[
                crate::pipeline::vertex_storage(0),
                crate::pipeline::vertex_storage(1),
                crate::pipeline::vertex_storage(2),
                crate::pipeline::vertex_uniform(3),
            ],
        });
        let module = shader_module(device, "blades.wgsl", include_str!("blades.wgsl"));
        let pipeline = crate::pipeline::build(
            device,
            &crate::pipeline::Spec {
                label: "blades",
                module: &module,
                layouts: &[globals, &layout],
                buffers: &[],
                topology: wgpu::PrimitiveTopology::TriangleStrip,
                cull: None,
                depth: crate::pipeline::DepthUse::Write,
                target,
                alpha_to_coverage: false,
            },
        );
        Ok(Self {
            pipeline,
            layout,
            cpu_chunks: Vec::new(),
            shape,
            instances,
            gpu_chunks: Vec::new(),
            list: Vec::new(),
            drawn: Vec::new(),
            segments: blades.segments as u32,
        })
    }

    fn bind(
        &self,
        device: &wgpu::Device,
        pos: &wgpu::Buffer,
        instances: &wgpu::Buffer,
        chunk: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        let shape = &self.shape;
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("blades"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: pos.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: shape.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: instances.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: chunk.as_entire_binding(),
                },
            ],
        })
    }

    /// Uploads the blade vertices and this frame's instance list: the blades
    /// of Geometry-LOD cells in visible patches, and those of Billboard-LOD
    /// cells nearer than `lod.geometry_m + band` to the viewpoint (the near
    /// blend band, [`crate::RenderParams::lod_blend_m`]; the shader thins
    /// them out). `debug` gives a blade's debug colour from its index and
    /// its cell's level (0 = normal shading). `upload` says which vertices
    /// to write; returns the bytes of blade vertices and of the instance
    /// list written.
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        sim: &Simulation,
        band: f32,
        debug: impl Fn(usize, Lod) -> u32,
        upload: Upload,
    ) -> (u64, u64) {
        let blades = &sim.field.blades;
        let mut upload = upload;
        if self.cpu_chunks.is_empty() {
            // A pass made for the GPU path drawing a CPU frame: a field
            // whose shapes pass one binding draws no blades rather than
            // failing.
            if self.make_cpu_chunks(device, sim).is_err() {
                self.list.clear();
                self.drawn.clear();
                return (0, 0);
            }
            upload = Upload::All;
        }
        let mut bytes = 0;
        for chunk in &self.cpu_chunks {
            bytes += upload_positions(queue, chunk, &sim.field, upload);
        }

        let layout = &sim.field.layout;
        let per_cell = layout.blades_per_cell as usize;
        let cells = &sim.field.cells;
        // The Geometry-LOD cells and the near blend band's Billboard-LOD
        // cells (the core's list, which bevy_trample draws too).
        self.list.clear();
        for c in drawn_blade_cells(
            layout,
            cells,
            &sim.visible,
            sim.eye(),
            sim.lod.geometry_m,
            band,
        ) {
            let level = cells.lod[c];
            for b in c * per_cell..(c + 1) * per_cell {
                // Blades a grass map left out (zero height) draw nothing.
                if blades.seg_len[b] > 0.0 {
                    self.list.push(BladeInstance {
                        blade: b as u32,
                        debug_rgba: debug(b, level),
                    });
                }
            }
        }
        let list_bytes = (self.list.len() * 8) as u64;
        if let Some(b) = crate::pipeline::grown(
            device,
            Some(&self.instances),
            "blade instances",
            wgpu::BufferUsages::STORAGE,
            list_bytes,
        ) {
            self.instances = b;
            self.rebind_cpu(device);
        }
        queue.write_buffer(&self.instances, 0, bytemuck::cast_slice(&self.list));
        // Each chunk draws the run of the (ascending) list it holds, from
        // its first listed instance on.
        let chunks: Vec<_> = self.cpu_chunks.iter().map(|c| c.blades.clone()).collect();
        self.drawn = split_at_chunks(&self.list, |i| u64::from(i.blade), &chunks);
        for (chunk, run) in self.cpu_chunks.iter().zip(&self.drawn) {
            queue.write_buffer(&chunk.uniform, 8, bytemuck::bytes_of(&(run.start as u32)));
        }
        (bytes, list_bytes)
    }

    /// Chunks of blade vertices the CPU path's draws use (0 before its
    /// first frame, or drawing the GPU path's buffers).
    #[must_use]
    pub fn chunks(&self) -> usize {
        self.cpu_chunks.len()
    }

    /// Blades drawn by the last [`BladePass::prepare`].
    #[must_use]
    pub fn drawn(&self) -> usize {
        self.list.len()
    }

    /// Records the draw into `pass`, `copies` drawn blades for each listed
    /// one ([`crate::RenderParams::near_density`]; at least 1).
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, copies: u32) {
        pass.set_pipeline(&self.pipeline);
        for (chunk, run) in self.cpu_chunks.iter().zip(&self.drawn) {
            if run.is_empty() {
                continue;
            }
            pass.set_bind_group(1, &chunk.bind_group, &[]);
            let instances = (run.len() as u32).saturating_mul(copies.max(1));
            pass.draw(0..2 * (self.segments + 1), 0..instances);
        }
    }

    /// The vertices of one blade's strip.
    #[must_use]
    pub fn vertices_per_blade(&self) -> u32 {
        2 * (self.segments + 1)
    }

    /// The bind groups of the GPU path's blades, one per chunk of `field`:
    /// its positions and `lists` (made by `GpuSimulation::record_draw_lists`
    /// earlier in the same encoder), for [`BladePass::draw_gpu`].
    pub fn bind_gpu(
        &mut self,
        device: &wgpu::Device,
        field: &trample_gpu::GpuField,
        lists: &trample_gpu::draw_lists::DrawLists,
    ) -> Vec<wgpu::BindGroup> {
        if self.gpu_chunks.len() != field.chunks.len() {
            self.gpu_chunks = field
                .chunks
                .iter()
                .map(|c| chunk_uniform(device, c.first_blade, c.blades, c.first_blade))
                .collect();
        }
        field
            .chunks
            .iter()
            .zip(&self.gpu_chunks)
            .map(|(chunk, uniform)| self.bind(device, &chunk.pos, &lists.blade_instances, uniform))
            .collect()
    }

    /// Records the GPU path's blades into `pass`: one indirect draw per
    /// chunk, group k drawn with the arguments at `16 k` of `args`.
    pub fn draw_gpu(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        groups: &[wgpu::BindGroup],
        args: &wgpu::Buffer,
    ) {
        pass.set_pipeline(&self.pipeline);
        for (k, group) in groups.iter().enumerate() {
            pass.set_bind_group(1, group, &[]);
            pass.draw_indirect(args, k as u64 * trample_gpu::draw_lists::DRAW_ARGS_BYTES);
        }
    }
}

/// Checks that the field's arrays a renderer binds whole fit one storage
/// binding of `device`: the blades' shapes (8 bytes a blade) and the
/// cells' flatness (4 bytes a cell, the ground's track). Gives the
/// binding's bytes.
///
/// # Errors
/// [`crate::RenderError::BladesTooLarge`] with the larger array's bytes.
pub fn check_whole_arrays(
    device: &wgpu::Device,
    sim: &Simulation,
) -> Result<u64, crate::RenderError> {
    let limits = device.limits();
    let allowed = limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size);
    let needed = (sim.field.blades.count as u64 * 8).max(sim.field.cells.flatness.len() as u64 * 4);
    if needed > allowed {
        return Err(crate::RenderError::BladesTooLarge { needed, allowed });
    }
    Ok(allowed)
}

/// A chunk's `(first blade, blades, first listed instance, 0)` uniform
/// (`chunk` in blades.wgsl): the GPU path lists a chunk's blades from its
/// first blade on; the CPU path's list is compact (rewritten each frame).
fn chunk_uniform(device: &wgpu::Device, first: u32, blades: u32, listed: u32) -> wgpu::Buffer {
    use wgpu::util::DeviceExt;
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("blade chunk"),
        contents: bytemuck::cast_slice(&[first, blades, listed, 0]),
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
    })
}

/// Which blade vertices a frame writes to the GPU.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Upload {
    /// Every vertex of the field (the first frame, or after steps the
    /// renderer did not see).
    All,
    /// The blades the last step changed ([`trample::field::Field::changed_blades`]),
    /// which is everything that moved since the previous frame drawn.
    Changed,
    /// Nothing (no step since the previous frame drawn).
    None,
}

/// Runs of changed blades closer than this many blades are written as one
/// (fewer, larger writes; the blades between are written unchanged).
pub const MERGE_GAP_BLADES: u32 = 32;

/// Writes `field`'s blade vertices (vertex-major, [`trample::field::Blades::pos_bytes`])
/// of `chunk`'s blades into its buffer (the same layout over the chunk's
/// blades) as `upload` says; returns the bytes written.
fn upload_positions(
    queue: &wgpu::Queue,
    chunk: &CpuChunk,
    field: &trample::field::Field,
    upload: Upload,
) -> u64 {
    let blades = &field.blades;
    const VERTEX: usize = std::mem::size_of::<trample::field::BladeVertex>();
    let bytes = blades.pos_bytes();
    let runs: Vec<Range<u32>> = match upload {
        Upload::None => return 0,
        Upload::All => vec![chunk.blades.clone()],
        Upload::Changed => {
            let mut runs: Vec<Range<u32>> = Vec::new();
            for r in field.changed_blades().ranges() {
                let r = r.start.max(chunk.blades.start)..r.end.min(chunk.blades.end);
                if r.is_empty() {
                    continue;
                }
                match runs.last_mut() {
                    Some(last) if r.start - last.end <= MERGE_GAP_BLADES => last.end = r.end,
                    _ => runs.push(r),
                }
            }
            runs
        }
    };
    let in_chunk = (chunk.blades.end - chunk.blades.start) as usize;
    let mut written = 0;
    for k in 0..=blades.segments {
        for r in &runs {
            let first = (k * blades.count + r.start as usize) * VERTEX;
            let last = (k * blades.count + r.end as usize) * VERTEX;
            let to = (k * in_chunk + (r.start - chunk.blades.start) as usize) * VERTEX;
            queue.write_buffer(&chunk.pos, to as u64, &bytes[first..last]);
            written += (last - first) as u64;
        }
    }
    written
}
