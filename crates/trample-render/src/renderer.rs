//! The frame: sky, ground, billboards, blades and objects in one pass into
//! the offscreen target, then read back.

use crate::billboards::BillboardPass;
use crate::blades::BladePass;
use crate::error::RenderError;
use crate::globals::Globals;
use crate::lines::LinePass;
use crate::objects::ObjectPass;
use crate::sky::SkyPass;
use crate::target::Target;
use crate::terrain::TerrainPass;
use glam::{UVec4, Vec3, Vec4};
use trample::Simulation;
use trample::force::propagation::NO_GENERATION;
use trample::step::BladeClass;

/// What the frame shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DebugView {
    /// The shaded scene.
    #[default]
    None,
    /// Colour by class: DBG red, PBG blue (darker each generation), blades
    /// touched in earlier frames dark red / dark blue, untouched green,
    /// billboards yellow, Texture-LOD ground grey.
    Classes,
    /// The shaded scene with each object's OBB-tree nodes at the current
    /// precision drawn over it (yellow; orange: leaves above the precision).
    Obb,
    /// The shaded scene with the patch grid over it (patch borders white,
    /// cell lines grey on small grids).
    Patches,
}

impl DebugView {
    /// Every view, in the order a viewer cycles through them.
    pub const ALL: [DebugView; 4] = [Self::None, Self::Classes, Self::Obb, Self::Patches];

    /// The view after this one in [`DebugView::ALL`], wrapping round.
    #[must_use]
    pub fn next(self) -> Self {
        let i = Self::ALL.iter().position(|&v| v == self).unwrap_or(0);
        Self::ALL[(i + 1) % Self::ALL.len()]
    }
}

impl std::str::FromStr for DebugView {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "none" => Ok(Self::None),
            "classes" => Ok(Self::Classes),
            "obb" => Ok(Self::Obb),
            "patches" => Ok(Self::Patches),
            _ => Err(format!(
                "unknown debug view {s:?}: expected none, classes, obb or patches"
            )),
        }
    }
}

/// Render settings (`RenderParams`, STYLE rule 4).
#[derive(Clone, Copy, Debug)]
pub struct RenderParams {
    /// Image width, pixels.
    pub width: u32,
    /// Image height, pixels.
    pub height: u32,
    /// MSAA samples: 4 by default; ask the adapter first
    /// ([`crate::headless::supported_msaa`]), 1 where it cannot.
    pub samples: u32,
    /// Debug view.
    pub debug: DebugView,
    /// Direction towards the sun (normalised on use). Default: high behind
    /// the default camera's left shoulder, so the blades facing it are lit.
    pub sun_dir: Vec3,
    /// Fog starts at this distance, metres (default 25: past the billboards' near edge).
    pub fog_start_m: f32,
    /// Fog is complete at this distance, metres (default 140).
    pub fog_end_m: f32,
}

impl Default for RenderParams {
    fn default() -> Self {
        Self {
            width: 1280,
            height: 720,
            samples: 4,
            debug: DebugView::None,
            sun_dir: Vec3::new(-0.35, 0.75, 0.55),
            fog_start_m: 25.0,
            fog_end_m: 140.0,
        }
    }
}

/// What the last frame drew.
#[derive(Clone, Copy, Debug, Default)]
pub struct FrameCounts {
    /// Geometric blades.
    pub blades: usize,
    /// Billboards.
    pub billboards: usize,
}

/// Draws a [`Simulation`] offscreen. Holds pipelines and GPU buffers; takes
/// the device and queue it was created with on every call.
pub struct Renderer {
    params: RenderParams,
    globals: wgpu::Buffer,
    globals_group: wgpu::BindGroup,
    target: Target,
    sky: SkyPass,
    terrain: TerrainPass,
    billboards: BillboardPass,
    blades: BladePass,
    objects: ObjectPass,
    lines: LinePass,
}

