//! The field on trample's GPU path with Bevy's own render device
//! (`TrampleField::on_gpu`, feature `gpu`): a sphere moved by a system
//! leaves the same track as on the CPU path (DESIGN §7's parity, 1e-3 m),
//! in one chunk of blade vertices or in several; the frame drawn from the
//! GPU's buffers (one indirect draw a chunk) is the CPU path's frame, and
//! so is the CPU path's frame drawn in chunks (a device whose binding is
//! under the field's vertices), without and with the grass's shadows
//! (`GrassLook::cast_shadows`), whose shadows point and spot lights cast
//! too; and a field the device cannot take stays on the CPU path and says
//! why.
//!
//! These tests need a Vulkan adapter (Bevy 0.19's wgpu is built without
//! GL here): lavapipe on CI (`.ci/run` installs it), a GPU elsewhere. No
//! adapter fails them; they never skip.

use bevy::camera::RenderTarget;
use bevy::prelude::*;
use bevy::render::pipelined_rendering::PipelinedRenderingPlugin;
use bevy::render::render_resource::{TextureFormat, TextureUsages};
use bevy::render::renderer::{RenderAdapterInfo, RenderDevice, RenderQueue};
use bevy::render::settings::{Backends, RenderCreation, WgpuFeatures, WgpuLimits, WgpuSettings};
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};
use bevy::render::{RenderApp, RenderPlugin};
use bevy::time::TimeUpdateStrategy;
use bevy::winit::WinitPlugin;
use bevy_trample::render::gpu::GrassGpu;
use bevy_trample::render::look::GrassLook;
use bevy_trample::{
    TrampleBackend, TrampleCamera, TrampleField, TramplePlugin, TrampleSystems, Trampler,
};
use std::sync::{Arc, Mutex};
use std::time::Duration;
use trample::builder::SimulationBuilder;
use trample::field::{FieldParams, LodParams};
use trample::step::SimParams;

/// Frame and fixed step: 1/60 s, one simulation step an update.
const DT: f64 = 1.0 / 60.0;
/// The sphere: radius, centre height, speed along +x (m, m/s), start x.
const RADIUS: f32 = 0.3;
const CENTRE_Y: f32 = 0.25;
const SPEED: f32 = 4.0;
const START_X: f32 = -4.0;
/// Steps compared: the sphere crosses 4 m of the field.
const FRAMES: usize = 60;
/// DESIGN §7: the GPU path within 1e-3 m of the CPU path.
const PARITY_M: f32 = 1e-3;
/// The frames compared: pixels.
const FRAME: [u32; 2] = [320, 180];

/// A storage binding of `kib` KiB (and enough storage buffers a stage).
fn binding_of(kib: u64) -> WgpuLimits {
    WgpuLimits {
        max_storage_buffers_per_shader_stage: 16,
        max_storage_buffer_binding_size: kib << 10,
        ..WgpuLimits::default()
    }
}

/// A storage binding of 768 KiB: the field's largest whole-field array
/// (its billboard list, 48 bytes a cell) just fits, and its 16,384 blades
/// × 5 vertices × 16 bytes (1.25 MiB) go in two chunks of patches.
fn small_binding() -> WgpuLimits {
    binding_of(768)
}

/// 12.8 × 12.8 m of grass (16,384 blades), the paper's lasting track,
/// blades to 30 m (all of them).
fn field() -> TrampleField {
    field_with_blades_to(30.0)
}

/// The same field drawn as blades to `geometry_m`, billboards beyond.
fn field_with_blades_to(geometry_m: f32) -> TrampleField {
    let builder = SimulationBuilder::new()
        .field(FieldParams {
            patches: [8, 8],
            cells_per_patch: 16,
            ..FieldParams::default()
        })
        .lod(LodParams {
            geometry_m,
            billboard_m: 40.0,
        })
        .sim(SimParams {
            recovery_s: f32::INFINITY,
            ..SimParams::default()
        });
    TrampleField::from_builder(&builder).expect("test field")
}

#[derive(Component)]
struct Mover;

fn drive(time: Res<Time>, mut movers: Query<&mut Transform, With<Mover>>) {
    for mut t in &mut movers {
        t.translation.x += SPEED * time.delta_secs();
    }
}

