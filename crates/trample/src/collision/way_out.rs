//! The way out of an object for a vertex inside it (ours, DESIGN §5
//! "Contact", "continuous"): the direction the contact response pushes it.
//!
//! Towards the closest surface point alone, the push jumps where two faces
//! are equally near — inside a faceted mesh, under every edge (the mesh's
//! interior medial axis): a vertex `d` deep that crosses the plane halfway
//! between two faces meeting at an angle `θ` is pushed `d · θ` elsewhere at
//! once. Two runs a few ulp apart (the CPU and GPU paths) then part by
//! millimetres, and a blade crushed centimetres deep by centimetres
//! (BENCHMARKS.md, session 18). So every triangle within
//! [`WAY_OUT_BAND_M`] beyond the closest one shares in the way out, by its
//! outward normal, its weight falling smoothly from 1 to 0 across the band
//! ([`way_out`]): the direction turns from one face's to the other's while
//! the vertex crosses the band, never at once. The normals, not the
//! directions to each triangle's closest point: a flat face cut into
//! triangles has one normal, so a vertex under it is pushed straight out
//! however it is cut (a neighbour's closest point, on the shared edge, lies
//! off to the side). Where the normals cancel (deep inside, at a ball's
//! centre) no rule can be continuous; the closest point's direction is
//! taken.

use glam::{Vec3, Vec3A};

use super::closest_point::{NearFaces, closest_point_on_triangle_region};
use super::exact::STACK_SIZE;
use crate::obb::ObbTree;

/// How far beyond a vertex's closest surface point, metres, the triangles
/// lie that share in its way out ([`way_out`]): 2 mm. Across the band the
/// push's direction turns from one face's normal to the next's, so a vertex
/// `d` deep under an edge between faces at an angle `θ` moves by about
/// `1 + d · θ² / band` times what it moves by itself (a few per cent for a
/// blade a centimetre deep under a ball of 1,280 faces, `θ` ≈ 0.1), instead
/// of jumping `d · θ`. Wider, the push strays further from the closest
/// point's: a vertex under an edge is pushed up to `θ / 2` off it and lands
/// that much short of the tolerance (the next round goes on).
pub const WAY_OUT_BAND_M: f32 = 0.002;

/// Calls `f(t, d_sq)` for every triangle `t` of `tree` whose point closest
/// to `p` (object frame) lies within `sqrt(max_sq)` of it, `d_sq` its
/// squared distance (measured as
/// [`closest_point_within_sq`](super::closest_point::closest_point_within_sq)
/// measures), in a fixed order: depth first, left child first. A node's box
/// holds its triangles, so a box farther than the bound is skipped whole.
/// Nothing for an empty tree, a non-finite `p` or a negative or NaN bound.
/// No allocation.
pub fn for_each_triangle_within_sq(
    tree: &ObbTree,
    p: Vec3,
    max_sq: f32,
    mut f: impl FnMut(usize, f32),
) {
    if tree.is_empty() || !p.is_finite() || max_sq.is_nan() || max_sq < 0.0 {
        return;
    }
    let mut stack = [0u32; STACK_SIZE];
    let mut len = 1;
    while len > 0 {
        len -= 1;
        let i = stack[len];
        let Some(node) = tree.nodes.get(i as usize) else {
            continue;
        };
        let q = node.obb.to_box_a(p.into());
        let box_sq = (q.abs() - Vec3A::from(node.obb.half))
            .max(Vec3A::ZERO)
            .length_squared();
        if box_sq > max_sq {
            continue;
        }
        let [l, r] = node.children;
        if node.is_leaf() || l <= i || r <= i || len + 2 > STACK_SIZE {
            let (first, count) = (node.first_tri as usize, node.tri_count as usize);
            let Some(tris) = tree.triangles.get(first..first.saturating_add(count)) else {
                continue;
            };
            for (k, tri) in tris.iter().enumerate() {
                let (q, _) = closest_point_on_triangle_region(p, tri);
                let d = q.distance_squared(p);
                if d <= max_sq {
                    f(first + k, d);
                }
            }
        } else {
            stack[len] = r;
            stack[len + 1] = l;
            len += 2;
        }
    }
}

