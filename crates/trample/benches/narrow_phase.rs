//! Narrow phase (paper §4.2) at precision 7 against the same queries through
//! parry3d (DESIGN §10: ours ≥ 10× faster, measured in one run).
//!
//! Inputs: the blade segments at rest of every patch the broad phase keeps
//! under the object (the default scene's 1,280-triangle sphere and the
//! knot's 6,144-triangle tube, posed at 4, 6 and 8 s), in the object's frame:
//! `field` is all of them (most miss the root box: one box test each),
//! `near` only those that meet the root box (they walk down the tree).
//!
//! The peer ([`common::peer::ParryObbTree`]) walks the same OBB tree in the
//! same order with parry3d's cuboid–segment SAT test in place of ours, and
//! shares the EqN directions and the inside test: it answers exactly the
//! same queries (checked before timing), so the ratio is the cost of the
//! box tests and the traversal around them. parry's own BVH is the peer of
//! the exact reference (`benches/exact.rs`), not of this: its AABB nodes
//! have no depth-`d` answer. Ratios print at the end (peer / ours).

mod common;

use common::peer::ParryObbTree;
use criterion::{BenchmarkId, Criterion, Throughput};
use std::hint::black_box;
use std::time::SystemTime;
use trample::collision::{Segments4, collide_segment, segment_hits_obb};
use trample::obb::Obb;

const PRECISION: u32 = 7;

fn bench(c: &mut Criterion) -> Vec<(String, String)> {
    let mut pairs = Vec::new();
    let mut group = c.benchmark_group("narrow_phase");
    for (shape, scene) in [("sphere", "default.toml"), ("knot", "knot.toml")] {
        let sim = common::sim(scene);
        let tree = &sim.bodies[0].tree;
        let peer = ParryObbTree::new(tree);
        let field = common::field_segments(&sim, common::pose_times());
        let near = common::near_segments(&sim, &field);
        for (set, segments) in [("field", &field), ("near", &near)] {
            // The same answers, or the comparison means nothing.
            let ours: Vec<bool> = segments
                .iter()
                .map(|&(a, b)| collide_segment(a, b, tree, PRECISION).is_some())
                .collect();
            let theirs: Vec<bool> = segments
                .iter()
                .map(|&(a, b)| peer.collide_segment(a, b, PRECISION).is_some())
                .collect();
            let differ = ours.iter().zip(&theirs).filter(|(a, b)| a != b).count();
            let hits = ours.iter().filter(|&&h| h).count();
            assert!(
                differ * 1000 <= hits.max(1),
                "{shape}/{set}: parry and ours disagree on {differ} of {hits} hits"
            );
            eprintln!(
                "narrow_phase {shape}/{set}: {} segments, {hits} hits at precision {PRECISION}, {differ} answered differently by parry3d",
                segments.len()
            );
            let input = format!("{shape}_{set}");
            group.throughput(Throughput::Elements(segments.len() as u64));
            group.bench_with_input(BenchmarkId::new("ours", &input), segments, |b, segs| {
                b.iter(|| {
                    segs.iter()
                        .filter(|&&(p0, p1)| {
                            collide_segment(black_box(p0), black_box(p1), tree, PRECISION).is_some()
                        })
                        .count()
                });
            });
            group.bench_with_input(BenchmarkId::new("parry3d", &input), segments, |b, segs| {
                b.iter(|| {
                    segs.iter()
                        .filter(|&&(p0, p1)| {
                            peer.collide_segment(black_box(p0), black_box(p1), PRECISION)
                                .is_some()
                        })
                        .count()
                });
            });
            pairs.push((
                format!("narrow_phase/ours/{input}"),
                format!("narrow_phase/parry3d/{input}"),
            ));
        }
    }
    group.finish();
    pairs.extend(bench_box_test(c));
    pairs
}

/// Hits of `segments` against `boxes`, one segment at a time.
fn scalar_hits(segments: &[(glam::Vec3, glam::Vec3)], boxes: &[Obb]) -> u32 {
    let mut n = 0;
    for &(a, b) in segments {
        for o in boxes {
            n += u32::from(segment_hits_obb(black_box(a), black_box(b), o));
        }
    }
    n
}

/// Hits of `segments` (a multiple of four) against `boxes`, four at a time.
fn wide_hits(segments: &[(glam::Vec3, glam::Vec3)], boxes: &[Obb]) -> u32 {
    let mut n = 0;
    for four in segments.chunks_exact(4) {
        let s = Segments4::new(
            std::array::from_fn(|i| black_box(four[i].0)),
            std::array::from_fn(|i| black_box(four[i].1)),
        );
        for o in boxes {
            n += s.hit_mask(o).count_ones();
        }
    }
    n
}

fn bench_box_test(c: &mut Criterion) -> Vec<(String, String)> {
    let mut pairs = Vec::new();
    let mut group = c.benchmark_group("segment_obb");
    for (shape, scene) in [("sphere", "default.toml"), ("knot", "knot.toml")] {
        let sim = common::sim(scene);
        let tree = &sim.bodies[0].tree;
        let field = common::field_segments(&sim, common::pose_times());
        let mut near = common::near_segments(&sim, &field);
        near.truncate(near.len() / 4 * 4);
        let boxes: Vec<Obb> = tree.nodes.iter().take(15).map(|n| n.obb).collect();
        assert_eq!(scalar_hits(&near, &boxes), wide_hits(&near, &boxes));
        let tests = (near.len() * boxes.len()) as u64;
        group.throughput(Throughput::Elements(tests));
        let input = format!("{shape}_near_x{}", boxes.len());
        group.bench_with_input(BenchmarkId::new("wide4", &input), &near, |b, segs| {
            b.iter(|| wide_hits(segs, &boxes));
        });
        group.bench_with_input(BenchmarkId::new("scalar", &input), &near, |b, segs| {
            b.iter(|| scalar_hits(segs, &boxes));
        });
        pairs.push((
            format!("segment_obb/wide4/{input}"),
            format!("segment_obb/scalar/{input}"),
        ));
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
