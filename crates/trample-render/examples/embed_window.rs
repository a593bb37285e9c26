//! The `embed_headless` host in a winit window: its own device, surface,
//! camera, render pass and depth buffer; an unlit pure magenta (255, 0,
//! 255) cube standing in the grass that the arrow keys drive (it sweeps
//! the grass as it goes), and trample drawing the grass into the host's
//! pass (`trample_render::FieldRenderer`). Escape closes it.
//!
//! ```sh
//! cargo run --release -p trample-render --example embed_window
//! cargo run --release -p trample-render --example embed_window -- --frames 60
//! ```
//! `--frames N` closes it after N frames (CI runs it so under Xvfb). The
//! window is X11 (XWayland on Wayland desktops), as the viewer's.

mod embed;

use std::sync::Arc;
use winit::application::ApplicationHandler;
use winit::event::{ElementState, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

/// How fast the arrow keys drive the cube, metres per second.
const SPEED_M_S: f32 = 1.5;

/// What the window holds once it exists.
struct Graphics {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    device: wgpu::Device,
    queue: wgpu::Queue,
    samples: u32,
    msaa: Option<wgpu::TextureView>,
    depth: wgpu::TextureView,
    host: embed::Host,
}

impl Graphics {
    /// The window's MSAA colour and depth attachments at its current size.
    fn make_attachments(&mut self) {
        let size = [self.config.width, self.config.height];
        self.msaa = (self.samples > 1).then(|| {
            embed::attachment(
                &self.device,
                "host colour (msaa)",
                self.config.format,
                size,
                self.samples,
                wgpu::TextureUsages::empty(),
            )
            .create_view(&Default::default())
        });
        self.depth = embed::attachment(
            &self.device,
            "host depth",
            embed::DEPTH,
            size,
            self.samples,
            wgpu::TextureUsages::empty(),
        )
        .create_view(&Default::default());
        self.host
            .set_aspect(self.config.width as f32 / self.config.height as f32);
    }
}

#[derive(Default)]
struct App {
    gfx: Option<Graphics>,
    error: Option<String>,
    /// Close after this many frames (`--frames N`).
    frame_limit: Option<u64>,
    frames: u64,
    /// Arrow keys held: left, right, up, down.
    held: [bool; 4],
}

impl App {
    fn create(&self, event_loop: &ActiveEventLoop) -> Result<Graphics, Box<dyn std::error::Error>> {
        let attributes = Window::default_attributes()
            .with_title("trample: embed_window (arrow keys drive the cube)")
            .with_inner_size(winit::dpi::PhysicalSize::new(960, 540));
        let window = Arc::new(event_loop.create_window(attributes)?);
        let desc = wgpu::InstanceDescriptor::new_with_display_handle_from_env(Box::new(
            event_loop.owned_display_handle(),
        ));
        let instance = wgpu::Instance::new(desc);
        let surface = instance.create_surface(window.clone())?;
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: Some(&surface),
        }))?;
        let (device, queue) =
            pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
                label: Some("host"),
                required_features: wgpu::Features::empty(),
                required_limits: trample_render::required_limits(&adapter),
                experimental_features: wgpu::ExperimentalFeatures::disabled(),
                memory_hints: wgpu::MemoryHints::Performance,
                trace: wgpu::Trace::Off,
            }))?;
        let size = window.inner_size();
        let caps = surface.get_capabilities(&adapter);
        // Whatever the surface offers first: trample encodes sRGB itself
        // for a format that is not an sRGB one.
        let format = *caps.formats.first().ok_or("the surface offers no format")?;
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            format,
            width: size.width.max(1),
            height: size.height.max(1),
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
        let samples = embed::msaa(&adapter, format, 4);
        let target = trample_render::TargetFormat {
            color: format,
            depth: Some(embed::DEPTH),
            samples,
        };
        let aspect = config.width as f32 / config.height as f32;
        let host = embed::Host::new(&device, &queue, target, aspect)?;
        let depth = embed::attachment(
            &device,
            "host depth",
            embed::DEPTH,
            [1, 1],
            samples,
            wgpu::TextureUsages::empty(),
        )
        .create_view(&Default::default());
        let mut g = Graphics {
            window,
            surface,
            config,
            device,
            queue,
            samples,
            msaa: None,
            depth,
            host,
        };
        g.make_attachments();
        Ok(g)
    }

    /// One frame: drive the cube by the keys held, step, draw, present.
    fn frame(&mut self) -> Result<(), Box<dyn std::error::Error>> {
        let Some(g) = self.gfx.as_mut() else {
            return Ok(());
        };
        let [l, r, u, d] = self.held.map(f32::from);
        let step = SPEED_M_S * embed::DT;
        g.host.cube_at.x += (r - l) * step;
        g.host.cube_at.z += (d - u) * step;
        g.host.step()?;
        let texture = match g.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t)
            | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                g.surface.configure(&g.device, &g.config);
                return Ok(());
            }
            _ => return Ok(()),
        };
        let view = texture.texture.create_view(&Default::default());
        let mut encoder = g.device.create_command_encoder(&Default::default());
        match &g.msaa {
            Some(m) => g
                .host
                .frame(&g.device, &g.queue, &mut encoder, m, Some(&view), &g.depth),
            None => g
                .host
                .frame(&g.device, &g.queue, &mut encoder, &view, None, &g.depth),
        }
        g.queue.submit([encoder.finish()]);
        g.window.pre_present_notify();
        texture.present();
        self.frames += 1;
        Ok(())
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gfx.is_some() {
            return;
        }
        match self.create(event_loop) {
            Ok(g) => self.gfx = Some(g),
            Err(e) => {
                self.error = Some(e.to_string());
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                if let Some(g) = self.gfx.as_mut() {
                    g.config.width = size.width.max(1);
                    g.config.height = size.height.max(1);
                    g.surface.configure(&g.device, &g.config);
                    g.make_attachments();
                }
            }
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.frame() {
                    self.error = Some(e.to_string());
                    event_loop.exit();
                }
                if self.frame_limit.is_some_and(|n| self.frames >= n) {
                    event_loop.exit();
                }
            }
            WindowEvent::KeyboardInput { event, .. } => {
                let PhysicalKey::Code(code) = event.physical_key else {
                    return;
                };
                let pressed = event.state == ElementState::Pressed;
                let key = match code {
                    KeyCode::Escape => {
                        event_loop.exit();
                        return;
                    }
                    KeyCode::ArrowLeft => 0,
                    KeyCode::ArrowRight => 1,
                    KeyCode::ArrowUp => 2,
                    KeyCode::ArrowDown => 3,
                    _ => return,
                };
                self.held[key] = pressed;
            }
            WindowEvent::Focused(false) => self.held = [false; 4],
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(g) = &self.gfx {
            g.window.request_redraw();
        }
    }
}

/// `--frames N` from the command line (anything else is refused).
fn frame_limit() -> Result<Option<u64>, Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.as_slice() {
        [] => Ok(None),
        [flag, n] if flag == "--frames" => {
            Ok(Some(n.parse().map_err(|_| {
                format!("--frames {n}: expected a whole number of frames")
            })?))
        }
        _ => Err(format!("usage: embed_window [--frames N]; got {args:?}").into()),
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut app = App {
        frame_limit: frame_limit()?,
        ..App::default()
    };
    let event_loop = EventLoop::new()?;
    event_loop.set_control_flow(ControlFlow::Poll);
    event_loop.run_app(&mut app)?;
    if let Some(e) = app.error {
        return Err(e.into());
    }
    println!("embed_window: {} frames drawn", app.frames);
    Ok(())
}
