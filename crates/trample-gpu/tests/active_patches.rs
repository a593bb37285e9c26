//! The active patches (`trample_gpu::active_patches`): the GPU's field-wide
//! passes run over lists of patches made from two marks a patch, dirty and
//! kept. The marks must cover every blade's state — a patch holding a
//! blade with a force, a contact or a generation is dirty, a patch holding
//! a displaced blade is kept — or a pass would skip a blade it must visit.
//! After every step of a ball rolling over a field, leaving and its track
//! recovering, this test checks both, that the lists follow the track and
//! not the field, that they empty once the field is back at rest, and that
//! the blades agree with the CPU twin throughout.

mod common;

use glam::{Quat, Vec3};
use trample::Simulation;
use trample::builder::{BodyBuilder, SimulationBuilder};
use trample::field::{FieldParams, LodParams};
use trample::object::TrackParams;
use trample::step::{HostView, SimParams};
use trample_gpu::GpuSimulation;

/// The step parity tests' vertex tolerance (m).
const VERTEX_TOLERANCE_M: f32 = 1e-3;

/// 6.4 × 6.4 m of grass in 32 × 32 patches of 2 × 2 cells of 0.1 m (small
/// patches: propagation reaches past the patches beside the listed ones,
/// where only its own marks make a patch dirty), every
/// cell geometric, seen from above; tracks recover in 0.1 s, flattened
/// blades as fast.
fn field() -> Simulation {
    SimulationBuilder::new()
        .field(FieldParams {
            patches: [32, 32],
            cells_per_patch: 2,
            ..FieldParams::default()
        })
        .lod(LodParams {
            geometry_m: 1000.0,
            billboard_m: 2000.0,
        })
        .sim(SimParams {
            // `[sim]`'s track recovers too (a removed body's blades are
            // `[sim]`'s).
            recovery_s: 0.1,
            trail: 0.0,
            // Pushes that propagate far (up to the generation cap).
            att: 0.7,
            threshold: 0.1,
            ..SimParams::default()
        })
        .host_view(
            HostView::look_at(Vec3::new(0.0, 10.0, 0.1), Vec3::ZERO, 1.0, 1.0, 0.1, 100.0).unwrap(),
        )
        .build()
        .unwrap()
}

/// Checks the marks against the blades after a step; returns the patches
/// on the last recover lists and the kept ones.
fn check(gpu: &common::TestGpu, g: &GpuSimulation, cpu: &Simulation, when: &str) -> (u32, usize) {
    let (device, queue) = (&gpu.device, &gpu.queue);
    let a = g.read_active_patches(device, queue).unwrap();
    for p in 0..a.dirty.len() {
        assert!(
            !a.touched[p] || a.dirty[p],
            "{when}: patch {p} holds a force, contact or generation but is not dirty"
        );
        assert!(
            !a.displaced[p] || a.kept[p],
            "{when}: patch {p} holds a displaced blade but is not kept"
        );
    }
    let pos = g.field.read_positions(device, queue).unwrap();
    let bl = &cpu.field.blades;
    let worst = pos.iter().enumerate().fold(0.0f32, |w, (i, p)| {
        let d = Vec3::new(p[0], p[1], p[2]).distance(bl.pos[i].vec3a().into());
        w.max(if d.is_nan() { f32::INFINITY } else { d })
    });
    assert!(
        worst <= VERTEX_TOLERANCE_M,
        "{when}: the GPU's blades are {worst} m from the CPU's"
    );
    (a.recover_listed, a.kept.iter().filter(|&&k| k).count())
}

#[test]
fn the_active_patches_cover_the_track_and_empty_at_rest() {
    let gpu = common::gpu();
    let (device, queue) = (&gpu.device, &gpu.queue);
    let mut cpu = field();
    let mut g = GpuSimulation::new(device, queue, cpu.clone()).expect("GPU simulation");
    let patches = 32 * 32;
    let dt = cpu.params.dt_s;
    let step = |cpu: &mut Simulation, g: &mut GpuSimulation| {
        cpu.step(dt).unwrap();
        g.step(device, queue, dt).unwrap();
    };

    // A ball whose track recovers in 0.1 s rolls along +x through the
    // field's middle rows.
    let ball = BodyBuilder::sphere("ball", 0.3)
        .at([-2.8, 0.25, 0.3])
        .track(TrackParams {
            recovery_s: Some(0.1),
            trail: Some(0.0),
            ..TrackParams::default()
        })
        .build()
        .unwrap();
    let id = cpu.add_body(ball.clone());
    assert_eq!(g.sim.add_body(ball), id);
    let mut p = Vec3::new(-2.8, 0.25, 0.3);
    let mut most = 0;
    for frame in 0..40 {
        p += Vec3::X * 5.0 * dt;
        cpu.move_body(id, p, Quat::IDENTITY, dt).unwrap();
        g.sim.move_body(id, p, Quat::IDENTITY, dt).unwrap();
        step(&mut cpu, &mut g);
        let (listed, _) = check(&gpu, &g, &cpu, &format!("rolling, frame {frame}"));
        if frame > 0 {
            most = most.max(listed);
        }
    }
    assert!(
        cpu.blades_away_from_rest() > 100,
        "the ball must leave a track"
    );
    // After the first step (every patch starts dirty and kept), the lists
    // hold the patches along the track, not the field.
    assert!(
        most > 0 && most <= patches / 2,
        "the recover lists held up to {most} of {patches} patches while the ball rolled"
    );

    // The ball leaves; its track recovers, and the lists empty.
    cpu.remove_body(id).unwrap();
    g.sim.remove_body(id).unwrap();
    let mut last = (u32::MAX, usize::MAX);
    for frame in 0..120 {
        step(&mut cpu, &mut g);
        last = check(&gpu, &g, &cpu, &format!("recovering, frame {frame}"));
    }
    assert_eq!(cpu.blades_away_from_rest(), 0, "the track must recover");
    assert_eq!(
        last,
        (0, 0),
        "at rest, no patch is listed for recovery or kept"
    );
}
