//! The exact collision reference (segment crosses a triangle, or lies inside
//! the closed mesh; `collision/exact.rs`) against the same question asked of
//! parry3d's `TriMesh` (its AABB BVH: a ray cast of the segment, then
//! `contains_local_point` of the midpoint for a closed mesh; see
//! `common::peer::ParryMesh`).
//!
//! Inputs as in `narrow_phase.rs`: the segments under the default scene's
//! sphere and the knot (`field`: all of the broad phase's patches; `near`:
//! those meeting the root box). Ours walks the OBB tree to the leaves and
//! answers most inside tests from the tree's voxel grid. Answers are
//! compared before timing; ratios print at the end (peer / ours).

mod common;

use common::peer::ParryMesh;
use criterion::{BenchmarkId, Criterion, Throughput};
use std::hint::black_box;
use std::time::SystemTime;
use trample::collision::segment_hits_exact;

fn bench(c: &mut Criterion) -> Vec<(String, String)> {
    let mut pairs = Vec::new();
    let mut group = c.benchmark_group("exact");
    for (shape, scene) in [("sphere", "default.toml"), ("knot", "knot.toml")] {
        let sim = common::sim(scene);
        let tree = &sim.bodies[0].tree;
        let peer = ParryMesh::new(tree);
        let field = common::field_segments(&sim, common::pose_times());
        let near = common::near_segments(&sim, &field);
        for (set, segments) in [("field", &field), ("near", &near)] {
            let ours: Vec<bool> = segments
                .iter()
                .map(|&(a, b)| segment_hits_exact(tree, a, b))
                .collect();
            let theirs: Vec<bool> = segments
                .iter()
                .map(|&(a, b)| peer.segment_hits(a, b))
                .collect();
            let differ = ours.iter().zip(&theirs).filter(|(a, b)| a != b).count();
            let hits = ours.iter().filter(|&&h| h).count();
            // Segments that graze a triangle may go either way in f32.
            assert!(
                differ * 100 <= hits.max(1),
                "{shape}/{set}: parry and ours disagree on {differ} of {hits} hits"
            );
            eprintln!(
                "exact {shape}/{set}: {} segments, {hits} exact hits, {differ} answered differently by parry3d",
                segments.len()
            );
            let input = format!("{shape}_{set}");
            group.throughput(Throughput::Elements(segments.len() as u64));
            group.bench_with_input(BenchmarkId::new("ours", &input), segments, |b, segs| {
                b.iter(|| {
                    segs.iter()
                        .filter(|&&(p0, p1)| segment_hits_exact(tree, black_box(p0), black_box(p1)))
                        .count()
                });
            });
            group.bench_with_input(BenchmarkId::new("parry3d", &input), segments, |b, segs| {
                b.iter(|| {
                    segs.iter()
                        .filter(|&&(p0, p1)| peer.segment_hits(black_box(p0), black_box(p1)))
                        .count()
                });
            });
            pairs.push((
                format!("exact/ours/{input}"),
                format!("exact/parry3d/{input}"),
            ));
        }
    }
    group.finish();
    pairs
}

fn main() {
    let since = SystemTime::now();
    let mut c = Criterion::default().configure_from_args();
    let pairs = bench(&mut c);
    c.final_summary();
    common::print_ratios(&pairs, since);
}