/// The plugin with a sphere trampler, on Bevy's renderer (no window) when
/// `render` is given (its limits constrained to `limits`), else headless.
fn app(field: TrampleField, render: Option<Option<WgpuLimits>>) -> App {
    app_on(
        field,
        render.map(|constrained_limits| WgpuSettings {
            backends: Some(Backends::VULKAN),
            constrained_limits,
            ..default()
        }),
    )
}

/// [`app`] on a renderer made with `settings` (Vulkan), else headless.
fn app_on(field: TrampleField, settings: Option<WgpuSettings>) -> App {
    let mut app = App::new();
    match settings {
        Some(settings) => {
            app.add_plugins(
                DefaultPlugins
                    .set(WindowPlugin {
                        primary_window: None,
                        exit_condition: bevy::window::ExitCondition::DontExit,
                        close_when_requested: false,
                        ..default()
                    })
                    .set(RenderPlugin {
                        render_creation: RenderCreation::from(settings),
                        synchronous_pipeline_compilation: true,
                        ..default()
                    })
                    .disable::<WinitPlugin>()
                    // The render world stays in the app (its buffers are
                    // looked at), rendering each update in turn.
                    .disable::<PipelinedRenderingPlugin>(),
            );
        }
        None => {
            app.add_plugins((MinimalPlugins, AssetPlugin::default(), TransformPlugin))
                .init_asset::<Mesh>();
        }
    }
    app.add_plugins(TramplePlugin)
        .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(
            DT,
        )))
        .insert_resource(Time::<Fixed>::from_seconds(DT))
        .insert_resource(field)
        .add_systems(FixedUpdate, drive.before(TrampleSystems::Step));
    let mesh = app
        .world_mut()
        .resource_mut::<Assets<Mesh>>()
        .add(Sphere::new(RADIUS).mesh().ico(3).expect("icosphere"));
    app.world_mut().spawn((
        Mesh3d(mesh),
        Transform::from_xyz(START_X, CENTRE_Y, 0.0),
        Trampler::default(),
        Mover,
    ));
    app
}

/// Runs `app` until Bevy's renderer has made its device (a few updates),
/// failing when it does not (no Vulkan adapter).
fn wait_for_device(app: &mut App) {
    app.finish();
    app.cleanup();
    for _ in 0..600 {
        if app.world().contains_resource::<RenderDevice>() {
            let info = app.world().resource::<RenderAdapterInfo>();
            eprintln!("adapter: {} ({:?})", info.name, info.backend);
            return;
        }
        std::thread::sleep(Duration::from_millis(10));
        app.update();
    }
    panic!(
        "Bevy made no render device: these tests need a Vulkan adapter (lavapipe: apt-get install mesa-vulkan-drivers libvulkan1)"
    );
}

/// The largest distance between the two fields' blade vertices, metres.
fn largest_difference(a: &TrampleField, b: &TrampleField) -> f32 {
    let (a, b) = (&a.sim.field.blades.pos, &b.sim.field.blades.pos);
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(p, q)| {
            let (p, q) = (glam::Vec3::from_array(p.pos), glam::Vec3::from_array(q.pos));
            p.distance(q)
        })
        .fold(0.0, f32::max)
}

/// Blades whose tip is more than 5 cm below rest.
fn pressed(field: &TrampleField) -> usize {
    let bl = &field.sim.field.blades;
    (0..bl.count).filter(|&b| bl.tip_lowering(b) > 0.05).count()
}

/// The steps `app`'s field has taken: its simulated time over `DT`.
fn steps_taken(app: &App) -> usize {
    (app.world().resource::<TrampleField>().sim.time / DT).round() as usize
}

/// Runs `gpu` (on the GPU path) and `cpu` (on the CPU path) to the same
/// simulated time, at least `FRAMES` steps; returns the steps.
fn run_both(gpu: &mut App, cpu: &mut App) -> usize {
    while steps_taken(gpu) < FRAMES {
        gpu.update();
    }
    while steps_taken(cpu) < steps_taken(gpu) {
        cpu.update();
    }
    assert_eq!(steps_taken(cpu), steps_taken(gpu));
    steps_taken(cpu)
}

