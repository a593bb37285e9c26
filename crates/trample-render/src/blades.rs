//! Geometric blades: the vertex buffer (the core's layout, uploaded each
//! frame), per-blade width and tint, and a compact instance list of the
//! blades of visible Geometry-LOD cells (built on the CPU each frame). With
//! the GPU path ([`BladePass::draw_gpu`]) nothing is uploaded: one indirect
//! draw per chunk of the field, straight from trample-gpu's buffers.

use crate::globals::shader_module;
use trample::Simulation;
use trample::field::{Lod, drawn_blade_cells};

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
    /// The CPU path's vertex buffer; `None` for a pass drawing the GPU
    /// path's buffers ([`BladePass::new_gpu`]) until a CPU frame needs it.
    pos: Option<wgpu::Buffer>,
    shape: wgpu::Buffer,
    instances: wgpu::Buffer,
    /// `(0, blade count)`: the CPU path's one chunk.
    whole: wgpu::Buffer,
    /// Per chunk of the GPU path: `(first blade, blades)`.
    gpu_chunks: Vec<wgpu::Buffer>,
    bind_group: Option<wgpu::BindGroup>,
    list: Vec<BladeInstance>,
    segments: u32,
}

impl BladePass {
    /// Creates the pass for `sim`'s field.
    ///
    /// # Errors
    /// The adapter cannot read storage buffers in vertex shaders, or the
    /// field's vertex buffer exceeds one storage binding.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        globals: &wgpu::BindGroupLayout,
        sim: &Simulation,
        target: &crate::TargetFormat,
    ) -> Result<Self, crate::RenderError> {
        let mut pass = Self::new_gpu(device, queue, globals, sim, target)?;
        pass.pos = Some(Self::cpu_positions(device, sim)?);
        pass.bind_group = Some(pass.bind_cpu(device));
        Ok(pass)
    }

    /// The CPU path's vertex buffer for `sim`'s field.
    fn cpu_positions(
        device: &wgpu::Device,
        sim: &Simulation,
    ) -> Result<wgpu::Buffer, crate::RenderError> {
        let allowed = device.limits().max_storage_buffer_binding_size;
        let needed = (sim.field.blades.pos.len().max(1) * 16) as u64;
        if needed > allowed {
            return Err(crate::RenderError::BladesTooLarge { needed, allowed });
        }
        Ok(device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("blade vertices"),
            size: needed,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        }))
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
        let instances = buffer("blade instances", 8 * 1024);
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("blades"),
            entries: &[
                crate::pipeline::vertex_storage(0),
                crate::pipeline::vertex_storage(1),
                crate::pipeline::vertex_storage(2),
                crate::pipeline::vertex_uniform(3),
            ],
        });
        let whole = chunk_uniform(device, 0, blades.count as u32);
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
            pos: None,
            shape,
            instances,
            whole,
            gpu_chunks: Vec::new(),
            bind_group: None,
            list: Vec::new(),
            segments: blades.segments as u32,
        })
    }

    /// The CPU path's bind group (its vertex buffer must exist).
    fn bind_cpu(&self, device: &wgpu::Device) -> wgpu::BindGroup {
        let pos = self.pos.as_ref().expect("made before binding");
        self.bind(device, pos, &self.instances, &self.whole)
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
        if self.pos.is_none() {
            // A pass made for the GPU path drawing a CPU frame: a field
            // over one binding draws no blades rather than failing.
            let Ok(pos) = Self::cpu_positions(device, sim) else {
                self.list.clear();
                return (0, 0);
            };
            self.pos = Some(pos);
            self.bind_group = Some(self.bind_cpu(device));
            upload = Upload::All;
        }
        let mut bytes = 0;
        if let Some(pos) = &self.pos {
            bytes += upload_positions(queue, pos, &sim.field, upload);
        }

        let layout = &sim.field.layout;
        let per_cell = layout.blades_per_cell as usize;
        let cells = &sim.field.cells;
        // The Geometry-LOD cells and the near blend band's Billboard-LOD
        // cells (the core's list, which bevy_trample draws too).
        self.list.clear();
        for c in drawn_blade_cells(
            layout,
            &cells.lod,
            &cells.base,
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
            self.bind_group = Some(self.bind_cpu(device));
        }
        queue.write_buffer(&self.instances, 0, bytemuck::cast_slice(&self.list));
        (bytes, list_bytes)
    }

    /// Blades drawn by the last [`BladePass::prepare`].
    #[must_use]
    pub fn drawn(&self) -> usize {
        self.list.len()
    }

    /// Records the draw into `pass`, `copies` drawn blades for each listed
    /// one ([`crate::RenderParams::near_density`]; at least 1).
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, copies: u32) {
        let Some(group) = self.bind_group.as_ref().filter(|_| !self.list.is_empty()) else {
            return;
        };
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(1, group, &[]);
        let instances = (self.list.len() as u32).saturating_mul(copies.max(1));
        pass.draw(0..2 * (self.segments + 1), 0..instances);
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
                .map(|c| chunk_uniform(device, c.first_blade, c.blades))
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

/// A chunk's `(first blade, blades)` uniform (`chunk` in blades.wgsl).
fn chunk_uniform(device: &wgpu::Device, first: u32, blades: u32) -> wgpu::Buffer {
    use wgpu::util::DeviceExt;
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("blade chunk"),
        contents: bytemuck::cast_slice(&[first, blades, 0, 0]),
        usage: wgpu::BufferUsages::UNIFORM,
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
/// into `pos` as `upload` says; returns the bytes written.
fn upload_positions(
    queue: &wgpu::Queue,
    pos: &wgpu::Buffer,
    field: &trample::field::Field,
    upload: Upload,
) -> u64 {
    let blades = &field.blades;
    const VERTEX: usize = std::mem::size_of::<trample::field::BladeVertex>();
    let bytes = blades.pos_bytes();
    match upload {
        Upload::None => 0,
        Upload::All => {
            queue.write_buffer(pos, 0, bytes);
            bytes.len() as u64
        }
        Upload::Changed => {
            let mut runs: Vec<std::ops::Range<u32>> = Vec::new();
            for r in field.changed_blades().ranges() {
                match runs.last_mut() {
                    Some(last) if r.start - last.end <= MERGE_GAP_BLADES => last.end = r.end,
                    _ => runs.push(r),
                }
            }
            let mut written = 0;
            for k in 0..=blades.segments {
                for r in &runs {
                    let first = (k * blades.count + r.start as usize) * VERTEX;
                    let last = (k * blades.count + r.end as usize) * VERTEX;
                    queue.write_buffer(pos, first as u64, &bytes[first..last]);
                    written += (last - first) as u64;
                }
            }
            written
        }
    }
}