/// Packs a linear colour as WGSL `unpack4x8unorm` reads it (alpha 255, so never 0).
fn pack(c: Vec3) -> u32 {
    let b = |x: f32| (x.clamp(0.0, 1.0) * 255.0).round() as u32;
    b(c.x) | (b(c.y) << 8) | (b(c.z) << 16) | (255 << 24)
}

/// Debug colour of blade `b` for [`DebugView::Classes`].
/// Classes view: DBG this step.
const DBG_NOW: Vec3 = Vec3::new(1.0, 0.03, 0.02);
/// Classes view: PBG this step at generation 1, fading by [`PBG_FADE`] a
/// generation (down to 30 %).
const PBG_NOW: Vec3 = Vec3::new(0.05, 0.35, 1.0);
const PBG_FADE: f32 = 0.1;
/// Classes view: DBG, PBG at an earlier step; untouched; billboards.
const DBG_EARLIER: Vec3 = Vec3::new(0.35, 0.02, 0.02);
const PBG_EARLIER: Vec3 = Vec3::new(0.02, 0.06, 0.35);
const UNTOUCHED: Vec3 = Vec3::new(0.08, 0.45, 0.06);
const BILLBOARD_DEBUG: Vec3 = Vec3::new(0.9, 0.75, 0.05);

fn class_colour(sim: &Simulation, b: usize) -> u32 {
    let g = sim.generation[b];
    let c = if g == 0 {
        DBG_NOW
    } else if g != NO_GENERATION {
        PBG_NOW * (1.0 - PBG_FADE * f32::from(g - 1)).max(0.3)
    } else if sim.class[b] == BladeClass::Direct {
        DBG_EARLIER
    } else if sim.class[b] == BladeClass::Propagated {
        PBG_EARLIER
    } else {
        UNTOUCHED
    };
    pack(c)
}

