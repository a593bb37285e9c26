//! Parity of the deformation and recovery stages alone (paper Eq. 5–7,
//! Fig. 7; DESIGN §6): the GPU's `bend` then `recover` passes against
//! `trample::deform::bend::bend_blade` then `trample::recovery::recover_blade`
//! on the same forces, over a generated field. Forces range from a nudge to
//! a flattening push, so the ground guard is exercised; contact weights
//! (Eq. 5's `num`) from a graze to three full segments, so recovery runs
//! partly (a blade an object holds does not recover).

mod common;

use glam::{Vec3, Vec3A};
use trample::deform::bend::{bend_blade, weights};
use trample::field::generate::GROUND_CLEARANCE_M;
use trample::field::{Field, FieldParams, MAX_SEGMENTS, Terrain};
use trample::recovery::{RECOVERY_TAIL_M, RecoveryParams, recover_blade};
use trample_gpu::{GpuCounters, GpuField, GpuForce, GpuStepParams};
use wgpu::util::DeviceExt;

/// Worst vertex difference allowed, metres: same steps in f32, with the
/// GPU's own rounding of sqrt and division (and fma where it fuses).
const TOLERANCE_M: f32 = 1e-5;

#[test]
fn bent_then_recovered_blades_match_the_cpu() {
    let gpu = common::gpu();
    let (device, queue) = (&gpu.device, &gpu.queue);
    let params = FieldParams {
        patches: [2, 2],
        cells_per_patch: 16,
        ..FieldParams::default()
    };
    let field = Field::generate(&params, Terrain::Flat(0.0)).unwrap();
    let (count, n) = (field.blades.count, field.blades.segments);
    let g = GpuField::from_field(device, queue, &field).unwrap();
    let h = 1.0 / 60.0;
    let recovery = RecoveryParams {
        recovery_s: 1.5,
        trail: 2.0,
    };
    // Every third blade gets a force: 0.1–300 m/s, contact weights 0.05–3.
    let mut seed = 0x0bad_5eed_1234_5678u64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 40) as f32 / (1u64 << 24) as f32
    };
    let forces: Vec<GpuForce> = (0..count)
        .map(|b| {
            if b % 3 != 0 {
                return GpuForce::default();
            }
            let dir = Vec3::new(next() * 2.0 - 1.0, next() - 0.7, next() * 2.0 - 1.0).normalize();
            let mag = 0.1 * 3000f32.powf(next());
            GpuForce {
                force: (dir * mag).to_array(),
                num: 0.05 + 2.95 * next(),
            }
        })
        .collect();
    g.write_forces(queue, &forces);

    let w = weights(n, 1.0, 2.0);
    let mut packed = [[0.0; 4]; 4];
    for (i, wi) in w.iter().enumerate() {
        packed[i / 4][i % 4] = *wi;
    }
    let groups_x = (count as u32).div_ceil(64);
    let step = GpuStepParams {
        a: [h, 0.5, 0.25, 0.0],
        b: [GROUND_CLEARANCE_M, recovery.recovery_s, recovery.trail, 1.0],
        weights: packed,
        // No generation passes: generation 0 for every blade with a force.
        counts: [count as u32, n as u32, 0, groups_x],
        eye: [0.0; 4],
        lod: [0.0; 4],
        cells: [0; 4],
        far: [0, 1, 0, 0],
    };
    let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytemuck::bytes_of(&step),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let state = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytemuck::bytes_of(&GpuCounters::default()),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
    });
    let groups = (groups_x, 1);
    let propagation = trample_gpu::propagation::Propagation::new(device);
    let bend = trample_gpu::bend::Bend::new(device);
    let mut recover = trample_gpu::recovery::Recovery::new(device);
    recover.write_owner_table(queue, &[recovery]);
    let mut enc = device.create_command_encoder(&Default::default());
    propagation.record_reset(device, &mut enc, &g, &uniform, &state);
    propagation.record(device, &mut enc, &g, &uniform, &state, groups, 0, None);
    bend.record(device, &mut enc, &g, &uniform, &state, None);
    queue.submit([enc.finish()]);
    let bent = g.read_positions(device, queue).unwrap();
    let mut enc = device.create_command_encoder(&Default::default());
    recover.record(device, &mut enc, &g, &uniform, &state, None);
    queue.submit([enc.finish()]);
    let recovered = g.read_positions(device, queue).unwrap();

    let bl = &field.blades;
    let (mut worst_bent, mut worst_recovered, mut flattened) = (0.0f32, 0.0f32, 0);
    // Blades recovering within the tail (`recovery::RECOVERY_TAIL_M`).
    let mut in_tail = 0;
    for (b, f) in forces.iter().enumerate() {
        let mut v = [Vec3A::ZERO; MAX_SEGMENTS + 1];
        let mut rest = [Vec3A::ZERO; MAX_SEGMENTS + 1];
        bl.load(b, &mut v);
        bl.load_rest(b, &mut rest);
        if f.num > 0.0 {
            let v1 = Vec3::from_array(f.force) * h;
            bend_blade(
                &mut v[..=n],
                bl.seg_len[b],
                v1,
                f.num,
                &w[..n],
                &field.terrain,
                GROUND_CLEARANCE_M,
            );
            flattened += usize::from(v[n].y < 0.5 * rest[n].y);
        }
        let diff = |got: &[[f32; 4]], v: &[Vec3A]| {
            (0..=n)
                .map(|k| {
                    Vec3A::new(
                        got[k * count + b][0],
                        got[k * count + b][1],
                        got[k * count + b][2],
                    )
                    .distance(v[k])
                })
                .fold(0.0f32, f32::max)
        };
        worst_bent = worst_bent.max(diff(&bent, &v));
        if f.num > 0.0 {
            let deviation = (0..=n)
                .map(|k| v[k].distance(rest[k]))
                .fold(0.0f32, f32::max);
            in_tail += usize::from(f.num < 1.0 && deviation < RECOVERY_TAIL_M);
            // Held by its contact weight (`step::recover`).
            recover_blade(
                &mut v[..=n],
                &rest[..=n],
                bl.seg_len[b],
                h * (1.0 - f.num.min(1.0)),
                &recovery,
                &field.terrain,
                GROUND_CLEARANCE_M,
            );
        }
        worst_recovered = worst_recovered.max(diff(&recovered, &v));
    }
    eprintln!(
        "{} forced blades ({flattened} flattened below half height, {in_tail} recovering within the tail): worst vertex difference {worst_bent:e} m after bending, {worst_recovered:e} m after recovery",
        count.div_ceil(3)
    );
    assert!(flattened > 10, "the ground guard was hardly exercised");
    assert!(in_tail > 10, "the recovery's tail was hardly exercised");
    assert!(worst_bent <= TOLERANCE_M && worst_recovered <= TOLERANCE_M);
}
