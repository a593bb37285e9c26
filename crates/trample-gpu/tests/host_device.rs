//! The GPU path on a device a host makes (issue 14 item 4): created with
//! `wgpu::Limits::default()` raised only by what `trample_gpu` publishes
//! (`required_limits`, `required_features`), it steps the busy scene and
//! builds the draw lists, bit for bit as on the test device with every
//! limit the adapter offers, with the steps recorded into the host's
//! encoders (`record_step`, several sub-steps a step) as with the
//! submit-for-you `step`; and the published limits are needed: the
//! default limits alone are refused with a message naming the limit, not
//! a wgpu panic; and so is a storage binding too small for one of the
//! whole-field arrays (the cells' rest boxes, the draw lists' billboards).

mod common;

use trample_gpu::draw_lists::GpuDrawParams;
use trample_gpu::{GpuError, GpuSimulation, required_features, required_limits};
use trample_testkit::scenes;

const FRAMES: u32 = 8;

/// The busy scene after [`FRAMES`] steps of 8 frames' time (several
/// sub-steps each), stepped by `step` or recorded into the host's encoder
/// (`host`), then the draw lists; the blade vertices.
fn run(gpu: &common::TestGpu, sim: &trample::Simulation, host: bool) -> Vec<[f32; 4]> {
    let (device, queue) = (&gpu.device, &gpu.queue);
    let mut g = GpuSimulation::new(device, queue, sim.clone()).expect("GPU simulation");
    let dt = sim.params.dt_s * 8.0;
    let mut substeps = 0;
    for _ in 0..FRAMES {
        if host {
            let mut enc = device.create_command_encoder(&Default::default());
            substeps += g.record_step(device, queue, &mut enc, dt).unwrap();
            queue.submit([enc.finish()]);
        } else {
            substeps += g.step(device, queue, dt).unwrap();
        }
    }
    assert!(substeps > FRAMES, "the steps must have several sub-steps");
    let mut enc = device.create_command_encoder(&Default::default());
    g.record_draw_lists(device, queue, &mut enc, GpuDrawParams::default());
    queue.submit([enc.finish()]);
    g.field.read_positions(device, queue).unwrap()
}

#[test]
fn a_device_with_the_published_limits_runs_the_gpu_path() {
    let sim = scenes::simulation(scenes::BUSY);
    let limits = required_limits(&sim);
    let default = trample_gpu::wgpu::Limits::default();
    eprintln!(
        "published: {} storage buffers a stage (default {}), binding {} bytes (default {})",
        limits.max_storage_buffers_per_shader_stage,
        default.max_storage_buffers_per_shader_stage,
        limits.max_storage_buffer_binding_size,
        default.max_storage_buffer_binding_size
    );
    let host = trample_testkit::gpu::test_gpu_exact(required_features(), limits);
    let full = common::gpu_without_timestamps();
    let a = run(&host, &sim, true);
    let b = run(&full, &sim, false);
    let c = run(&host, &sim, false);
    assert_eq!(a.len(), sim.field.blades.pos.len());
    assert!(c == b, "the host's device and the test device differ");
    assert!(a == b, "record_step and step differ");
    assert!(
        a.iter()
            .zip(&sim.field.blades.pos)
            .any(|(p, q)| p[1] != q.vec3a().y),
        "the run must move blades"
    );
}

#[test]
fn the_default_limits_alone_are_refused_with_a_message() {
    let sim = scenes::simulation(scenes::BUSY);
    let needed = trample_gpu::limits::storage_buffers_per_stage(false);
    let default = trample_gpu::wgpu::Limits::default();
    if needed <= default.max_storage_buffers_per_shader_stage {
        eprintln!("the step fits the default limits: nothing to refuse");
        return;
    }
    let host = trample_testkit::gpu::test_gpu_exact(required_features(), default);
    match GpuSimulation::new(&host.device, &host.queue, sim) {
        Err(GpuError::Limit(m)) => {
            eprintln!("{m}");
            assert!(m.contains("storage buffers") && m.contains("required_limits"));
        }
        Err(e) => panic!("wrong error: {e}"),
        Ok(_) => panic!("accepted a device below the step's needs"),
    }
}

/// A device whose storage binding holds the step's per-blade arrays but
/// not the cells' rest boxes (32 bytes a cell) is refused with a message
/// naming them, not a wgpu validation panic; one that holds the step but
/// not the draw lists' billboards (48 bytes a cell) is told so by
/// `supports_draw_lists`, before any list is made.
#[test]
fn a_binding_too_small_for_a_whole_field_array_is_refused_with_its_name() {
    // 65,536 cells of one blade and no object: the cells' arrays are the
    // largest bindings.
    let text = "[field]\npatches = [16, 16]\ncells_per_patch = 16\n";
    let sim = trample::scene::Scene::parse(text, "cells.toml", std::path::Path::new("."))
        .expect("scene")
        .build()
        .expect("simulation");
    assert!(sim.bodies.is_empty());
    let cells = sim.field.cells.lod.len() as u64;
    let blades = sim.field.blades.count as u64;
    assert!(
        32 * cells > 16 * blades,
        "the rest boxes are the largest array"
    );
    let with_binding = |bytes: u64| {
        let mut limits = required_limits(&sim);
        limits.max_storage_buffer_binding_size = bytes;
        trample_testkit::gpu::test_gpu_exact(required_features(), limits)
    };
    let host = with_binding(32 * cells - 4);
    match GpuSimulation::new(&host.device, &host.queue, sim.clone()) {
        Err(GpuError::TooLarge { what, bytes, .. }) => {
            eprintln!("{what}: {bytes} bytes");
            assert!(what.contains("rest boxes") && bytes == 32 * cells, "{what}");
        }
        Err(e) => panic!("wrong error: {e}"),
        Ok(_) => panic!("accepted a binding smaller than the cells' rest boxes"),
    }
    let host = with_binding(48 * cells - 4);
    let g = GpuSimulation::new(&host.device, &host.queue, sim.clone()).expect("the step fits");
    match g.supports_draw_lists(&host.device) {
        Err(GpuError::TooLarge { what, bytes, .. }) => {
            assert!(what.contains("billboard") && bytes == 48 * cells, "{what}");
        }
        other => panic!("draw lists over the binding not refused: {other:?}"),
    }
    let host = with_binding(48 * cells);
    let g = GpuSimulation::new(&host.device, &host.queue, sim).expect("the step fits");
    g.supports_draw_lists(&host.device).expect("the lists fit");
}
