//! The ground: a grid mesh over the field's terrain (and a margin of one
//! field size around it, so the horizon is not an edge), textured with the
//! generated grass texture.

use crate::globals::shader_module;
use bytemuck::{Pod, Zeroable};
use trample::Simulation;

/// Grid quads along each side of the ground mesh.
pub const GRID: u32 = 192;

/// A ground vertex. Layout-compatible with `VertexIn` in terrain.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GroundVertex {
    /// World position.
    pub position: [f32; 3],
    /// Unit normal.
    pub normal: [f32; 3],
}

const _: () = assert!(std::mem::size_of::<GroundVertex>() == 24);

/// The ground pass.
pub struct TerrainPass {
    pipeline: wgpu::RenderPipeline,
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
    bind_group: wgpu::BindGroup,
}

/// The ground mesh of `sim`'s field: vertices and triangle indices.
#[must_use]
pub fn ground_mesh(sim: &Simulation) -> (Vec<GroundVertex>, Vec<u32>) {
    let layout = &sim.field.layout;
    let [gx, gz] = layout.grid_size();
    let size = [gx as f32 * layout.cell_size, gz as f32 * layout.cell_size];
    // One field size of margin on every side.
    let min = [layout.origin[0] - size[0], layout.origin[1] - size[1]];
    let span = [3.0 * size[0], 3.0 * size[1]];
    let terrain = &sim.field.terrain;
    let at = |i: u32, j: u32| {
        let x = min[0] + span[0] * i as f32 / GRID as f32;
        let z = min[1] + span[1] * j as f32 / GRID as f32;
        glam::Vec3::new(x, terrain.height_at(x, z), z)
    };
    let mut vertices = Vec::with_capacity(((GRID + 1) * (GRID + 1)) as usize);
    for j in 0..=GRID {
        for i in 0..=GRID {
            let p = at(i, j);
            let dx = at((i + 1).min(GRID), j) - at(i.saturating_sub(1), j);
            let dz = at(i, (j + 1).min(GRID)) - at(i, j.saturating_sub(1));
            let n = dz.cross(dx).normalize_or(glam::Vec3::Y);
            vertices.push(GroundVertex {
                position: p.to_array(),
                normal: n.to_array(),
            });
        }
    }
    let mut indices = Vec::with_capacity((GRID * GRID * 6) as usize);
    let v = |i: u32, j: u32| j * (GRID + 1) + i;
    for j in 0..GRID {
        for i in 0..GRID {
            indices.extend_from_slice(&[
                v(i, j),
                v(i, j + 1),
                v(i + 1, j),
                v(i + 1, j),
                v(i, j + 1),
                v(i + 1, j + 1),
            ]);
        }
    }
    (vertices, indices)
}

impl TerrainPass {
    /// Builds the ground mesh and texture of `sim`'s field.
    #[must_use]
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        globals: &wgpu::BindGroupLayout,
        sim: &Simulation,
        target: &crate::TargetFormat,
    ) -> Self {
        use wgpu::util::DeviceExt;
        let (vertices, indices) = ground_mesh(sim);
        let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("ground vertices"),
            contents: bytemuck::cast_slice(&vertices),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let index_count = indices.len() as u32;
        let indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("ground indices"),
            contents: bytemuck::cast_slice(&indices),
            usage: wgpu::BufferUsages::INDEX,
        });
        let texture = crate::textures::upload(
            device,
            queue,
            "ground grass",
            crate::textures::ground_grass(11),
        );
        let sampler = crate::textures::repeat_sampler(device);
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("terrain"),
            entries: &crate::pipeline::texture_and_sampler(0),
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("terrain"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&texture),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Sampler(&sampler),
                },
            ],
        });
        let module = shader_module(device, "terrain.wgsl", include_str!("terrain.wgsl"));
        let attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];
        let pipeline = crate::pipeline::build(
            device,
            &crate::pipeline::Spec {
                label: "terrain",
                module: &module,
                layouts: &[globals, &layout],
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<GroundVertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &attributes,
                })],
                topology: wgpu::PrimitiveTopology::TriangleList,
                cull: None,
                depth: crate::pipeline::DepthUse::Write,
                target,
                alpha_to_coverage: false,
            },
        );
        Self {
            pipeline,
            vertices,
            indices,
            index_count,
            bind_group,
        }
    }

    /// Records the draw into `pass`.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(1, &self.bind_group, &[]);
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.index_count, 0, 0..1);
    }
}
