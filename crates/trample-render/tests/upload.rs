//! Uploads only what changed (issue 14 items 2–3): a renderer that saw
//! every step writes only the blades each step changed, and draws exactly
//! the frame a fresh renderer (which writes every blade) draws of the same
//! state. Runs on the adapter of `WGPU_BACKEND`; no adapter = failure.

use trample::Simulation;
use trample::scene::Scene;
use trample_render::{RenderParams, Renderer};

const W: u32 = 160;
const H: u32 = 120;

/// A 3.2 m field seen from above with a ball rolling through it, drawn as
/// blades (to 50 m).
fn scene() -> Simulation {
    scene_with_blades_to(50.0)
}

/// The same, drawn as blades to `geometry_m` from the camera and as
/// billboards beyond.
fn scene_with_blades_to(geometry_m: f32) -> Simulation {
    let toml = format!(
        r#"
[field]
patches = [4, 4]
cells_per_patch = 8
cell_size_m = 0.1
blade_width_m = 0.03
[lod]
geometry_m = {geometry_m}
billboard_m = 60.0
[sim]
recovery_s = 1.0
[camera]
path = {{ kind = "static", position = [0.0, 3.0, 0.8] }}
look_at = {{ kind = "point", at = [0.0, 0.0, 0.0] }}
aspect = {aspect}
[[objects]]
name = "ball"
shape = {{ kind = "sphere", radius_m = 0.3, subdivisions = 2 }}
orientation = "rolling"
path = {{ kind = "line", from = [-2.0, 0.3, 0.0], to = [2.0, 0.3, 0.0], duration_s = 1.0 }}
"#,
        aspect = W as f32 / H as f32,
    );
    Scene::parse(&toml, "upload.toml", std::path::Path::new("."))
        .unwrap()
        .build()
        .unwrap()
}

/// The adapter's device and the frames' parameters.
fn device_and_params() -> (trample_render::headless::Gpu, RenderParams) {
    let gpu = trample_render::headless::create_device()
        .unwrap_or_else(|e| panic!("the upload test needs an adapter: {e}"));
    let params = RenderParams {
        width: W,
        height: H,
        samples: gpu.msaa(4),
        ..Default::default()
    };
    (gpu, params)
}

#[test]
fn changed_blades_only_and_the_same_frame_as_a_full_upload() {
    let (gpu, params) = device_and_params();
    let (device, queue) = (&gpu.device, &gpu.queue);
    let mut sim = scene();
    let full_bytes = sim.field.blades.pos_bytes().len() as u64;
    let mut follower = Renderer::new(device, queue, &sim, params).unwrap();
    let first = follower.draw(device, queue, &sim);
    assert!(
        first.vertex_bytes == full_bytes,
        "the first frame writes every vertex"
    );
    let mut most = 0;
    for frame in 0..45 {
        sim.step(1.0 / 60.0).unwrap();
        let counts = follower.draw(device, queue, &sim);
        // Every step of the run changes some blades (the ball is in the
        // field), never all of them.
        assert!(
            counts.vertex_bytes > 0 && counts.vertex_bytes < full_bytes / 2,
            "frame {frame}: {} bytes of vertices written of {full_bytes}",
            counts.vertex_bytes
        );
        most = most.max(counts.vertex_bytes);
    }
    eprintln!("upload: at most {most} bytes a frame after the first, field {full_bytes} bytes");
    assert!(sim.blades_away_from_rest() > 100, "the ball bent the grass");
    let followed = follower.read_frame(device, queue).unwrap();
    let fresh = Renderer::new(device, queue, &sim, params)
        .unwrap()
        .render(device, queue, &sim)
        .unwrap();
    let differing = followed
        .pixels()
        .zip(fresh.pixels())
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(
        differing, 0,
        "{differing} pixels differ between the renderer that uploaded only changes and a fresh one"
    );
    // A frame without a step writes no blade vertex.
    let again = follower.draw(device, queue, &sim);
    assert_eq!(again.vertex_bytes, 0);
}

/// A device on `gpu`'s adapter whose storage bindings hold `bytes`.
fn device_with_binding(
    gpu: &trample_render::headless::Gpu,
    bytes: u64,
) -> (wgpu::Device, wgpu::Queue) {
    let limits = wgpu::Limits {
        max_storage_buffer_binding_size: bytes,
        ..trample_render::required_limits(&gpu.adapter)
    };
    pollster::block_on(gpu.adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("small bindings"),
        required_limits: limits,
        ..Default::default()
    }))
    .expect("a device with smaller limits than the adapter's")
}

