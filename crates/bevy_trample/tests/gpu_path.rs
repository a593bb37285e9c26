//! The field on trample's GPU path with Bevy's own render device
//! (`TrampleField::on_gpu`, feature `gpu`): a sphere moved by a system
//! leaves the same track as on the CPU path (DESIGN §7's parity, 1e-3 m),
//! the draws get the GPU's buffers, and a field the device cannot take
//! stays on the CPU path and says why.
//!
//! These tests need a Vulkan adapter (Bevy 0.19's wgpu is built without
//! GL here): lavapipe on CI (`.ci/run` installs it), a GPU elsewhere. No
//! adapter fails them; they never skip.

use bevy::prelude::*;
use bevy::render::RenderPlugin;
use bevy::render::renderer::{RenderAdapterInfo, RenderDevice, RenderQueue};
use bevy::render::settings::{Backends, RenderCreation, WgpuLimits, WgpuSettings};
use bevy::time::TimeUpdateStrategy;
use bevy::winit::WinitPlugin;
use bevy_trample::{TrampleBackend, TrampleField, TramplePlugin, TrampleSystems, Trampler};
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

/// 12.8 × 12.8 m of grass (16,384 blades), the paper's lasting track.
fn field() -> TrampleField {
    let builder = SimulationBuilder::new()
        .field(FieldParams {
            patches: [8, 8],
            cells_per_patch: 16,
            ..FieldParams::default()
        })
        .lod(LodParams {
            geometry_m: 30.0,
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
    let mut app = App::new();
    match render {
        Some(constrained_limits) => {
            app.add_plugins(
                DefaultPlugins
                    .set(WindowPlugin {
                        primary_window: None,
                        exit_condition: bevy::window::ExitCondition::DontExit,
                        close_when_requested: false,
                        ..default()
                    })
                    .set(RenderPlugin {
                        render_creation: RenderCreation::from(WgpuSettings {
                            backends: Some(Backends::VULKAN),
                            constrained_limits,
                            ..default()
                        }),
                        synchronous_pipeline_compilation: true,
                        ..default()
                    })
                    .disable::<WinitPlugin>(),
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

#[test]
fn a_sphere_on_the_gpu_path_leaves_the_cpu_paths_track() {
    let mut gpu = app(field().on_gpu(), Some(None));
    wait_for_device(&mut gpu);
    let mut cpu = app(field(), None);
    // As many simulated steps on each: time, not updates, decides.
    let steps = |app: &App| (app.world().resource::<TrampleField>().sim.time / DT).round() as usize;
    while steps(&gpu) < FRAMES {
        gpu.update();
    }
    while steps(&cpu) < steps(&gpu) {
        cpu.update();
    }
    assert_eq!(steps(&cpu), steps(&gpu));
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
    assert!(
        on_gpu.gpu_draw_buffers().is_some(),
        "the draws get the GPU's buffers"
    );
    // Until read back, the CPU side keeps the blades as handed over.
    let before = pressed(&on_gpu);
    on_gpu.read_back_gpu(&device, &queue).expect("read back");
    let on_cpu = cpu.world().resource::<TrampleField>();
    let (track_gpu, track_cpu) = (pressed(&on_gpu), pressed(on_cpu));
    let worst = largest_difference(&on_gpu, on_cpu);
    eprintln!(
        "{} steps: pressed blades GPU {track_gpu} (before the read-back {before}), CPU {track_cpu}; largest difference {worst:.2e} m",
        steps(&cpu)
    );
    assert!(track_cpu > 100, "the sphere pressed {track_cpu} blades");
    assert!(before < track_gpu, "the read-back brought the GPU's track");
    assert!(
        worst <= PARITY_M,
        "GPU and CPU paths {worst} m apart (DESIGN §7: {PARITY_M} m)"
    );
}

#[test]
fn a_field_the_device_cannot_take_stays_on_the_cpu_path_and_says_why() {
    // A device with WebGPU's default limits (8 storage buffers a shader
    // stage): the step's stages bind more. Then one with enough of them but
    // a storage binding of 256 KiB: the field's 16,384 blades × 5 vertices
    // × 16 bytes (1.3 MiB) would need chunks, and the draws bind one.
    let few_buffers = WgpuLimits::default();
    let small_binding = WgpuLimits {
        max_storage_buffers_per_shader_stage: 16,
        max_storage_buffer_binding_size: 256 << 10,
        ..WgpuLimits::default()
    };
    for (limits, words) in [
        (few_buffers, ["storage buffers", "required_limits"]),
        (small_binding, ["16384 blades", "chunks"]),
    ] {
        let mut app = app(field().on_gpu(), Some(Some(limits)));
        wait_for_device(&mut app);
        for _ in 0..FRAMES {
            app.update();
        }
        let field = app.world().resource::<TrampleField>();
        let why = field.gpu_refused().expect("refused");
        assert!(words.iter().all(|w| why.contains(w)), "{why}");
        assert_eq!(field.backend(), TrampleBackend::Cpu);
        assert!(field.gpu_draw_buffers().is_none());
        // The CPU path went on with the same simulation: the sphere's track.
        assert!(pressed(field) > 100, "{} blades pressed", pressed(field));
    }
}
