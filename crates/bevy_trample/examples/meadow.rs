//! A car in the paper's meadow (262,144 blades, 51.2 m square), driven with
//! the arrow keys (up/down: faster/slower, left/right: steer; until a key
//! is pressed it drives a slow curve on its own), a camera following it,
//! Bevy's lighting: a directional light with shadows, ambient light, fog.
//! The car is `scenes/meshes/beetle.obj`; its `Trampler` collides the same
//! mesh it is drawn with. Ahead of it a walker (a skinned mesh: a torso
//! and two legs, three joints) strides through the grass: its legs swing,
//! Bevy's skinning draws them, and its `Trampler` collides the mesh as the
//! skin poses it (`bevy_trample::skin`).
//!
//! ```sh
//! cargo run --release -p bevy_trample --example meadow
//! # N frames of 1/60 s each, the last one saved, then exit (tests, CI):
//! cargo run --release -p bevy_trample --example meadow -- --frames 45 --screenshot meadow.png
//! # The paper's look, for comparison: a hard switch between levels of
//! # detail, one drawn blade per simulated blade.
//! cargo run --release -p bevy_trample --example meadow -- --hard-switch
//! # The field stepped on trample's GPU path with Bevy's device, the draws
//! # reading its buffers (the CPU path steps it until the device exists).
//! cargo run --release -p bevy_trample --example meadow -- --gpu
//! # The blades cast shadows too (on the ground and on each other).
//! cargo run --release -p bevy_trample --example meadow -- --grass-shadows
//! ```

use anyhow::{Context, Result, bail};
use bevy::asset::RenderAssetUsages;
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::light::CascadeShadowConfigBuilder;
use bevy::mesh::skinning::{SkinnedMesh, SkinnedMeshInverseBindposes};
use bevy::mesh::{Indices, PrimitiveTopology, VertexAttributeValues};
use bevy::pbr::DistanceFog;
use bevy::prelude::*;
use bevy::render::RenderPlugin;
use bevy::render::view::screenshot::{Screenshot, save_to_disk};
use bevy::time::TimeUpdateStrategy;
use bevy::window::{PresentMode, WindowResolution};
use bevy_trample::{
    GrassLook, TrampleCamera, TrampleField, TramplePlugin, TrampleSystems, Trampler,
};
use std::path::PathBuf;
use std::time::Duration;

/// The car's length, metres (the mesh is ~0.9 units long along z).
const CAR_SCALE: f32 = 4.5;
/// Fixed step and, with `--frames`, the time of every frame: 1/60 s.
const DT: f64 = 1.0 / 60.0;

/// What the command line asked for.
#[derive(Resource, Clone, Debug, Default)]
struct Args {
    /// Frames to render before saving the last (`--frames N`), then exit.
    frames: Option<u32>,
    /// Where the last frame goes (`--screenshot FILE`, PNG).
    screenshot: Option<PathBuf>,
    /// The paper's look (`--hard-switch`): levels of detail switched at a
    /// distance with no blend band, one blade drawn per simulated blade.
    hard_switch: bool,
    /// The GPU path (`--gpu`): `TrampleField::on_gpu`.
    gpu: bool,
    /// The grass casts shadows (`--grass-shadows`):
    /// `GrassLook::cast_shadows`.
    grass_shadows: bool,
}

fn parse_args() -> Result<Args> {
    let mut args = Args::default();
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        match a.as_str() {
            "--frames" => {
                let v = it.next().context("--frames needs a number of frames")?;
                let n: u32 = v
                    .parse()
                    .with_context(|| format!("--frames {v}: must be a whole number >= 1"))?;
                if n == 0 {
                    bail!("--frames 0: must be a whole number >= 1");
                }
                args.frames = Some(n);
            }
            "--screenshot" => {
                let v = it.next().context("--screenshot needs a file name (PNG)")?;
                args.screenshot = Some(PathBuf::from(v));
            }
            "--hard-switch" => args.hard_switch = true,
            "--gpu" => args.gpu = true,
            "--grass-shadows" => args.grass_shadows = true,
            "-h" | "--help" => {
                println!(
                    "meadow [--frames N] [--screenshot FILE.png] [--hard-switch] [--gpu] [--grass-shadows]\n  \
                     arrow keys: drive the car\n  \
                     --hard-switch: the paper's look (no blend bands, no extra blades near the camera)\n  \
                     --gpu: step the field on trample's GPU path with Bevy's device\n  \
                     --grass-shadows: the grass casts shadows (GrassLook::cast_shadows)"
                );
                std::process::exit(0);
            }
            other => bail!(
                "unknown argument {other:?} (allowed: --frames N, --screenshot FILE, --hard-switch, --gpu, --grass-shadows)"
            ),
        }
    }
    if args.screenshot.is_some() && args.frames.is_none() {
        bail!("--screenshot needs --frames N (the frame to save)");
    }
    Ok(args)
}

