//! Parity of the propagation stage alone (paper §5.2, Eq. 4): the GPU's
//! generation passes against `trample::force::propagation::propagate_forces`
//! on the same DBG forces, over a generated field's neighbour table (it
//! crosses patch borders). Generations must be identical and forces equal
//! (both sum the same terms in the same order). Twice: with the paper's
//! hard threshold and every ancestor wholly held, and with the
//! simulation's fade-in and ancestors held by their contact weights (some
//! lightly: they take part of a neighbour's push, on both paths).

mod common;

use glam::Vec3;
use trample::field::{Field, FieldParams, Terrain};
use trample::force::propagation::{NO_GENERATION, PropagationParams, propagate_forces};
use trample_gpu::readback::read_buffer;
use trample_gpu::{GpuCounters, GpuField, GpuForce, GpuStepParams};
use wgpu::util::DeviceExt;

#[test]
fn generations_and_forces_match_the_cpu() {
    let gpu = common::gpu();
    for (fade, hold) in [
        (0.0, 0.0),
        (trample::force::propagation::THRESHOLD_FADE, 0.1),
    ] {
        compare(&gpu.device, &gpu.queue, fade, hold);
    }
}

fn compare(device: &wgpu::Device, queue: &wgpu::Queue, fade: f32, hold: f32) {
    let params = FieldParams {
        patches: [4, 4],
        cells_per_patch: 8,
        ..FieldParams::default()
    };
    let field = Field::generate(&params, Terrain::Flat(0.0)).unwrap();
    let count = field.blades.count;
    let g = GpuField::from_field(device, queue, &field).unwrap();
    let full = PropagationParams {
        att: 0.5,
        threshold: 0.25,
        max_generations: 32,
        threshold_fade: fade,
        hold_weight: hold,
    };
    // Deterministic DBG blades with horizontal-ish forces of 0.3–6 m/s.
    let mut seed = 0x1234_5678_9abc_def0u64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 40) as f32 / (1u64 << 24) as f32
    };
    let mut start = vec![Vec3::ZERO; count];
    let mut weight = vec![0.0f32; count];
    let mut dbg = Vec::new();
    for _ in 0..120 {
        let b = (next() * count as f32) as usize % count;
        let f = Vec3::new(next() * 2.0 - 1.0, next() * 0.2, next() * 2.0 - 1.0).normalize()
            * (0.3 + 5.7 * next());
        if start[b] == Vec3::ZERO {
            start[b] = f;
            // Contact weights from a graze to firmly held (all 1 for the paper).
            weight[b] = if hold > 0.0 { 0.02 + 0.2 * next() } else { 1.0 };
            dbg.push(b as u32);
        }
    }
    dbg.sort_unstable();
    // Cut at 3 generations, then in full, on the same GPU field: the
    // candidates left listed at the cap must not hide any from the next
    // sub-step.
    for cap in [3, full.max_generations] {
        let prop = PropagationParams {
            max_generations: cap,
            ..full
        };
        run(device, queue, &field, &g, &prop, &start, &weight, &dbg);
    }
}

/// One sub-step's propagation on `g` from `start` forces against the CPU's.
#[allow(clippy::too_many_arguments)]
fn run(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    field: &Field,
    g: &GpuField,
    prop: &PropagationParams,
    start: &[Vec3],
    weight: &[f32],
    dbg: &[u32],
) {
    let (fade, hold) = (prop.threshold_fade, prop.hold_weight);
    let count = field.blades.count;
    let mut force = start.to_vec();
    let gpu_forces: Vec<GpuForce> = force
        .iter()
        .zip(weight)
        .map(|(f, &w)| GpuForce {
            force: f.to_array(),
            num: w,
        })
        .collect();
    g.write_forces(queue, &gpu_forces);

    let groups_x = (count as u32).div_ceil(64);
    let step = GpuStepParams {
        a: [1.0 / 60.0, prop.att, prop.threshold, 0.0],
        b: [0.002, 0.0, 0.0, 0.0],
        weights: [[0.0; 4]; 4],
        counts: [
            count as u32,
            field.blades.segments as u32,
            prop.max_generations,
            groups_x,
        ],
        eye: [0.0; 4],
        lod: [0.0, fade, hold, 0.0],
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
    let kernel = trample_gpu::propagation::Propagation::new(device);
    let mut enc = device.create_command_encoder(&Default::default());
    kernel.record_reset(device, &mut enc, g, &uniform, &state);
    kernel.record(
        device,
        &mut enc,
        g,
        &uniform,
        &state,
        (groups_x, 1),
        prop.max_generations,
        None,
    );
    queue.submit([enc.finish()]);

    let mut generation = vec![NO_GENERATION; count];
    let cpu = propagate_forces(
        dbg,
        &field.layout.neighbours,
        &mut force,
        &mut generation,
        weight,
        prop,
    );
    let gpu_gen = g.read_u32(device, queue, &g.generation).unwrap();
    let gpu_force = g.read_forces(device, queue).unwrap();
    let counters: Vec<GpuCounters> = read_buffer(device, queue, &state, "counters").unwrap();
    assert!(cpu.pbg.len() > 100, "only {} PBG blades", cpu.pbg.len());
    // The cut run must stop at its cap, the full one go past it.
    if prop.max_generations == 3 {
        assert_eq!(cpu.generations, 3, "the cap must cut propagation");
    } else {
        assert!(cpu.generations > 3, "{} generations", cpu.generations);
    }
    let taken = cpu
        .pbg
        .iter()
        .filter(|&&b| weight[b as usize] > 0.0)
        .count();
    if hold > 0.0 {
        assert!(taken > 5, "only {taken} lightly held ancestors took a push");
    }
    eprintln!(
        "cap {}, fade {fade}, hold {hold}: {} DBG ({taken} of them also pushed), {} PBG over {} generations (GPU: {} PBG, {} generations)",
        prop.max_generations,
        dbg.len(),
        cpu.pbg.len(),
        cpu.generations,
        counters[0].pbg,
        counters[0].generations
    );
    assert_eq!(counters[0].pbg as usize, cpu.pbg.len());
    assert_eq!(counters[0].generations, cpu.generations);
    for b in 0..count {
        assert_eq!(gpu_gen[b], u32::from(generation[b]), "blade {b}");
        let d = Vec3::from_array(gpu_force[b].force) - force[b];
        assert!(
            d.length() <= 1e-6 * (1.0 + force[b].length()),
            "blade {b}: {d}"
        );
    }
}
