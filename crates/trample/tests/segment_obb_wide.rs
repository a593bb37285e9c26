//! The four-wide segment–OBB test (`Segments4::hit_mask`, issue 16 item 2)
//! answers exactly as the scalar test (`segment_hits_obb`) on every lane:
//! random segments and boxes, and adversarial ones — segments grazing a
//! face, an edge or a corner, lying in a face's plane, parallel to faces,
//! of zero length, far from the origin, and with non-finite endpoints
//! beside finite lanes (rejected, never a hit, never spilling into the
//! other lanes).

mod common;

use common::Rng;
use glam::{Quat, Vec3};
use trample::collision::{Segments4, segment_hits_obb};
use trample::obb::Obb;

/// Checks one group of four against the scalar test; returns the hits.
fn check(p0: [Vec3; 4], p1: [Vec3; 4], obb: &Obb, what: &str) -> u32 {
    let mask = Segments4::new(p0, p1).hit_mask(obb);
    for i in 0..4 {
        let scalar = segment_hits_obb(p0[i], p1[i], obb);
        assert_eq!(
            mask >> i & 1 == 1,
            scalar,
            "{what}, lane {i}: {} – {} against {obb:?}",
            p0[i],
            p1[i]
        );
    }
    mask.count_ones()
}

fn random_obb(rng: &mut Rng) -> Obb {
    let rot = Quat::from_scaled_axis(rng.vec(1.0).normalize_or(Vec3::X) * rng.f32(0.0, 3.2));
    Obb {
        center: rng.vec(2.0),
        axes: [rot * Vec3::X, rot * Vec3::Y, rot * Vec3::Z],
        half: Vec3::new(rng.f32(0.0, 1.0), rng.f32(0.0, 1.0), rng.f32(0.0, 1.0)),
    }
}

#[test]
fn wide_test_equals_scalar_test_on_random_segments() {
    let mut rng = Rng(4);
    let mut hits = 0;
    let groups = 50_000;
    for g in 0..groups {
        let obb = random_obb(&mut rng);
        let p0 = [(); 4].map(|_| obb.center + rng.vec(2.5));
        let p1 = [(); 4].map(|_| obb.center + rng.vec(2.5));
        hits += check(p0, p1, &obb, &format!("group {g}"));
    }
    // Both answers are common.
    assert!(
        hits > groups / 5 && hits < 3 * groups,
        "{hits} hits of {}",
        4 * groups
    );
}