fn main() -> Result<()> {
    let args = parse_args()?;
    let mut file = TrampleField::paper_meadow();
    file.sim.precision = 6;
    file.sim.recovery_s = 6.0;
    file.lod.geometry_m = 16.0;
    file.lod.billboard_m = 40.0;
    file.wind.strength_m = 0.02;
    file.wind.gust_m = 0.05;
    let mut field = TrampleField::from_scene_file(&file)?;
    if args.gpu {
        field = field.on_gpu();
    }
    let car = car_mesh()?;

    let mut app = App::new();
    app.add_plugins(
        DefaultPlugins
            .set(WindowPlugin {
                primary_window: Some(Window {
                    title: "bevy_trample: meadow".into(),
                    resolution: WindowResolution::new(1280, 720),
                    present_mode: PresentMode::AutoVsync,
                    ..default()
                }),
                ..default()
            })
            .set(RenderPlugin {
                // With --frames, frame N shows everything: a pipeline is
                // ready the frame it is first needed (on a software
                // driver, compiling them takes seconds).
                synchronous_pipeline_compilation: args.frames.is_some(),
                ..default()
            }),
    )
    .add_plugins(TramplePlugin)
    .insert_resource(field)
    .insert_resource(Time::<Fixed>::from_seconds(DT))
    .insert_resource(ClearColor(Color::srgb(0.62, 0.75, 0.90)))
    .insert_resource(GlobalAmbientLight {
        color: Color::srgb(0.75, 0.85, 1.0),
        brightness: 600.0,
        ..default()
    })
    .insert_resource(CarMesh(Some(car)))
    .insert_resource(GrassLook {
        cast_shadows: args.grass_shadows,
        ..if args.hard_switch {
            GrassLook {
                near_density: 1,
                ..GrassLook::without_blend_bands()
            }
        } else {
            GrassLook::default()
        }
    })
    .insert_resource(args.clone())
    .add_systems(Startup, setup)
    .add_systems(FixedUpdate, (drive, walk).before(TrampleSystems::Step))
    .add_systems(PostUpdate, follow.before(TransformSystems::Propagate))
    .add_systems(Last, frames);
    if args.frames.is_some() {
        // Every frame is 1/60 s of the simulation however long it takes to draw.
        app.insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(
            DT,
        )));
    }
    app.run();
    Ok(())
}

/// The car's mesh until `setup` adds it to the assets.
#[derive(Resource)]
struct CarMesh(Option<Mesh>);

/// The beetle, scaled to ~4 m, its bottom on y = 0, centred on x and z,
/// its front along +z.
fn car_mesh() -> Result<Mesh> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/meshes/beetle.obj"
    );
    let tri = trample::object::load_mesh_file(std::path::Path::new(path))
        .with_context(|| format!("reading {path}"))?;
    let (lo, hi) = tri.bounds().context("beetle.obj has no vertices")?;
    let centre = (lo + hi) * 0.5;
    // Flat-shaded: three vertices a triangle.
    let positions: Vec<[f32; 3]> = tri
        .indices
        .iter()
        .flat_map(|t| t.iter().map(|&i| tri.positions[i as usize]))
        .map(|p| {
            let p = (p - glam::Vec3::new(centre.x, lo.y, centre.z)) * CAR_SCALE;
            p.to_array()
        })
        .collect();
    let n = positions.len() as u32;
    let mut mesh = Mesh::new(
        PrimitiveTopology::TriangleList,
        RenderAssetUsages::MAIN_WORLD | RenderAssetUsages::RENDER_WORLD,
    )
    .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, positions)
    .with_inserted_indices(Indices::U32((0..n).collect()));
    mesh.duplicate_vertices();
    mesh.compute_flat_normals();
    Ok(mesh)
}

