//! Bodies a host adds, moves, teleports and removes on a running simulation,
//! on the GPU path (issue 14 item 1, "on both paths"): the GPU simulation
//! is created with no body, and the same host calls are made on it and on
//! a CPU twin. After each phase the two fields agree (vertices, classes and
//! track owners), so the GPU path follows what the CPU path is tested for
//! in `crates/trample/tests/host_bodies.rs`: a moved body's track, no
//! track between a teleport's two places, a removed body acting no more
//! and the blades of the bodies after it keeping their own recovery (their
//! track owners renumbered on the GPU as on the CPU).

mod common;

use glam::{Quat, Vec3};
use trample::Simulation;
use trample::builder::{BodyBuilder, SimulationBuilder};
use trample::field::{FieldParams, LodParams};
use trample::object::TrackParams;
use trample::step::{HostView, SimParams};
use trample_gpu::GpuSimulation;

/// Largest vertex distance between the paths (m). The step parity tests
/// hold 1e-3 m after 200 frames.
const VERTEX_TOLERANCE_M: f32 = 1e-3;
/// Fraction of blades whose class or track owner may differ (a grazing
/// contact decided differently by a few ulp; step_parity's tolerance).
const CLASS_TOLERANCE: f64 = 0.002;

/// 6 × 6 m of grass (3 × 3 patches of 20 × 20 cells of 0.1 m), every cell
/// geometric, seen by a host camera from above; the paper's recovery (none)
/// for `[sim]`; no bodies yet.
fn field() -> Simulation {
    SimulationBuilder::new()
        .field(FieldParams {
            patches: [3, 3],
            cells_per_patch: 20,
            ..FieldParams::default()
        })
        .lod(LodParams {
            geometry_m: 1000.0,
            billboard_m: 2000.0,
        })
        .sim(SimParams::default())
        .host_view(
            HostView::look_at(Vec3::new(0.0, 10.0, 0.1), Vec3::ZERO, 1.0, 1.0, 0.1, 100.0).unwrap(),
        )
        .build()
        .unwrap()
}

/// The two paths' differences: the largest vertex distance (m), and the
/// fractions of blades whose class and whose track owner differ; also the
/// GPU's owners.
fn compare(gpu: &common::TestGpu, g: &GpuSimulation, cpu: &Simulation, phase: &str) -> Vec<u8> {
    let (device, queue) = (&gpu.device, &gpu.queue);
    let pos = g.field.read_positions(device, queue).unwrap();
    let bl = &cpu.field.blades;
    let worst = pos.iter().enumerate().fold(0.0f32, |w, (i, p)| {
        let d = Vec3::new(p[0], p[1], p[2]).distance(bl.pos[i].vec3a().into());
        w.max(if d.is_nan() { f32::INFINITY } else { d })
    });
    let class = g.field.read_u32(device, queue, &g.field.class).unwrap();
    let n = class.len() as f64;
    let class_diff = class
        .iter()
        .zip(&cpu.class)
        .filter(|&(&k, &c)| k & 0xff != c as u32)
        .count() as f64
        / n;
    let owners: Vec<u8> = class.iter().map(|&k| (k >> 8 & 0xff) as u8).collect();
    let owner_diff = owners
        .iter()
        .zip(&cpu.track_owner)
        .filter(|(a, b)| a != b)
        .count() as f64
        / n;
    eprintln!(
        "{phase}: worst vertex {worst:.2e} m, classes differ {class_diff:.4}, owners differ {owner_diff:.4}, CPU blades away from rest {}",
        cpu.blades_away_from_rest()
    );
    assert!(
        worst <= VERTEX_TOLERANCE_M,
        "{phase}: the GPU's blades are {worst} m from the CPU's"
    );
    assert!(
        class_diff <= CLASS_TOLERANCE,
        "{phase}: classes differ on {class_diff}"
    );
    assert!(
        owner_diff <= CLASS_TOLERANCE,
        "{phase}: owners differ on {owner_diff}"
    );
    owners
}

/// The same host call on both paths; its result (the same on both).
fn both<T: PartialEq + std::fmt::Debug>(
    cpu: &mut Simulation,
    g: &mut GpuSimulation,
    f: impl Fn(&mut Simulation) -> T,
) -> T {
    let on_cpu = f(cpu);
    assert_eq!(
        on_cpu,
        f(&mut g.sim),
        "the host call must do the same on both paths"
    );
    on_cpu
}

/// `frames` steps of `dt` on both paths; on the GPU submitted by `step`,
/// or recorded into the host's encoder (`host`).
fn steps(
    gpu: &common::TestGpu,
    g: &mut GpuSimulation,
    cpu: &mut Simulation,
    frames: u32,
    host: bool,
) {
    let (device, queue) = (&gpu.device, &gpu.queue);
    let dt = cpu.params.dt_s;
    for _ in 0..frames {
        cpu.step(dt).unwrap();
        if host {
            let mut encoder = device.create_command_encoder(&Default::default());
            g.record_step(device, queue, &mut encoder, dt).unwrap();
            queue.submit([encoder.finish()]);
        } else {
            g.step(device, queue, dt).unwrap();
        }
    }
}

