//! The window and its event loop: winit events go to egui first, then to
//! the [`App`]; each redraw steps the simulation, renders the frame into the
//! renderer's target, draws the panel over it, copies it onto the surface
//! ([`Blit`]) and presents it.

use crate::ViewError;
use crate::app::App;
use crate::backend::{BackendKind, GpuDevice, StartBackend};
use crate::blit::Blit;
use crate::input::Key;
use crate::panel::{self, FrameStats};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;
use trample::scene::Scene;
use trample_render::{RenderParams, Renderer};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

/// What `trample view` was asked for.
#[derive(Clone, Debug)]
pub struct ViewOptions {
    /// The scene.
    pub scene: Scene,
    /// Inner size of the window, pixels. Default 960 × 540: software
    /// rendering of the default scene takes seconds a frame at 1280 × 720.
    pub size: [u32; 2],
    /// Close after this many frames (for tests and scripts).
    pub frames: Option<u64>,
    /// Write the last frame (with the panel) to this PNG on closing.
    pub screenshot: Option<PathBuf>,
    /// MSAA samples wanted (1 where the adapter cannot).
    pub samples: u32,
    /// The simulation path to start on (the panel switches it live).
    pub backend: StartBackend,
}

/// Opens the window and runs until it is closed (or `frames` are drawn).
///
/// # Errors
/// [`ViewError::NoDisplay`] when there is no display; the others when the
/// scene, the GPU or a screenshot fails.
pub fn run(options: ViewOptions) -> Result<(), ViewError> {
    let app = App::new(options.scene.clone())?;
    let event_loop = EventLoop::new().map_err(|e| ViewError::NoDisplay(one_line(&e)))?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut viewer = Viewer {
        app,
        options,
        gfx: None,
        error: None,
        frames: 0,
        last: Instant::now(),
        stats: FrameStats::default(),
        mouse: Mouse::default(),
    };
    event_loop
        .run_app(&mut viewer)
        .map_err(|e| ViewError::Graphics(one_line(&e)))?;
    match viewer.error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

fn one_line(e: &dyn std::fmt::Display) -> String {
    e.to_string().replace('\n', " ")
}

#[derive(Default)]
struct Mouse {
    dragging: bool,
    last: Option<(f64, f64)>,
}

/// Everything that needs the window.
struct Graphics {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    device: wgpu::Device,
    queue: wgpu::Queue,
    renderer: Renderer,
    render_params: RenderParams,
    field_version: u64,
    blit: Blit,
    egui_ctx: egui::Context,
    egui_state: egui_winit::State,
    egui_renderer: egui_wgpu::Renderer,
}

struct Viewer {
    app: App,
    options: ViewOptions,
    gfx: Option<Graphics>,
    error: Option<ViewError>,
    frames: u64,
    last: Instant,
    stats: FrameStats,
    mouse: Mouse,
}

impl Viewer {
    fn fail(&mut self, event_loop: &ActiveEventLoop, e: ViewError) {
        self.error.get_or_insert(e);
        event_loop.exit();
    }

    fn create_graphics(&mut self, event_loop: &ActiveEventLoop) -> Result<Graphics, ViewError> {
        let [w, h] = self.options.size;
        let attributes = Window::default_attributes()
            .with_title("trample")
            .with_inner_size(winit::dpi::PhysicalSize::new(w, h));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .map_err(|e| ViewError::NoDisplay(one_line(&e)))?,
        );
        let desc = wgpu::InstanceDescriptor::new_with_display_handle_from_env(Box::new(
            event_loop.owned_display_handle(),
        ));
        let instance = wgpu::Instance::new(desc);
        let surface = instance
            .create_surface(window.clone())
            .map_err(|e| ViewError::Graphics(format!("surface: {}", one_line(&e))))?;
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: Some(&surface),
        }))
        .map_err(|e| ViewError::Graphics(format!("no adapter for the window: {}", one_line(&e))))?;
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("trample view"),
            required_features: wgpu::Features::empty(),
            required_limits: trample_render::required_limits(&adapter),
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        }))
        .map_err(|e| ViewError::Graphics(format!("device: {}", one_line(&e))))?;
        let lent = GpuDevice::new(device.clone(), queue.clone(), &adapter);
        self.stats.adapter.clone_from(&lent.adapter);
        self.app.attach_gpu(lent);
        let size = window.inner_size();
        let (w, h) = (size.width.max(1), size.height.max(1));
        let caps = surface.get_capabilities(&adapter);
        let format = caps
            .formats
            .iter()
            .copied()
            .find(wgpu::TextureFormat::is_srgb)
            .or_else(|| caps.formats.first().copied())
            .ok_or_else(|| ViewError::Graphics("the surface offers no format".into()))?;
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            format,
            width: w,
            height: h,
            present_mode: wgpu::PresentMode::AutoVsync,
            desired_maximum_frame_latency: 2,
            alpha_mode: caps
                .alpha_modes
                .first()
                .copied()
                .unwrap_or(wgpu::CompositeAlphaMode::Auto),
            view_formats: vec![],
        };
        surface.configure(&device, &config);
        let render_params = RenderParams {
            width: w,
            height: h,
            samples: trample_render::headless::supported_msaa(&adapter, self.options.samples),
            debug: self.app.debug,
            ..RenderParams::default()
        };
        self.app.set_aspect(w as f32 / h as f32);
        let renderer = Renderer::new(&device, &queue, self.app.sim(), render_params)
            .map_err(|e| ViewError::Graphics(one_line(&e)))?;
        let egui_ctx = egui::Context::default();
        let egui_state = egui_winit::State::new(
            egui_ctx.clone(),
            egui::ViewportId::ROOT,
            &*window,
            Some(window.scale_factor() as f32),
            None,
            Some(device.limits().max_texture_dimension_2d as usize),
        );
        let egui_renderer = egui_wgpu::Renderer::new(
            &device,
            trample_render::COLOR_FORMAT,
            egui_wgpu::RendererOptions::default(),
        );
        Ok(Graphics {
            blit: Blit::new(&device, format),
            window,
            surface,
            config,
            device,
            queue,
            renderer,
            render_params,
            field_version: self.app.field_version,
            egui_ctx,
            egui_state,
            egui_renderer,
        })
    }

    /// One frame; returns whether the viewer should close.
    fn frame(&mut self) -> Result<bool, ViewError> {
        let now = Instant::now();
        let dt = now.duration_since(self.last).as_secs_f64();
        self.last = now;
        // The first frame also builds pipelines: the average starts after it.
        self.stats.frame_ms = if self.frames <= 1 {
            dt * 1e3
        } else {
            0.9 * self.stats.frame_ms + 0.1 * dt * 1e3
        };
        self.app.update(dt as f32)?;
        let Some(g) = self.gfx.as_mut() else {
            return Ok(false);
        };
        if g.field_version != self.app.field_version {
            g.renderer = Renderer::new(&g.device, &g.queue, self.app.sim(), g.render_params)
                .map_err(|e| ViewError::Graphics(one_line(&e)))?;
            g.field_version = self.app.field_version;
        }
        g.renderer.set_debug(self.app.debug);

        let raw = g.egui_state.take_egui_input(&g.window);
        let (app, stats) = (&mut self.app, &self.stats);
        let out = g.egui_ctx.run_ui(raw, |ui| panel::show(ui, app, stats));
        g.egui_state
            .handle_platform_output(&g.window, out.platform_output);
        let jobs = g.egui_ctx.tessellate(out.shapes, out.pixels_per_point);
        let mut textures = out.textures_delta;
        for (id, delta) in textures.set.drain(..) {
            g.egui_renderer
                .update_texture(&g.device, &g.queue, id, &delta);
        }
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [g.render_params.width, g.render_params.height],
            pixels_per_point: out.pixels_per_point,
        };

        let mut encoder = g
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("view frame"),
            });
        // The GPU path is drawn straight from its buffers.
        if let Some(gpu) = self.app.gpu_mut() {
            g.renderer
                .encode_gpu(&g.device, &g.queue, gpu, &mut encoder);
            self.stats.drawn_on_gpu = true;
        } else {
            let counts = g
                .renderer
                .encode(&g.device, &g.queue, self.app.sim(), &mut encoder);
            self.stats.blades_drawn = counts.blades;
            self.stats.billboards_drawn = counts.billboards;
            self.stats.drawn_on_gpu = false;
        }
        let mut commands =
            g.egui_renderer
                .update_buffers(&g.device, &g.queue, &mut encoder, &jobs, &screen);
        {
            let mut pass = encoder
                .begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("egui"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: g.renderer.frame_view(),
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Load,
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    depth_stencil_attachment: None,
                    timestamp_writes: None,
                    occlusion_query_set: None,
                    multiview_mask: None,
                })
                .forget_lifetime();
            g.egui_renderer.render(&mut pass, &jobs, &screen);
        }
        let surface_texture = match g.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t)
            | wgpu::CurrentSurfaceTexture::Suboptimal(t) => Some(t),
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                g.surface.configure(&g.device, &g.config);
                None
            }
            _ => None,
        };
        if let Some(t) = &surface_texture {
            let view = t
                .texture
                .create_view(&wgpu::TextureViewDescriptor::default());
            g.blit
                .draw(&g.device, &mut encoder, g.renderer.frame_view(), &view);
        }
        commands.push(encoder.finish());
        g.queue.submit(commands);
        if let Some(t) = surface_texture {
            g.window.pre_present_notify();
            t.present();
        }
        for id in textures.free.drain(..) {
            g.egui_renderer.free_texture(&id);
        }
        self.frames += 1;

        let last = self.options.frames.is_some_and(|n| self.frames >= n);
        if std::mem::take(&mut self.app.screenshot_requested) {
            let path = PathBuf::from(format!("trample-view-{:05}.png", self.app.sim().frame));
            save_frame(g, &path)?;
            self.app.message = format!("wrote {}", path.display());
        }
        if last && let Some(path) = &self.options.screenshot {
            save_frame(g, path)?;
        }
        Ok(last)
    }

    /// Puts the simulation on the path `--backend` asks for, now that the
    /// window's device is there, and says which on stderr (as `simulate`).
    fn start_backend(&mut self) {
        let wanted = self.options.backend.resolve(self.app.gpu_device());
        let adapter = self
            .app
            .gpu_device()
            .map_or_else(String::new, |d| d.adapter.clone());
        match (self.options.backend, wanted) {
            (StartBackend::Auto, BackendKind::Cpu) => eprintln!(
                "trample: {adapter} is a software adapter: CPU path (--backend gpu forces the GPU path)"
            ),
            (_, BackendKind::Cpu) => {}
            (_, BackendKind::Gpu) => match self.app.set_backend(BackendKind::Gpu) {
                Ok(()) => eprintln!("trample: GPU path on {adapter}"),
                Err(e) => eprintln!("trample: {e}"),
            },
        }
    }

    fn resize(&mut self, width: u32, height: u32) -> Result<(), ViewError> {
        let Some(g) = self.gfx.as_mut() else {
            return Ok(());
        };
        if width == 0 || height == 0 {
            return Ok(()); // minimised
        }
        g.config.width = width;
        g.config.height = height;
        g.surface.configure(&g.device, &g.config);
        g.renderer
            .resize(&g.device, width, height)
            .map_err(|e| ViewError::Graphics(one_line(&e)))?;
        g.render_params.width = width;
        g.render_params.height = height;
        self.app.set_aspect(width as f32 / height as f32);
        Ok(())
    }
}

