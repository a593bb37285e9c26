//! Parity of the narrow phase and DBG forces (paper §4.2, Eq. 2): the GPU
//! kernel against `trample::collision::collide_blade` and the CPU's EqF sum,
//! on the built-in shapes at precisions 1–7. Hit flags must be identical,
//! segment by segment; forces agree within a stated tolerance.

mod common;

use glam::{Quat, Vec3, Vec3A};
use trample::collision::{BladeContacts, collide_blade};
use trample::field::{Blades, Lod};
use trample::force::eqf::eqf;
use trample::obb::{DEFAULT_MAX_DEPTH, ObbTree};
use trample::object::shapes::{capsule, cuboid, knot, sphere};
use trample::object::{Pose, TriMesh};
use trample_gpu::upload::Uploads;
use trample_gpu::{GpuField, GpuObjects, NarrowPhase};

/// Relative tolerance on Σ EqF per blade: the GPU takes the same steps in
/// f32, but may contract a·b + c into an fma and computes `length`,
/// `normalize` and the quaternion rotation of the contact with its own
/// rounding (a few ulps on unit vectors and speeds of a few m/s).
const FORCE_TOLERANCE: f32 = 1e-4;

const SEGMENTS: usize = 4;

/// Deterministic xorshift in [0, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.next()
    }
}

/// `side²` blades with jittered vertices over a square of half width
/// `reach` centred under `centre`: roots from well below to above the
/// object's centre, so segments cross its surface, lie wholly inside it or
/// miss it.
fn blades_around(centre: Vec3, reach: f32, side: usize, seed: u64) -> Blades {
    let mut rng = Rng(seed);
    let count = side * side;
    let mut pos = vec![Vec3A::ZERO; count * (SEGMENTS + 1)];
    let mut seg_len = vec![0.0; count];
    for b in 0..count {
        let (i, j) = ((b % side) as f32, (b / side) as f32);
        let x = centre.x - reach + 2.0 * reach * (i + 0.5) / side as f32;
        let z = centre.z - reach + 2.0 * reach * (j + 0.5) / side as f32;
        let mut p = Vec3::new(x, centre.y + rng.range(-1.2, 0.2) * reach, z);
        let step = rng.range(0.05, 0.35) * reach;
        pos[b] = p.into();
        for k in 1..=SEGMENTS {
            let d = Vec3::new(rng.range(-0.4, 0.4), 1.0, rng.range(-0.4, 0.4)).normalize() * step;
            p += d;
            pos[k * count + b] = p.into();
        }
        seg_len[b] = step;
    }
    Blades::new(
        SEGMENTS,
        pos.into_iter().map(Into::into).collect(),
        seg_len,
        vec![0.01; count],
        vec![0.0; count],
    )
}

/// The CPU reference for one object: per blade (hit mask, Σ EqF, num), as
/// `trample::step::stages::narrow_phase` computes it.
fn cpu_reference(
    blades: &Blades,
    tree: &ObbTree,
    pose: &Pose,
    precision: u32,
) -> Vec<(u32, Vec3, u32)> {
    let n = blades.segments;
    let mut contacts = BladeContacts::default();
    (0..blades.count)
        .map(|b| {
            let local: Vec<Vec3> = (0..=n)
                .map(|k| pose.to_local(Vec3::from(blades.vertex(b, k))))
                .collect();
            collide_blade(&local, tree, precision, &mut contacts);
            let mut force = Vec3::ZERO;
            for k in 0..n {
                if contacts.mask & (1 << k) != 0 {
                    let c = contacts.contacts[k];
                    let speed = pose.point_velocity(pose.to_world(c.point)).length();
                    force += eqf(speed, pose.rotation * c.dir);
                }
            }
            (contacts.mask, force, contacts.mask.count_ones())
        })
        .collect()
}

fn shapes() -> Vec<(&'static str, TriMesh)> {
    vec![
        ("sphere", sphere(0.5, 3)),
        ("box", cuboid(Vec3::new(0.5, 0.3, 0.4))),
        ("capsule", capsule(0.3, 0.8)),
        ("knot", knot(1.2)),
    ]
}

fn pose() -> Pose {
    Pose {
        position: Vec3::new(0.05, 0.2, -0.03),
        rotation: Quat::from_euler(glam::EulerRot::YXZ, 0.7, 0.3, -0.2),
        velocity: Vec3::new(2.0, 0.0, 0.5),
        angular_velocity: Vec3::new(0.0, 0.0, -3.0),
    }
}

