//! The winding number of an open mesh (`collision/winding.rs`,
//! `collision/winding_grid.rs`), what the contact response asks of an
//! object with `track.open_inside = "winding"`: the beetle car at 4.5 m
//! (as `scenes/parked_car.toml` has it), points anywhere in its root box
//! and points near its surface (within ±4 % of its size along a
//! triangle's normal, seeded), each summed down the tree
//! (`winding_number`) and read from the grid where it is trusted
//! (`winding_at`). Prints the grid's size and build time, and how many
//! points the grid answers alone. Small mode: 2,000 points instead of
//! 100,000.

mod common;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use std::hint::black_box;
use std::path::Path;
use trample::collision::winding::winding_number;
use trample::collision::winding_grid::winding_at;
use trample::obb::{DEFAULT_MAX_DEPTH, ObbTree};
use trample::object::load_mesh_file;

/// `count` points of each kind: in the root box, and near the surface.
fn points(tree: &ObbTree, count: usize) -> [(&'static str, Vec<Vec3>); 2] {
    let mut next = common::uniform(0x005e_ed0f_3a11);
    let o = tree.nodes[0].obb;
    let in_box = (0..count)
        .map(|_| {
            let q = (Vec3::new(next(), next(), next()) * 2.0 - 1.0) * o.half;
            o.center + o.axes[0] * q.x + o.axes[1] * q.y + o.axes[2] * q.z
        })
        .collect();
    let near = (0..count)
        .map(|_| common::point_near_surface(tree, &mut next).0)
        .collect();
    [("box", in_box), ("near", near)]
}

fn bench(c: &mut Criterion) {
    let count = if common::small() { 2_000 } else { 100_000 };
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/meshes/beetle.obj");
    let mut mesh = load_mesh_file(&path).expect("mesh loads");
    for p in &mut mesh.positions {
        *p *= 4.5;
    }
    let mut tree = ObbTree::build(&mesh, DEFAULT_MAX_DEPTH);
    let start = std::time::Instant::now();
    tree.enable_winding();
    let built = start.elapsed();
    let grid = tree.winding_grid.as_ref().expect("an open mesh's grid");
    let mut notes = vec![format!(
        "beetle: {} triangles, grid {:?} voxels, {} corners, built in {:.0} ms",
        tree.triangles.len(),
        grid.voxels,
        grid.corners.len(),
        built.as_secs_f64() * 1e3
    )];
    let mut group = c.benchmark_group("winding");
    for (kind, queries) in points(&tree, count) {
        let whole = queries
            .iter()
            .filter(|&&p| grid.sample(p).is_some_and(|(_, t)| t >= 1.0))
            .count();
        // The grid stays within the tree sum's tolerance of it.
        let worst = queries
            .iter()
            .take(2_000)
            .map(|&p| (winding_at(&tree, p) - winding_number(&tree, p)).abs())
            .fold(0.0f32, f32::max);
        assert!(worst < 0.1, "{kind}: grid {worst} from the tree sum");
        notes.push(format!(
            "{kind}: {whole} of {} points answered by the grid alone; worst {worst:.4} from the tree sum",
            queries.len()
        ));
        group.throughput(Throughput::Elements(queries.len() as u64));
        group.bench_with_input(BenchmarkId::new("tree_sum", kind), &queries, |b, qs| {
            b.iter(|| {
                qs.iter()
                    .map(|&p| winding_number(&tree, black_box(p)))
                    .sum::<f32>()
            });
        });
        group.bench_with_input(BenchmarkId::new("grid", kind), &queries, |b, qs| {
            b.iter(|| {
                qs.iter()
                    .map(|&p| winding_at(&tree, black_box(p)))
                    .sum::<f32>()
            });
        });
    }
    group.finish();
    for n in notes {
        eprintln!("winding {n}");
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
