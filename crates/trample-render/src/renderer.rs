//! The offscreen host of a [`FieldRenderer`]: its own colour and depth
//! target ([`Target`]), one pass a frame that it opens and clears, the
//! simulation's camera, and the read-back to an image. What `trample run`,
//! `trample bench --render`, the viewer and the tests draw with.

use crate::error::RenderError;
use crate::field_renderer::{FieldRenderer, FrameCounts};
use crate::globals::Globals;
use crate::params::{DebugView, RenderParams};
use crate::target::Target;
use crate::{FrameCamera, TargetFormat};
use trample::Simulation;

/// Draws a [`Simulation`] offscreen at `params.width × params.height`
/// with `params.samples` MSAA samples, with the camera in charge of the
/// simulation ([`FrameCamera::of`]). Holds the target and a
/// [`FieldRenderer`]; takes the device and queue it was created with on
/// every call.
pub struct Renderer {
    field: FieldRenderer,
    target: Target,
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
        let target = Target::new(device, params.width, params.height, params.samples)?;
        let format = TargetFormat::offscreen(params.samples);
        Ok(Self {
            field: FieldRenderer::new(device, queue, sim, format, params)?,
            target,
        })
    }

    /// A renderer that draws the field of a GPU-path simulation straight
    /// from its buffers ([`Renderer::encode_gpu`]; `gpu.sim` gives the
    /// camera, objects and terrain): no blade vertex buffer of its own (the
    /// GPU path's chunks are drawn one indirect draw each).
    ///
    /// # Errors
    /// As [`Renderer::new`], less the field's size.
    pub fn new_gpu(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        gpu: &trample_gpu::GpuSimulation,
        params: RenderParams,
    ) -> Result<Self, RenderError> {
        let target = Target::new(device, params.width, params.height, params.samples)?;
        let format = TargetFormat::offscreen(params.samples);
        Ok(Self {
            field: FieldRenderer::new_gpu(device, queue, gpu, format, params)?,
            target,
        })
    }

    /// The settings this renderer was made with.
    #[must_use]
    pub fn params(&self) -> &RenderParams {
        self.field.params()
    }

    /// The [`FieldRenderer`] it hosts.
    #[must_use]
    pub fn field_renderer(&mut self) -> &mut FieldRenderer {
        &mut self.field
    }

    /// The camera of `sim`'s frame at this renderer's aspect.
    #[must_use]
    pub fn camera_of(&self, sim: &Simulation) -> FrameCamera {
        let p = self.params();
        FrameCamera::of(sim, p.width as f32 / p.height as f32)
    }

    /// The per-frame uniform every pass reads, for `sim`'s frame (camera,
    /// sun, fog, debug view, wind). Public for tests and tools that run the
    /// shared WGSL (`globals.wgsl`) themselves.
    #[must_use]
    pub fn globals_of(&self, sim: &Simulation) -> Globals {
        self.field.globals_of(sim, &self.camera_of(sim))
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
        let camera = self.camera_of(sim);
        let counts = self.field.prepare(device, queue, encoder, sim, &camera);
        self.record_pass(encoder);
        counts
    }

    /// Records the frame of a GPU-path simulation into `encoder`, drawing
    /// its blades and billboards straight from its buffers
    /// ([`FieldRenderer::prepare_gpu`]); nothing of the field is read back
    /// or uploaded. The camera, objects, terrain and debug lines come from
    /// `gpu.sim` (kept up to date by `GpuSimulation::step`). The renderer
    /// must come from [`Renderer::new_gpu`] or [`Renderer::new`] for the
    /// same field.
    pub fn encode_gpu(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        gpu: &mut trample_gpu::GpuSimulation,
        encoder: &mut wgpu::CommandEncoder,
    ) {
        let camera = self.camera_of(&gpu.sim);
        self.field.prepare_gpu(device, queue, encoder, gpu, &camera);
        self.record_pass(encoder);
    }

    /// Opens the one pass of the frame on the target (cleared), lets the
    /// field renderer record into it, and ends it.
    fn record_pass(&self, encoder: &mut wgpu::CommandEncoder) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("scene"),
            color_attachments: &[Some(self.target.color_attachment(wgpu::Color::BLACK))],
            depth_stencil_attachment: Some(self.target.depth_attachment()),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        self.field.render(&mut pass);
    }

    /// The frame the passes resolve into: single-sample [`crate::COLOR_FORMAT`],
    /// `params().width × params().height`, sampleable (see [`Renderer::encode`]).
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
        let p = self.params();
        if (width, height) != (p.width, p.height) {
            self.target = Target::new(device, width, height, p.samples)?;
            self.field.set_size(width, height);
        }
        Ok(())
    }

    /// Switches the debug view from the next frame on.
    pub fn set_debug(&mut self, debug: DebugView) {
        self.field.set_debug(debug);
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

    /// Draws `sim`'s current state and waits until the GPU has drawn it,
    /// without reading it back: what a frame costs an application that
    /// presents it (`trample bench --render --no-readback`). The frame is
    /// in [`Renderer::frame_view`].
    ///
    /// # Errors
    /// [`RenderError::Readback`] when the wait fails (device lost).
    pub fn draw_and_wait(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        sim: &Simulation,
    ) -> Result<FrameCounts, RenderError> {
        let mut counts = FrameCounts::default();
        record_and_wait(device, queue, "frame", |e| {
            counts = self.encode(device, queue, sim, e);
        })?;
        Ok(counts)
    }

    /// [`Renderer::draw_and_wait`] for the GPU path ([`Renderer::encode_gpu`]).
    ///
    /// # Errors
    /// [`RenderError::Readback`] when the wait fails (device lost).
    pub fn draw_gpu_and_wait(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        gpu: &mut trample_gpu::GpuSimulation,
    ) -> Result<(), RenderError> {
        record_and_wait(device, queue, "frame (GPU path)", |e| {
            self.encode_gpu(device, queue, gpu, e);
        })
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

/// Records a frame with `record` into an encoder of its own, submits it
/// and waits for everything submitted to `queue`.
fn record_and_wait(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    record: impl FnOnce(&mut wgpu::CommandEncoder),
) -> Result<(), RenderError> {
    let mut encoder =
        device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label) });
    record(&mut encoder);
    queue.submit([encoder.finish()]);
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map(drop)
        .map_err(|e| RenderError::Readback(e.to_string()))
}
