//! OBB-tree build (the paper's off-line stage, `obb/build.rs`): covariance
//! fit, split along the longest axis, EqN per node, plus the inside grid of
//! a closed mesh. Icospheres of 1,280, 20,480 and 327,680 triangles and the
//! knot (6,144); small mode: the 1,280-triangle sphere and the knot.
//! Throughput: triangles.

mod common;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;
use trample::obb::ObbTree;
use trample::obb::build::DEFAULT_MAX_DEPTH;
use trample::object::shapes;

fn bench(c: &mut Criterion) {
    let levels: &[u32] = if common::small() { &[3] } else { &[3, 5, 7] };
    let mut meshes: Vec<(String, _)> = levels
        .iter()
        .map(|&l| (format!("sphere_l{l}"), shapes::sphere(1.0, l)))
        .collect();
    meshes.push(("knot".into(), shapes::knot(2.4)));
    let mut group = c.benchmark_group("obb_build");
    group.sample_size(10);
    for (name, mesh) in &meshes {
        group.throughput(Throughput::Elements(mesh.triangle_count() as u64));
        group.bench_with_input(BenchmarkId::from_parameter(name), mesh, |b, m| {
            b.iter(|| ObbTree::build(black_box(m), DEFAULT_MAX_DEPTH));
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
