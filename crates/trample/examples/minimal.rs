//! The smallest host: a field and a box built in code (no scene file), the
//! host's own camera deciding the level of detail, and a host loop that
//! moves the box through the grass for 120 frames, printing each step's
//! timings and, at the end, the DBG count and what a renderer would upload.
//!
//! ```sh
//! cargo run --release -p trample --example minimal
//! ```

use glam::{Quat, Vec3};
use trample::builder::{BodyBuilder, SimulationBuilder};
use trample::field::{FieldParams, LodParams};
use trample::step::{BladeClass, HostView, SimParams};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // 12.8 × 12.8 m of grass: 8 × 8 patches of 16 × 16 cells of 0.1 m,
    // one blade a cell (16,384 blades); grass stands up again over 2 s.
    let mut sim = SimulationBuilder::new()
        .field(FieldParams {
            patches: [8, 8],
            cells_per_patch: 16,
            ..FieldParams::default()
        })
        .lod(LodParams {
            geometry_m: 10.0,
            billboard_m: 25.0,
        })
        .sim(SimParams {
            recovery_s: 2.0,
            ..SimParams::default()
        })
        .build()?;

    // The host's box: 0.8 × 0.5 × 0.6 m, its bottom 5 cm above the ground.
    let y = 0.3;
    let crate_id = sim.add_body(
        BodyBuilder::cuboid("crate", [0.4, 0.25, 0.3])
            .at([-5.0, y, 0.0])
            .build()?,
    );

    let dt = 1.0 / 60.0;
    for frame in 0..120 {
        // The host's game loop: its camera follows the box from behind...
        let t = frame as f32 * dt;
        let at = Vec3::new(-5.0 + 4.0 * t, y, (2.0 * t).sin());
        let eye = at + Vec3::new(-4.0, 3.0, 3.0);
        sim.set_view(HostView::look_at(eye, at, 0.9, 16.0 / 9.0, 0.1, 200.0)?)?;
        // ...and it moves the box at 4 m/s, weaving, turning as it goes.
        let heading = Quat::from_rotation_y((2.0 * t).cos().atan2(2.0));
        sim.move_body(crate_id, at, heading, dt)?;
        let timings = sim.step(dt)?;
        println!("frame {frame:3}: {timings}");
    }

    let hit = sim
        .class
        .iter()
        .filter(|&&c| c == BladeClass::Direct)
        .count();
    println!(
        "final DBG count: {} blades hit in the last step, {hit} blades hit directly in the run",
        sim.timings.dbg_blades
    );
    println!(
        "last step changed {} of {} blades and {} of {} cells ({} bytes of vertices in all)",
        sim.changed_blades().count(),
        sim.field.blades.count,
        sim.changed_cells().count(),
        sim.field.cells.lod.len(),
        sim.field.blades.pos_bytes().len(),
    );
    Ok(())
}
