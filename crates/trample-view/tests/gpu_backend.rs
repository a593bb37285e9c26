//! The panel's backend choice, without a window: the app switches to the GPU
//! path on a headless device (`trample_render::headless`, which honours
//! `WGPU_BACKEND`; CI uses `gl`, Mesa llvmpipe), is driven by scripted keys
//! with live parameter edits and moves the grass as the CPU path does,
//! hands its state back to the CPU path, rebuilds on a reset, refuses a
//! scene it cannot run and survives a lost device on the CPU path. No
//! adapter is a test failure, not a skip.

use std::path::Path;
use trample::scene::Scene;
use trample_view::app::ShapeChoice;
use trample_view::input::Key;
use trample_view::{App, BackendKind, GpuDevice};

/// 4,096 blades (llvmpipe runs the GPU path slowly), recovery on.
const SCENE: &str = r#"
[field]
patches = [4, 4]
cells_per_patch = 16
[sim]
precision = 3
recovery_s = 0.5
# Every displaced blade every step: a field handed back from the GPU
# starts the strides' clocks again (`rescan_displaced`), which the CPU
# run compared with kept, so a blade could reach rest a step apart.
recovery_stride_m = 0.0
[[objects]]
name = "ball"
shape = { kind = "sphere", radius_m = 0.5, subdivisions = 2 }
orientation = "rolling"
path = { kind = "line", from = [-2.0, 0.5, 0.0], to = [2.0, 0.5, 0.0], duration_s = 4.0 }
"#;

fn device() -> GpuDevice {
    let gpu = trample_render::headless::create_device().unwrap_or_else(|e| {
        panic!("no GPU adapter for the viewer's GPU tests (set WGPU_BACKEND=gl for llvmpipe): {e}")
    });
    GpuDevice::new(gpu.device, gpu.queue, &gpu.adapter)
}

fn app(scene: &str) -> App {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    App::new(Scene::parse(scene, "test", &dir).unwrap()).unwrap()
}

/// `frames` frames of 1/60 s with `keys` held down, then released.
fn hold(app: &mut App, keys: &[Key], frames: usize) {
    for &k in keys {
        app.key(k, true, false);
    }
    for _ in 0..frames {
        app.update(1.0 / 60.0).unwrap();
    }
    for &k in keys {
        app.key(k, false, false);
    }
}

/// Largest distance between the same vertex of `a` and `b`, metres.
fn max_gap(a: &App, b: &App) -> f32 {
    let (a, b) = (&a.sim().field.blades.pos, &b.sim().field.blades.pos);
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(p, q)| p.vec3a().distance(q.vec3a()))
        .fold(0.0, f32::max)
}

/// Blades with a vertex away from rest, from the field itself.
fn bent(app: &App) -> usize {
    let bl = &app.sim().field.blades;
    (0..bl.count).filter(|&b| !bl.is_at_rest(b)).count()
}