/// Reads the frame back (scene and panel) and writes it as a PNG.
fn save_frame(g: &Graphics, path: &std::path::Path) -> Result<(), ViewError> {
    let err = |reason: String| ViewError::Screenshot {
        path: path.display().to_string(),
        reason,
    };
    let image = g
        .renderer
        .read_frame(&g.device, &g.queue)
        .map_err(|e| err(one_line(&e)))?;
    image.save(path).map_err(|e| err(one_line(&e)))
}

impl ApplicationHandler for Viewer {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gfx.is_some() {
            return;
        }
        match self.create_graphics(event_loop) {
            Ok(g) => {
                self.gfx = Some(g);
                self.start_backend();
                self.last = Instant::now();
            }
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let consumed = match self.gfx.as_mut() {
            Some(g) => g.egui_state.on_window_event(&g.window, &event).consumed,
            None => false,
        };
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                if let Err(e) = self.resize(size.width, size.height) {
                    self.fail(event_loop, e);
                }
            }
            WindowEvent::RedrawRequested => match self.frame() {
                Ok(true) => event_loop.exit(),
                Ok(false) => {}
                Err(e) => self.fail(event_loop, e),
            },
            WindowEvent::Focused(false) => self.app.input.release_all(),
            WindowEvent::KeyboardInput { event, .. } => {
                let PhysicalKey::Code(code) = event.physical_key else {
                    return;
                };
                let pressed = event.state == ElementState::Pressed;
                if code == KeyCode::Escape && pressed {
                    event_loop.exit();
                } else if let Some(key) = key_of(code) {
                    // Releases always count, so no key stays held.
                    if !consumed || !pressed {
                        self.app.key(key, pressed, event.repeat);
                    }
                }
            }
            WindowEvent::MouseInput { state, button, .. } => {
                if matches!(button, MouseButton::Left | MouseButton::Right) {
                    self.mouse.dragging = state == ElementState::Pressed && !consumed;
                }
            }
            WindowEvent::CursorMoved { position, .. } => {
                if self.mouse.dragging
                    && let Some((x, y)) = self.mouse.last
                {
                    self.app
                        .drag((position.x - x) as f32, (position.y - y) as f32);
                }
                self.mouse.last = Some((position.x, position.y));
            }
            WindowEvent::MouseWheel { delta, .. } if !consumed => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => (p.y / 40.0) as f32,
                };
                self.app.scroll(lines);
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(g) = &self.gfx {
            g.window.request_redraw();
        }
    }
}

