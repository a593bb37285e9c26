//! Billboards: one instance per Billboard-LOD cell of a visible patch, built
//! on the CPU each frame from the cells' base, height and current slope;
//! a list over one storage binding is drawn in pieces (one buffer and one
//! draw a piece, [`trample::field::list_pieces`]).

use crate::globals::shader_module;
use glam::{UVec4, Vec4};
use trample::Simulation;
use trample::deform::billboard::billboard_top;
use trample::field::generate::GROUND_CLEARANCE_M;
use trample::field::{Lod, drawn_cells, list_pieces};

/// Billboard width / cell side: "a bit longer than the cell" (DESIGN §8), so
/// neighbouring billboards overlap and no gap shows between cells.
pub const WIDTH_OVER_CELL: f32 = 1.6;

/// Blades painted on the clump texture (one cell holds one blade in the
/// paper's field; a few per texture keep the billboard band as dense as the
/// geometric band once the texture is split across two crossed quads).
pub const CLUMP_BLADES: u32 = 6;

/// Seed of the clump texture's blades.
pub const CLUMP_SEED: u64 = 7;

/// One drawn billboard. Layout-compatible with `Billboard` in billboards.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct BillboardInstance {
    /// xyz base centre, w half width (m).
    pub base: Vec4,
    /// xyz base → top edge, `normalize(slope) · height` (Eq. 8) kept above
    /// the ground ([`billboard_top`]); w unused.
    pub top: Vec4,
    /// x debug colour (RGBA8, 0 = textured), y per-cell seed.
    pub extra: UVec4,
}

const _: () = assert!(std::mem::size_of::<BillboardInstance>() == 48);

/// The billboard pass: pipeline, clump texture and instance buffer.
pub struct BillboardPass {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    clump: wgpu::TextureView,
    sampler: wgpu::Sampler,
    /// The instance buffers, one a piece of the list within one storage
    /// binding, and their bind groups.
    pieces: Vec<(wgpu::Buffer, wgpu::BindGroup)>,
    /// This frame's billboards a piece.
    counts: Vec<u32>,
    list: Vec<BillboardInstance>,
}

