//! The field's renderer as wgpu middleware (issue 14 item 3; the pattern of
//! STYLE.md, as egui-wgpu and glyphon): made from the host's device and
//! target formats, [`FieldRenderer::prepare`] uploads a frame (recording
//! into the host's encoder where it needs to: the GPU path's draw lists,
//! the sun's shadow map), [`FieldRenderer::render`]
//! records the draws into the render pass the host opened. It never opens,
//! clears or ends a pass and never owns a surface, so grass and the host's
//! own geometry share one colour and one depth buffer and hide each other
//! where they should.
//!
//! The offscreen [`crate::Renderer`] (the CLI, the viewer, the tests) is a
//! small host of it.
//!
//! ```no_run
//! # fn frame(device: &wgpu::Device, queue: &wgpu::Queue, sim: &trample::Simulation,
//! #          color: &wgpu::TextureView, depth: &wgpu::TextureView, camera: trample_render::FrameCamera)
//! #          -> Result<(), trample_render::RenderError> {
//! use trample_render::{FieldRenderer, Layers, RenderParams, TargetFormat};
//! let target = TargetFormat {
//!     color: wgpu::TextureFormat::Bgra8UnormSrgb,
//!     depth: Some(wgpu::TextureFormat::Depth32Float),
//!     samples: 1,
//! };
//! let params = RenderParams { layers: Layers { objects: false, ..Layers::default() }, ..Default::default() };
//! let mut grass = FieldRenderer::new(device, queue, sim, target, params)?;
//! // Every frame, after the simulation's step:
//! let mut encoder = device.create_command_encoder(&Default::default());
//! grass.prepare(device, queue, &mut encoder, sim, &camera);
//! {
//!     let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
//!         label: Some("host pass"),
//!         color_attachments: &[Some(wgpu::RenderPassColorAttachment {
//!             view: color,
//!             depth_slice: None,
//!             resolve_target: None,
//!             ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::BLACK), store: wgpu::StoreOp::Store },
//!         })],
//!         depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
//!             view: depth,
//!             depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
//!             stencil_ops: None,
//!         }),
//!         timestamp_writes: None,
//!         occlusion_query_set: None,
//!         multiview_mask: None,
//!     });
//!     // ... the host's own draws, before or after ...
//!     grass.render(&mut pass);
//! }
//! queue.submit([encoder.finish()]);
//! # Ok(()) }
//! ```

use crate::billboards::BillboardPass;
use crate::blades::{BladePass, Upload};
use crate::classes::{
    BILLBOARD_DEBUG, DBG_EARLIER, DBG_NOW, PBG_EARLIER, PBG_FADE, PBG_NOW, UNTOUCHED, band_colour,
    class_colour, pack,
};
use crate::error::RenderError;
use crate::globals::Globals;
use crate::lines::LinePass;
use crate::objects::ObjectPass;
use crate::params::{DebugView, Layers, RenderParams};
use crate::shadows::ShadowPass;
use crate::sky::SkyPass;
use crate::terrain::TerrainPass;
use crate::{FrameCamera, TargetFormat};
use glam::{UVec4, Vec3, Vec4};
use trample::Simulation;

/// What the last [`FieldRenderer::prepare`] set up to draw.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameCounts {
    /// Geometric blades (0 on the GPU path, whose lists stay on the GPU).
    pub blades: usize,
    /// Billboards (0 on the GPU path).
    pub billboards: usize,
    /// Draws of the blades: one a chunk of blade vertices within one
    /// storage binding (1 for a field within one; 0 on the GPU path).
    pub blade_chunks: usize,
    /// Draws of the billboards: one a piece of their list within one
    /// storage binding (0 on the GPU path).
    pub billboard_pieces: usize,
    /// Bytes of blade vertices written for the frame: only those of the
    /// blades the last step changed ([`trample::field::Field::changed_blades`])
    /// when the renderer saw the step before, none without a step, all of
    /// them otherwise (16 bytes a vertex).
    pub vertex_bytes: u64,
    /// Bytes written to the GPU for the frame in all: the blade vertices,
    /// the draw lists, the uniforms.
    pub uploaded_bytes: u64,
}