/// The unit direction in which a vertex at `p` (object frame), `depth`
/// metres (> 0) from its closest surface point `nearest`, is pushed out
/// (`near`: the triangles the closest-point walk listed within
/// [`WAY_OUT_BAND_M`] beyond it, in its order; when it overflowed, the tree
/// is walked again, in [`for_each_triangle_within_sq`]'s order):
/// the normalised sum of the outward unit normals of every triangle within
/// `depth + WAY_OUT_BAND_M` of `p`, each weighted by `(1 − (d − depth) /
/// WAY_OUT_BAND_M)²` for a triangle `d` from `p` — 1 at the closest
/// point, falling to 0 with zero slope at the band's far edge, so a
/// triangle enters the sum without a jump. `(nearest − p) / depth` where
/// the sum cancels (or no triangle is met: an empty tree).
#[must_use]
pub fn way_out(tree: &ObbTree, p: Vec3, nearest: Vec3, depth: f32, near: &NearFaces) -> Vec3 {
    let reach = depth + WAY_OUT_BAND_M;
    let max_sq = reach * reach;
    let mut sum = Vec3::ZERO;
    let mut add = |t: usize, d_sq: f32| {
        let x = ((d_sq.sqrt() - depth) / WAY_OUT_BAND_M).clamp(0.0, 1.0);
        let w = (1.0 - x) * (1.0 - x);
        let [a, b, c] = tree.triangles[t];
        sum += (b - a).cross(c - a).normalize_or_zero() * w;
    };
    if near.overflow {
        for_each_triangle_within_sq(tree, p, max_sq, &mut add);
    } else {
        for &(t, d_sq) in &near.tris[..near.len] {
            if d_sq <= max_sq {
                add(t as usize, d_sq);
            }
        }
    }
    sum.try_normalize().unwrap_or_else(|| (nearest - p) / depth)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::closest_point::closest_point_on_mesh;
    use crate::object::shapes::{cuboid, knot, sphere};
    use crate::test_rng::XorShift;

    /// Every triangle within the bound, none beyond it: against a brute
    /// force over the triangles, at random points near a sphere and a knot.
    #[test]
    fn the_walk_meets_every_triangle_within_the_bound() {
        let mut rng = XorShift(0x9e37_79b9_7f4a_7c15u64);
        for mesh in [sphere(1.0, 3), knot(2.4)] {
            let tree = ObbTree::build(&mesh, 32);
            for _ in 0..300 {
                let p = Vec3::new(
                    rng.range(-1.3, 1.3),
                    rng.range(-1.3, 1.3),
                    rng.range(-1.3, 1.3),
                );
                let bound = rng.range(0.0, 0.3);
                let near = |t: &[Vec3; 3]| {
                    closest_point_on_triangle_region(p, t).0.distance_squared(p) <= bound * bound
                };
                let want: Vec<usize> = (0..tree.triangles.len())
                    .filter(|&t| near(&tree.triangles[t]))
                    .collect();
                let mut got = Vec::new();
                for_each_triangle_within_sq(&tree, p, bound * bound, |t, d| {
                    assert!(d <= bound * bound);
                    got.push(t);
                });
                got.sort_unstable();
                assert_eq!(got, want, "{p} within {bound}");
            }
        }
    }

    /// A vertex a centimetre deep under an edge of a faceted ball, moved
    /// across the plane halfway between the edge's two faces in steps of
    /// 10 µm: its target moves by about as much at each step. Towards the
    /// closest point alone it jumped from one face to the other, ~0.7 mm in
    /// one step (a ratio near 70).
    #[test]
    fn the_push_turns_smoothly_under_an_edge() {
        let tree = ObbTree::build(&sphere(1.0, 3), 32);
        let tris = &tree.triangles;
        let normal = |[a, b, c]: [Vec3; 3]| (b - a).cross(c - a).normalize();
        let (ta, tb, shared) = (1..tris.len())
            .find_map(|j| {
                let common: Vec<Vec3> = tris[0]
                    .iter()
                    .filter(|v| tris[j].iter().any(|w| w.distance(**v) < 1e-6))
                    .copied()
                    .collect();
                (common.len() == 2).then(|| (tris[0], tris[j], common))
            })
            .expect("a triangle beside the first");
        let (na, nb) = (normal(ta), normal(tb));
        let mid = (shared[0] + shared[1]) * 0.5;
        let start = mid - (na + nb).normalize() * 0.01;
        let across = (na - nb).normalize();
        let step = 1e-5;
        let mut worst = 0.0f32;
        let mut prev: Option<(Vec3, Vec3)> = None;
        for i in -200..=200 {
            let p = start + across * (i as f32 * step);
            let q = crate::collision::contact::push_out(&tree, p, 0.1).expect("1 cm deep");
            if let Some((pp, pq)) = prev {
                worst = worst.max((q - pq).length() / (p - pp).length());
            }
            prev = Some((p, q));
        }
        assert!(worst < 3.0, "the target moved {worst} times the step");
    }

    /// The closest-point walk that lists the near faces finds the plain
    /// walk's closest point bit for bit, and lists (unless it overflowed)
    /// exactly the triangles within the band beyond it.
    #[test]
    fn the_walk_lists_the_faces_within_the_band() {
        use crate::collision::closest_point::{
            closest_point_and_near_within_sq, closest_point_within_sq,
        };
        let mut rng = XorShift(0x1234_5678_9abc_def1u64);
        let mut overflowed = 0;
        for mesh in [sphere(1.0, 3), knot(2.4), cuboid(Vec3::new(0.6, 0.3, 0.9))] {
            let tree = ObbTree::build(&mesh, 32);
            for _ in 0..500 {
                let p = Vec3::new(
                    rng.range(-1.3, 1.3),
                    rng.range(-1.3, 1.3),
                    rng.range(-1.3, 1.3),
                );
                let bound = if rng.unit() < 0.5 {
                    f32::INFINITY
                } else {
                    rng.range(0.0, 0.5)
                };
                let plain = closest_point_within_sq(&tree, p, bound);
                let mut near = NearFaces::new(WAY_OUT_BAND_M);
                let listed = closest_point_and_near_within_sq(&tree, p, bound, &mut near);
                assert_eq!(format!("{plain:?}"), format!("{listed:?}"), "{p}");
                let Some(s) = listed else { continue };
                if near.overflow {
                    overflowed += 1;
                    continue;
                }
                let reach = s.distance_sq.sqrt() + WAY_OUT_BAND_M;
                let mut want = Vec::new();
                for_each_triangle_within_sq(&tree, p, reach * reach, |t, _| want.push(t as u32));
                want.sort_unstable();
                let mut got: Vec<u32> = near.tris[..near.len]
                    .iter()
                    .filter(|&&(_, d)| d <= reach * reach)
                    .map(|&(t, _)| t)
                    .collect();
                got.sort_unstable();
                assert_eq!(got, want, "{p}");
            }
        }
        assert!(overflowed < 50, "{overflowed} overflowed");
    }

    /// Under a flat face cut into two triangles, the way out is the face's
    /// normal, also near the cut (where the other triangle's closest point,
    /// on the cut, lies within the band).
    #[test]
    fn under_a_flat_face_the_way_out_is_its_normal() {
        let tree = ObbTree::build(&cuboid(Vec3::new(0.6, 0.3, 0.9)), 32);
        for x in [-0.4, -0.1, 0.0, 0.05, 0.3] {
            for z in [-0.7, -0.2, 0.0, 0.1, 0.6] {
                let p = Vec3::new(x, 0.29, z);
                let s = closest_point_on_mesh(&tree, p, f32::INFINITY).unwrap();
                let mut near = NearFaces::new(WAY_OUT_BAND_M);
                let _ = crate::collision::closest_point::closest_point_and_near_within_sq(
                    &tree,
                    p,
                    f32::INFINITY,
                    &mut near,
                );
                let u = way_out(&tree, p, s.point, s.distance_sq.sqrt(), &near);
                assert!(u.distance(Vec3::Y) < 1e-6, "{p}: {u}");
            }
        }
    }
}