/// The GPU path against the CPU path on a device with `limits` (None:
/// the adapter's), `chunks` chunks of blade vertices expected.
fn parity(limits: Option<WgpuLimits>, chunks: usize) {
    let mut gpu = app(field().on_gpu(), Some(limits));
    wait_for_device(&mut gpu);
    let mut cpu = app(field(), None);
    let steps = run_both(&mut gpu, &mut cpu);
    let world = gpu.world_mut();
    let (device, queue) = (
        world.resource::<RenderDevice>().clone(),
        world.resource::<RenderQueue>().clone(),
    );
    let mut on_gpu = world.resource_mut::<TrampleField>();
    assert_eq!(
        on_gpu.backend(),
        TrampleBackend::Gpu,
        "{:?}",
        on_gpu.gpu_refused()
    );
    let buffers = on_gpu
        .gpu_draw_buffers()
        .expect("the draws get the GPU's buffers");
    assert_eq!(buffers.chunks.len(), chunks);
    // Until read back, the CPU side keeps the blades as handed over.
    let before = pressed(&on_gpu);
    on_gpu.read_back_gpu(&device, &queue).expect("read back");
    let on_cpu = cpu.world().resource::<TrampleField>();
    let (track_gpu, track_cpu) = (pressed(&on_gpu), pressed(on_cpu));
    let worst = largest_difference(&on_gpu, on_cpu);
    eprintln!(
        "{steps} steps, {chunks} chunk(s): pressed blades GPU {track_gpu} (before the read-back {before}), CPU {track_cpu}; largest difference {worst:.2e} m"
    );
    assert!(track_cpu > 100, "the sphere pressed {track_cpu} blades");
    assert!(before < track_gpu, "the read-back brought the GPU's track");
    assert!(
        worst <= PARITY_M,
        "GPU and CPU paths {worst} m apart (DESIGN §7: {PARITY_M} m)"
    );
}

#[test]
fn a_sphere_on_the_gpu_path_leaves_the_cpu_paths_track() {
    parity(None, 1);
}

#[test]
fn a_field_in_chunks_on_the_gpu_path_leaves_the_cpu_paths_track() {
    parity(Some(small_binding()), 2);
}

#[test]
fn a_field_the_device_cannot_take_stays_on_the_cpu_path_and_says_why() {
    // A device with WebGPU's default limits (8 storage buffers a shader
    // stage): the step's stages bind more. A storage binding of 512 KiB
    // less 4 bytes: the cells' rest boxes (32 bytes a cell, 512 KiB) are
    // one array of the step. 767 KiB: the step's arrays fit, the draw
    // lists' billboards (48 bytes a cell, 768 KiB) do not. 96 KiB: the
    // rest boxes again, and the CPU path's draws cannot bind the blades'
    // shapes (8 bytes a blade, 128 KiB) either.
    // On the CPU path the blade vertices (1.25 MiB) are drawn in chunks of
    // whole patches (20 KiB a patch): 1 on WebGPU's 128 MiB, 3 of 25
    // patches at 512 KiB, 2 at 767 KiB; none drawn at 96 KiB.
    let mut rest_boxes = binding_of(512);
    rest_boxes.max_storage_buffer_binding_size -= 4;
    for (limits, words, drawn_chunks) in [
        (
            WgpuLimits::default(),
            ["storage buffers", "required_limits"],
            Some(1),
        ),
        (rest_boxes, ["rest boxes", "524288 bytes"], Some(3)),
        (
            binding_of(767),
            ["billboard instances", "786432 bytes"],
            Some(2),
        ),
        (binding_of(96), ["rest boxes", "524288 bytes"], None),
    ] {
        let mut app = app(field().on_gpu(), Some(Some(limits)));
        wait_for_device(&mut app);
        for _ in 0..FRAMES - 3 {
            app.update();
        }
        // A camera for the last frames: the draws are queued and drawn (or
        // skip, when the field is not drawn).
        add_camera(&mut app, true);
        for _ in 0..3 {
            app.update();
        }
        let field = app.world().resource::<TrampleField>();
        let why = field.gpu_refused().expect("refused");
        eprintln!("refused: {why}");
        assert!(words.iter().all(|w| why.contains(w)), "{why}");
        assert_eq!(field.backend(), TrampleBackend::Cpu);
        assert!(field.gpu_draw_buffers().is_none());
        // The CPU path went on with the same simulation: the sphere's track.
        assert!(pressed(field) > 100, "{} blades pressed", pressed(field));
        let drawn = app
            .sub_app(RenderApp)
            .world()
            .get_resource::<GrassGpu>()
            .map(|g| g.chunks.len());
        assert_eq!(drawn, drawn_chunks, "{why}");
    }
}