/// The car's controls: speed (m/s) and heading (radians about y).
#[derive(Component, Default)]
struct Car {
    speed: f32,
    heading: f32,
    /// A key was pressed: the player drives, not the autopilot.
    manual: bool,
}

/// The walker: hip height, the legs' half spacing and half width, the
/// torso's half size (m), walking speed (m/s) and the legs' swing (rad).
const HIP_Y: f32 = 0.9;
const LEG_X: f32 = 0.13;
const LEG_HALF: f32 = 0.07;
const TORSO_HALF: Vec3 = Vec3::new(0.24, 0.28, 0.13);
const WALK_SPEED: f32 = 1.4;
const SWING: f32 = 0.45;

/// The walker's stride and its legs' joints.
#[derive(Component)]
struct Walker {
    /// Distance walked, m (the legs' phase).
    walked: f32,
    legs: [Entity; 2],
}

/// A skinned mesh's vertex and index lists, as they are filled.
#[derive(Default)]
struct Lists {
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    joints: Vec<[u16; 4]>,
    indices: Vec<u32>,
}

/// A box from `lo` to `hi` on joint `joint`: 24 vertices (4 a face, flat
/// normals) appended to `lists`.
fn skinned_box(lo: Vec3, hi: Vec3, joint: u16, lists: &mut Lists) {
    let c = |x: bool, y: bool, z: bool| {
        Vec3::new(
            if x { hi.x } else { lo.x },
            if y { hi.y } else { lo.y },
            if z { hi.z } else { lo.z },
        )
    };
    // Each face: its normal and its corners counter-clockwise seen from outside.
    let faces = [
        (
            Vec3::X,
            [
                c(true, false, false),
                c(true, true, false),
                c(true, true, true),
                c(true, false, true),
            ],
        ),
        (
            Vec3::NEG_X,
            [
                c(false, false, true),
                c(false, true, true),
                c(false, true, false),
                c(false, false, false),
            ],
        ),
        (
            Vec3::Y,
            [
                c(false, true, false),
                c(false, true, true),
                c(true, true, true),
                c(true, true, false),
            ],
        ),
        (
            Vec3::NEG_Y,
            [
                c(false, false, true),
                c(false, false, false),
                c(true, false, false),
                c(true, false, true),
            ],
        ),
        (
            Vec3::Z,
            [
                c(true, false, true),
                c(true, true, true),
                c(false, true, true),
                c(false, false, true),
            ],
        ),
        (
            Vec3::NEG_Z,
            [
                c(false, false, false),
                c(false, true, false),
                c(true, true, false),
                c(true, false, false),
            ],
        ),
    ];
    for (n, corners) in faces {
        let first = lists.positions.len() as u32;
        lists.positions.extend(corners.map(|p| p.to_array()));
        lists.normals.extend([n.to_array(); 4]);
        lists.joints.extend([[joint, 0, 0, 0]; 4]);
        lists
            .indices
            .extend([first, first + 1, first + 2, first, first + 2, first + 3]);
    }
}

/// The walker's mesh in its bind pose (feet on y = 0, facing +z): the torso
/// on joint 0 (the walker itself), the legs on joints 1 and 2 (its hips).
fn walker_mesh() -> Mesh {
    let mut lists = Lists::default();
    let torso = Vec3::new(0.0, HIP_Y + TORSO_HALF.y, 0.0);
    skinned_box(torso - TORSO_HALF, torso + TORSO_HALF, 0, &mut lists);
    for (joint, x) in [(1, -LEG_X), (2, LEG_X)] {
        let half = Vec3::new(LEG_HALF, 0.0, LEG_HALF);
        skinned_box(
            Vec3::new(x, 0.0, 0.0) - half,
            Vec3::new(x, HIP_Y, 0.0) + half,
            joint,
            &mut lists,
        );
    }
    let Lists {
        positions,
        normals,
        joints,
        indices,
    } = lists;
    let n = positions.len();
    Mesh::new(
        PrimitiveTopology::TriangleList,
        RenderAssetUsages::MAIN_WORLD | RenderAssetUsages::RENDER_WORLD,
    )
    .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, positions)
    .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, normals)
    .with_inserted_attribute(
        Mesh::ATTRIBUTE_JOINT_INDEX,
        VertexAttributeValues::Uint16x4(joints),
    )
    .with_inserted_attribute(
        Mesh::ATTRIBUTE_JOINT_WEIGHT,
        vec![[1.0f32, 0.0, 0.0, 0.0]; n],
    )
    .with_inserted_indices(Indices::U32(indices))
}