#[test]
fn bodies_added_moved_teleported_and_removed_on_the_gpu() {
    host_bodies(false);
}

#[test]
fn bodies_come_and_go_with_steps_recorded_into_the_hosts_encoder() {
    host_bodies(true);
}

fn host_bodies(host: bool) {
    let gpu = common::gpu();
    let (device, queue) = (&gpu.device, &gpu.queue);
    let mut cpu = field();
    let mut g = GpuSimulation::new(device, queue, cpu.clone()).expect("GPU simulation");
    let dt = cpu.params.dt_s;

    // A crate, added and moved along +x at 1.5 m/s: a track on both paths.
    let crate_body = BodyBuilder::cuboid("crate", [0.3, 0.25, 0.3])
        .at([-2.2, 0.3, -1.5])
        .build()
        .unwrap();
    let a = both(&mut cpu, &mut g, |s| s.add_body(crate_body.clone()));
    let mut p = Vec3::new(-2.2, 0.3, -1.5);
    for _ in 0..40 {
        p += Vec3::X * 1.5 * dt;
        both(&mut cpu, &mut g, |s| s.move_body(a, p, Quat::IDENTITY, dt)).unwrap();
        steps(&gpu, &mut g, &mut cpu, 1, host);
    }
    assert!(
        cpu.blades_away_from_rest() > 100,
        "the crate must leave a track"
    );
    let owners = compare(&gpu, &g, &cpu, "moved");
    assert!(
        owners.contains(&1),
        "the crate's blades are its own (owner 1)"
    );

    // Teleported: no track between the two places, on either path.
    let there = Vec3::new(1.5, 0.3, 1.5);
    both(&mut cpu, &mut g, |s| {
        s.teleport_body(a, there, Quat::from_rotation_y(0.3))
    })
    .unwrap();
    steps(&gpu, &mut g, &mut cpu, 10, host);
    compare(&gpu, &g, &cpu, "teleported");

    // A ball whose track recovers in 0.4 s (`[sim]`'s never does) joins,
    // rolling along -z.
    let ball = BodyBuilder::sphere("ball", 0.35)
        .at([-1.0, 0.3, 2.0])
        .track(TrackParams {
            recovery_s: Some(0.4),
            ..TrackParams::default()
        })
        .build()
        .unwrap();
    let b = both(&mut cpu, &mut g, |s| s.add_body(ball.clone()));
    let mut q = Vec3::new(-1.0, 0.3, 2.0);
    for _ in 0..30 {
        q -= Vec3::Z * 1.5 * dt;
        both(&mut cpu, &mut g, |s| s.move_body(b, q, Quat::IDENTITY, dt)).unwrap();
        steps(&gpu, &mut g, &mut cpu, 1, host);
    }
    let owners = compare(&gpu, &g, &cpu, "ball added");
    assert!(
        owners.contains(&2),
        "the ball's blades are its own (owner 2)"
    );

    // The crate leaves: its blades go to `[sim]` (owner 0, never
    // recovering), the ball's become owner 1 and keep recovering in 0.4 s
    // on the GPU as on the CPU (with the owners not renumbered, the GPU
    // would read owner 2's settings: `[sim]`'s, and never recover them).
    both(&mut cpu, &mut g, |s| s.remove_body(a).map(|body| body.id)).unwrap();
    steps(&gpu, &mut g, &mut cpu, 45, host);
    let owners = compare(&gpu, &g, &cpu, "crate removed");
    assert!(
        !owners.contains(&2),
        "no blade keeps a removed body's number"
    );
    assert!(owners.contains(&1), "the ball's blades are owner 1 now");
}

/// A host's animated mesh on the GPU path
/// (`Simulation::set_body_vertices`): a crate whose vertices the host
/// slides along +x, its pose kept, on both paths; the GPU uploads the
/// refitted tree every sub-step as it does an animated glTF's, and the two
/// fields agree.
#[test]
fn a_mesh_the_host_deforms_is_followed_on_the_gpu() {
    let gpu = common::gpu();
    let (device, queue) = (&gpu.device, &gpu.queue);
    let mut cpu = field();
    let mut g = GpuSimulation::new(device, queue, cpu.clone()).expect("GPU simulation");
    let dt = cpu.params.dt_s;
    let mesh = trample::object::shapes::cuboid(Vec3::new(0.3, 0.25, 0.3));
    let crate_body = BodyBuilder::mesh("crate", &mesh)
        .at([-2.2, 0.3, -1.5])
        .build()
        .unwrap();
    let a = both(&mut cpu, &mut g, |s| s.add_body(crate_body.clone()));
    let rest = mesh.positions;
    let mut offset = Vec3::ZERO;
    for _ in 0..40 {
        offset += Vec3::X * 1.5 * dt;
        let vertices: Vec<Vec3> = rest.iter().map(|&p| p + offset).collect();
        both(&mut cpu, &mut g, |s| s.set_body_vertices(a, &vertices, dt)).unwrap();
        steps(&gpu, &mut g, &mut cpu, 1, false);
    }
    assert!(
        cpu.blades_away_from_rest() > 100,
        "the slid mesh must leave a track"
    );
    compare(&gpu, &g, &cpu, "slid mesh");
}
