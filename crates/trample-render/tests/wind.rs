//! Wind (DESIGN §6, ours) is drawn at draw time: a steady wind along +x
//! leans the blades towards +x on screen (the green of the `classes` view
//! moves right), gusts make the picture change with time, and the
//! simulation state is not touched. Runs on the adapter of `WGPU_BACKEND`;
//! no adapter = failure.

mod common;

use trample::Simulation;
use trample::scene::Scene;
use trample::wind::WindParams;
use trample_render::{DebugView, RenderParams, Renderer};

const W: u32 = 200;
const H: u32 = 120;

/// A 1.6 m field of blades, all geometry, seen from the side (+z, looking
/// towards −z): +x is to the right of the picture.
fn scene() -> Simulation {
    let toml = format!(
        r#"
[field]
patches = [2, 2]
cells_per_patch = 8
blades_per_cell = 4
cell_size_m = 0.1
[lod]
geometry_m = 50.0
billboard_m = 60.0
[camera]
path = {{ kind = "static", position = [0.0, 0.45, 1.6] }}
look_at = {{ kind = "point", at = [0.0, 0.15, 0.0] }}
aspect = {aspect}
"#,
        aspect = W as f32 / H as f32
    );
    Scene::parse(&toml, "wind.toml", std::path::Path::new("."))
        .unwrap()
        .build()
        .unwrap()
}

fn render(sim: &Simulation, debug: DebugView) -> image::RgbaImage {
    let gpu = trample_render::headless::create_device()
        .unwrap_or_else(|e| panic!("the wind test needs an adapter: {e}"));
    let params = RenderParams {
        // The simulated blades alone: the near copies (render density)
        // carry the same leaning shape but fill this close-up with green,
        // which would blur the centroid the test reads.
        near_density: 1,
        ..common::test_params(&gpu, W, H, debug)
    };
    Renderer::new(&gpu.device, &gpu.queue, sim, params)
        .unwrap()
        .render(&gpu.device, &gpu.queue, sim)
        .unwrap()
}

/// Mean x of the untouched-blade green of the `classes` view, and how many
/// such pixels there are.
fn green_centroid(img: &image::RgbaImage) -> (f64, usize) {
    let (mut sum, mut n) = (0.0, 0usize);
    for (x, _, p) in img.enumerate_pixels() {
        let [r, g, b] = [p[0], p[1], p[2]].map(u16::from);
        if g > 40 && g > 2 * r && g > 2 * b {
            sum += f64::from(x);
            n += 1;
        }
    }
    (sum / n.max(1) as f64, n)
}

fn differing_pixels(a: &image::RgbaImage, b: &image::RgbaImage) -> usize {
    a.pixels()
        .zip(b.pixels())
        .filter(|(p, q)| (0..3).any(|c| p[c].abs_diff(q[c]) > 24))
        .count()
}

#[test]
fn steady_wind_leans_the_drawn_blades_downwind_and_leaves_the_state_alone() {
    let calm = scene();
    let mut windy = scene();
    windy.wind = WindParams {
        strength_m: 0.3,
        ..WindParams::default()
    };
    let (c0, n0) = green_centroid(&render(&calm, DebugView::Classes));
    let (c1, n1) = green_centroid(&render(&windy, DebugView::Classes));
    assert!(n0 > 1000 && n1 > 1000, "blade pixels: {n0}, {n1}");
    assert!(
        c1 - c0 > 3.0,
        "green centroid x: calm {c0:.1}, wind +x {c1:.1}"
    );
    // Blowing the other way leans them the other way.
    windy.wind.direction_deg = 180.0;
    let (c2, _) = green_centroid(&render(&windy, DebugView::Classes));
    assert!(
        c0 - c2 > 3.0,
        "green centroid x: calm {c0:.1}, wind −x {c2:.1}"
    );
    // Draw time only: the blades the simulation holds are at rest.
    assert_eq!(windy.blade_vertices(), calm.blade_vertices());
}