impl Renderer {
    /// Uploads `sim`'s field, ground and objects and builds the pipelines.
    ///
    /// # Errors
    /// A bad size, or an adapter that cannot pull blade vertices.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        sim: &Simulation,
        params: RenderParams,
    ) -> Result<Self, RenderError> {
        Self::with_blades(device, queue, sim, params, false)
    }

    /// A renderer that draws the field of a GPU-path simulation straight
    /// from its buffers ([`Renderer::encode_gpu`]; `gpu.sim` gives the
    /// camera, objects and terrain): no blade vertex buffer of its own, so
    /// fields over one storage binding draw too.
    ///
    /// # Errors
    /// As [`Renderer::new`], less the field's size.
    pub fn new_gpu(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        gpu: &trample_gpu::GpuSimulation,
        params: RenderParams,
    ) -> Result<Self, RenderError> {
        Self::with_blades(device, queue, &gpu.sim, params, true)
    }

    fn with_blades(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        sim: &Simulation,
        params: RenderParams,
        gpu: bool,
    ) -> Result<Self, RenderError> {
        let target = Target::new(device, params.width, params.height, params.samples)?;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("globals"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let globals = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("globals"),
            size: std::mem::size_of::<Globals>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let globals_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("globals"),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: globals.as_entire_binding(),
            }],
        });
        let s = params.samples;
        Ok(Self {
            params,
            globals,
            globals_group,
            sky: SkyPass::new(device, &layout, s),
            terrain: TerrainPass::new(device, queue, &layout, sim, s),
            billboards: BillboardPass::new(device, queue, &layout, s),
            blades: if gpu {
                BladePass::new_gpu(device, queue, &layout, sim, s)?
            } else {
                BladePass::new(device, queue, &layout, sim, s)?
            },
            objects: ObjectPass::new(device, &layout, sim, s),
            lines: LinePass::new(device, &layout, s),
            target,
        })
    }

    /// The settings this renderer was made with.
    #[must_use]
    pub fn params(&self) -> &RenderParams {
        &self.params
    }

    /// The per-frame uniform every pass reads, for `sim`'s frame (camera,
    /// sun, fog, debug view, wind). Public for tests and tools that run the
    /// shared WGSL (`globals.wgsl`) themselves.
    #[must_use]
    pub fn globals_of(&self, sim: &Simulation) -> Globals {
        let view_proj = sim.view_proj(self.params.width as f32 / self.params.height as f32);
        Globals {
            view_proj,
            inv_view_proj: view_proj.inverse(),
            eye: sim.eye().extend(sim.time as f32),
            sun_dir: self.params.sun_dir.normalize_or(Vec3::Y).extend(0.55),
            sun_color: Vec4::new(1.0, 0.93, 0.8, 0.0) * 1.1,
            sky_zenith: Vec4::new(0.16, 0.32, 0.72, 0.0),
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
                0,
            ),
            wind: {
                let d = sim.wind.direction();
                Vec4::new(d.x, sim.wind.strength_m, d.z, sim.wind.gust_m)
            },
            gusts: Vec4::new(sim.wind.gust_period_s, sim.wind.gust_wavelength_m, 0.0, 0.0),
        }
    }

    /// Draws `sim`'s current state and submits it (see also [`Renderer::render`],
    /// which also reads the frame back).
    pub fn draw(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        sim: &Simulation,
    ) -> FrameCounts {
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("frame"),
        });
        let counts = self.encode(device, queue, sim, &mut encoder);
        self.target.copy_out(&mut encoder);
        queue.submit([encoder.finish()]);
        counts
    }

    /// Uploads `sim`'s current state and records the scene pass into
    /// `encoder` (the caller submits it): the frame is then in
    /// [`Renderer::frame_view`], where a window can draw an overlay on it
    /// and present it. [`Renderer::draw`] is this plus the copy for read-back.
    pub fn encode(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        sim: &Simulation,
        encoder: &mut wgpu::CommandEncoder,
    ) -> FrameCounts {
        let debug = self.params.debug == DebugView::Classes;
        if debug {
            self.blades
                .prepare(device, queue, sim, |b| class_colour(sim, b));
        } else {
            self.blades.prepare(device, queue, sim, |_| 0);
        }
        let bb_colour = self.billboard_colour();
        self.billboards.prepare(device, queue, sim, bb_colour);
        self.prepare_scene(device, queue, sim);

        {
            let mut pass = self.begin_scene(encoder);
            self.blades.draw(&mut pass);
            self.billboards.draw(&mut pass);
            self.lines.draw(&mut pass);
        }
        FrameCounts {
            blades: self.blades.drawn(),
            billboards: self.billboards.drawn(),
        }
    }

    /// The frame the passes resolve into: single-sample [`crate::COLOR_FORMAT`],
    /// `params().width × params().height`, sampleable (see [`Renderer::encode`]).
    /// Records the frame of a GPU-path simulation into `encoder`, drawing
    /// its blades and billboards straight from its buffers: the draw lists
    /// are built on the GPU (`GpuSimulation::record_draw_lists`) and drawn
    /// with indirect draws; nothing of the field is read back or uploaded.
    /// The camera, objects, terrain and debug lines come from `gpu.sim`
    /// (kept up to date by `GpuSimulation::step`). The renderer must come
    /// from [`Renderer::new_gpu`] or [`Renderer::new`] for the same field.
    pub fn encode_gpu(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        gpu: &mut trample_gpu::GpuSimulation,
        encoder: &mut wgpu::CommandEncoder,
    ) {
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
                0.0,
                0.0,
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
        self.prepare_scene(device, queue, &gpu.sim);
        let Some(lists) = gpu.draw_lists() else {
            return;
        };
        let mut pass = self.begin_scene(encoder);
        self.blades.draw_gpu(device, &mut pass, &gpu.field, lists);
        self.billboards
            .draw_gpu(device, &mut pass, lists, gpu.field.chunks.len());
        self.lines.draw(&mut pass);
    }

    /// The billboards' colour in the classes view (0: textured).
    fn billboard_colour(&self) -> u32 {
        if self.params.debug == DebugView::Classes {
            pack(BILLBOARD_DEBUG)
        } else {
            0
        }
    }

    /// Globals, objects and debug lines of `sim`'s frame.
    fn prepare_scene(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, sim: &Simulation) {
        queue.write_buffer(&self.globals, 0, bytemuck::bytes_of(&self.globals_of(sim)));
        self.objects.prepare(queue, sim);
        let view = self.params.debug;
        self.lines.prepare(
            device,
            queue,
            sim,
            view == DebugView::Obb,
            view == DebugView::Patches,
        );
    }

    /// The scene pass with sky, terrain and objects recorded; the field's
    /// passes follow.
    fn begin_scene<'e>(&self, encoder: &'e mut wgpu::CommandEncoder) -> wgpu::RenderPass<'e> {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("scene"),
            color_attachments: &[Some(self.target.color_attachment(wgpu::Color::BLACK))],
            depth_stencil_attachment: Some(self.target.depth_attachment()),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, &self.globals_group, &[]);
        self.sky.draw(&mut pass);
        self.terrain.draw(&mut pass);
        self.objects.draw(&mut pass);
        pass
    }

    #[must_use]
    pub fn frame_view(&self) -> &wgpu::TextureView {
        self.target.frame_view()
    }

    /// Reads back what is in [`Renderer::frame_view`] now (the last frame
    /// and whatever was drawn over it), sRGB RGBA8.
    ///
    /// # Errors
    /// [`RenderError::Readback`] when the frame cannot be read.
    pub fn read_frame(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<image::RgbaImage, RenderError> {
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("read frame"),
        });
        self.target.copy_out(&mut encoder);
        queue.submit([encoder.finish()]);
        self.target.read(device)
    }

    /// Resizes the frame to `width × height` pixels (a window was resized).
    ///
    /// # Errors
    /// [`RenderError::BadSize`] for a zero or too large side; the renderer
    /// keeps its old size then.
    pub fn resize(
        &mut self,
        device: &wgpu::Device,
        width: u32,
        height: u32,
    ) -> Result<(), RenderError> {
        if (width, height) != (self.params.width, self.params.height) {
            self.target = Target::new(device, width, height, self.params.samples)?;
            self.params.width = width;
            self.params.height = height;
        }
        Ok(())
    }

    /// Switches the debug view from the next frame on.
    pub fn set_debug(&mut self, debug: DebugView) {
        self.params.debug = debug;
    }

    /// Draws `sim`'s current state and reads it back (sRGB RGBA8).
    ///
    /// # Errors
    /// [`RenderError::Readback`] when the frame cannot be read.
    pub fn render(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        sim: &Simulation,
    ) -> Result<image::RgbaImage, RenderError> {
        self.draw(device, queue, sim);
        self.target.read(device)
    }

    /// [`Renderer::encode_gpu`], submitted, with the frame copied for
    /// read-back ([`Renderer::read_frame`] or [`Renderer::render_gpu`]).
    pub fn draw_gpu(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        gpu: &mut trample_gpu::GpuSimulation,
    ) {
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("frame (GPU path)"),
        });
        self.encode_gpu(device, queue, gpu, &mut encoder);
        self.target.copy_out(&mut encoder);
        queue.submit([encoder.finish()]);
    }

    /// Draws the GPU path's current state ([`Renderer::draw_gpu`]) and reads
    /// the image back: the frame, not the field, crosses to the CPU.
    ///
    /// # Errors
    /// [`RenderError`] when the read-back fails.
    pub fn render_gpu(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        gpu: &mut trample_gpu::GpuSimulation,
    ) -> Result<image::RgbaImage, RenderError> {
        self.draw_gpu(device, queue, gpu);
        self.target.read(device)
    }
}