fn setup(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
    mut bindposes: ResMut<Assets<SkinnedMeshInverseBindposes>>,
    mut car_mesh: ResMut<CarMesh>,
) {
    let Some(mesh) = car_mesh.0.take() else {
        return;
    };
    // The walker, 5 m ahead of the car and 2.5 m to its right, going the
    // car's way: the car passes it after a few seconds.
    let heading = 0.6;
    let (forward, right) = (
        Vec3::new(f32::sin(heading), 0.0, f32::cos(heading)),
        Vec3::new(-f32::cos(heading), 0.0, f32::sin(heading)),
    );
    let at = Vec3::new(-12.0, 0.0, -6.0) + forward * 5.0 + right * 2.5;
    let walker = commands
        .spawn((
            Mesh3d(meshes.add(walker_mesh())),
            MeshMaterial3d(materials.add(StandardMaterial {
                base_color: Color::srgb(0.95, 0.6, 0.08),
                perceptual_roughness: 0.6,
                ..default()
            })),
            Transform::from_translation(at).with_rotation(Quat::from_rotation_y(heading)),
            Trampler::default(),
        ))
        .id();
    let legs = [-LEG_X, LEG_X].map(|x| {
        commands
            .spawn((Transform::from_xyz(x, HIP_Y, 0.0), ChildOf(walker)))
            .id()
    });
    // Inverse bind poses: the walker's origin, then each hip.
    let inverse_bindposes = bindposes.add(SkinnedMeshInverseBindposes::from(vec![
        Mat4::IDENTITY,
        Mat4::from_translation(Vec3::new(LEG_X, -HIP_Y, 0.0)),
        Mat4::from_translation(Vec3::new(-LEG_X, -HIP_Y, 0.0)),
    ]));
    commands.entity(walker).insert((
        SkinnedMesh {
            inverse_bindposes,
            joints: vec![walker, legs[0], legs[1]],
        },
        Walker { walked: 0.0, legs },
    ));
    commands.spawn((
        Car {
            speed: 5.0,
            heading: 0.6,
            manual: false,
        },
        Mesh3d(meshes.add(mesh)),
        MeshMaterial3d(materials.add(StandardMaterial {
            base_color: Color::srgb(0.75, 0.08, 0.05),
            perceptual_roughness: 0.35,
            metallic: 0.2,
            ..default()
        })),
        Transform::from_xyz(-12.0, 0.0, -6.0).with_rotation(Quat::from_rotation_y(0.6)),
        Trampler {
            precision: 6,
            // The beetle has no floor: its hollow counts as inside by the
            // mesh's winding number, so no grass stands in the car.
            track: trample::object::TrackParams {
                open_inside: trample::object::OpenInside::Winding,
                ..default()
            },
            ..default()
        },
    ));
    commands.spawn((
        DirectionalLight {
            illuminance: 9_000.0,
            shadow_maps_enabled: true,
            ..default()
        },
        Transform::from_xyz(0.0, 10.0, 0.0).looking_at(Vec3::new(-0.6, 0.0, 0.8), Vec3::Y),
        CascadeShadowConfigBuilder {
            maximum_distance: 40.0,
            first_cascade_far_bound: 12.0,
            ..default()
        }
        .build(),
    ));
    commands.spawn((
        Camera3d::default(),
        // Multisampling costs four times the fragments on a software driver.
        Msaa::Off,
        Tonemapping::AcesFitted,
        Projection::Perspective(PerspectiveProjection {
            fov: 50f32.to_radians(),
            far: 200.0,
            ..default()
        }),
        Transform::from_xyz(-12.0, 4.0, -14.0).looking_at(Vec3::new(-12.0, 0.0, -6.0), Vec3::Y),
        DistanceFog {
            color: Color::srgb(0.62, 0.75, 0.90),
            falloff: bevy::pbr::FogFalloff::Linear {
                start: 25.0,
                end: 70.0,
            },
            ..default()
        },
        TrampleCamera,
    ));
}

