//! Many tramplers at once: balls, crates, standing capsules (a game
//! character's usual collider) and rings circling a meadow, each an entity with a Bevy mesh and a `Trampler`, seen from
//! above. With `--gpu` the field steps on trample's GPU path with Bevy's own
//! device (`TrampleField::on_gpu`) and the draws read the GPU's buffers.
//! Every 60 frames it prints the frame rate and the step's time (Bevy's
//! diagnostics `trample/step_ms`: on the GPU path the time to record the
//! step).
//!
//! ```sh
//! cargo run --release -p bevy_trample --example herd                      # 32 objects, CPU path
//! cargo run --release -p bevy_trample --example herd -- --gpu --objects 128 --patches 64
//! # N frames of 1/60 s each, the last one saved, then exit:
//! cargo run --release -p bevy_trample --example herd -- --gpu --frames 30 --screenshot herd.png
//! ```

use anyhow::{Context, Result, bail};
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::diagnostic::{DiagnosticsStore, FrameTimeDiagnosticsPlugin};
use bevy::prelude::*;
use bevy::render::RenderPlugin;
use bevy::render::view::screenshot::{Screenshot, save_to_disk};
use bevy::time::TimeUpdateStrategy;
use bevy::window::{PresentMode, WindowResolution};
use bevy_trample::{TrampleCamera, TrampleField, TramplePlugin, TrampleSystems, Trampler};
use std::path::PathBuf;
use std::time::Duration;

/// Fixed step and, with `--frames`, the time of every frame: 1/60 s.
const DT: f64 = 1.0 / 60.0;
/// Cells a patch side, and a cell's side (m): the paper's.
const CELLS_PER_PATCH: u32 = 32;
const CELL_M: f32 = 0.1;

/// What the command line asked for.
#[derive(Resource, Clone, Debug)]
struct Args {
    /// Tramplers (`--objects N`, 1..=1024).
    objects: u32,
    /// Patches a side (`--patches N`, 1..=128; 16 is the paper's field).
    patches: u32,
    /// The GPU path (`--gpu`).
    gpu: bool,
    /// Frames to run (`--frames N`), then exit.
    frames: Option<u32>,
    /// Where the last frame goes (`--screenshot FILE`, PNG).
    screenshot: Option<PathBuf>,
}

impl Default for Args {
    fn default() -> Self {
        Self {
            objects: 32,
            patches: 16,
            gpu: false,
            frames: None,
            screenshot: None,
        }
    }
}

/// The whole number after flag `flag`, within `range`.
fn number(
    it: &mut impl Iterator<Item = String>,
    flag: &str,
    range: std::ops::RangeInclusive<u32>,
) -> Result<u32> {
    let v = it
        .next()
        .with_context(|| format!("{flag} needs a number"))?;
    let n: u32 = v.parse().with_context(|| {
        format!(
            "{flag} {v}: must be a whole number in {}..={}",
            range.start(),
            range.end()
        )
    })?;
    if !range.contains(&n) {
        bail!("{flag} {n}: must be in {}..={}", range.start(), range.end());
    }
    Ok(n)
}

fn parse_args() -> Result<Args> {
    let mut args = Args::default();
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        match a.as_str() {
            "--objects" => args.objects = number(&mut it, "--objects", 1..=1024)?,
            "--patches" => args.patches = number(&mut it, "--patches", 1..=128)?,
            "--frames" => args.frames = Some(number(&mut it, "--frames", 1..=u32::MAX)?),
            "--screenshot" => {
                let v = it.next().context("--screenshot needs a file name (PNG)")?;
                args.screenshot = Some(PathBuf::from(v));
            }
            "--gpu" => args.gpu = true,
            "-h" | "--help" => {
                println!(
                    "herd [--objects N] [--patches N] [--gpu] [--frames N] [--screenshot FILE.png]\n  \
                     --objects N: tramplers (default 32)\n  \
                     --patches N: patches a side, 32 x 32 cells of 0.1 m each (default 16: the paper's field)\n  \
                     --gpu: step the field on trample's GPU path with Bevy's device"
                );
                std::process::exit(0);
            }
            other => bail!(
                "unknown argument {other:?} (allowed: --objects N, --patches N, --gpu, --frames N, --screenshot FILE)"
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
    file.field.patches = [args.patches, args.patches];
    file.field.cells_per_patch = CELLS_PER_PATCH;
    file.field.cell_size_m = CELL_M;
    file.sim.recovery_s = 8.0;
    // 128 patches a side is scenes/herd.toml's field (16.8 M blades, about
    // 10 GiB): its limit, over the default 8 GiB.
    file.sim.memory_limit_gib = 12.0;
    let side = args.patches as f32 * CELLS_PER_PATCH as f32 * CELL_M;
    // Blades within a third of the field, billboards to its far edge.
    file.lod.geometry_m = (side / 3.0).clamp(8.0, 40.0);
    file.lod.billboard_m = side.max(file.lod.geometry_m + 10.0);
    let mut field = TrampleField::from_scene_file(&file)?;
    if args.gpu {
        field = field.on_gpu();
    }
    let mut app = App::new();
    app.add_plugins((
        DefaultPlugins
            .set(WindowPlugin {
                primary_window: Some(Window {
                    title: "bevy_trample: herd".into(),
                    resolution: WindowResolution::new(1280, 720),
                    present_mode: PresentMode::AutoNoVsync,
                    ..default()
                }),
                ..default()
            })
            .set(RenderPlugin {
                synchronous_pipeline_compilation: args.frames.is_some(),
                ..default()
            }),
        FrameTimeDiagnosticsPlugin::default(),
        TramplePlugin,
    ))
    .insert_resource(field)
    .insert_resource(Time::<Fixed>::from_seconds(DT))
    .insert_resource(ClearColor(Color::srgb(0.62, 0.75, 0.90)))
    .insert_resource(args.clone())
    .add_systems(Startup, setup)
    .add_systems(FixedUpdate, circle.before(TrampleSystems::Step))
    .add_systems(Last, (report, frames));
    if args.frames.is_some() {
        app.insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(
            DT,
        )));
    }
    app.run();
    Ok(())
}