impl BillboardPass {
    /// Creates the pass and generates the clump texture.
    #[must_use]
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        globals: &wgpu::BindGroupLayout,
        target: &crate::TargetFormat,
    ) -> Self {
        let clump = crate::textures::upload(
            device,
            queue,
            "grass clump",
            crate::textures::grass_clump(CLUMP_SEED, CLUMP_BLADES),
        );
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("clump"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        let [t, s] = crate::pipeline::texture_and_sampler(1);
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("billboards"),
            entries: &[crate::pipeline::vertex_storage(0), t, s],
        });
        let module = shader_module(device, "billboards.wgsl", include_str!("billboards.wgsl"));
        let pipeline = crate::pipeline::build(
            device,
            &crate::pipeline::Spec {
                label: "billboards",
                module: &module,
                layouts: &[globals, &layout],
                buffers: &[],
                topology: wgpu::PrimitiveTopology::TriangleList,
                cull: None,
                depth: crate::pipeline::DepthUse::Write,
                target,
                alpha_to_coverage: false,
            },
        );
        // 256 billboards to start with, fewer on a device binding less.
        let limits = device.limits();
        let limit = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        let instances = Self::buffer(device, (48 * 256).min(limit / 48 * 48).max(16));
        let bind_group = Self::bind(device, &layout, &instances, &clump, &sampler);
        Self {
            pipeline,
            layout,
            clump,
            sampler,
            pieces: vec![(instances, bind_group)],
            counts: Vec::new(),
            list: Vec::new(),
        }
    }

    fn buffer(device: &wgpu::Device, size: u64) -> wgpu::Buffer {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("billboard instances"),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    }

    fn bind(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        instances: &wgpu::Buffer,
        clump: &wgpu::TextureView,
        sampler: &wgpu::Sampler,
    ) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("billboards"),
            layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: instances.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(clump),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::Sampler(sampler),
                },
            ],
        })
    }

    /// Builds and uploads this frame's billboards: Billboard-LOD cells of
    /// visible patches. `debug` is the billboards' debug colour (0 = textured).
    /// Returns the bytes written.
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        sim: &Simulation,
        debug: u32,
    ) -> u64 {
        let layout = &sim.field.layout;
        let cells = &sim.field.cells;
        let half = half_width(layout.cell_size);
        self.list.clear();
        for c in drawn_cells(layout, cells, &sim.visible, Lod::Billboard) {
            // Eq. 8's top edge with the core's ground guard: a slope that
            // points into the ground lays the billboard on it instead.
            let top = billboard_top(
                cells.base[c],
                cells.slope[c],
                cells.height[c],
                &sim.field.terrain,
                GROUND_CLEARANCE_M,
            ) - cells.base[c];
            self.list.push(BillboardInstance {
                base: cells.base[c].extend(half),
                top: top.extend(0.0),
                extra: UVec4::new(debug, c as u32, 0, 0),
            });
        }
        let bytes = (self.list.len() * 48) as u64;
        let limits = device.limits();
        let limit = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        self.counts.clear();
        for (k, piece) in list_pieces(self.list.len(), 48, limit)
            .into_iter()
            .enumerate()
        {
            let data = &self.list[piece];
            let current = self.pieces.get(k).map(|(b, _)| b);
            if let Some(b) = crate::pipeline::grown(
                device,
                current,
                "billboard instances",
                wgpu::BufferUsages::STORAGE,
                std::mem::size_of_val(data) as u64,
            ) {
                let group = Self::bind(device, &self.layout, &b, &self.clump, &self.sampler);
                if k < self.pieces.len() {
                    self.pieces[k] = (b, group);
                } else {
                    self.pieces.push((b, group));
                }
            }
            queue.write_buffer(&self.pieces[k].0, 0, bytemuck::cast_slice(data));
            self.counts.push(data.len() as u32);
        }
        bytes
    }

    /// Billboards drawn by the last [`BillboardPass::prepare`].
    #[must_use]
    pub fn drawn(&self) -> usize {
        self.list.len()
    }

    /// Billboards drawn from each piece of the list by the last
    /// [`BillboardPass::prepare`] (one piece for a list within one binding).
    #[must_use]
    pub fn pieces(&self) -> &[u32] {
        &self.counts
    }

    /// Records the draws into `pass`: one a piece of the list.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        if self.list.is_empty() {
            return;
        }
        pass.set_pipeline(&self.pipeline);
        for ((_, group), &count) in self.pieces.iter().zip(&self.counts) {
            pass.set_bind_group(1, group, &[]);
            pass.draw(0..VERTICES, 0..count);
        }
    }

    /// The bind group of the GPU path's billboards (`lists`, made by
    /// `GpuSimulation::record_draw_lists` earlier in the same encoder), for
    /// [`BillboardPass::draw_gpu`].
    #[must_use]
    pub fn bind_gpu(
        &self,
        device: &wgpu::Device,
        lists: &trample_gpu::draw_lists::DrawLists,
    ) -> wgpu::BindGroup {
        Self::bind(
            device,
            &self.layout,
            &lists.billboards,
            &self.clump,
            &self.sampler,
        )
    }

    /// Records the GPU path's billboards into `pass`: one indirect draw
    /// whose arguments follow the `chunks` blade ones in `args`.
    pub fn draw_gpu(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        group: &wgpu::BindGroup,
        args: &wgpu::Buffer,
        chunks: usize,
    ) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(1, group, &[]);
        pass.draw_indirect(
            args,
            chunks as u64 * trample_gpu::draw_lists::DRAW_ARGS_BYTES,
        );
    }
}

/// Vertices of one billboard: two crossed quads (billboards.wgsl).
pub const VERTICES: u32 = 12;

/// Half the width of a billboard over cells of `cell_size` metres.
#[must_use]
pub fn half_width(cell_size: f32) -> f32 {
    0.5 * WIDTH_OVER_CELL * cell_size
}