/// The viewer's key for a physical key code.
#[must_use]
pub fn key_of(code: KeyCode) -> Option<Key> {
    Some(match code {
        KeyCode::ArrowUp => Key::ArrowUp,
        KeyCode::ArrowDown => Key::ArrowDown,
        KeyCode::ArrowLeft => Key::ArrowLeft,
        KeyCode::ArrowRight => Key::ArrowRight,
        KeyCode::KeyW => Key::W,
        KeyCode::KeyA => Key::A,
        KeyCode::KeyS => Key::S,
        KeyCode::KeyD => Key::D,
        KeyCode::KeyQ => Key::Q,
        KeyCode::KeyE => Key::E,
        KeyCode::Space => Key::Space,
        KeyCode::KeyN => Key::N,
        KeyCode::KeyR => Key::R,
        KeyCode::KeyT => Key::T,
        KeyCode::KeyG => Key::G,
        KeyCode::KeyC => Key::C,
        KeyCode::KeyV => Key::V,
        KeyCode::KeyP => Key::P,
        KeyCode::KeyH => Key::H,
        KeyCode::BracketLeft => Key::BracketLeft,
        KeyCode::BracketRight => Key::BracketRight,
        KeyCode::ShiftLeft | KeyCode::ShiftRight => Key::Shift,
        _ => return None,
    })
}