#[test]
fn the_gpu_backend_drives_like_the_cpu_backend_and_hands_its_state_back() {
    let dev = device();
    let mut cpu = app(SCENE);
    let mut gpu = app(SCENE);
    gpu.attach_gpu(dev.clone());
    gpu.set_backend(BackendKind::Gpu).unwrap();
    assert_eq!(gpu.backend().kind(), BackendKind::Gpu);
    assert!(gpu.message.contains(&dev.adapter), "{}", gpu.message);

    // The same script on both: accelerate, then a live precision key and
    // attenuation edit, then turn; per-stage GPU times for the last part.
    for app in [&mut cpu, &mut gpu] {
        hold(app, &[Key::ArrowUp], 40);
        app.key(Key::BracketRight, true, false);
        app.key(Key::BracketRight, false, false);
        app.sim_mut().params.att = 0.9;
        app.stage_times = true;
        hold(app, &[Key::ArrowUp, Key::ArrowLeft], 20);
    }
    assert_eq!(gpu.backend().kind(), BackendKind::Gpu, "{}", gpu.message);
    assert_eq!(gpu.sim().params.precision, 4);
    assert_eq!(gpu.sim().frame, 60);
    let (pc, pg) = (cpu.sim().bodies[0].pose, gpu.sim().bodies[0].pose);
    assert!(pc.position.distance(pg.position) < 1e-5, "{pc:?} {pg:?}");
    assert!(pc.position.x > -2.0 + 1.5, "driven: {pc:?}");
    // The field stays on the GPU (drawn from there): read it back to compare.
    gpu.sync_field().unwrap();
    assert!(bent(&gpu) > 100, "{} blades bent", bent(&gpu));
    let gap = max_gap(&cpu, &gpu);
    assert!(gap < 1e-3, "GPU and CPU fields {gap} m apart");
    let (tc, tg) = (&cpu.sim().timings, &gpu.sim().timings);
    assert!(tc.dbg_blades > 0);
    assert_eq!(
        (tc.dbg_blades, tc.pbg_blades, tc.generations),
        (tg.dbg_blades, tg.pbg_blades, tg.generations)
    );
    assert_eq!(cpu.sim().class, gpu.sim().class, "whole-run classes");
    // Stage times come from the GPU's profiling mode while shown...
    assert!(tg.narrow_ms > 0.0 && tg.propagation_ms > 0.0, "{tg}");
    let stats = gpu.backend().gpu_stats().unwrap();
    assert!(stats.profiled && stats.readback_ms > 0.0, "{stats:?}");
    // ... and are not measured (0) otherwise.
    gpu.stage_times = false;
    cpu.stage_times = false;
    hold(&mut gpu, &[Key::ArrowUp], 1);
    hold(&mut cpu, &[Key::ArrowUp], 1);
    let tg = &gpu.sim().timings;
    assert!(!gpu.backend().gpu_stats().unwrap().profiled);
    assert!(tg.stages().iter().all(|(_, ms)| *ms == 0.0), "{tg}");
    assert!(tg.total_ms > 0.0 && tg.dbg_blades > 0, "{tg}");

    // Back to the CPU: the field carries over as it is...
    gpu.sync_field().unwrap();
    let before = gpu.sim().field.blades.pos.clone();
    gpu.set_backend(BackendKind::Cpu).unwrap();
    assert_eq!(gpu.backend().kind(), BackendKind::Cpu);
    assert_eq!(gpu.message, "simulating on the CPU");
    assert_eq!(gpu.sim().field.blades.pos, before);
    assert_eq!(gpu.sim().frame, 61);
    // ... and goes on as the CPU path's own: the ball coasts, the blades
    // bent on the GPU recover (1 s at τ = 0.5 s).
    hold(&mut cpu, &[], 60);
    hold(&mut gpu, &[], 60);
    let gap = max_gap(&cpu, &gpu);
    assert!(gap < 1e-3, "after the switch back: {gap} m apart");
    assert_eq!(
        gpu.sim().blades_away_from_rest(),
        cpu.sim().blades_away_from_rest()
    );
}

#[test]
fn a_scene_the_gpu_path_refuses_stays_on_the_cpu_with_a_message() {
    // Noise hills of 10 µm wavelength: the GPU's table of the lattice
    // would pass one storage binding.
    let hills = SCENE.replace(
        "cells_per_patch = 16",
        "cells_per_patch = 16\nterrain = { kind = \"noise\", amplitude_m = 0.05, wavelength_m = 0.00001 }",
    );
    let mut app = app(&hills);
    // No device lent: refused, and said so.
    let e = app.set_backend(BackendKind::Gpu).unwrap_err();
    assert!(e.contains("no GPU device"), "{e}");
    assert_eq!(app.backend().kind(), BackendKind::Cpu);
    app.attach_gpu(device());
    let e = app.set_backend(BackendKind::Gpu).unwrap_err();
    assert!(
        e.starts_with("GPU path refused")
            && e.contains("noise lattice")
            && e.ends_with("on the CPU"),
        "{e}"
    );
    assert_eq!(app.message, e, "the panel shows it");
    assert_eq!(app.backend().kind(), BackendKind::Cpu);
    assert!(app.backend().adapter().is_none());
    // The CPU path runs on.
    hold(&mut app, &[Key::ArrowUp], 40);
    assert_eq!(app.sim().frame, 40);
    assert!(app.sim().blades_away_from_rest() > 0);
}