/// Adds a camera (the trample camera) drawing into an image of `FRAME`
/// pixels, looking at the sphere's track, and a sun that casts shadows
/// (the grass's own with `GrassLook::cast_shadows`, in one cascade of 1024
/// × 1024 texels: Bevy's four of 2048 would cost a software rasteriser
/// sixteen times the texels); returns the image. The camera draws when
/// `drawing`, else from [`draw_frames`] on.
fn add_camera(app: &mut App, drawing: bool) -> Handle<Image> {
    let handle = add_camera_alone(app, drawing);
    app.insert_resource(bevy::light::DirectionalLightShadowMap { size: 1024 });
    app.world_mut().spawn((
        DirectionalLight {
            shadow_maps_enabled: true,
            ..default()
        },
        bevy::light::CascadeShadowConfigBuilder {
            num_cascades: 1,
            maximum_distance: 20.0,
            ..default()
        }
        .build(),
        Transform::from_xyz(2.0, 5.0, 3.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    handle
}

/// The camera of [`add_camera`] without its sun.
fn add_camera_alone(app: &mut App, drawing: bool) -> Handle<Image> {
    let mut image =
        Image::new_target_texture(FRAME[0], FRAME[1], TextureFormat::Rgba8UnormSrgb, None);
    image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    let handle = app.world_mut().resource_mut::<Assets<Image>>().add(image);
    app.world_mut().spawn((
        Camera3d::default(),
        // Without Bevy's `tonemapping_luts` feature (the default tone
        // mapping's table) the frame would be magenta.
        bevy::core_pipeline::tonemapping::Tonemapping::Reinhard,
        RenderTarget::from(handle.clone()),
        Camera {
            is_active: drawing,
            ..default()
        },
        Transform::from_xyz(-1.0, 3.0, 5.0).looking_at(Vec3::new(-1.0, 0.0, 0.0), Vec3::Y),
        TrampleCamera,
    ));
    handle
}

/// Turns the drawing of `app`'s cameras on or off.
fn draw_frames(app: &mut App, drawing: bool) {
    let mut cameras = app.world_mut().query::<&mut Camera>();
    for mut camera in cameras.iter_mut(app.world_mut()) {
        camera.is_active = drawing;
    }
}

/// The image `app`'s camera draws now (RGBA8). With `idle`, the cameras
/// draw two frames and then idle while the screenshot comes back (an
/// update later) and after: each frame drawn costs a software rasteriser
/// about a second. (Not where lights come and go: a spot light spawned
/// after the cameras idled was not drawn in the next three frames.)
fn capture(app: &mut App, image: &Handle<Image>, idle: bool) -> Vec<u8> {
    draw_frames(app, true);
    let got: Arc<Mutex<Option<Vec<u8>>>> = Arc::default();
    let slot = got.clone();
    app.world_mut()
        .spawn(Screenshot::image(image.clone()))
        .observe(move |shot: On<ScreenshotCaptured>| {
            *slot.lock().expect("slot") = shot.image.data.clone();
        });
    for frame in 0..100 {
        app.update();
        if let Some(pixels) = got.lock().expect("slot").take() {
            return pixels;
        }
        if idle && frame == 1 {
            draw_frames(app, false);
        }
    }
    panic!("no screenshot after 100 frames");
}

/// Pixels whose colour differs by more than 8 (of 255) in some channel,
/// and the mean difference over all channels.
fn compare(a: &[u8], b: &[u8]) -> (usize, f64) {
    assert_eq!(a.len(), b.len());
    let differing = a
        .chunks(4)
        .zip(b.chunks(4))
        .filter(|(p, q)| p.iter().zip(*q).any(|(x, y)| x.abs_diff(*y) > 8))
        .count();
    let sum: u64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| u64::from(x.abs_diff(*y)))
        .sum();
    (differing, sum as f64 / a.len() as f64)
}

/// Blades to 4 m from the eye, billboards beyond (fading in over the
/// default 4 m band): the camera of `add_camera` (3 m up, 5 m from its
/// target) sees blades alone in its lowest rows (the ground 3.7 to 4 m
/// away) and billboards alone past 8 m (rows 26 to 56, where the field
/// ends; the blades' shadows fall 1.5 m at most from them).
fn frame_field() -> TrampleField {
    field_with_blades_to(4.0)
}

/// The frames of `apps` (on the renderer), each without and then with
/// `GrassLook::cast_shadows` (a sun that casts shadows in both), after
/// `FRAMES` steps; saved as `{prefix}_{name}.png` and
/// `{prefix}_shadows_{name}.png`.
fn frames_without_and_with_shadows(
    apps: &mut [&mut App],
    prefix: &str,
    names: &[&str],
) -> (Vec<Vec<u8>>, Vec<Vec<u8>>) {
    let (mut plain, mut shaded) = (Vec::new(), Vec::new());
    for app in apps.iter_mut() {
        wait_for_device(app);
        // The camera for the last few steps (the field's levels of detail
        // and drawn lists are its), drawing only once paused: each frame
        // costs a software rasteriser seconds.
        while steps_taken(app) < FRAMES - 5 {
            app.update();
        }
        let image = add_camera(app, false);
        while steps_taken(app) < FRAMES {
            app.update();
        }
        // Paused: the GPU path's ground track, copied back a frame or two
        // behind the grass, catches up (the cameras idle); then the frames.
        app.world_mut().resource_mut::<Time<Virtual>>().pause();
        for _ in 0..2 {
            app.update();
        }
        plain.push(capture(app, &image, true));
        app.world_mut().resource_mut::<GrassLook>().cast_shadows = true;
        shaded.push(capture(app, &image, true));
        assert_eq!(steps_taken(app), FRAMES);
    }
    save_frames(prefix, names, &plain);
    save_frames(&format!("{prefix}_shadows"), names, &shaded);
    (plain, shaded)
}

/// Each of `frames` (after the first) against the first, the CPU path's:
/// at most one pixel in a thousand differs, and little.
fn same_frames(frames: &[Vec<u8>], names: &[&str], shadows: &str) {
    let pixels = (FRAME[0] * FRAME[1]) as usize;
    for (name, frame) in names.iter().zip(frames).skip(1) {
        let (differing, mean) = compare(&frames[0], frame);
        eprintln!(
            "{name} against the CPU path, {shadows} grass shadows: {differing} of {pixels} pixels differ, mean difference {mean:.3}"
        );
        assert!(
            differing * 1000 <= pixels && mean < 0.25,
            "{name}, {shadows} grass shadows: {differing} of {pixels} pixels differ (mean {mean:.3})"
        );
    }
}

/// The frames of the CPU path, the GPU path in one chunk and the GPU path
/// in two (one indirect draw a chunk), without and with the grass's
/// shadows: the GPU path's frames are the CPU path's.
#[test]
fn the_frames_drawn_from_the_gpus_buffers_are_the_cpu_paths_with_and_without_grass_shadows() {
    let mut cpu = app(frame_field(), Some(None));
    let mut gpu = app(frame_field().on_gpu(), Some(None));
    let mut chunked = app(frame_field().on_gpu(), Some(Some(small_binding())));
    let names = ["cpu", "gpu", "gpu_chunks"];
    let (plain, shaded) = frames_without_and_with_shadows(
        &mut [&mut cpu, &mut gpu, &mut chunked],
        "bevy_trample_gpu_path",
        &names,
    );
    let on = |app: &App| app.world().resource::<TrampleField>().backend();
    assert_eq!(
        [on(&cpu), on(&gpu), on(&chunked)],
        [
            TrampleBackend::Cpu,
            TrampleBackend::Gpu,
            TrampleBackend::Gpu
        ]
    );
    let names = ["CPU path", "GPU path, one chunk", "GPU path, two chunks"];
    same_frames(&plain, &names, "without");
    same_frames(&shaded, &names, "with");
}

/// The CPU path's frames, and those of the CPU path on a binding of 256
/// KiB, Bevy's own least (its uploads in chunks of 12 patches, one draw a
/// chunk; its billboards in pieces of 5,461), and on a device without
/// unclipped depth (the shadows' depth clamped in the vertex stages
/// instead), without and with `GrassLook::cast_shadows`: the same frames.
/// With shadows, the grass drawn into the sun's shadow map darkens the
/// frame (blades and billboards shade the ground and each other), where
/// blades are drawn and where only billboards are, and brightens nothing.
#[test]
fn the_grass_casts_shadows_and_the_frames_drawn_in_chunks_or_clamped_are_the_cpu_paths() {
    let clipped = WgpuSettings {
        backends: Some(Backends::VULKAN),
        disabled_features: Some(WgpuFeatures::DEPTH_CLIP_CONTROL),
        ..default()
    };
    let mut cpu = app(frame_field(), Some(None));
    let mut cpu_chunked = app(frame_field(), Some(Some(binding_of(256))));
    let mut clamped = app_on(frame_field(), Some(clipped));
    let names = ["cpu", "cpu_chunks", "clamped"];
    let (plain, shaded) = frames_without_and_with_shadows(
        &mut [&mut cpu, &mut cpu_chunked, &mut clamped],
        "bevy_trample_grass",
        &names,
    );
    // The last device has no unclipped depth: the clamped vertex stages.
    let unclipped = |app: &mut App| {
        app.sub_app(RenderApp)
            .world()
            .resource::<bevy::pbr::PrepassPipeline>()
            .depth_clip_control_supported
    };
    eprintln!("the adapter's unclipped depth: {}", unclipped(&mut cpu));
    assert!(!unclipped(&mut clamped));
    // The CPU path's vertices: one buffer on the adapter's limits, six
    // chunks of patches on the small binding; its billboards one piece, or
    // several.
    let chunks = |app: &mut App| {
        let gpu = app.sub_app(RenderApp).world().resource::<GrassGpu>();
        (
            gpu.chunk_blades.clone(),
            gpu.drawn.clone(),
            gpu.billboard_counts.clone(),
        )
    };
    let (whole, _, billboards) = chunks(&mut cpu);
    assert_eq!((whole.len(), whole.first()), (1, Some(&(0..16_384))));
    assert_eq!(billboards.len(), 1);
    let (cut, drawn, pieces) = chunks(&mut cpu_chunked);
    eprintln!(
        "CPU path on 256 KiB: {} chunks, blade instances {drawn:?}; billboards {billboards:?} in pieces {pieces:?}",
        cut.len()
    );
    assert_eq!(cut.len(), 6, "{cut:?}");
    assert!(
        drawn.iter().filter(|d| !d.is_empty()).count() >= 2,
        "blades from several chunks: {drawn:?}"
    );
    assert!(pieces.len() >= 2, "billboards in pieces: {pieces:?}");
    assert_eq!(pieces.iter().sum::<u32>(), billboards[0]);
    let pixels = (FRAME[0] * FRAME[1]) as usize;
    // Grass fills the lower part of the frame: the frames are not empty.
    let green = plain[0]
        .chunks(4)
        .filter(|p| p[1] > p[0] && p[1] > p[2])
        .count();
    assert!(green > pixels / 3, "{green} of {pixels} pixels green");
    let names = ["CPU path", "CPU path, in chunks", "no unclipped depth"];
    same_frames(&plain, &names, "without");
    same_frames(&shaded, &names, "with");
    // Pixels of `rows` darker and brighter with the grass's shadows than
    // without.
    let row = 4 * FRAME[0] as usize;
    let changed = |rows: std::ops::Range<usize>| {
        darker_and_brighter(
            &plain[0][rows.start * row..rows.end * row],
            &shaded[0][rows.start * row..rows.end * row],
        )
    };
    let (darker, brighter) = changed(0..FRAME[1] as usize);
    eprintln!("grass shadows: {darker} of {pixels} pixels darker, {brighter} brighter");
    assert!(darker > pixels / 10, "{darker} of {pixels} pixels darker");
    assert!(
        brighter * 100 <= pixels,
        "{brighter} of {pixels} pixels brighter"
    );
    // Where only blades are drawn, and where only billboards are.
    for (name, rows) in [("blades", 162..180), ("billboards", 30..52)] {
        let (darker, _) = changed(rows.clone());
        let of = rows.len() * FRAME[0] as usize;
        eprintln!("{name}' rows {rows:?}: {darker} of {of} pixels darker");
        assert!(darker * 10 > of, "{name}: {darker} of {of} pixels darker");
    }
}

/// Pixels darker and brighter in `on` than in `off` (by more than 24 in
/// the sum of R, G and B).
fn darker_and_brighter(off: &[u8], on: &[u8]) -> (usize, usize) {
    let luma = |p: &[u8]| u32::from(p[0]) + u32::from(p[1]) + u32::from(p[2]);
    let (mut darker, mut brighter) = (0, 0);
    for (off, on) in off.chunks(4).zip(on.chunks(4)) {
        let (a, b) = (luma(off), luma(on));
        darker += usize::from(b + 24 < a);
        brighter += usize::from(a + 24 < b);
    }
    (darker, brighter)
}

/// A light that casts shadows over the track: `"point"`, 2.5 m above it,
/// else a spot light from 4 m, aimed at the camera's target.
fn spawn_light(world: &mut World, kind: &str) -> Entity {
    if kind == "point" {
        return world
            .spawn((
                PointLight {
                    intensity: 4.0e6,
                    range: 20.0,
                    shadow_maps_enabled: true,
                    ..default()
                },
                Transform::from_xyz(0.0, 2.5, 1.0),
            ))
            .id();
    }
    world
        .spawn((
            SpotLight {
                intensity: 8.0e6,
                range: 20.0,
                outer_angle: 0.9,
                inner_angle: 0.6,
                shadow_maps_enabled: true,
                ..default()
            },
            Transform::from_xyz(1.0, 4.0, 2.0).looking_at(Vec3::new(-1.0, 0.0, 0.0), Vec3::Y),
        ))
        .id()
}

/// A point light (its six cube faces) and a spot light cast the grass's
/// shadows too, as the sun does: each alone over the field (no sun), the
/// frame without and with `GrassLook::cast_shadows` — their shadow views
/// are perspective ones, with no depth clamp. The frame is lit (not black),
/// the grass's shadows darken a good part of it, and brighten nothing.
#[test]
fn point_and_spot_lights_cast_the_grass_shadows() {
    let mut app = app(frame_field(), Some(None));
    wait_for_device(&mut app);
    while steps_taken(&app) < FRAMES {
        app.update();
    }
    app.world_mut().resource_mut::<Time<Virtual>>().pause();
    let image = add_camera_alone(&mut app, true);
    let pixels = (FRAME[0] * FRAME[1]) as usize;
    for name in ["point", "spot"] {
        let light = spawn_light(app.world_mut(), name);
        app.world_mut().resource_mut::<GrassLook>().cast_shadows = false;
        let off = capture(&mut app, &image, false);
        app.world_mut().resource_mut::<GrassLook>().cast_shadows = true;
        let on = capture(&mut app, &image, false);
        app.world_mut().despawn(light);
        save_frames(
            &format!("bevy_trample_{name}_light"),
            &["without", "with"],
            &[off.clone(), on.clone()],
        );
        let lit = off
            .chunks(4)
            .filter(|p| u32::from(p[0]) + u32::from(p[1]) + u32::from(p[2]) > 60)
            .count();
        let (darker, brighter) = darker_and_brighter(&off, &on);
        eprintln!(
            "{name} light: {lit} of {pixels} pixels lit; grass shadows: {darker} darker, {brighter} brighter"
        );
        assert!(
            lit > pixels / 3,
            "{name} light: {lit} of {pixels} pixels lit"
        );
        assert!(
            darker > pixels / 20,
            "{name} light: {darker} of {pixels} pixels darker"
        );
        assert!(
            brighter * 100 <= pixels,
            "{name} light: {brighter} of {pixels} pixels brighter"
        );
    }
}

/// Writes the frames to the temporary folder as `{prefix}_{name}.png`, to
/// look at, and prints their paths.
fn save_frames(prefix: &str, names: &[&str], frames: &[Vec<u8>]) {
    let dir = std::env::temp_dir();
    for (name, frame) in names.iter().zip(frames) {
        let path = dir.join(format!("{prefix}_{name}.png"));
        image::save_buffer(
            &path,
            frame,
            FRAME[0],
            FRAME[1],
            image::ExtendedColorType::Rgba8,
        )
        .expect("frame written");
        eprintln!("{}", path.display());
    }
}
