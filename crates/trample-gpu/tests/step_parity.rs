//! Whole-run parity: `GpuSimulation::step` against `Simulation::step` on
//! the same scene for 300 frames (a four-object scene for 200; a scene with
//! a moving camera, so that cells change level, billboards bend and
//! transitions run, for 300); the rolling ball over value-noise hills and
//! over a height map (200 each: the ground guard on terrain).
//! Reports the worst vertex and billboard-slope differences and the DBG/PBG
//! and LOD differences; asserts them within the stated tolerances.

mod common;

use trample::Simulation;
use trample::scene::Scene;
use trample_gpu::GpuSimulation;

/// Worst vertex distance allowed after the run, metres. The two paths take
/// the same steps in f32, but the GPU may fuse multiply-adds and rounds
/// `sqrt`, `exp` and quaternion rotations its own way; a blade whose hit
/// flag then flips at a tie bends one step more or less (a few mm); the
/// bends stack over the run. Measured on llvmpipe (GL), 2026-11-21:
/// 1.3e-5 m (rolling ball, 300 frames), 4.0e-6 m (four objects, 200),
/// 4.8e-6 m (moving camera with billboards and transitions, 300); 4.7e-6 m
/// over noise hills and 6.0e-6 m over a height map (200 each; with the
/// GPU's guard on flat ground instead, 0.25 m and 0.48 m: the tests see
/// the terrain).
const VERTEX_TOLERANCE_M: f32 = 1e-3;

/// Blades whose class (untouched / DBG / PBG) may differ at the end, as a
/// fraction of the field: a flipped tie changes a blade's class. Measured
/// on llvmpipe: 0 in both runs, and the DBG/PBG counts equal in every frame.
const CLASS_TOLERANCE: f64 = 0.002;

const ROLLING_BALL: &str = r#"
name = "gpu-parity"
[field]
patches = [4, 4]
cells_per_patch = 16             # 4 * 16 * 0.1 = 6.4 m square, 4,096 blades
[lod]
geometry_m = 500.0               # every cell geometric: LOD is not on the GPU yet
billboard_m = 600.0
[sim]
precision = 5
recovery_s = 1.5
[camera]
path = { kind = "line", from = [-4.0, 2.0, 3.0], to = [4.0, 2.0, 3.0], duration_s = 5.0 }
look_at = { kind = "point", at = [0.0, 0.0, 0.0] }
[[objects]]
name = "ball"
shape = { kind = "sphere", radius_m = 0.5 }
orientation = "rolling"
path = { kind = "line", from = [-3.5, 0.5, 0.2], to = [3.5, 0.5, -0.3], duration_s = 5.0 }
"#;

const FOUR_OBJECTS: &str = r#"
name = "gpu-parity-busy"
[field]
patches = [3, 3]
cells_per_patch = 16
[lod]
geometry_m = 500.0
billboard_m = 600.0
[sim]
precision = 7
recovery_s = 2.0
[camera]
path = { kind = "circle", center = [0.0, 2.0, 0.0], radius_m = 3.2, period_s = 9.0 }
look_at = { kind = "point", at = [0.0, 0.0, 0.0] }
[[objects]]
name = "ball"
shape = { kind = "sphere", radius_m = 0.4 }
orientation = "rolling"
path = { kind = "circle", center = [0.0, 0.4, 0.0], radius_m = 1.2, period_s = 4.0 }
[[objects]]
name = "crate"
shape = { kind = "box", half_extents_m = [0.3, 0.25, 0.45] }
orientation = "face_motion"
path = { kind = "circle", center = [0.3, 0.2, -0.3], radius_m = 1.6, period_s = 7.0, phase_rad = 2.0 }
[[objects]]
name = "knot"
shape = { kind = "knot", size_m = 0.8 }
path = { kind = "circle", center = [-0.7, 0.35, 0.6], radius_m = 0.8, period_s = 5.5, phase_rad = 4.0 }
[[objects]]
name = "pill"
shape = { kind = "capsule", radius_m = 0.2, length_m = 0.6 }
rotation_deg = [0.0, 0.0, 90.0]
orientation = "face_motion"
path = { kind = "circle", center = [0.2, 0.2, 0.2], radius_m = 1.9, period_s = 3.0, phase_rad = 1.0 }
"#;

const LOD_SCENE: &str = r#"
name = "gpu-parity-lod"
[field]
patches = [6, 6]
cells_per_patch = 16             # 9.6 m square, 9,216 blades
[lod]
geometry_m = 2.5                 # the camera's moves change levels: transitions
billboard_m = 5.0
[sim]
precision = 3
recovery_s = 3.0
[camera]
path = { kind = "line", from = [-5.0, 1.5, 1.0], to = [5.0, 1.5, 1.0], duration_s = 5.0 }
look_at = { kind = "object", name = "ball" }
[[objects]]
name = "ball"
shape = { kind = "sphere", radius_m = 0.5 }
orientation = "rolling"
path = { kind = "line", from = [-4.5, 0.5, -1.0], to = [4.5, 0.5, 0.5], duration_s = 5.0 }
[[objects]]
name = "crate"
shape = { kind = "box", half_extents_m = [0.3, 0.25, 0.45] }
orientation = "face_motion"
path = { kind = "line", from = [4.0, 0.2, -3.0], to = [-4.0, 0.2, 3.5], duration_s = 5.0 }
"#;