#[test]
fn a_field_reset_on_the_gpu_rebuilds_it_with_the_new_density_and_shape() {
    let mut app = app(SCENE);
    app.attach_gpu(device());
    app.set_backend(BackendKind::Gpu).unwrap();
    hold(&mut app, &[Key::ArrowUp], 10);
    let blades = app.sim().field.blades.count;
    app.pending.blades_per_cell = 2;
    app.pending.shape = ShapeChoice::MeshFile;
    app.pending.mesh_path = "meshes/beetle.obj".into();
    app.key(Key::R, true, false);
    assert_eq!(app.message, format!("field reset: {} blades", 2 * blades));
    assert_eq!(app.backend().kind(), BackendKind::Gpu);
    assert_eq!(app.sim().field.blades.count, 2 * blades);
    assert_eq!(app.sim().bodies[0].object.mesh.triangle_count(), 2053);
    assert_eq!((app.sim().frame, bent(&app)), (0, 0), "at rest");
    // The 0.9 m beetle, centred 0.5 m up, reaches the 0.45 m blades when
    // driven a little lower: drive it, the GPU bends the new field.
    app.sim_mut().bodies[0].pose.position.y = 0.3;
    hold(&mut app, &[Key::ArrowUp], 30);
    assert_eq!(app.backend().kind(), BackendKind::Gpu, "{}", app.message);
    app.sync_field().unwrap();
    assert!(bent(&app) > 0);
}

#[test]
fn a_lost_device_puts_the_simulation_back_on_the_cpu_with_a_message() {
    let dev = device();
    let mut app = app(SCENE);
    app.attach_gpu(dev.clone());
    app.set_backend(BackendKind::Gpu).unwrap();
    hold(&mut app, &[Key::ArrowUp], 20);
    app.sync_field().unwrap();
    let bent_before = bent(&app);
    assert!(bent_before > 0);
    // As a driver reset or an unplugged GPU would.
    dev.device.destroy();
    hold(&mut app, &[Key::ArrowUp], 10);
    assert_eq!(app.backend().kind(), BackendKind::Cpu);
    assert!(
        app.message.starts_with("GPU error") && app.message.contains("on the CPU"),
        "{}",
        app.message
    );
    assert!(!app.message.contains('\n'));
    // The failed step is not retaken (its time may have passed on the
    // GPU side); the other nine ran on the CPU from the last state read back.
    assert!((29..=30).contains(&app.sim().frame), "{}", app.sim().frame);
    assert!(bent(&app) >= bent_before);
    // Asking for the GPU again says why not, and stays on the CPU.
    let e = app.set_backend(BackendKind::Gpu).unwrap_err();
    assert!(
        e.starts_with("GPU path refused") && e.contains("failed"),
        "{e}"
    );
    assert_eq!(app.backend().kind(), BackendKind::Cpu);
    assert!(app.gpu_failed().is_some());
    // A new device: the GPU path again, from the CPU's state.
    app.attach_gpu(device());
    assert!(app.gpu_failed().is_none());
    app.set_backend(BackendKind::Gpu).unwrap();
    let frame = app.sim().frame;
    hold(&mut app, &[Key::ArrowUp], 5);
    assert_eq!(app.backend().kind(), BackendKind::Gpu, "{}", app.message);
    assert_eq!(app.sim().frame, frame + 5);
}

#[test]
fn a_panic_inside_gpu_work_comes_back_as_a_message() {
    let dev = device();
    let out: Result<(), String> =
        trample_view::backend::guarded(&dev.device, || panic!("mapping refused"));
    assert_eq!(
        out.unwrap_err(),
        "GPU error: wgpu panicked: mapping refused"
    );
    // A validation error is caught by the scopes, not wgpu's panicking
    // default handler: a buffer larger than the device allows.
    let out = trample_view::backend::guarded(&dev.device, || {
        let _ = dev.device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size: u64::MAX / 4,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        Ok(())
    });
    assert!(out.unwrap_err().starts_with("GPU error: "));
}

/// Switching to the GPU in the middle of a run: the blades the CPU bent
/// must go on recovering on the GPU.
#[test]
fn blades_bent_on_the_cpu_recover_after_the_switch_to_the_gpu() {
    let mut cpu = app(SCENE);
    let mut gpu = app(SCENE);
    gpu.attach_gpu(device());
    for app in [&mut cpu, &mut gpu] {
        hold(app, &[Key::ArrowUp], 40);
    }
    gpu.set_backend(BackendKind::Gpu).unwrap();
    assert_eq!(max_gap(&cpu, &gpu), 0.0, "the field carries over");
    // The ball coasts to a stop; the track recovers (τ = 0.5 s).
    for app in [&mut cpu, &mut gpu] {
        hold(app, &[], 90);
    }
    assert_eq!(gpu.backend().kind(), BackendKind::Gpu, "{}", gpu.message);
    gpu.sync_field().unwrap();
    let gap = max_gap(&cpu, &gpu);
    assert!(gap < 1e-3, "GPU and CPU fields {gap} m apart");
}
