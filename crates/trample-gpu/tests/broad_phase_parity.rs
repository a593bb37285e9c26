//! The GPU broad phase lists the patches the CPU's does
//! (`trample::collision::broad_phase::patches_hit`, paper §4 stage 2): four
//! objects (sphere, rotated box, knot, capsule) at 120 instants of their
//! paths, on a field cut into three chunks. The GPU's list must hold every
//! patch of the CPU's (it tests with twice the CPU's slack); measured on
//! llvmpipe (GL), 2026-11-21: the lists are equal at every instant, and
//! that is asserted (a wider slack that lists one more patch fails here:
//! then say so and allow it).

mod common;

use trample::collision::broad_phase::patches_hit;
use trample::scene::Scene;
use trample_gpu::GpuField;
use trample_gpu::broad_phase::BroadPhase;
use trample_gpu::cells::GpuWorldObb;
use wgpu::util::DeviceExt;

const SCENE: &str = r#"
name = "gpu-broad-phase"
[field]
patches = [8, 8]
cells_per_patch = 8              # 0.8 m patches, 6.4 m square
[sim]
precision = 4
[[objects]]
name = "ball"
shape = { kind = "sphere", radius_m = 0.4 }
orientation = "rolling"
path = { kind = "circle", center = [0.0, 0.4, 0.0], radius_m = 2.2, period_s = 4.0 }
[[objects]]
name = "crate"
shape = { kind = "box", half_extents_m = [0.3, 0.25, 0.45] }
rotation_deg = [0.0, 30.0, 15.0]
orientation = "face_motion"
path = { kind = "circle", center = [0.3, 0.2, -0.3], radius_m = 1.6, period_s = 7.0, phase_rad = 2.0 }
[[objects]]
name = "knot"
shape = { kind = "knot", size_m = 0.8 }
path = { kind = "circle", center = [-0.7, 0.35, 0.6], radius_m = 2.8, period_s = 5.5, phase_rad = 4.0 }
[[objects]]
name = "pill"
shape = { kind = "capsule", radius_m = 0.2, length_m = 0.6 }
rotation_deg = [0.0, 0.0, 90.0]
orientation = "face_motion"
path = { kind = "circle", center = [0.2, 0.2, 0.2], radius_m = 3.0, period_s = 3.0, phase_rad = 1.0 }
"#;

#[test]
fn gpu_lists_the_patches_the_cpu_broad_phase_hits() {
    let gpu = common::gpu();
    let (device, queue) = (&gpu.device, &gpu.queue);
    let mut sim = Scene::parse(SCENE, "broad.toml", std::path::Path::new("."))
        .and_then(|s| s.build())
        .expect("scene builds");
    let layout = sim.field.layout.clone();
    // 64 patches of 64 blades × 5 vertices × 16 bytes: chunks of 24, 24, 16 patches.
    let field =
        GpuField::from_field_chunked(device, queue, &sim.field, Some(24 * 64 * 5 * 16)).unwrap();
    assert_eq!(field.chunks.len(), 3);
    let n = sim.bodies.len();
    let broad = BroadPhase::new(device, &field, &layout, n as u32).unwrap();
    let roots = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: &vec![0u8; n * std::mem::size_of::<GpuWorldObb>()],
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
    });
    let mut listed = 0usize;
    let mut hits = Vec::new();
    for i in 0..120 {
        let t = i as f32 * 0.1;
        let mut cpu = Vec::new();
        let mut boxes = Vec::new();
        for body in &mut sim.bodies {
            body.set_time(t);
            patches_hit(&layout.patch_list, &body.world_root, &mut hits);
            cpu.extend_from_slice(&hits);
            boxes.push(GpuWorldObb::new(&body.world_root, &layout, 0.3));
        }
        cpu.sort_unstable();
        cpu.dedup();
        queue.write_buffer(&roots, 0, bytemuck::cast_slice(&boxes));
        let mut enc = device.create_command_encoder(&Default::default());
        broad.record(device, &mut enc, &roots);
        queue.submit([enc.finish()]);
        let got = broad.read_patches(device, queue).unwrap();
        let missing: Vec<_> = cpu.iter().filter(|p| !got.contains(p)).collect();
        assert!(
            missing.is_empty(),
            "t = {t}: GPU misses patches {missing:?}"
        );
        assert_eq!(got, cpu, "t = {t}: extra patches");
        listed += got.len();
    }
    // The objects do touch the field, at different patches over time.
    assert!(listed > 120, "{listed} patches listed over 120 instants");
    eprintln!("broad phase: {listed} patches listed over 120 instants, none extra");
}
