//! Renders a trample field with wgpu (DESIGN §8): geometric blades pulled
//! from the core's vertex buffer, billboards whose top edge follows the
//! cell's slope (Eq. 8), a textured ground, shaded objects, sky, fog, MSAA.
//!
//! Two ways in: [`FieldRenderer`] records the field into a render pass a
//! host (a game) opened, with the host's formats, depth buffer and camera
//! (wgpu middleware: `prepare`, then `render(&mut pass)`); [`Renderer`] is
//! a small host of it that draws offscreen to an image (the CLI, the
//! viewer, the tests). The examples `embed_headless` and `embed_window`
//! show a host drawing its own geometry and the grass in one pass.
//!
//! Library functions take a `&wgpu::Device` and `&wgpu::Queue`; only
//! [`headless::create_device`] makes one (for tools and tests).
//!
//! ```no_run
//! let mut sim = trample::scene::Scene::default_scene()?.build()?;
//! let gpu = trample_render::headless::create_device()?;
//! let params = trample_render::RenderParams { width: 320, height: 180, samples: gpu.msaa(4), ..Default::default() };
//! let mut renderer = trample_render::Renderer::new(&gpu.device, &gpu.queue, &sim, params)?;
//! sim.step(1.0 / 60.0)?;
//! renderer.render(&gpu.device, &gpu.queue, &sim)?.save("frame.png")?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod billboards;
pub mod blades;
mod classes;
pub mod error;
pub mod field_renderer;
pub mod frame_camera;
pub mod globals;
pub mod headless;
pub mod lines;
pub mod objects;
pub mod params;
pub mod pipeline;
pub mod renderer;
pub mod shadows;
pub mod sky;
pub mod target;
pub mod target_format;
pub mod terrain;
pub mod textures;

pub use error::RenderError;
pub use field_renderer::{FieldRenderer, FrameCounts};
pub use frame_camera::FrameCamera;
pub use params::{DebugView, Layers, RenderParams};
pub use renderer::Renderer;
pub use target_format::TargetFormat;

/// Colour format of the frame: sRGB, so shaders work in linear colour and
/// the bytes read back are what a PNG stores.
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// Depth format.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Every WGSL file of the crate with the name it has on disk, as compiled
/// (the shared globals prepended): for validation tests.
#[must_use]
pub fn shader_sources() -> Vec<(&'static str, String)> {
    use globals::shader_source;
    vec![
        ("blades.wgsl", shader_source(include_str!("blades.wgsl"))),
        (
            "billboards.wgsl",
            shader_source(include_str!("billboards.wgsl")),
        ),
        ("terrain.wgsl", shader_source(include_str!("terrain.wgsl"))),
        ("objects.wgsl", shader_source(include_str!("objects.wgsl"))),
        ("sky.wgsl", shader_source(include_str!("sky.wgsl"))),
        ("lines.wgsl", shader_source(include_str!("lines.wgsl"))),
        ("shadows.wgsl", shader_source(include_str!("shadows.wgsl"))),
    ]
}

/// The limits to ask of `adapter`: all it offers (the blade buffer alone is
/// 21 MiB for the paper's field, above wgpu's default binding size on some
/// adapters).
#[must_use]
pub fn required_limits(adapter: &wgpu::Adapter) -> wgpu::Limits {
    adapter.limits()
}
