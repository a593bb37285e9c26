//! A host program that embeds trample without a window: it brings its own
//! device, camera, render pass and depth buffer, draws an unlit pure
//! magenta (255, 0, 255) cube standing in the grass, and lets trample draw
//! the grass into that same pass (`trample_render::FieldRenderer`), so
//! grass in front of the cube hides part of it. Writes the frame to OUT.png.
//!
//! ```sh
//! cargo run --release -p trample-render --example embed_headless -- OUT.png
//! ```
//! The GPU backend follows `WGPU_BACKEND` (e.g. `gl` for Mesa llvmpipe).

mod embed;

/// Frame size, pixels.
const SIZE: [u32; 2] = [640, 360];
/// Steps before the frame is drawn: the grass settles round the cube.
const STEPS: u32 = 30;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = match std::env::args_os().nth(1) {
        Some(p) => std::path::PathBuf::from(p),
        None => return Err("usage: embed_headless OUT.png".into()),
    };
    // The host's own device (STYLE rule 3: trample never makes one).
    let desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    let instance = wgpu::Instance::new(desc);
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        force_fallback_adapter: false,
        compatible_surface: None,
    }))?;
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("host"),
        required_features: wgpu::Features::empty(),
        required_limits: trample_render::required_limits(&adapter),
        experimental_features: wgpu::ExperimentalFeatures::disabled(),
        memory_hints: wgpu::MemoryHints::Performance,
        trace: wgpu::Trace::Off,
    }))?;
    let info = adapter.get_info();
    let frame = embed::render_headless(&device, &queue, &adapter, SIZE, STEPS, true)?;
    frame.save(&out)?;
    let magenta = frame.pixels().filter(|p| p.0[..3] == [255, 0, 255]).count();
    println!(
        "embed_headless: {}×{} frame on {} ({:?}) written to {}; {magenta} pure magenta pixels",
        SIZE[0],
        SIZE[1],
        info.name,
        info.backend,
        out.display()
    );
    Ok(())
}