#[test]
fn a_field_over_one_binding_is_uploaded_and_drawn_in_chunks() {
    // 1,024 blades of 5 vertices: 80 KiB of vertices. A binding of 32 KiB
    // holds 409 blades' vertices: three chunks (before: BladesTooLarge).
    let (gpu, params) = device_and_params();
    let (small, small_queue) = device_with_binding(&gpu, 32 << 10);
    let mut sim = scene();
    let full_bytes = sim.field.blades.pos_bytes().len() as u64;
    assert_eq!(full_bytes, 80 << 10);
    let mut chunked = Renderer::new(&small, &small_queue, &sim, params)
        .unwrap_or_else(|e| panic!("a field in chunks: {e}"));
    let first = chunked.draw(&small, &small_queue, &sim);
    assert_eq!(
        first.vertex_bytes, full_bytes,
        "every vertex, chunk by chunk"
    );
    assert_eq!(first.blade_chunks, 3);
    // Changed blades only, split between the chunks they lie in.
    for _ in 0..45 {
        sim.step(1.0 / 60.0).unwrap();
        let counts = chunked.draw(&small, &small_queue, &sim);
        assert!(counts.vertex_bytes > 0 && counts.vertex_bytes < full_bytes / 2);
    }
    let in_chunks = chunked.read_frame(&small, &small_queue).unwrap();
    let (device, queue) = (&gpu.device, &gpu.queue);
    let whole = Renderer::new(device, queue, &sim, params)
        .unwrap()
        .render(device, queue, &sim)
        .unwrap();
    let differing = in_chunks
        .pixels()
        .zip(whole.pixels())
        .filter(|(a, b)| a != b)
        .count();
    let grass = whole
        .pixels()
        .filter(|p| p[1] > p[0] && p[1] > p[2])
        .count();
    eprintln!("in chunks against whole: {differing} pixels differ; {grass} green");
    assert!(grass > (W * H / 4) as usize, "{grass} grass pixels");
    assert_eq!(
        differing, 0,
        "{differing} pixels differ between the field in chunks and whole"
    );
    // The blades' shapes (8 bytes a blade, 8 KiB) over the binding: refused
    // with the sizes before any pass binds them.
    let (tiny, tiny_queue) = device_with_binding(&gpu, 6 << 10);
    match Renderer::new(&tiny, &tiny_queue, &sim, params) {
        Err(
            e @ trample_render::RenderError::BladesTooLarge {
                needed: 8192,
                allowed: 6144,
            },
        ) => eprintln!("refused: {e}"),
        Err(e) => panic!("another refusal: {e}"),
        Ok(_) => panic!("a binding of 6 KiB took the field"),
    }
}

#[test]
fn billboards_over_one_binding_are_drawn_in_pieces() {
    // Blades to 3 m, billboards beyond, seen from 3 m up: every cell a
    // billboard (1,024 of 48 bytes) and, in the near blend band, its blades
    // too. A binding of 16 KiB takes 341 billboards a piece (4 pieces) and
    // 204 blades' vertices a chunk (6 chunks).
    let (gpu, params) = device_and_params();
    let (small, small_queue) = device_with_binding(&gpu, 16 << 10);
    let mut sim = scene_with_blades_to(3.0);
    for _ in 0..20 {
        sim.step(1.0 / 60.0).unwrap();
    }
    let mut pieces = Renderer::new(&small, &small_queue, &sim, params).unwrap();
    let cut = pieces.draw(&small, &small_queue, &sim);
    let in_pieces = pieces.read_frame(&small, &small_queue).unwrap();
    let (device, queue) = (&gpu.device, &gpu.queue);
    let mut whole = Renderer::new(device, queue, &sim, params).unwrap();
    let all = whole.draw(device, queue, &sim);
    let one = whole.read_frame(device, queue).unwrap();
    eprintln!("whole: {all:?}\nin pieces: {cut:?}");
    assert_eq!((all.blade_chunks, all.billboard_pieces), (1, 1));
    assert!(
        cut.blade_chunks >= 2 && cut.billboard_pieces >= 2,
        "{cut:?}"
    );
    assert_eq!((cut.blades, cut.billboards), (all.blades, all.billboards));
    assert!(all.blades > 100 && all.billboards > 341, "{all:?}");
    let differing = in_pieces
        .pixels()
        .zip(one.pixels())
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(differing, 0, "{differing} pixels differ");
}
