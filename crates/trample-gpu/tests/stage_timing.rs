//! Per-stage GPU times of `GpuSimulation`'s profiling mode (issue 4, item
//! 4): timestamp queries on a device that has them (both Mesa drivers do
//! through wgpu 29), wall time per stage on one created without them. In
//! either way every stage time is non-negative, their sum fits in the
//! step's wall time, and the narrow phase takes time when an object touches
//! the field. Speed itself is not asserted.

mod common;

use std::time::Instant;

use common::TestGpu;
use trample::object::PathParams;
use trample::scene::Scene;
use trample_gpu::{GpuSimulation, StageTiming, TIMESTAMP_FEATURES};
use trample_testkit::scenes;

/// A ball crossing 60 m a step (3.6 km/s at 60 steps/s) far from a small
/// field: 600 sub-steps of at most 0.1 m (the cell size), 4,200
/// timestamps, more than one query set holds
/// (`trample_gpu::profile::MAX_QUERIES`, 4,096).
const BULLET: &str = r#"
name = "gpu-stage-timing-substeps"
[field]
patches = [1, 1]
cells_per_patch = 8
[lod]
geometry_m = 500.0
billboard_m = 600.0
[sim]
precision = 3
max_substeps = 1024
[camera]
path = { kind = "line", from = [-4.0, 2.0, 3.0], to = [4.0, 2.0, 3.0], duration_s = 5.0 }
look_at = { kind = "point", at = [0.0, 0.0, 0.0] }
[[objects]]
name = "bullet"
shape = { kind = "sphere", radius_m = 0.05 }
path = { kind = "line", from = [-1800.0, 5.0, 0.0], to = [1800.0, 5.0, 0.0], duration_s = 1.0 }
"#;

/// The test kit's rolling ball, resting in the middle of its 4,096-blade
/// field: it touches blades in every step.
fn resting_ball() -> Scene {
    let mut scene = scenes::scene(scenes::ROLLING_BALL);
    scene.file.objects[0].path = PathParams::Static {
        position: [0.0, 0.45, 0.0],
    };
    scene
}

fn build(gpu: &TestGpu, scene: &Scene) -> GpuSimulation {
    GpuSimulation::new(&gpu.device, &gpu.queue, scenes::build(scene)).expect("GPU simulation")
}

/// Steps `g` `frames` times in profiling mode and checks each step's stage
/// times; returns the largest number of sub-steps seen.
fn check_steps(gpu: &TestGpu, g: &mut GpuSimulation, frames: u32, touching: bool) -> u32 {
    let (device, queue) = (&gpu.device, &gpu.queue);
    g.set_profiling(true);
    let dt = g.sim.params.dt_s;
    let mut most = 0;
    for frame in 0..frames {
        let clock = Instant::now();
        let substeps = g.step(device, queue, dt).unwrap();
        let wall_ms = clock.elapsed().as_secs_f64() * 1e3;
        most = most.max(substeps);
        let t = g.sim.timings.clone();
        let stages = [
            ("lod", t.lod_ms),
            ("narrow", t.narrow_ms),
            ("propagation", t.propagation_ms),
            ("deformation", t.deformation_ms),
            ("transitions", t.transitions_ms),
            ("recovery", t.recovery_ms),
        ];
        let sum: f64 = stages.iter().map(|s| s.1).sum();
        eprintln!(
            "{} frame {frame}: {substeps} sub-step(s), {wall_ms:.2} ms wall, stages {stages:?} (sum {sum:.3} ms)",
            g.stage_timing().name()
        );
        for (name, ms) in stages {
            assert!(ms.is_finite() && ms >= 0.0, "{name}: {ms} ms");
        }
        assert!(
            sum <= wall_ms && sum <= t.total_ms,
            "stage sum {sum} ms over the step's wall time {wall_ms} ms (total_ms {})",
            t.total_ms
        );
        assert!(t.lod_ms > 0.0, "the LOD stage runs in every sub-step");
        if touching {
            let dbg = g.read_counters(device, queue).unwrap().dbg;
            assert!(
                dbg > 0,
                "the ball must touch blades for the test to mean anything"
            );
            assert!(
                t.narrow_ms > 0.0,
                "narrow phase {} ms with {dbg} DBG blades",
                t.narrow_ms
            );
        }
    }
    most
}

#[test]
fn profiling_times_each_stage_with_timestamps_where_the_device_has_them() {
    let gpu = common::gpu();
    let offered = gpu.adapter.features().contains(TIMESTAMP_FEATURES);
    eprintln!(
        "adapter: {}, timestamp features offered: {offered}",
        gpu.adapter_name()
    );
    assert_eq!(
        gpu.device.features().contains(TIMESTAMP_FEATURES),
        offered,
        "the test device must enable the timestamp features the adapter offers"
    );
    let mut g = build(&gpu, &resting_ball());
    let expected = if offered {
        StageTiming::Timestamp
    } else {
        StageTiming::Wall
    };
    assert_eq!(g.stage_timing(), expected);
    // Not profiling: no stage time, only the recording time.
    g.step(&gpu.device, &gpu.queue, g.sim.params.dt_s).unwrap();
    let t = &g.sim.timings;
    assert_eq!(
        [
            t.lod_ms,
            t.narrow_ms,
            t.propagation_ms,
            t.deformation_ms,
            t.transitions_ms,
            t.recovery_ms
        ],
        [0.0; 6]
    );
    check_steps(&gpu, &mut g, 5, true);
}

#[test]
fn without_the_timestamp_features_profiling_falls_back_to_wall_time() {
    let gpu = common::gpu_without_timestamps();
    let mut g = build(&gpu, &resting_ball());
    assert_eq!(g.stage_timing(), StageTiming::Wall);
    assert_eq!(g.stage_timing().name(), "wall");
    check_steps(&gpu, &mut g, 3, true);
}

#[test]
fn a_step_with_more_timestamps_than_one_query_set_holds_is_read_back_in_parts() {
    let gpu = common::gpu();
    let mut g = build(&gpu, &scenes::scene(BULLET));
    let most = check_steps(&gpu, &mut g, 1, false);
    assert!(
        most * 7 > trample_gpu::profile::MAX_QUERIES,
        "{most} sub-steps do not fill a query set"
    );
}
