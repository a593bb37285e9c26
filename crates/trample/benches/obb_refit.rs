//! Deforming meshes, per frame (obb/refit.rs, object/skin.rs): the OBB-tree
//! refit of a 10,000-triangle closed tube bending like a limb (both axis
//! rules), and of the walker (`scenes/meshes/walker.glb`, 7,880 triangles)
//! skinned at successive frames of its walk; the CPU skinning alone; and,
//! for comparison with the refit, rebuilding the tree and rebuilding the
//! inside grid (what the refit avoids), and 1,000 inside queries with the
//! grid and by the ray alone (what dropping it costs). Throughput:
//! triangles (vertices for skinning, points for queries). Small mode: two
//! frames, fewer samples.

mod common;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::{Quat, Vec3};
use std::f32::consts::TAU;
use std::hint::black_box;
use trample::collision::exact::{point_inside, point_inside_by_ray};
use trample::collision::inside_grid::InsideGrid;
use trample::obb::refit::Nesting;
use trample::obb::{AxisRule, DEFAULT_MAX_DEPTH, ObbTree, RefitMap, RefitScratch};
use trample::object::skin::SkinScratch;
use trample::object::{SkinnedMesh, TriMesh};

/// A closed torus tube of 100 × 50 quads: 10,000 triangles, major radius
/// 0.5 m, tube radius 0.12 m, in the x–y plane (about the size of a leg).
fn tube() -> TriMesh {
    let (n, m) = (100u32, 50u32);
    let mut positions = Vec::new();
    for i in 0..n {
        let a = TAU * i as f32 / n as f32;
        let centre = Vec3::new(0.5 * a.cos(), 0.5 * a.sin(), 0.0);
        for j in 0..m {
            let b = TAU * j as f32 / m as f32;
            positions.push(centre * (1.0 + 0.24 * b.cos()) + Vec3::Z * 0.12 * b.sin());
        }
    }
    let id = |i: u32, j: u32| (i % n) * m + j % m;
    let mut indices = Vec::new();
    for i in 0..n {
        for j in 0..m {
            indices.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            indices.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    TriMesh { positions, indices }
}

/// `frames` poses of the tube: the half with x > 0 turns about z through
/// the origin, up to 60°, smoothly in x (a knee bending and unbending).
fn tube_frames(mesh: &TriMesh, frames: usize) -> Vec<Vec<Vec3>> {
    (0..frames)
        .map(|f| {
            let degrees = 60.0 * (TAU * f as f32 / frames as f32).sin().abs();
            mesh.positions
                .iter()
                .map(|&p| {
                    let s = (p.x / 0.62 * 4.0).clamp(0.0, 1.0);
                    let s = s * s * (3.0 - 2.0 * s);
                    Quat::from_rotation_z((degrees * s).to_radians()) * p
                })
                .collect()
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let frames = if common::small() { 2 } else { 16 };
    let tube = tube();
    let tube_poses = tube_frames(&tube, frames);
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/meshes/walker.glb"
    );
    let walker = SkinnedMesh::load(std::path::Path::new(path)).expect("walker.glb loads");
    let walk = walker.animation("walk").expect("walk");
    let mut scratch = SkinScratch::default();
    let walker_poses: Vec<Vec<Vec3>> = (0..frames)
        .map(|f| {
            let mut out = Vec::new();
            let t = walk.duration_s * f as f32 / frames as f32;
            walker.pose_into(Some(walk), t, &mut scratch, &mut out);
            out
        })
        .collect();

    let mut group = c.benchmark_group("obb_refit");
    group.sample_size(if common::small() { 10 } else { 50 });
    for (name, mesh, poses) in [
        ("tube_10k", &tube, &tube_poses),
        ("walker", &walker.bind, &walker_poses),
    ] {
        group.throughput(Throughput::Elements(mesh.triangle_count() as u64));
        // `_untilted`: a tree without tilted boxes (`obb::slabs`), as the
        // simulation refits a skin at every pose (`step/rig.rs`).
        for (rule, nesting, tilted) in [
            (AxisRule::Fixed, Nesting::Tight, true),
            (AxisRule::Fixed, Nesting::Tight, false),
            (AxisRule::Fit, Nesting::Tight, true),
            (AxisRule::Fit, Nesting::Contain, true),
        ] {
            let mut tree = ObbTree::build(mesh, DEFAULT_MAX_DEPTH);
            if !tilted {
                tree.slabs.clear();
            }
            let map = RefitMap::new(&tree, mesh).expect("own mesh");
            let mut refit_scratch = RefitScratch::default();
            let mut frame = 0;
            let untilted = if tilted { "" } else { "_untilted" };
            let id = BenchmarkId::new(format!("refit_{rule:?}_{nesting:?}{untilted}"), name);
            group.bench_function(id, |b| {
                b.iter(|| {
                    frame = (frame + 1) % poses.len();
                    tree.refit(
                        &map,
                        black_box(&poses[frame]),
                        rule,
                        nesting,
                        &mut refit_scratch,
                    )
                    .expect("valid");
                });
            });
        }
        let deformed = TriMesh {
            positions: poses[poses.len() / 2].clone(),
            indices: mesh.indices.clone(),
        };
        group.bench_function(BenchmarkId::new("rebuild", name), |b| {
            b.iter(|| ObbTree::build(black_box(&deformed), DEFAULT_MAX_DEPTH));
        });
        let tree = ObbTree::build(&deformed, DEFAULT_MAX_DEPTH);
        group.bench_function(BenchmarkId::new("inside_grid", name), |b| {
            b.iter(|| InsideGrid::build(black_box(&tree), |p| point_inside_by_ray(&tree, p)));
        });
        // What dropping the grid costs a query: 1,000 seeded points in the
        // root box, answered with the grid and by the ray alone.
        let root = tree.nodes[0].obb;
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let points: Vec<Vec3> = (0..1000)
            .map(|_| {
                let mut unit = || {
                    seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
                    (seed >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0
                };
                let q = Vec3::new(unit(), unit(), unit()) * root.half;
                root.center + root.axes[0] * q.x + root.axes[1] * q.y + root.axes[2] * q.z
            })
            .collect();
        group.throughput(Throughput::Elements(points.len() as u64));
        group.bench_function(BenchmarkId::new("inside_1000_grid", name), |b| {
            b.iter(|| points.iter().filter(|&&p| point_inside(&tree, p)).count());
        });
        group.bench_function(BenchmarkId::new("inside_1000_ray", name), |b| {
            b.iter(|| {
                points
                    .iter()
                    .filter(|&&p| point_inside_by_ray(&tree, p))
                    .count()
            });
        });
    }
    group.throughput(Throughput::Elements(walker.bind.positions.len() as u64));
    let mut frame = 0;
    let mut out = Vec::new();
    group.bench_function(BenchmarkId::new("skin", "walker"), |b| {
        b.iter(|| {
            frame = (frame + 1) % frames;
            let t = walk.duration_s * frame as f32 / frames as f32;
            walker.pose_into(Some(walk), black_box(t), &mut scratch, &mut out);
        });
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