#[test]
fn hit_flags_identical_and_forces_close_at_every_precision_on_builtin_shapes() {
    let gpu = common::gpu();
    let (device, queue) = (&gpu.device, &gpu.queue);
    eprintln!("adapter: {}", gpu.adapter_name());
    let kernel = NarrowPhase::new(device);
    let pose = pose();
    let blades = blades_around(pose.position, 0.9, 64, 0x5eed);
    let lod = vec![Lod::Geometry; blades.count];
    let field =
        GpuField::new(device, &blades, &lod, 1, &vec![[u32::MAX; 4]; blades.count]).unwrap();
    let mut worst = 0.0f32;
    for (name, mesh) in shapes() {
        let tree = ObbTree::build(&mesh, DEFAULT_MAX_DEPTH);
        let mut objects = GpuObjects::new(device, &[&tree], (0, 0)).unwrap();
        objects.set_pose(0, &pose);
        for precision in 1..=7 {
            let cpu = cpu_reference(&blades, &tree, &pose, precision);
            let mut enc = device.create_command_encoder(&Default::default());
            kernel.record(
                device,
                queue,
                &mut Uploads::new(),
                &mut enc,
                &field,
                &mut objects,
                precision,
                None,
            );
            queue.submit([enc.finish()]);
            let masks = field.read_hit_masks(device, queue).unwrap();
            let forces = field.read_forces(device, queue).unwrap();
            let mismatched: Vec<usize> = (0..blades.count)
                .filter(|&b| masks[b] != cpu[b].0)
                .collect();
            let hits: u32 = cpu.iter().map(|c| c.2).sum();
            for &b in mismatched.iter().take(5) {
                eprintln!(
                    "{name} p{precision} blade {b}: gpu {:04b} cpu {:04b}",
                    masks[b], cpu[b].0
                );
            }
            assert!(
                mismatched.is_empty(),
                "{name} p{precision}: {} of {} blades differ",
                mismatched.len(),
                blades.count
            );
            assert!(
                hits > 50,
                "{name} p{precision}: only {hits} segment hits, the test would prove little"
            );
            for b in 0..blades.count {
                let (_, f, num) = cpu[b];
                let g = Vec3::from_slice(&forces[b].force);
                assert_eq!(forces[b].num, num as f32, "{name} p{precision} blade {b}");
                let err = (g - f).length() / (1.0 + f.length());
                worst = worst.max(err);
                assert!(
                    err <= FORCE_TOLERANCE,
                    "{name} p{precision} blade {b}: gpu {g} cpu {f}"
                );
            }
            eprintln!("{name} p{precision}: {hits} segment hits identical");
        }
    }
    eprintln!("worst relative force difference: {worst:e}");
}

#[test]
fn several_objects_sum_their_forces_and_skip_non_geometric_cells() {
    let gpu = common::gpu();
    let (device, queue) = (&gpu.device, &gpu.queue);
    let kernel = NarrowPhase::new(device);
    let a = pose();
    let b = Pose {
        position: a.position + Vec3::new(0.4, -0.1, 0.2),
        ..Pose::at_rest(Vec3::ZERO)
    };
    let blades = blades_around(a.position, 1.2, 48, 0xfeed);
    // Every third cell (one blade each) is a billboard: no collision there.
    let lod: Vec<Lod> = (0..blades.count)
        .map(|c| {
            if c % 3 == 0 {
                Lod::Billboard
            } else {
                Lod::Geometry
            }
        })
        .collect();
    let field =
        GpuField::new(device, &blades, &lod, 1, &vec![[u32::MAX; 4]; blades.count]).unwrap();
    let trees = [
        ObbTree::build(&sphere(0.5, 3), DEFAULT_MAX_DEPTH),
        ObbTree::build(&knot(1.0), DEFAULT_MAX_DEPTH),
    ];
    let mut objects = GpuObjects::new(device, &[&trees[0], &trees[1]], (0, 0)).unwrap();
    objects.set_pose(0, &a);
    objects.set_pose(1, &b);
    let precision = 5;
    let mut enc = device.create_command_encoder(&Default::default());
    kernel.record(
        device,
        queue,
        &mut Uploads::new(),
        &mut enc,
        &field,
        &mut objects,
        precision,
        None,
    );
    queue.submit([enc.finish()]);
    let forces = field.read_forces(device, queue).unwrap();
    let ra = cpu_reference(&blades, &trees[0], &a, precision);
    let rb = cpu_reference(&blades, &trees[1], &b, precision);
    let mut both = 0;
    for i in 0..blades.count {
        let (f, num) = if lod[i] == Lod::Geometry {
            (ra[i].1 + rb[i].1, ra[i].2 + rb[i].2)
        } else {
            (Vec3::ZERO, 0)
        };
        both += usize::from(ra[i].2 > 0 && rb[i].2 > 0 && lod[i] == Lod::Geometry);
        assert_eq!(forces[i].num, num as f32, "blade {i}");
        let g = Vec3::from_slice(&forces[i].force);
        assert!(
            (g - f).length() <= FORCE_TOLERANCE * (1.0 + f.length()),
            "blade {i}: gpu {g} cpu {f}"
        );
    }
    assert!(both > 0, "no blade was hit by both objects");
}
