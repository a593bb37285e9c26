//! The closest-point walk (`collision/closest_point.rs`), what the contact
//! response asks some 120 thousand times a step on the herd (BENCHMARKS.md,
//! session 22): points near the surface of the ball, the knot, the beetle
//! car and the cow (within ±4 % of the mesh's size along a triangle's
//! normal, seeded), each asked with the bound a hint gives (the distance to
//! the triangle the point was made from, as `push_out_hinted` bounds its
//! walk), with no bound, and as `push_out_hinted` asks it ("near": the
//! hint's bound plus `PUSH_BLEND_M`, keeping the near points). Prints the
//! walk's cost in nodes at the end. Small mode: 2,000 points instead of
//! 200,000.

mod common;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use std::hint::black_box;
use std::path::Path;
use trample::collision::closest_point::{
    NearPoints, closest_point_and_near, closest_point_on_triangle_region, closest_point_within_sq,
};
use trample::collision::contact::PUSH_BLEND_M;
use trample::obb::{DEFAULT_MAX_DEPTH, ObbTree};
use trample::object::shapes::{knot, sphere};
use trample::object::{TriMesh, load_mesh_file};

/// The meshes asked, by name: the herd's ball and knot, and the two meshes
/// of `scenes/meshes`.
fn meshes() -> Vec<(&'static str, TriMesh)> {
    let mesh = |file: &str| {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../scenes/meshes")
            .join(file);
        load_mesh_file(&path).expect("mesh loads")
    };
    vec![
        ("ball", sphere(0.8, 3)),
        ("knot", knot(1.4)),
        ("beetle", mesh("beetle.obj")),
        ("cow", mesh("spot.obj")),
    ]
}

/// `count` points near the surface of `tree` and the squared distance of
/// the triangle each was made from (seeded xorshift).
fn points(tree: &ObbTree, count: usize) -> Vec<(Vec3, f32)> {
    let mut next = common::uniform(0x1234_5678_9abc);
    (0..count)
        .map(|_| {
            let (p, tri) = common::point_near_surface(tree, &mut next);
            let (q, _) = closest_point_on_triangle_region(p, &tri);
            (p, q.distance_squared(p))
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let count = if common::small() { 2_000 } else { 200_000 };
    let mut group = c.benchmark_group("closest_point");
    let mut notes = Vec::new();
    for (name, mesh) in meshes() {
        let tree = ObbTree::build(&mesh, DEFAULT_MAX_DEPTH);
        let queries = points(&tree, count);
        // The bounded walk finds the unbounded one's point (the bound
        // holds a triangle at least as near).
        for &(p, bound) in queries.iter().take(2_000) {
            let (a, b) = (
                closest_point_within_sq(&tree, p, bound),
                closest_point_within_sq(&tree, p, f32::INFINITY),
            );
            assert_eq!(
                a.map(|s| s.distance_sq),
                b.map(|s| s.distance_sq),
                "{name} at {p}"
            );
        }
        notes.push(format!(
            "{name}: {} triangles, {} nodes",
            tree.triangles.len(),
            tree.nodes.len()
        ));
        group.throughput(Throughput::Elements(queries.len() as u64));
        group.bench_with_input(BenchmarkId::new("hinted", name), &queries, |b, qs| {
            b.iter(|| {
                qs.iter()
                    .filter_map(|&(p, bound)| closest_point_within_sq(&tree, black_box(p), bound))
                    .count()
            });
        });
        group.bench_with_input(BenchmarkId::new("unbounded", name), &queries, |b, qs| {
            b.iter(|| {
                qs.iter()
                    .filter_map(|&(p, _)| {
                        closest_point_within_sq(&tree, black_box(p), f32::INFINITY)
                    })
                    .count()
            });
        });
        // What the contact response asks (`push_out_hinted`): the hint's
        // bound and the blend's reach past it, keeping the near points.
        let reached: Vec<(Vec3, f32)> = queries
            .iter()
            .map(|&(p, d_sq)| (p, (d_sq.sqrt() + PUSH_BLEND_M).powi(2)))
            .collect();
        group.bench_with_input(BenchmarkId::new("near", name), &reached, |b, qs| {
            b.iter(|| {
                let mut near = NearPoints::default();
                qs.iter()
                    .filter_map(|&(p, bound)| {
                        closest_point_and_near(&tree, black_box(p), bound, PUSH_BLEND_M, &mut near)
                    })
                    .count()
            });
        });
    }
    group.finish();
    for n in notes {
        eprintln!("closest_point {n}");
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