/// Where the field's draws of the last prepared frame come from.
enum Source {
    /// Nothing prepared yet.
    Nothing,
    /// The renderer's own buffers, uploaded from a CPU-path simulation.
    Cpu,
    /// The GPU path's buffers: one bind group per chunk of blades and the
    /// billboards', drawn with indirect arguments.
    Gpu {
        blades: Vec<wgpu::BindGroup>,
        billboards: wgpu::BindGroup,
        args: wgpu::Buffer,
    },
}

/// Draws a trample field (blades, billboards; optionally the sky, ground
/// and bodies: [`Layers`]) into a render pass the host owns. See the
/// module docs for a frame.
pub struct FieldRenderer {
    params: RenderParams,
    target: TargetFormat,
    globals: wgpu::Buffer,
    globals_group: wgpu::BindGroup,
    sky: SkyPass,
    terrain: TerrainPass,
    billboards: BillboardPass,
    blades: BladePass,
    objects: ObjectPass,
    shadows: ShadowPass,
    lines: LinePass,
    /// `Simulation::frame` of the blade vertices on the GPU; `None`: none
    /// (or not known to be those of the simulation drawn).
    uploaded_frame: Option<u64>,
    source: Source,
}

impl FieldRenderer {
    /// A renderer for `sim`'s field drawing into passes of `target`'s
    /// formats: builds the pipelines, uploads the ground, the textures and
    /// the bodies' meshes. `params`' `width`, `height` and `samples` are
    /// not used (the host's pass and camera say them).
    ///
    /// # Errors
    /// [`RenderError::NoVertexStorage`] for an adapter that cannot read
    /// storage buffers in vertex shaders, [`RenderError::BladesTooLarge`]
    /// for a field whose blades' shapes (8 bytes a blade) or cells'
    /// flatness (4 bytes a cell) pass one storage binding. Blade vertices over one binding are uploaded and drawn in
    /// chunks ([`trample::field::chunks`]).
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        sim: &Simulation,
        target: TargetFormat,
        params: RenderParams,
    ) -> Result<Self, RenderError> {
        Self::with_blades(device, queue, sim, target, params, false)
    }

    /// A renderer that draws the field of a GPU-path simulation straight
    /// from its buffers ([`FieldRenderer::prepare_gpu`]; `gpu.sim` gives
    /// the objects and terrain): no blade vertex buffer of its own (the
    /// GPU path's chunks are drawn one indirect draw each).
    ///
    /// # Errors
    /// As [`FieldRenderer::new`], less the field's size.
    pub fn new_gpu(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        gpu: &trample_gpu::GpuSimulation,
        target: TargetFormat,
        params: RenderParams,
    ) -> Result<Self, RenderError> {
        // The draw lists' buffers within one storage binding, or a message
        // instead of a validation error at the first frame.
        if let Err(trample_gpu::GpuError::TooLarge { bytes, limit, .. }) =
            gpu.supports_draw_lists(device)
        {
            return Err(RenderError::BladesTooLarge {
                needed: bytes,
                allowed: limit,
            });
        }
        Self::with_blades(device, queue, &gpu.sim, target, params, true)
    }

    fn with_blades(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        sim: &Simulation,
        target: TargetFormat,
        params: RenderParams,
        gpu: bool,
    ) -> Result<Self, RenderError> {
        // The field's whole arrays within one binding, or a message before
        // any pass binds them.
        crate::blades::check_whole_arrays(device, sim)?;
        // Group 0: the globals, and the sun's shadow map with its
        // comparison sampler (shadows.rs).
        let [map_entry, sampler_entry] = crate::shadows::layout_entries();
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("globals"),
            entries: &[
                crate::pipeline::uniform(0, wgpu::ShaderStages::VERTEX_FRAGMENT),
                map_entry,
                sampler_entry,
            ],
        });
        let globals = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("globals"),
            size: std::mem::size_of::<Globals>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let t = &target;
        let objects = ObjectPass::new(device, &layout, sim, t);
        let shadows = ShadowPass::new(device, &globals, objects.layout(), &params);
        let [map, sampler] = shadows.bind_entries();
        let globals_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("globals"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: globals.as_entire_binding(),
                },
                map,
                sampler,
            ],
        });
        Ok(Self {
            params,
            target,
            globals,
            globals_group,
            sky: SkyPass::new(device, &layout, t),
            terrain: TerrainPass::new(device, queue, &layout, sim, t, params.track_darkening),
            billboards: BillboardPass::new(device, queue, &layout, t),
            blades: if gpu {
                BladePass::new_gpu(device, queue, &layout, sim, t)?
            } else {
                BladePass::new(device, queue, &layout, sim, t)?
            },
            objects,
            shadows,
            lines: LinePass::new(device, &layout, t),
            uploaded_frame: None,
            source: Source::Nothing,
        })
    }

    /// The settings this renderer draws with.
    #[must_use]
    pub fn params(&self) -> &RenderParams {
        &self.params
    }

    /// The target its pipelines were built for.
    #[must_use]
    pub fn target(&self) -> &TargetFormat {
        &self.target
    }

    /// Switches the debug view from the next frame on.
    pub fn set_debug(&mut self, debug: DebugView) {
        self.params.debug = debug;
    }

    /// Switches layers on or off from the next frame on.
    pub fn set_layers(&mut self, layers: Layers) {
        self.params.layers = layers;
    }

    /// Sets the offscreen size in the parameters ([`crate::Renderer::resize`]).
    pub(crate) fn set_size(&mut self, width: u32, height: u32) {
        self.params.width = width;
        self.params.height = height;
    }

    /// Makes the next [`FieldRenderer::prepare`] write every blade vertex:
    /// for a host that changed blades outside a step (or hands in another
    /// simulation of the same field). Steps need no call: the renderer
    /// follows `Simulation::frame` and uploads everything when it missed a
    /// step.
    pub fn upload_all_next(&mut self) {
        self.uploaded_frame = None;
    }

    /// The per-frame uniform every pass reads, for `sim`'s frame seen by
    /// `camera` (sun, fog, debug view, wind, the target's colour encoding).
    /// Public for tests and tools that run the shared WGSL (`globals.wgsl`)
    /// themselves.
    #[must_use]
    pub fn globals_of(&self, sim: &Simulation, camera: &FrameCamera) -> Globals {
        let view_proj = camera.view_proj;
        let sun = self.params.sun_dir.normalize_or(Vec3::Y);
        let map = self.shadows.size();
        let radius = self.params.shadow_m.max(1.0);
        let (light_view_proj, depth_per_m) =
            crate::shadows::light_view_proj(sun, camera.eye, radius, map);
        // Receivers test 1.5 texels (at least 2 cm) nearer the sun than
        // they are: no acne on the bodies' own lit sides.
        let bias_m = (3.0 * radius / map as f32).max(0.02);
        Globals {
            view_proj,
            inv_view_proj: view_proj.inverse(),
            eye: camera.eye.extend(sim.time as f32),
            sun_dir: sun.extend(0.55),
            sun_color: Vec4::new(1.0, 0.93, 0.8, 0.0) * 1.1,
            // w: the spacing of simulated blades (m), over which
            // `blades.wgsl` scatters the drawn copies.
            sky_zenith: Vec4::new(
                0.16,
                0.32,
                0.72,
                sim.field.layout.cell_size
                    / (sim.field.layout.blades_per_cell.max(1) as f32).sqrt(),
            ),
            sky_horizon: Vec4::new(0.62, 0.72, 0.82, 0.0),
            fog: Vec4::new(
                self.params.fog_start_m,
                self.params.fog_end_m,
                sim.lod.geometry_m,
                sim.lod.billboard_m,
            ),
            params: UVec4::new(
                u32::from(self.params.debug == DebugView::Classes),
                sim.field.blades.segments as u32,
                sim.field.blades.count as u32,
                u32::from(self.target.shader_encodes_srgb()),
            ),
            wind: {
                let d = sim.wind.direction();
                Vec4::new(d.x, sim.wind.strength_m, d.z, sim.wind.gust_m)
            },
            gusts: Vec4::new(
                sim.wind.gust_period_s,
                sim.wind.gust_wavelength_m,
                self.params.near_density.max(1) as f32,
                self.params.near_density_m,
            ),
            blend: {
                let [near, far] = self.params.blend_bands(&sim.lod);
                Vec4::new(near, far, 0.0, 0.0)
            },
            light_view_proj,
            shadow: Vec4::new(
                if self.shadows.enabled() {
                    self.params.shadow_strength.clamp(0.0, 1.0)
                } else {
                    0.0
                },
                self.params.ambient_occlusion.max(0.0),
                bias_m * depth_per_m,
                0.0,
            ),
        }
    }

    /// Uploads `sim`'s current state for a frame seen by `camera` (the
    /// host's matrices): the blades the last step changed (all of them
    /// when this renderer did not see the step before), the draw lists of
    /// the visible patches, the bodies' poses, and the sun's shadow map (a
    /// depth-only pass of its own, recorded into `encoder`:
    /// [`crate::shadows`]). Call once a frame, after the step and before
    /// [`FieldRenderer::render`]; open the host's pass on `encoder` after
    /// it (or on an encoder submitted after it); submit `encoder` after it
    /// (the CPU path writes through `queue`, which lands before the
    /// encoder's commands).
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        sim: &Simulation,
        camera: &FrameCamera,
    ) -> FrameCounts {
        let upload = match self.uploaded_frame {
            Some(f) if f == sim.frame => Upload::None,
            Some(f) if f + 1 == sim.frame => Upload::Changed,
            _ => Upload::All,
        };
        let [band, _] = self.params.blend_bands(&sim.lod);
        let (vertex_bytes, mut bytes) = if self.params.debug == DebugView::Classes {
            let billboard = pack(BILLBOARD_DEBUG);
            self.blades.prepare(
                device,
                queue,
                sim,
                band,
                |b, level| band_colour(class_colour(sim, b), level, billboard),
                upload,
            )
        } else {
            self.blades
                .prepare(device, queue, sim, band, |_, _| 0, upload)
        };
        self.uploaded_frame = Some(sim.frame);
        bytes += match upload {
            Upload::None => 0,
            Upload::Changed => self.terrain.prepare(queue, &sim.field, false),
            Upload::All => self.terrain.prepare(queue, &sim.field, true),
        };
        let bb_colour = self.billboard_colour();
        bytes += self.billboards.prepare(device, queue, sim, bb_colour);
        bytes += self.prepare_scene(device, queue, encoder, sim, camera);
        self.source = Source::Cpu;
        FrameCounts {
            blades: self.blades.drawn(),
            billboards: self.billboards.drawn(),
            blade_chunks: self.blades.chunks(),
            billboard_pieces: self.billboards.pieces().len(),
            vertex_bytes,
            uploaded_bytes: bytes + vertex_bytes,
        }
    }

    /// [`FieldRenderer::prepare`] for a GPU-path simulation, drawn straight
    /// from its buffers: the draw lists are built on the GPU
    /// (`GpuSimulation::record_draw_lists`, recorded into `encoder`) and
    /// drawn with indirect draws; nothing of the field is read back or
    /// uploaded. The objects, terrain and debug lines come from `gpu.sim`
    /// (kept up to date by `GpuSimulation::step`). The renderer must come
    /// from [`FieldRenderer::new_gpu`] or [`FieldRenderer::new`] for the
    /// same field.
    pub fn prepare_gpu(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        gpu: &mut trample_gpu::GpuSimulation,
        camera: &FrameCamera,
    ) -> FrameCounts {
        let classes = self.params.debug == DebugView::Classes;
        let draw = trample_gpu::draw_lists::GpuDrawParams {
            counts: [0; 4],
            draw: [
                self.blades.vertices_per_blade(),
                crate::billboards::VERTICES,
                u32::from(classes),
                self.billboard_colour(),
            ],
            size: [
                crate::billboards::half_width(gpu.sim.field.layout.cell_size),
                self.params.near_density.max(1) as f32,
                self.params.blend_bands(&gpu.sim.lod)[0],
                0.0,
            ],
            palette: [
                pack(DBG_NOW),
                pack(DBG_EARLIER),
                pack(PBG_EARLIER),
                pack(UNTOUCHED),
            ],
            pbg: [PBG_NOW.x, PBG_NOW.y, PBG_NOW.z, PBG_FADE],
        };
        gpu.record_draw_lists(device, queue, encoder, draw);
        // The CPU copy of the field is not what the GPU path draws.
        self.uploaded_frame = None;
        self.terrain.bind_gpu(device, &gpu.field.flatness);
        let bytes = self.prepare_scene(device, queue, encoder, &gpu.sim, camera);
        self.source = match gpu.draw_lists() {
            Some(lists) => Source::Gpu {
                blades: self.blades.bind_gpu(device, &gpu.field, lists),
                billboards: self.billboards.bind_gpu(device, lists),
                args: lists.args.clone(),
            },
            None => Source::Nothing,
        };
        FrameCounts {
            uploaded_bytes: bytes,
            ..FrameCounts::default()
        }
    }

    /// Records the frame prepared last into `pass`, a pass the host opened
    /// on a target of [`FieldRenderer::target`]'s formats: the sky, ground
    /// and bodies as [`Layers`] say, the blades and billboards, the debug
    /// lines. Sets its own pipelines and bind groups 0 and 1; a host that
    /// draws after it sets its own again.
    pub fn render(&self, pass: &mut wgpu::RenderPass<'_>) {
        let layers = self.params.layers;
        pass.set_bind_group(0, &self.globals_group, &[]);
        if layers.sky {
            self.sky.draw(pass);
        }
        if layers.terrain {
            self.terrain.draw(pass);
        }
        if layers.objects {
            self.objects.draw(pass);
        }
        match &self.source {
            Source::Nothing => {}
            Source::Cpu => {
                self.blades.draw(pass, self.params.near_density);
                self.billboards.draw(pass);
            }
            Source::Gpu {
                blades,
                billboards,
                args,
            } => {
                self.blades.draw_gpu(pass, blades, args);
                self.billboards
                    .draw_gpu(pass, billboards, args, blades.len());
            }
        }
        self.lines.draw(pass);
    }

    /// The billboards' colour in the classes view (0: textured).
    fn billboard_colour(&self) -> u32 {
        if self.params.debug == DebugView::Classes {
            pack(BILLBOARD_DEBUG)
        } else {
            0
        }
    }

    /// Globals, objects, the shadow map (recorded into `encoder`) and
    /// debug lines of `sim`'s frame; returns the bytes written.
    fn prepare_scene(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        sim: &Simulation,
        camera: &FrameCamera,
    ) -> u64 {
        let globals = self.globals_of(sim, camera);
        queue.write_buffer(&self.globals, 0, bytemuck::bytes_of(&globals));
        let mut bytes = std::mem::size_of::<Globals>() as u64;
        // The bodies cast shadows even when the host draws them itself
        // (the objects layer off).
        if self.params.layers.objects || self.shadows.enabled() {
            bytes += self.objects.prepare(device, queue, sim);
        }
        self.shadows.encode(encoder, &self.objects);
        let view = self.params.debug;
        bytes += self.lines.prepare(
            device,
            queue,
            sim,
            view == DebugView::Obb,
            view == DebugView::Patches,
        );
        bytes
    }
}