/// Worst billboard-slope difference allowed (dimensionless; slopes are
/// directions of length ≈ 1). Measured on llvmpipe (GL), 2026-11-21:
/// 3.5e-6 (LOD scene, 300 frames, 1,389 bent billboards).
const SLOPE_TOLERANCE: f32 = 1e-3;

/// The scene of `text` with relative paths (a height map) in `dir`.
fn build_in(text: &str, dir: &std::path::Path) -> Simulation {
    Scene::parse(text, "parity.toml", dir)
        .and_then(|s| s.build())
        .expect("scene builds")
}

/// Runs both paths for `frames`; returns (worst vertex distance, class
/// differences, frames whose DBG count differs, frames whose PBG count differs).
fn run_both(text: &str, frames: u32) -> (f32, usize, u32, u32) {
    run_both_in(text, std::path::Path::new("."), frames)
}

/// [`run_both`] with the scene's relative paths in `dir`.
fn run_both_in(text: &str, dir: &std::path::Path, frames: u32) -> (f32, usize, u32, u32) {
    let gpu = common::gpu();
    let (device, queue) = (&gpu.device, &gpu.queue);
    let mut cpu = build_in(text, dir);
    let mut g = GpuSimulation::new(device, queue, cpu.clone()).expect("GPU simulation");
    let dt = cpu.params.dt_s;
    let (mut dbg_frames, mut pbg_frames, mut touched) = (0, 0, 0u64);
    for _ in 0..frames {
        cpu.step(dt).unwrap();
        g.step(device, queue, dt).unwrap();
        let c = g.read_counters(device, queue).unwrap();
        dbg_frames += u32::from(c.dbg != cpu.timings.dbg_blades);
        pbg_frames += u32::from(c.pbg != cpu.timings.pbg_blades);
        touched += u64::from(cpu.timings.dbg_blades);
    }
    assert!(
        touched > 100,
        "the object must touch grass for the test to mean anything"
    );
    let pos = g.field.read_positions(device, queue).unwrap();
    let bl = &cpu.field.blades;
    let mut worst = 0.0f32;
    for (i, p) in pos.iter().enumerate() {
        let d = glam::Vec3A::new(p[0], p[1], p[2]).distance(bl.pos[i]);
        worst = worst.max(if d.is_nan() { f32::INFINITY } else { d });
    }
    let class = g.field.read_u32(device, queue, &g.field.class).unwrap();
    let class_diff = class
        .iter()
        .zip(&cpu.class)
        .filter(|(a, b)| **a != u32::from(**b))
        .count();
    let moved = (0..bl.count).filter(|&b| !bl.is_at_rest(b)).count();
    let cells = &cpu.field.cells;
    let state = g
        .field
        .read_u32(device, queue, &g.field.cell_state)
        .unwrap();
    let lod_diff = (0..cells.lod.len())
        .filter(|&c| state[c] & 3 != cells.lod[c] as u32)
        .count();
    let slopes: Vec<[f32; 4]> =
        trample_gpu::readback::read_buffer(device, queue, &g.field.slope, "slopes").unwrap();
    let (mut worst_slope, mut bent) = (0.0f32, 0);
    for (c, s) in slopes.iter().enumerate() {
        let d = glam::Vec3::new(s[0], s[1], s[2]).distance(cells.slope[c]);
        worst_slope = worst_slope.max(if d.is_nan() { f32::INFINITY } else { d });
        bent += usize::from(!cells.slope_at_rest(c));
        if d > 1e-3 && std::env::var("DEBUG_SLOPES").is_ok() {
            eprintln!(
                "cell {c}: lod {:?} state {:05b} gpu {s:?} cpu {} origin {}",
                cells.lod[c], state[c], cells.slope[c], cells.slope_origin[c]
            );
        }
    }
    eprintln!(
        "{frames} frames, {} blades ({moved} away from rest on the CPU), {} cells ({bent} bent billboards): \
         worst vertex difference {worst:e} m, worst slope difference {worst_slope:e}, \
         {class_diff} class differences, {lod_diff} LOD differences, \
         DBG count differs in {dbg_frames} frames, PBG in {pbg_frames}",
        bl.count,
        cells.lod.len()
    );
    assert_eq!(lod_diff, 0, "levels of detail differ");
    assert!(
        worst_slope <= SLOPE_TOLERANCE,
        "worst slope difference {worst_slope}"
    );
    (worst, class_diff, dbg_frames, pbg_frames)
}

#[test]
fn rolling_ball_300_frames_matches_the_cpu() {
    let (worst, class_diff, _, _) = run_both(ROLLING_BALL, 300);
    assert!(
        worst <= VERTEX_TOLERANCE_M,
        "worst vertex difference {worst} m"
    );
    assert!(
        class_diff as f64 <= CLASS_TOLERANCE * 4096.0,
        "{class_diff} class differences"
    );
}