/// A trampler going round its circle.
#[derive(Component)]
struct Circling {
    centre: Vec2,
    radius: f32,
    /// Radians a second (the sign is the direction).
    rate: f32,
    phase: f32,
    /// Height of the mesh's centre (m).
    y: f32,
}

/// A number in [0, 1) from `i` and `salt` (the same herd every run).
fn hash01(i: u32, salt: u32) -> f32 {
    let mut x = i.wrapping_mul(0x9e37_79b9) ^ salt.wrapping_mul(0x85eb_ca6b);
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    (x >> 8) as f32 / (1u32 << 24) as f32
}

fn setup(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
    args: Res<Args>,
) {
    let side = args.patches as f32 * CELLS_PER_PATCH as f32 * CELL_M;
    let half = side * 0.5;
    // Four kinds: a ball, a crate, a standing capsule (a game character's
    // usual collider), a ring on edge; each with the height of its centre
    // (the grass is ~0.45 m tall).
    let kinds = [
        (
            meshes.add(Sphere::new(0.5).mesh().ico(3).expect("ball")),
            0.4,
            Color::srgb(0.85, 0.2, 0.15),
        ),
        (
            meshes.add(Cuboid::new(1.0, 0.8, 1.6)),
            0.35,
            Color::srgb(0.6, 0.45, 0.25),
        ),
        (
            meshes.add(Capsule3d::new(0.35, 1.2)),
            0.3,
            Color::srgb(0.2, 0.35, 0.8),
        ),
        (
            meshes.add(Torus::new(0.3, 0.6)),
            0.5,
            Color::srgb(0.9, 0.8, 0.2),
        ),
    ];
    let kinds: Vec<_> = kinds
        .into_iter()
        .map(|(mesh, y, colour)| (mesh, y, materials.add(colour)))
        .collect();
    for i in 0..args.objects {
        let (mesh, y, material) = &kinds[i as usize % kinds.len()];
        let radius = 2.0 + hash01(i, 3) * (half * 0.4).max(1.0);
        let reach = (half - radius - 2.0).max(0.0);
        let centre = Vec2::new(
            (hash01(i, 1) * 2.0 - 1.0) * reach,
            (hash01(i, 2) * 2.0 - 1.0) * reach,
        );
        // 2–6 m/s along the circle, either way round.
        let speed = 2.0 + hash01(i, 4) * 4.0;
        let rate = speed / radius * if hash01(i, 5) < 0.5 { -1.0 } else { 1.0 };
        let mut t = Transform::from_xyz(centre.x, *y, centre.y);
        if i % kinds.len() as u32 == 3 {
            // The ring on edge.
            t.rotate_x(std::f32::consts::FRAC_PI_2);
        }
        commands.spawn((
            Mesh3d(mesh.clone()),
            MeshMaterial3d(material.clone()),
            t,
            Trampler::default(),
            Circling {
                centre,
                radius,
                rate,
                phase: hash01(i, 6) * std::f32::consts::TAU,
                y: *y,
            },
        ));
    }
    commands.spawn((
        Camera3d::default(),
        Tonemapping::AcesFitted,
        Transform::from_xyz(0.0, side * 0.45, side * 0.55).looking_at(Vec3::ZERO, Vec3::Y),
        TrampleCamera,
    ));
    commands.spawn((
        DirectionalLight {
            illuminance: 9_000.0,
            shadow_maps_enabled: true,
            ..default()
        },
        Transform::from_xyz(4.0, 10.0, 3.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
}

/// Moves each trampler along its circle (the contact speed comes from the
/// motion), in the fixed timestep before the simulation step.
fn circle(time: Res<Time>, mut movers: Query<(&mut Transform, &Circling)>) {
    let t = time.elapsed_secs();
    for (mut transform, c) in &mut movers {
        let a = c.phase + c.rate * t;
        let p = c.centre + Vec2::new(a.cos(), a.sin()) * c.radius;
        transform.translation = Vec3::new(p.x, c.y, p.y);
    }
}

/// Every 60 frames: the frame rate and the simulation step's time.
fn report(
    diagnostics: Res<DiagnosticsStore>,
    field: Res<TrampleField>,
    args: Res<Args>,
    mut frame: Local<u32>,
) {
    *frame += 1;
    if !frame.is_multiple_of(60) {
        return;
    }
    let value = |path: &bevy::diagnostic::DiagnosticPath| {
        diagnostics
            .get(path)
            .and_then(bevy::diagnostic::Diagnostic::smoothed)
            .unwrap_or(f64::NAN)
    };
    println!(
        "frame {}: {:.1} fps, step {:.2} ms ({:?} path{}), {} objects, {} blades",
        *frame,
        value(&FrameTimeDiagnosticsPlugin::FPS),
        value(&bevy_trample::diagnostics::STEP_MS),
        field.backend(),
        field
            .gpu_refused()
            .map_or(String::new(), |why| format!("; GPU path refused: {why}")),
        args.objects,
        field.sim.field.blades.count,
    );
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
    match &args.screenshot {
        Some(path) if *frame == n => {
            let _ = std::fs::remove_file(path);
            commands
                .spawn(Screenshot::primary_window())
                .observe(save_to_disk(path.clone()));
        }
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