#[test]
fn gusts_change_the_picture_with_time_and_calm_does_not() {
    let mut sim = scene();
    let a = render(&sim, DebugView::None);
    sim.time = 0.75;
    let b = render(&sim, DebugView::None);
    assert_eq!(
        differing_pixels(&a, &b),
        0,
        "calm: time alone changed the picture"
    );
    sim.wind = WindParams {
        gust_m: 0.2,
        gust_period_s: 3.0,
        ..WindParams::default()
    };
    sim.time = 0.0;
    let c = render(&sim, DebugView::None);
    sim.time = 0.75;
    let d = render(&sim, DebugView::None);
    let changed = differing_pixels(&c, &d);
    assert!(changed > 500, "a gust moved only {changed} pixels");
}

/// `wind_tip_offset` in `globals.wgsl` is `trample::wind::tip_offset`: the
/// shared WGSL, run in a compute shader on the globals the renderer makes,
/// gives the Rust formula's offset at roots across the field and instants
/// across a gust period (within 2e-5 m: f32 `sin` of the GPU).
#[test]
fn the_shaders_wind_is_the_cores_formula() {
    use wgpu::util::DeviceExt;
    let gpu = trample_render::headless::create_device()
        .unwrap_or_else(|e| panic!("the wind test needs an adapter: {e}"));
    let (device, queue) = (&gpu.device, &gpu.queue);
    let mut sim = scene();
    sim.wind = WindParams {
        direction_deg: 35.0,
        strength_m: 0.04,
        gust_m: 0.07,
        gust_period_s: 2.5,
        gust_wavelength_m: 6.0,
    };
    let renderer = Renderer::new(device, queue, &sim, RenderParams::default()).unwrap();
    let roots: Vec<[f32; 4]> = (0..64)
        .map(|i| {
            let (x, z) = ((i % 8) as f32 * 1.7 - 6.0, (i / 8) as f32 * 2.3 - 8.0);
            [x, 0.1 * x, z, 0.0]
        })
        .collect();
    let source = trample_render::globals::shader_source(
        "@group(0) @binding(3) var<storage, read> roots: array<vec4<f32>>;
         @group(0) @binding(4) var<storage, read_write> out: array<vec4<f32>>;
         @compute @workgroup_size(64)
         fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
             out[gid.x] = vec4<f32>(wind_tip_offset(roots[gid.x].xyz), 0.0);
         }",
    );
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("wind formula"),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: None,
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let roots_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytemuck::cast_slice(&roots),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let size = (roots.len() * 16) as u64;
    let out = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut worst = 0.0f32;
    for t in [0.0, 0.4, 1.1, 1.9, 3.3] {
        sim.time = t;
        let globals = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: None,
            contents: bytemuck::bytes_of(&renderer.globals_of(&sim)),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: globals.as_entire_binding(),
                },
                // 1 and 2: the shadow map's, declared by globals.wgsl.
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: roots_buf.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: out.as_entire_binding(),
                },
            ],
        });
        let mut enc = device.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(1, 1, 1);
        }
        enc.copy_buffer_to_buffer(&out, 0, &staging, 0, size);
        queue.submit([enc.finish()]);
        staging
            .slice(..)
            .map_async(wgpu::MapMode::Read, |r| r.unwrap());
        device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
        let got: Vec<[f32; 4]> =
            bytemuck::cast_slice(&staging.slice(..).get_mapped_range()).to_vec();
        staging.unmap();
        for (r, g) in roots.iter().zip(&got) {
            let want =
                trample::wind::tip_offset(&sim.wind, glam::Vec3::new(r[0], r[1], r[2]), t as f32);
            let d = (glam::Vec3::new(g[0], g[1], g[2]) - want).length();
            worst = worst.max(d);
            assert!(d < 2e-5, "root {r:?}, t = {t}: shader {g:?}, core {want}");
        }
    }
    // The wind is not calm: the comparison means something.
    assert!(
        trample::wind::tip_offset(&sim.wind, glam::Vec3::ZERO, 0.0).length() > 0.03,
        "worst {worst}"
    );
}
