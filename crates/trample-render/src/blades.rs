//! Geometric blades: the vertex buffer (the core's layout, uploaded each
//! frame), per-blade width and tint, and a compact instance list of the
//! blades of visible Geometry-LOD cells (built on the CPU each frame).

use crate::globals::shader_module;
use trample::Simulation;
use trample::field::Lod;

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
    pos: wgpu::Buffer,
    shape: wgpu::Buffer,
    instances: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    staging: Vec<[f32; 4]>,
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
        samples: u32,
    ) -> Result<Self, crate::RenderError> {
        let limits = device.limits();
        if limits.max_storage_buffers_per_shader_stage < 3 {
            return Err(crate::RenderError::NoVertexStorage);
        }
        let blades = &sim.field.blades;
        let pos_bytes = (blades.pos.len().max(1) * 16) as u64;
        if pos_bytes > limits.max_storage_buffer_binding_size {
            return Err(crate::RenderError::BladesTooLarge {
                needed: pos_bytes,
                allowed: limits.max_storage_buffer_binding_size,
            });
        }
        let buffer = |label, size: u64| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let pos = buffer("blade vertices", pos_bytes);
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
                depth_write: true,
                samples,
                alpha_to_coverage: false,
            },
        );
        let bind_group = Self::bind(device, &layout, &pos, &shape, &instances);
        Ok(Self {
            pipeline,
            layout,
            pos,
            shape,
            instances,
            bind_group,
            staging: Vec::new(),
            list: Vec::new(),
            segments: blades.segments as u32,
        })
    }

    fn bind(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        pos: &wgpu::Buffer,
        shape: &wgpu::Buffer,
        instances: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("blades"),
            layout,
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
            ],
        })
    }

    /// Uploads the blade vertices and this frame's instance list: the blades
    /// of Geometry-LOD cells in visible patches. `debug` gives a blade's debug
    /// colour (0 = normal shading).
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        sim: &Simulation,
        debug: impl Fn(usize) -> u32,
    ) {
        let blades = &sim.field.blades;
        self.staging.clear();
        self.staging
            .extend(blades.pos.iter().map(|v| [v.x, v.y, v.z, 1.0]));
        queue.write_buffer(&self.pos, 0, bytemuck::cast_slice(&self.staging));

        let layout = &sim.field.layout;
        let per_cell = layout.blades_per_cell as usize;
        self.list.clear();
        for (p, patch) in layout.patch_list.iter().enumerate() {
            if !sim.visible.get(p).copied().unwrap_or(true) {
                continue;
            }
            let first = patch.first_cell as usize;
            for c in first..first + layout.cells_in_patch() {
                if sim.field.cells.lod[c] != Lod::Geometry {
                    continue;
                }
                for b in c * per_cell..(c + 1) * per_cell {
                    self.list.push(BladeInstance {
                        blade: b as u32,
                        debug_rgba: debug(b),
                    });
                }
            }
        }
        let bytes = (self.list.len() * 8) as u64;
        if bytes > self.instances.size() {
            self.instances = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("blade instances"),
                size: bytes.next_power_of_two(),
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            self.bind_group = Self::bind(
                device,
                &self.layout,
                &self.pos,
                &self.shape,
                &self.instances,
            );
        }
        queue.write_buffer(&self.instances, 0, bytemuck::cast_slice(&self.list));
    }

    /// Blades drawn by the last [`BladePass::prepare`].
    #[must_use]
    pub fn drawn(&self) -> usize {
        self.list.len()
    }

    /// Records the draw into `pass`.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        if self.list.is_empty() {
            return;
        }
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(1, &self.bind_group, &[]);
        pass.draw(0..2 * (self.segments + 1), 0..self.list.len() as u32);
    }
}