/// Arrow keys: up/down change the speed, left/right steer. The autopilot
/// drives a slow curve until a key is pressed. The car stays on the field.
fn drive(
    time: Res<Time>,
    keys: Option<Res<ButtonInput<KeyCode>>>,
    mut cars: Query<(&mut Car, &mut Transform)>,
) {
    let dt = time.delta_secs();
    for (mut car, mut t) in &mut cars {
        let key = |k| keys.as_ref().is_some_and(|keys| keys.pressed(k));
        let (up, down, left, right) = (
            key(KeyCode::ArrowUp),
            key(KeyCode::ArrowDown),
            key(KeyCode::ArrowLeft),
            key(KeyCode::ArrowRight),
        );
        car.manual |= up || down || left || right;
        let turn = if car.manual {
            car.speed = (car.speed
                + 6.0 * dt * (f32::from(u8::from(up)) - f32::from(u8::from(down))))
            .clamp(-4.0, 12.0);
            f32::from(u8::from(left)) - f32::from(u8::from(right))
        } else {
            0.25
        };
        car.heading += turn * 0.9 * dt * car.speed.abs().min(4.0) / 4.0;
        let forward = Vec3::new(car.heading.sin(), 0.0, car.heading.cos());
        let next = t.translation + forward * car.speed * dt;
        // 51.2 m field: keep 3 m from its edges.
        t.translation = next.clamp(Vec3::new(-22.6, 0.0, -22.6), Vec3::new(22.6, 0.0, 22.6));
        t.rotation = Quat::from_rotation_y(car.heading);
    }
}

/// The walker strides on at `WALK_SPEED` (turning back before the field's
/// edge), its legs swinging about its hips, one forward as the other goes
/// back: a step every `2 · HIP_Y · sin(SWING)` metres or so.
fn walk(
    time: Res<Time>,
    mut walkers: Query<(&mut Walker, &mut Transform)>,
    mut hips: Query<&mut Transform, Without<Walker>>,
) {
    let dt = time.delta_secs();
    for (mut w, mut t) in &mut walkers {
        let forward = t.rotation * Vec3::Z;
        if (t.translation + forward * 3.0).abs().max_element() > 22.6 {
            t.rotate_y(std::f32::consts::PI);
        }
        let forward = t.rotation * Vec3::Z;
        t.translation += forward * WALK_SPEED * dt;
        w.walked += WALK_SPEED * dt;
        let stride = 4.0 * HIP_Y * SWING.sin();
        let phase = std::f32::consts::TAU * w.walked / stride;
        for (leg, sign) in w.legs.iter().zip([1.0, -1.0]) {
            if let Ok(mut hip) = hips.get_mut(*leg) {
                hip.rotation = Quat::from_rotation_x(sign * SWING * phase.sin());
            }
        }
    }
}

/// The camera follows the car from behind and above.
fn follow(
    cars: Query<&Transform, (With<Car>, Without<Camera3d>)>,
    mut cameras: Query<&mut Transform, With<Camera3d>>,
) {
    let (Ok(car), Ok(mut cam)) = (cars.single(), cameras.single_mut()) else {
        return;
    };
    let back = car.rotation * Vec3::new(0.0, 0.0, -1.0);
    let eye = car.translation + back * 9.0 + Vec3::Y * 4.0;
    *cam = Transform::from_translation(eye).looking_at(car.translation + Vec3::Y * 0.8, Vec3::Y);
}

/// `--frames N`: saves frame N (`--screenshot`) and exits once it is written.
fn frames(
    mut commands: Commands,
    args: Res<Args>,
    mut frame: Local<u32>,
    mut exit: MessageWriter<AppExit>,
) {
    let Some(n) = args.frames else { return };
    *frame += 1;
    debug!("frame {}", *frame);
    match &args.screenshot {
        Some(path) if *frame == n => {
            let _ = std::fs::remove_file(path);
            commands
                .spawn(Screenshot::primary_window())
                .observe(save_to_disk(path.clone()));
        }
        // The capture is written a few frames later, on another thread.
        Some(path)
            if *frame > n
                && (std::fs::metadata(path).is_ok_and(|m| m.len() > 0) || *frame > n + 600) =>
        {
            exit.write(AppExit::Success);
        }
        None if *frame >= n => {
            exit.write(AppExit::Success);
        }
        _ => {}
    }
}
