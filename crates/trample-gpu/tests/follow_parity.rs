//! Parity of `follow.wgsl` (track everywhere, DESIGN §2: every cell's
//! billboard slope and flatness from its blades, Eq. 9–12) with its CPU
//! twin `trample::deform::transition::cell_offset_and_flatness`, on the
//! blades the GPU left, after a run in which grass is pressed and comes
//! back to rest. The pass skips a cell whose blades are at rest and were at
//! rest when it last computed it (`AT_REST` in `cell.wgsl`): a cell whose
//! blades came back to rest must still be computed once more, so that it
//! holds exactly the rest values.

mod common;

use trample::deform::transition::cell_offset_and_flatness;
use trample_gpu::GpuSimulation;
use trample_testkit::scenes;

/// Slope and flatness difference allowed on a cell whose blades are away
/// from rest (the GPU's own rounding of sqrt and division).
const TOLERANCE: f32 = 1e-6;

/// Runs `frames` frames of the rolling ball with a short recovery (blades
/// come back to rest behind the ball) and `blades_per_cell` blades a cell,
/// then checks every cell against the CPU's function of the GPU's blades.
fn check_cells_follow_their_blades(blades_per_cell: u32, frames: u32) {
    let text = scenes::ROLLING_BALL
        .replace("recovery_s = 1.5", "recovery_s = 0.05")
        .replace(
            "cells_per_patch = 16 ",
            &format!("cells_per_patch = 16\nblades_per_cell = {blades_per_cell} "),
        );
    assert!(text.contains("recovery_s = 0.05") && text.contains("blades_per_cell"));
    let sim = scenes::build(&scenes::scene(&text));
    assert!(
        sim.params.track_everywhere,
        "the follow pass runs with track_everywhere"
    );
    let gpu = common::gpu();
    let (device, queue) = (&gpu.device, &gpu.queue);
    let dt = sim.params.dt_s;
    let mut g = GpuSimulation::new(device, queue, sim).expect("GPU simulation");
    // The blades away from rest a third of the way through.
    let mut early = Vec::new();
    for frame in 0..frames {
        g.step(device, queue, dt).unwrap();
        if frame == frames / 3 {
            let pos = g.field.read_positions(device, queue).unwrap();
            let bl = &g.sim.field.blades;
            early = (0..bl.count)
                .filter(|&b| {
                    (0..=bl.segments).any(|k| {
                        let (i, p) = (k * bl.count + b, pos[k * bl.count + b]);
                        glam::Vec3A::new(p[0], p[1], p[2]) != bl.rest[i].vec3a()
                    })
                })
                .collect();
        }
    }
    g.sync_to_cpu(device, queue).unwrap();
    let state = g
        .field
        .read_u32(device, queue, &g.field.cell_state)
        .unwrap();
    let sim = &g.sim;
    let (blades, cells) = (&sim.field.blades, &sim.field.cells);
    let bpc = sim.field.layout.blades_per_cell as usize;
    let mut recovered_cells = 0;
    let (mut rest_diff, mut worst) = (0, 0.0f32);
    for (c, &s) in state.iter().enumerate().take(cells.lod.len()) {
        let range = c * bpc..(c + 1) * bpc;
        let (off, flat) = cell_offset_and_flatness(blades, range.clone());
        let slope = cells.slope_origin[c] + off;
        if range.clone().all(|b| blades.is_at_rest(b)) {
            // Exactly the rest values, the bent flag clear.
            rest_diff += usize::from(
                cells.slope[c] != cells.slope_origin[c] || cells.flatness[c] != flat || s & 16 != 0,
            );
            recovered_cells += usize::from(s & 32 != 0);
        } else {
            let d = cells.slope[c]
                .distance(slope)
                .max((cells.flatness[c] - flat).abs());
            worst = worst.max(if d.is_nan() { f32::INFINITY } else { d });
        }
    }
    let back = early.iter().filter(|&&b| blades.is_at_rest(b)).count();
    eprintln!(
        "blades_per_cell {bpc}: {} blades away from rest at frame {}, {back} of them back \
         at rest at the end; {rest_diff} cells at rest off their rest values, worst other \
         cell {worst:e}",
        early.len(),
        frames / 3
    );
    assert!(
        back > 100,
        "the ball must press grass that comes back to rest for the test to mean anything \
         ({} away from rest, {back} back)",
        early.len()
    );
    assert_eq!(
        rest_diff, 0,
        "cells at rest must hold exactly their rest values"
    );
    assert!(
        recovered_cells > 0,
        "no cell was marked as computed at rest"
    );
    assert!(worst <= TOLERANCE, "worst cell difference {worst}");
}

#[test]
fn cells_follow_their_blades_back_to_rest() {
    check_cells_follow_their_blades(1, 150);
}

#[test]
fn cells_of_two_blades_follow_them_back_to_rest() {
    check_cells_follow_their_blades(2, 150);
}