#[test]
fn four_objects_200_frames_match_the_cpu() {
    let (worst, class_diff, _, _) = run_both(FOUR_OBJECTS, 200);
    assert!(
        worst <= VERTEX_TOLERANCE_M,
        "worst vertex difference {worst} m"
    );
    assert!(
        class_diff as f64 <= CLASS_TOLERANCE * 2304.0,
        "{class_diff} class differences"
    );
}

#[test]
fn moving_camera_with_billboards_and_transitions_300_frames_matches_the_cpu() {
    let (worst, class_diff, _, _) = run_both(LOD_SCENE, 300);
    assert!(
        worst <= VERTEX_TOLERANCE_M,
        "worst vertex difference {worst} m"
    );
    assert!(
        class_diff as f64 <= CLASS_TOLERANCE * 9216.0,
        "{class_diff} class differences"
    );
}

/// The rolling ball's scene with `terrain` (a TOML inline table) under the
/// field, the ball's path lifted by `lift` metres over the hills.
fn on_terrain(terrain: &str) -> String {
    ROLLING_BALL
        .replace(
            "cells_per_patch = 16             # 4 * 16 * 0.1 = 6.4 m square, 4,096 blades",
            &format!("cells_per_patch = 16\nterrain = {terrain}"),
        )
        .replace(
            "from = [-3.5, 0.5, 0.2], to = [3.5, 0.5, -0.3]",
            "from = [-3.5, 0.55, 0.2], to = [3.5, 0.55, -0.3]",
        )
}

#[test]
fn rolling_ball_over_noise_hills_matches_the_cpu() {
    let text =
        on_terrain(r#"{ kind = "noise", amplitude_m = 0.25, wavelength_m = 1.3, seed = 7 }"#);
    assert!(text.contains("noise"));
    let (worst, class_diff, _, _) = run_both(&text, 200);
    assert!(
        worst <= VERTEX_TOLERANCE_M,
        "worst vertex difference {worst} m"
    );
    assert!(
        class_diff as f64 <= CLASS_TOLERANCE * 4096.0,
        "{class_diff} class differences"
    );
}

#[test]
fn rolling_ball_over_a_height_map_matches_the_cpu() {
    let dir = std::env::temp_dir().join(format!("trample-gpu-heightmap-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // 33 × 33 samples: a ridge across the ball's path and a slope.
    let img = image::ImageBuffer::from_fn(33, 33, |x, z| {
        let ridge = (-((x as f32 - 16.0) / 4.0).powi(2)).exp();
        let v = 0.6 * ridge + 0.4 * z as f32 / 32.0;
        image::Luma([(v * 65535.0) as u16])
    });
    img.save(dir.join("hills.png")).unwrap();
    let text = on_terrain(r#"{ kind = "heightmap", path = "hills.png", height_scale_m = 0.3 }"#);
    let (worst, class_diff, _, _) = run_both_in(&text, &dir, 200);
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(
        worst <= VERTEX_TOLERANCE_M,
        "worst vertex difference {worst} m"
    );
    assert!(
        class_diff as f64 <= CLASS_TOLERANCE * 4096.0,
        "{class_diff} class differences"
    );
}

/// A simulation handed to the GPU mid-run (as the viewer's backend switch
/// does) carries its state over: blades the CPU bent go on recovering on
/// the GPU (they start in the displaced set) and the classes so far are
/// kept. 120 frames on the CPU, then 120 on both paths.
#[test]
fn a_simulation_handed_over_mid_run_goes_on_like_the_cpu() {
    let gpu = common::gpu();
    let (device, queue) = (&gpu.device, &gpu.queue);
    let mut cpu = build_in(ROLLING_BALL, std::path::Path::new("."));
    let dt = cpu.params.dt_s;
    for _ in 0..120 {
        cpu.step(dt).unwrap();
    }
    let bent = (0..cpu.field.blades.count)
        .filter(|&b| !cpu.field.blades.is_at_rest(b))
        .count();
    assert!(bent > 100, "only {bent} blades bent before the hand-over");
    let mut g = GpuSimulation::new(device, queue, cpu.clone()).unwrap();
    let class = g.field.read_u32(device, queue, &g.field.class).unwrap();
    assert!(
        class
            .iter()
            .zip(&cpu.class)
            .all(|(a, b)| *a == u32::from(*b))
    );
    for _ in 0..120 {
        cpu.step(dt).unwrap();
        g.step(device, queue, dt).unwrap();
    }
    let pos = g.field.read_positions(device, queue).unwrap();
    let worst = pos
        .iter()
        .zip(&cpu.field.blades.pos)
        .map(|(p, q)| glam::Vec3A::new(p[0], p[1], p[2]).distance(*q))
        .fold(0.0f32, f32::max);
    eprintln!(
        "hand-over after 120 frames, 120 more: worst vertex difference {worst:e} m ({bent} blades bent at the hand-over)"
    );
    assert!(
        worst <= VERTEX_TOLERANCE_M,
        "worst vertex difference {worst} m"
    );
}
