//! The ground: a grid mesh over the field's terrain (and a margin of one
//! field size around it, so the horizon is not an edge), textured with the
//! generated grass texture, darkened where the field's cells are flattened
//! (`Cells::flatness`: the track at every level of detail, issue 12 item 4 /
//! issue 15 item 4 — ground-texture cells show it too).

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

/// Where a cell's flatness is in the flatness buffer: the field's layout
/// (`FieldLayout::cell_index`). Layout-compatible with `TrackGrid` in
/// terrain.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct TrackGrid {
    /// World x, z of the field's corner (metres).
    pub origin: [f32; 2],
    /// Cell side, metres.
    pub cell_size: f32,
    /// How much a fully flattened cell darkens the ground, in [0, 1]
    /// ([`crate::RenderParams::track_darkening`]).
    pub darkening: f32,
    /// Cells along x and z.
    pub grid: [u32; 2],
    /// Patches along x.
    pub patches_x: u32,
    /// Cells along a patch side.
    pub cells_per_patch: u32,
    /// rgb: what the ground texture's colour is multiplied by far from
    /// the eye, without ambient occlusion ([`far_tint`]); w unused.
    pub far_tint: [f32; 4],
    /// rgb: what the billboards' ambient occlusion at full strength takes
    /// off `far_tint` ([`far_tint`]; terrain.wgsl scales it by the
    /// strength); w unused.
    pub far_occlusion: [f32; 4],
}

const _: () = assert!(std::mem::size_of::<TrackGrid>() == 64);

/// The ground's tint at ground-texture level (issue 15 item 1): the mean
/// colour of the billboards' grass clump over the mean colour of the
/// ground texture (linear), so that the ground where cells are at
/// ground-texture level shows, on average, the colour the billboards show
/// nearer (no ring where they give way to it); and the part of it the
/// billboards' ambient occlusion takes off at full strength (darker
/// towards their base, globals.wgsl `grass_ao`: `0.55 · v²` at texture row
/// `v`, 1 at the base). Returns `(far_tint, far_occlusion)`. The texture
/// keeps its detail; terrain.wgsl fades the tint in across the billboard
/// band.
#[must_use]
pub fn far_tint(ground: &crate::textures::Pixels) -> ([f32; 4], [f32; 4]) {
    let clump = crate::textures::grass_clump(
        crate::billboards::CLUMP_SEED,
        crate::billboards::CLUMP_BLADES,
    );
    let colour = crate::textures::mean_linear(&clump);
    let occluded = crate::textures::mean_linear_by_row(&clump, |v| 0.55 * v * v);
    let ground = crate::textures::mean_linear(ground);
    let over = |x: [f32; 3]| {
        let t = |c: usize| x[c] / ground[c].max(1e-4);
        [t(0), t(1), t(2), 0.0]
    };
    (over(colour), over(occluded))
}

/// The ground pass.
pub struct TerrainPass {
    pipeline: wgpu::RenderPipeline,
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
    layout: wgpu::BindGroupLayout,
    texture: wgpu::TextureView,
    sampler: wgpu::Sampler,
    grid: wgpu::Buffer,
    /// The CPU path's flatness, one `f32` a cell (cell-index order).
    flatness: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    /// The GPU path's flatness bound instead ([`TerrainPass::bind_gpu`]).
    gpu_group: Option<wgpu::BindGroup>,
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
    /// Builds the ground mesh and texture of `sim`'s field; a fully
    /// flattened cell darkens the ground by `darkening` (0–1).
    #[must_use]
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        globals: &wgpu::BindGroupLayout,
        sim: &Simulation,
        target: &crate::TargetFormat,
        darkening: f32,
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
        let ground = crate::textures::ground_grass(11);
        let (far_tint, far_occlusion) = far_tint(&ground);
        let texture = crate::textures::upload(device, queue, "ground grass", ground);
        let sampler = crate::textures::repeat_sampler(device);
        let [t, smp] = crate::pipeline::texture_and_sampler(0);
        let storage = wgpu::BindGroupLayoutEntry {
            binding: 2,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only: true },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let uniform = crate::pipeline::uniform(3, wgpu::ShaderStages::FRAGMENT);
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("terrain"),
            entries: &[t, smp, storage, uniform],
        });
        let field = &sim.field.layout;
        let grid = TrackGrid {
            origin: field.origin,
            cell_size: field.cell_size,
            darkening: darkening.clamp(0.0, 1.0),
            grid: field.grid_size(),
            patches_x: field.patches[0],
            cells_per_patch: field.cells_per_patch,
            far_tint,
            far_occlusion,
        };
        let grid = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("track grid"),
            contents: bytemuck::bytes_of(&grid),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let flatness = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("cell flatness"),
            contents: bytemuck::cast_slice(&sim.field.cells.flatness),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        });
        let bind_group = bind(device, &layout, &texture, &sampler, &flatness, &grid);
        let module = shader_module(device, "terrain.wgsl", include_str!("terrain.wgsl"));
        let attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];
        let pipeline = crate::pipeline::build(
            device,
            &crate::pipeline::Spec {
                label: "terrain",
                module: &module,
                layouts: &[globals, &layout],
                buffers: &[wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<GroundVertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &attributes,
                }],
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
            layout,
            texture,
            sampler,
            grid,
            flatness,
            bind_group,
            gpu_group: None,
        }
    }

    /// Writes the flatness of the cells the last step changed (every
    /// cell's when `all`), and draws the CPU path's from now on; returns
    /// the bytes written.
    pub fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        field: &trample::field::Field,
        all: bool,
    ) -> u64 {
        self.gpu_group = None;
        let flatness = &field.cells.flatness;
        if all {
            queue.write_buffer(&self.flatness, 0, bytemuck::cast_slice(flatness));
            return (flatness.len() * 4) as u64;
        }
        let mut bytes = 0;
        for r in field.changed_cells().ranges() {
            let (a, b) = (r.start as usize, r.end as usize);
            queue.write_buffer(
                &self.flatness,
                (a * 4) as u64,
                bytemuck::cast_slice(&flatness[a..b]),
            );
            bytes += ((b - a) * 4) as u64;
        }
        bytes
    }

    /// Draws the GPU path's flatness (`GpuField::flatness`, one `f32` a
    /// cell in the same order) from now on.
    pub fn bind_gpu(&mut self, device: &wgpu::Device, flatness: &wgpu::Buffer) {
        self.gpu_group = Some(bind(
            device,
            &self.layout,
            &self.texture,
            &self.sampler,
            flatness,
            &self.grid,
        ));
    }

    /// Records the draw into `pass`.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(1, self.gpu_group.as_ref().unwrap_or(&self.bind_group), &[]);
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.index_count, 0, 0..1);
    }
}

/// The ground's bind group: texture, sampler, the cells' flatness and
/// where each cell is.
fn bind(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    texture: &wgpu::TextureView,
    sampler: &wgpu::Sampler,
    flatness: &wgpu::Buffer,
    grid: &wgpu::Buffer,
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("terrain"),
        layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(texture),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::Sampler(sampler),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: flatness.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: grid.as_entire_binding(),
            },
        ],
    })
}
