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
//!
//! The `contact_walk` group times the narrow phase as the simulation runs
//! it: `contact_blade` on whole blades (one walk per blade, the wide
//! four-segment test, boxes grown by the contact shell, each contact's
//! weight and direction) against parry3d's box test walking the same grown
//! boxes one segment at a time (`ParryObbTree::contact_hit`), after
//! checking that both find the same segment contacts.

mod common;

use common::peer::ParryObbTree;
use criterion::{BenchmarkId, Criterion, Throughput};
use std::hint::black_box;
use std::time::SystemTime;
use trample::collision::{
    BladeContacts, LocalMotion, Segments4, collide_segment, contact_blade, segment_hits_obb,
};
use trample::obb::Obb;

const PRECISION: u32 = 7;

/// The contact shell of the default scene (`sim.contact_shell_m`), metres.
const SHELL: f32 = 0.005;

/// Segments per blade in the scenes measured (`field.segments`).
const SEGMENTS: usize = 4;

fn bench(c: &mut Criterion) -> Vec<(String, String)> {
    let mut pairs = Vec::new();
    let mut group = c.benchmark_group("narrow_phase");
    for (shape, scene) in [("sphere", "default.toml"), ("knot", "knot.toml")] {
        let sim = common::sim(scene);
        let tree = &sim.bodies[0].tree;
        let peer = ParryObbTree::new(tree, SHELL);
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
            // What the tilted boxes (`obb::slabs`) cost or save: the same
            // walk on the boxes alone (more hits: the boxes' false ones).
            let mut boxes_only = trample::obb::ObbTree::clone(tree);
            boxes_only.slabs.clear();
            group.bench_with_input(
                BenchmarkId::new("ours_boxes_only", &input),
                segments,
                |b, segs| {
                    b.iter(|| {
                        segs.iter()
                            .filter(|&&(p0, p1)| {
                                collide_segment(
                                    black_box(p0),
                                    black_box(p1),
                                    &boxes_only,
                                    PRECISION,
                                )
                                .is_some()
                            })
                            .count()
                    });
                },
            );
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
    pairs.extend(bench_contact_walk(c));
    pairs.extend(bench_box_test(c));
    pairs
}

/// The blades of `segments` (runs of [`SEGMENTS`] consecutive segments, as
/// `common::field_segments` lists them) as vertex lists.
fn blades_of(segments: &[(glam::Vec3, glam::Vec3)]) -> Vec<[glam::Vec3; SEGMENTS + 1]> {
    segments
        .chunks_exact(SEGMENTS)
        .map(|s| std::array::from_fn(|k| if k == 0 { s[0].0 } else { s[k - 1].1 }))
        .collect()
}

/// Segment hits of the simulation's narrow phase: one walk per blade, four
/// segments at a time with the wide test (`contact_blade`), boxes grown by
/// the contact shell, each contact's weight, direction and point computed.
fn ours_contact_hits(blades: &[[glam::Vec3; SEGMENTS + 1]], tree: &trample::obb::ObbTree) -> u32 {
    let mut out = BladeContacts::default();
    let mut n = 0;
    for b in blades {
        contact_blade(
            black_box(b),
            tree,
            PRECISION,
            SHELL,
            &LocalMotion::STILL,
            &mut out,
        );
        n += out.mask.count_ones();
    }
    n
}

/// The same question per segment, every box test by parry3d.
fn parry_contact_hits(blades: &[[glam::Vec3; SEGMENTS + 1]], peer: &ParryObbTree) -> u32 {
    let mut n = 0;
    for b in blades {
        for k in 0..SEGMENTS {
            n += u32::from(peer.contact_hit(black_box(b[k]), black_box(b[k + 1]), PRECISION));
        }
    }
    n
}

/// The narrow phase as the simulation runs it (issue 16: "now with the
/// wide test"): `contact_blade` on whole blades against parry3d's box test
/// walking the same grown boxes segment by segment.
fn bench_contact_walk(c: &mut Criterion) -> Vec<(String, String)> {
    let mut pairs = Vec::new();
    let mut group = c.benchmark_group("contact_walk");
    for (shape, scene) in [("sphere", "default.toml"), ("knot", "knot.toml")] {
        let sim = common::sim(scene);
        let tree = &sim.bodies[0].tree;
        let peer = ParryObbTree::new(tree, SHELL);
        let field = blades_of(&common::field_segments(&sim, common::pose_times()));
        let root = tree.reach[0];
        let grown = Obb {
            half: root.half + glam::Vec3::splat(SHELL),
            ..root
        };
        let near: Vec<_> = field
            .iter()
            .copied()
            .filter(|b| b.windows(2).any(|s| segment_hits_obb(s[0], s[1], &grown)))
            .collect();
        for (set, blades) in [("field", &field), ("near", &near)] {
            // The same answers, or the comparison means nothing.
            let mut out = BladeContacts::default();
            let (mut hits, mut differ) = (0, 0);
            for b in blades {
                contact_blade(b, tree, PRECISION, SHELL, &LocalMotion::STILL, &mut out);
                for k in 0..SEGMENTS {
                    let ours = out.mask >> k & 1 == 1;
                    hits += usize::from(ours);
                    differ += usize::from(ours != peer.contact_hit(b[k], b[k + 1], PRECISION));
                }
            }
            assert!(
                differ * 1000 <= hits.max(1),
                "{shape}/{set}: parry and ours disagree on {differ} of {hits} contacts"
            );
            eprintln!(
                "contact_walk {shape}/{set}: {} blades, {hits} segment contacts at precision {PRECISION}, {differ} answered differently by parry3d",
                blades.len()
            );
            let input = format!("{shape}_{set}");
            group.throughput(Throughput::Elements((blades.len() * SEGMENTS) as u64));
            group.bench_with_input(BenchmarkId::new("ours", &input), blades, |b, blades| {
                b.iter(|| ours_contact_hits(blades, tree));
            });
            group.bench_with_input(BenchmarkId::new("parry3d", &input), blades, |b, blades| {
                b.iter(|| parry_contact_hits(blades, &peer));
            });
            pairs.push((
                format!("contact_walk/ours/{input}"),
                format!("contact_walk/parry3d/{input}"),
            ));
        }
    }
    group.finish();
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