/// Points of an axis-aligned box's surface and edges, where the slab and
/// edge tests tie exactly.
#[test]
fn wide_test_equals_scalar_test_on_adversarial_segments() {
    let boxes = [
        Obb {
            center: Vec3::ZERO,
            axes: [Vec3::X, Vec3::Y, Vec3::Z],
            half: Vec3::new(1.0, 0.5, 0.25),
        },
        Obb {
            center: Vec3::new(1000.0, -3.0, 250.0),
            axes: [Vec3::X, Vec3::Y, Vec3::Z],
            half: Vec3::new(0.125, 2.0, 0.0),
        },
        Obb {
            center: Vec3::new(0.1, 0.2, 0.3),
            axes: {
                let r = Quat::from_rotation_y(0.7) * Quat::from_rotation_x(-0.3);
                [r * Vec3::X, r * Vec3::Y, r * Vec3::Z]
            },
            half: Vec3::new(0.3, 0.2, 0.1),
        },
    ];
    let (mut hits, mut total) = (0, 0);
    for (bi, obb) in boxes.iter().enumerate() {
        let [u, v, w] = obb.axes;
        let at = |x: f32, y: f32, z: f32| obb.center + u * x + v * y + w * z;
        let (hx, hy, hz) = (obb.half.x, obb.half.y, obb.half.z);
        let mut segments: Vec<(Vec3, Vec3)> = Vec::new();
        for s in [-1.0f32, 1.0] {
            // In a face's plane, across it and beside it.
            segments.push((at(s * hx, -2.0 * hy, 0.0), at(s * hx, 2.0 * hy, 0.0)));
            segments.push((
                at(s * hx, 0.0, -2.0 * hz - 0.1),
                at(s * hx, 0.0, 2.0 * hz + 0.1),
            ));
            segments.push((
                at(s * hx * 1.0001, -2.0, 0.0),
                at(s * hx * 1.0001, 2.0, 0.0),
            ));
            // Along an edge, and touching a corner from outside.
            segments.push((at(s * hx, s * hy, -3.0), at(s * hx, s * hy, 3.0)));
            segments.push((at(s * hx, hy, hz), at(s * 2.0 * hx, 2.0 * hy, 2.0 * hz)));
            // Grazing an edge diagonally (the edge axes decide).
            segments.push((at(s * 2.0 * hx, 0.0, hz), at(0.0, s * 2.0 * hy, hz)));
            segments.push((at(s * 2.0 * hx, hy, 0.0), at(0.0, hy, s * 2.0 * hz)));
            segments.push((at(0.0, s * 2.0 * hy, 2.0 * hz), at(2.0 * hx, 0.0, 0.0)));
            // Parallel to faces: constant in two box coordinates.
            segments.push((at(-3.0, s * hy, 0.0), at(3.0, s * hy, 0.0)));
            segments.push((at(-3.0, s * hy * 1.5, 0.0), at(3.0, s * hy * 1.5, 0.0)));
            segments.push((at(0.0, -3.0, s * hz), at(0.0, 3.0, s * hz)));
            // Ending exactly on a face.
            segments.push((at(s * 3.0 * hx, 0.0, 0.0), at(s * hx, 0.0, 0.0)));
            // Degenerate: points on the surface, inside, outside.
            segments.push((at(s * hx, 0.0, 0.0), at(s * hx, 0.0, 0.0)));
            segments.push((at(s * hx, s * hy, s * hz), at(s * hx, s * hy, s * hz)));
            segments.push((obb.center, obb.center));
            segments.push((at(s * 2.0 * hx, 0.0, 0.0), at(s * 2.0 * hx, 0.0, 0.0)));
        }
        // Signed zeros and a segment through the centre.
        segments.push((Vec3::splat(-0.0), Vec3::splat(0.0)));
        segments.push((at(-5.0, -5.0, -5.0), at(5.0, 5.0, 5.0)));
        // Every segment in every lane, with the others' neighbours beside it.
        for (i, &(a, b)) in segments.iter().enumerate() {
            for lane in 0..4 {
                let mut p0 = [0; 4].map(|k| segments[(i + k + 1) % segments.len()].0);
                let mut p1 = [0; 4].map(|k| segments[(i + k + 1) % segments.len()].1);
                p0[lane] = a;
                p1[lane] = b;
                hits += check(p0, p1, obb, &format!("box {bi}, segment {i}"));
                total += 4;
                // Reversed.
                hits += check(p1, p0, obb, &format!("box {bi}, segment {i} reversed"));
                total += 4;
            }
        }
    }
    assert!(hits > total / 4 && hits < total, "{hits} hits of {total}");
}

#[test]
fn non_finite_lanes_miss_and_leave_the_others_alone() {
    let obb = Obb {
        center: Vec3::ZERO,
        axes: [Vec3::X, Vec3::Y, Vec3::Z],
        half: Vec3::ONE,
    };
    let through = (Vec3::new(-2.0, 0.0, 0.0), Vec3::new(2.0, 0.0, 0.0));
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        for lane in 0..4 {
            for k in 0..3 {
                let mut p0 = [through.0; 4];
                let p1 = [through.1; 4];
                p0[lane][k] = bad;
                let mask = Segments4::new(p0, p1).hit_mask(&obb);
                assert_eq!(
                    mask,
                    0b1111 & !(1 << lane),
                    "{bad} in lane {lane}, axis {k}"
                );
                check(p0, p1, &obb, "non-finite");
            }
        }
    }
    // A NaN box misses everything.
    let nan = Obb {
        center: Vec3::NAN,
        ..obb
    };
    assert_eq!(
        Segments4::new([through.0; 4], [through.1; 4]).hit_mask(&nan),
        0
    );
}
