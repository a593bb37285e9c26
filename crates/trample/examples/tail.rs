//! A host's animated mesh: a creature's tail lying in the grass, swishing
//! from side to side while the creature stands still. The host bends the
//! tail's vertices every frame (its own animation: here, a curl that grows
//! towards the tip) and hands them to the simulation with
//! `Simulation::set_body_vertices`; the body's OBB tree is refitted at
//! every sub-step, and each node pushes with its own speed (the tip, which
//! moves the most, pushes the hardest). Prints, every half second, the
//! step's timings, how many blades the tail bent and how far its tip is
//! from where it lay.
//!
//! ```sh
//! cargo run --release -p trample --example tail
//! ```

use glam::{Quat, Vec3};
use trample::builder::{BodyBuilder, SimulationBuilder};
use trample::field::{FieldParams, LodParams};
use trample::object::TriMesh;
use trample::step::{HostView, SimParams};

/// The tail: length, half width and half height (m), and the rings of
/// four vertices along it (the more rings, the smoother it bends).
const LENGTH: f32 = 1.6;
const HALF_WIDTH: f32 = 0.06;
const HALF_HEIGHT: f32 = 0.08;
const RINGS: u32 = 17;

/// A box along +x from the root (x = 0) to the tip, cut into rings: the
/// host's mesh, vertex `4 · ring + corner`.
fn tail_mesh() -> TriMesh {
    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    let mut positions = Vec::new();
    for r in 0..RINGS {
        let x = LENGTH * r as f32 / (RINGS - 1) as f32;
        for (y, z) in corners {
            positions.push(Vec3::new(x, y * HALF_HEIGHT, z * HALF_WIDTH));
        }
    }
    let mut indices = Vec::new();
    for r in 0..RINGS - 1 {
        for c in 0..4 {
            let (a, b) = (4 * r + c, 4 * r + (c + 1) % 4);
            let (a2, b2) = (a + 4, b + 4);
            indices.push([a, b, b2]);
            indices.push([a, b2, a2]);
        }
    }
    // The caps: the root's faces -x, the tip's +x.
    let tip = 4 * (RINGS - 1);
    indices.extend([
        [0, 3, 2],
        [0, 2, 1],
        [tip, tip + 1, tip + 2],
        [tip, tip + 2, tip + 3],
    ]);
    TriMesh { positions, indices }
}

/// The host's animation at time `t`: each vertex turned about the root's
/// vertical axis by an angle that grows with the square of its distance
/// along the tail, swinging ±50° at the tip, once every 1.5 s.
fn swish(rest: &[Vec3], t: f32) -> Vec<Vec3> {
    let swing = 0.87 * (std::f32::consts::TAU * t / 1.5).sin();
    rest.iter()
        .map(|&p| {
            let along = p.x / LENGTH;
            Quat::from_rotation_y(swing * along * along) * p
        })
        .collect()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // 6.4 × 6.4 m of grass (4 × 4 patches of 16 × 16 cells of 0.1 m);
    // grass stands up again over 1.5 s.
    let mut sim = SimulationBuilder::new()
        .field(FieldParams {
            patches: [4, 4],
            cells_per_patch: 16,
            ..FieldParams::default()
        })
        .lod(LodParams {
            geometry_m: 10.0,
            billboard_m: 25.0,
        })
        .sim(SimParams {
            recovery_s: 1.5,
            ..SimParams::default()
        })
        .host_view(HostView::look_at(
            Vec3::new(0.0, 3.0, -3.0),
            Vec3::ZERO,
            0.9,
            16.0 / 9.0,
            0.1,
            100.0,
        )?)
        .build()?;
    // The tail's root at the origin, 10 cm up: it lies in the grass.
    let mesh = tail_mesh();
    let tail = sim.add_body(
        BodyBuilder::mesh("tail", &mesh)
            .at([0.0, 0.1, 0.0])
            .build()?,
    );

    let dt = 1.0 / 60.0;
    let tip = mesh.positions[4 * (RINGS as usize - 1)];
    for frame in 1..=180 {
        let t = frame as f32 * dt;
        let now = swish(&mesh.positions, t);
        sim.set_body_vertices(tail, &now, dt)?;
        let timings = sim.step(dt)?.clone();
        if frame % 30 == 0 {
            let moved = now[4 * (RINGS as usize - 1)].distance(tip);
            println!(
                "t = {t:.1} s: {timings}; {} blades bent, the tip {moved:.2} m from where it lay",
                sim.blades_away_from_rest()
            );
        }
    }
    Ok(())
}
